# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""Shared pieces of the nodes: message helpers, stamp pairing, input checks, the main loop."""
import math

from .._rclpy import take_all

__all__ = ['stamp_to_ns', 'ns_to_stamp', 'joint_index', 'finite', 'take_queued',
           'StampPairing', 'Rejects', 'PairedInput', 'run_node']


def take_queued(sub, cls):
    """
    Return the messages already queued on subscription ``sub`` (oldest first).

    Taken straight from the subscription, without a turn of the executor (which
    costs about 0.2 ms in rclpy); ``cls`` is the subscription's message type.
    """
    return [msg for msg, _ in take_all(sub, cls)]


def stamp_to_ns(stamp):
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def ns_to_stamp(ns, stamp):
    """Fill a builtin_interfaces/Time from integer nanoseconds."""
    stamp.sec, stamp.nanosec = divmod(int(ns), 1_000_000_000)
    return stamp


def joint_index(msg, joint):
    """Index of ``joint`` in a JointState's name list, or None."""
    try:
        return list(msg.name).index(joint)
    except ValueError:
        return None


def finite(*values):
    return all(math.isfinite(v) for v in values)


class StampPairing:
    """
    Pair joint states with the temperature sample of the same stamp (lockstep).

    In ``sync`` mode a state is processed only once the temperature with its
    stamp has arrived (the simulator publishes one with every state), which
    makes processing independent of the order in which the two topics are
    delivered.  Otherwise the latest temperature is used.
    """

    def __init__(self, sync, max_pending=10000):
        self.sync = sync
        self.temps = {}
        self.latest = None
        self.pending = {}
        self.max_pending = max_pending

    def temperature(self, ns, xi):
        """Record a temperature; returns states now ready [(ns, payload)]."""
        self.latest = xi
        if not self.sync:
            return []
        self.temps[ns] = xi
        ready = []
        if ns in self.pending:
            ready.append((ns, self.pending.pop(ns), xi))
        self._trim()
        return ready

    def state(self, ns, payload):
        """Offer a state; returns [(ns, payload, xi)] ready to process."""
        if not self.sync:
            return [] if self.latest is None else [(ns, payload, self.latest)]
        if ns in self.temps:
            return [(ns, payload, self.temps.pop(ns))]
        self.pending[ns] = payload
        self._trim()
        return []

    def _trim(self):
        for d in (self.temps, self.pending):
            while len(d) > self.max_pending:
                d.pop(next(iter(d)))


class Rejects:
    """Mixin: log (rate-limited) and count messages a node ignores."""

    rejected = 0

    def _reject(self, what):
        self.rejected += 1
        if self.rejected <= 10 or self.rejected % 1000 == 0:
            self.get_logger().warning(f'ignored {what} (rejected so far: {self.rejected})')


class PairedInput(Rejects):
    """
    Mixin: validated /joint_states + /joint_temperature input, paired by stamp.

    The node sets ``joint``, ``pair`` (:class:`StampPairing`) and
    ``state_fields`` (JointState fields it needs) and implements
    ``process(ns, values, xi)``.
    """

    state_fields = ('position', 'velocity')

    def on_temperature(self, msg):
        if not finite(msg.temperature):
            self._reject('a non-finite temperature')
            return
        for item in self.pair.temperature(stamp_to_ns(msg.header.stamp), msg.temperature):
            self.process(*item)

    def on_state(self, msg):
        i = joint_index(msg, self.joint)
        arrays = [getattr(msg, f) for f in self.state_fields]
        if i is None or i >= min(len(a) for a in arrays):
            self._reject(f'a joint state without {"/".join(self.state_fields)} for {self.joint}')
            return
        values = tuple(a[i] for a in arrays)
        if not finite(*values):
            self._reject('a joint state with NaN/inf')
            return
        for item in self.pair.state(stamp_to_ns(msg.header.stamp), values):
            self.process(*item)


def run_node(factory, name, args=None, drain=True):
    """
    Run a node as the ``main()`` body: init, spin, quiet end on Ctrl-C / SIGTERM.

    The first SIGINT/SIGTERM stops the node *after* it has processed what is
    already queued (``drain``; e.g. an estimator behind a simulator that has
    finished), so no answer is lost; a second signal exits at once.  Bad
    parameters (:class:`~friction_joint.exceptions.FrictionJointError`) end
    with a one-line error naming the problem and exit status 2.  A node may
    end itself by raising ``SystemExit(0)`` from a callback.  A node with a
    ``spin_step(executor)`` method runs its own loop: it is called instead of
    ``executor.spin_once``.

    The single-threaded executor is used: ``rclpy.experimental.EventsExecutor``
    is faster but was seen to stop delivering messages to one of two
    subscriptions on these wheels.
    """
    import signal
    import sys
    import time

    import rclpy
    from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
    from rclpy.signals import SignalHandlerOptions

    from ...exceptions import FrictionJointError

    stop = []

    def on_signal(signum, frame):
        stop.append(signum)
        if len(stop) > 1:
            raise KeyboardInterrupt

    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    old = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
    node = executor = None
    status = 0
    try:
        node = factory()
        executor = SingleThreadedExecutor()
        executor.add_node(node)
        spin = getattr(node, 'spin_step', None) or (lambda ex: ex.spin_once(timeout_sec=0.1))
        while not stop and rclpy.ok():
            spin(executor)
        t_end = time.monotonic() + 30.0
        while drain and rclpy.ok() and time.monotonic() < t_end:
            t0 = time.monotonic()
            executor.spin_once(timeout_sec=1.0)
            if time.monotonic() - t0 >= 1.0:
                break                                   # idle: everything queued is done
    except FrictionJointError as exc:
        print(f'{name}: error: {exc}', file=sys.stderr)
        status = 2
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except SystemExit as exc:
        status = exc.code or 0
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        if node is not None and rclpy.ok():
            from rclpy.duration import Duration
            for pub in node.publishers:          # let reliable peers take the last samples
                try:
                    pub.wait_for_all_acked(Duration(seconds=2.0))
                except Exception:                # noqa: BLE001 - best effort on the way out
                    pass
        if executor is not None:
            executor.shutdown()
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return status
