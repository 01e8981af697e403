# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The rclpy internals this package relies on, isolated in one place with the reasons.

Public rclpy does not offer two things the nodes need at 1-3 kHz:

* taking every message queued on a subscription *without an executor turn*
  (an executor turn costs about 0.2 ms of CPU in rclpy, which a 3 kHz
  lockstep loop or a recorder at 16 k msg/s cannot afford).  The
  subscription's C handle (``Subscription.handle``, an rclpy implementation
  object) has ``take_message(cls, raw)``; :func:`take_message` wraps it;
* waiting for a message on a few subscriptions without an executor turn
  (:class:`Waiter`, on rclpy's ``WaitSet`` as ``rclpy.wait_for_message``
  uses it): a two-process ping-pong makes 3344 round trips/s this way
  against 1500/s with executors on both sides;
* the exception type of a failed publish on a keep-all publisher whose
  subscriber has stopped taking (``RCLError`` from the C extension), which
  replay turns into a named error;
* the ``/clock`` subscription of rclpy's time source (``Node._time_source``,
  ``TimeSource._clock_sub``): its callback raises ``ValueError`` on a
  ``/clock`` with negative seconds, out of the executor, which ends the node;
  :func:`guard_clock` puts a check in front of it;
* the names of the parameters given on the command line (``-p``, params
  files) for a node, so that an unknown one is an error as an unknown key in
  a gear file is: rclpy keeps them in ``Node._parameter_overrides`` and only
  declares the ones the node asks for.

If a later rclpy moves these, this module is the one to change.  It also
re-exports the public rclpy names the command line needs, so that only
:mod:`friction_joint.ros` imports rclpy.
"""
import contextlib
import os
import sys
import tempfile

from rclpy.executors import ExternalShutdownException
from rclpy.impl.implementation_singleton import rclpy_implementation

__all__ = ['ExternalShutdownException', 'RCLError', 'take_message',
           'take_all', 'parameter_override_names',
           'parameter_overrides', 'Waiter', 'guard_clock', 'held_stderr']

#: raised by rcl calls that fail, e.g. publishing to a full keep-all queue
RCLError = rclpy_implementation.RCLError


def held_stderr(call):
    """
    Return ``call()`` with what C code (rcl) writes to stderr held back meanwhile.

    On success the held-back output is written to stderr; on failure it is
    dropped, so the caller's one-line report of the exception is all there is.
    """
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, AttributeError, ValueError):   # no stderr to hold back
        return call()
    ok = False
    with tempfile.TemporaryFile() as held:
        try:
            os.dup2(held.fileno(), 2)
            try:
                result = call()
                ok = True
            finally:
                os.dup2(saved, 2)
                os.close(saved)
        finally:
            if ok:
                held.seek(0)
                text = held.read().decode('utf-8', 'replace')
                if text:
                    sys.stderr.write(text)
                    sys.stderr.flush()
    return result


def take_message(subscription, msg_class, raw=False):
    """
    Take one queued message of ``subscription`` or None, without an executor turn.

    Returns what the C handle returns: ``(message, info)`` or None.  The caller
    must hold the handle (``with subscription.handle:``); :func:`take_all` does.
    """
    return subscription.handle.take_message(msg_class, raw)


def take_all(subscription, msg_class, raw=False):
    """Every message already queued on ``subscription``: a list of ``(message, info)``."""
    out = []
    with subscription.handle:
        while (taken := take_message(subscription, msg_class, raw)) is not None:
            out.append(taken)
    return out


def parameter_override_names(node):
    """Return the names of the parameters given to ``node`` on the command line (a set)."""
    return set(getattr(node, '_parameter_overrides', {}))


def parameter_overrides(node):
    """Return ``{name: rclpy.parameter.Parameter}`` given to ``node`` on the command line."""
    return dict(getattr(node, '_parameter_overrides', {}))


def guard_clock(node, check):
    """
    Put ``check(msg)`` in front of rclpy's ``/clock`` callback of ``node`` (use_sim_time).

    ``check`` returns True to pass the message to rclpy's time source, False to
    drop it (it logs and counts).  Returns False when the node has no ``/clock``
    subscription (``use_sim_time`` off).
    """
    source = getattr(node, '_time_source', None)
    sub = getattr(source, '_clock_sub', None)
    if sub is None:
        return False
    inner = sub.callback

    def callback(msg):
        if check(msg):
            inner(msg)
    sub.callback = callback
    return True


class Waiter:
    """
    Wait until one of some subscriptions has a message queued, without an executor turn.

    Parameters
    ----------
    node : rclpy.node.Node
        The node that owns the subscriptions (its context is waited on).
    subscriptions : sequence of rclpy.subscription.Subscription
        What to wait for; take the messages with :func:`take_all` afterwards.

    """

    def __init__(self, node, subscriptions):
        self.subscriptions = list(subscriptions)
        self.wait_set = rclpy_implementation.WaitSet(len(self.subscriptions), 0, 0, 0, 0, 0,
                                                     node.context.handle)

    def wait(self, timeout_sec):
        """Block until a subscription has data or ``timeout_sec`` has passed."""
        with contextlib.ExitStack() as stack:
            self.wait_set.clear_entities()
            for sub in self.subscriptions:
                stack.enter_context(sub.handle)
                self.wait_set.add_subscription(sub.handle)
            self.wait_set.wait(int(timeout_sec * 1e9))
