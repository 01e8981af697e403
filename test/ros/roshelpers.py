# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Helpers for tests that run ROS 2 processes: isolated domains, spawning, teardown.

Isolation (see ``ROS2-NOTES.md``): every test gets its own ``ROS_DOMAIN_ID``
and ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``; processes start in their own
session and are always stopped with SIGINT, then their process group is
killed.  The fixtures in ``conftest.py`` wrap these helpers:

- ``ros_env``: environment dict of a fresh domain (also set in ``os.environ``,
  so an in-test rclpy node joins the same domain);
- ``spawn``: ``spawn(cmd)`` starts a process in that environment and stops it
  at the end of the test;
- ``ros_node``: an in-test rclpy node (own context) in that domain.

Waiting (the tests must hold on a loaded machine): a test waits for a
*condition* (a line in a process's output, a matched peer, the answer to a
stamp) with a generous deadline, :data:`DEADLINE`, and goes on as soon as the
condition holds; it never sleeps a fixed time to let something happen, and it
asserts what arrived and what it contains, never how much arrived in a fixed
wall-time window (rates and latencies are measured by
``benchmarks/bench_nodes.py``).
"""
import contextlib
import fcntl
import itertools
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time

__all__ = ['PYTHON', 'DEADLINE', 'domain_id', 'release_domain', 'ros_environ', 'wait_until',
           'Proc', 'spawn',
           'TestNode', 'ros_node', 'reliable_qos', 'stamp_ns', 'param_if_declared']

#: the interpreter running the tests (the project's venv)
PYTHON = sys.executable

#: s: how long a test waits for a condition before it fails (returns as soon as it holds);
#: generous, for a machine loaded by other jobs (start-up of a node takes 0.3-0.5 s when idle)
DEADLINE = 60.0

_counter = itertools.count()
_FIRST, _COUNT = 10, 220          # domain ids 10..229 (Fast DDS ports stay below 65535)
_LOCKS = os.path.join(tempfile.gettempdir(), 'friction_joint-ros-domains')
_held = {}                        # domain id -> its open lock file


def domain_id():
    """
    Reserve and return a ``ROS_DOMAIN_ID`` (10..229) for one test.

    Several pytest processes may run at once on one machine (engineers, CI
    jobs): an id is taken only if no other process holds its lock file
    (``flock``, released by :func:`release_domain` or when the process ends),
    so two tests never share a domain (a stranger's ``/clock`` or states in a
    test's domain made it fail).  The search starts from the pid and a counter.
    """
    os.makedirs(_LOCKS, exist_ok=True)
    start = os.getpid() * 37 + next(_counter)
    for i in range(_COUNT):
        domain = _FIRST + (start + i) % _COUNT
        if domain in _held:
            continue
        fh = open(os.path.join(_LOCKS, f'{domain}.lock'), 'w')
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.close()
            continue
        _held[domain] = fh
        return domain
    raise RuntimeError(f'every ROS domain id {_FIRST}..{_FIRST + _COUNT - 1} is in use')


def release_domain(domain):
    """Release a domain id reserved by :func:`domain_id` (its processes stopped)."""
    fh = _held.pop(int(domain), None)
    if fh is not None:
        fh.close()


def ros_environ(domain=None, base=None):
    """Environment dict for ROS processes of one test: own domain, localhost discovery."""
    env = dict(os.environ if base is None else base)
    env.pop('ROS_LOCALHOST_ONLY', None)
    env['ROS_DOMAIN_ID'] = str(domain_id() if domain is None else domain)
    env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    env['PYTHONUNBUFFERED'] = '1'
    return env


def wait_until(predicate, timeout=DEADLINE, poll=0.02):
    """Poll ``predicate()`` until true or ``timeout`` s have passed; returns its last value."""
    t_end = time.monotonic() + timeout
    while True:
        value = predicate()
        if value or time.monotonic() > t_end:
            return value
        time.sleep(poll)


def stamp_ns(msg):
    """Return the header stamp of ``msg`` in integer nanoseconds."""
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


def param_if_declared(module, name, value):
    """
    Return ``{name: value}`` if the node of ``module`` declares parameter ``name``, else ``{}``.

    For a test that must pin a node parameter which not every version of the
    node has (an unknown parameter ends a node with exit 2).
    """
    import importlib
    defaults = getattr(importlib.import_module(module), 'DEFAULTS', {})
    return {name: value} if name in defaults else {}


class Proc:
    """
    A started process whose stdout and stderr are collected by reader threads.

    Attributes
    ----------
    popen : subprocess.Popen
    stdout, stderr : str
        Output so far (complete after :meth:`stop` or :meth:`wait`).

    """

    def __init__(self, cmd, env, cwd=None):
        self.cmd = [str(c) for c in cmd]
        self.popen = subprocess.Popen(self.cmd, env=env, cwd=cwd, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True,
                                      start_new_session=True)
        self._out, self._err = [], []
        self._cond = threading.Condition()
        self._threads = [threading.Thread(target=self._pump, args=(s, buf), daemon=True)
                         for s, buf in ((self.popen.stdout, self._out),
                                        (self.popen.stderr, self._err))]
        for t in self._threads:
            t.start()

    def _pump(self, stream, buf):
        for line in stream:
            with self._cond:
                buf.append(line)
                self._cond.notify_all()

    @property
    def stdout(self):
        with self._cond:
            return ''.join(self._out)

    @property
    def stderr(self):
        with self._cond:
            return ''.join(self._err)

    def wait_for(self, text, timeout=DEADLINE):
        """Wait until ``text`` appears on stdout or stderr; False on timeout or exit."""
        t_end = time.monotonic() + timeout
        with self._cond:
            while text not in ''.join(self._out) + ''.join(self._err):
                left = t_end - time.monotonic()
                if left <= 0 or (self.popen.poll() is not None and
                                 not any(t.is_alive() for t in self._threads)):
                    return False
                self._cond.wait(min(left, 0.1))
            return True

    def wait(self, timeout=DEADLINE):
        """Wait for the process to end by itself; returns its exit status."""
        rc = self.popen.wait(timeout)
        for t in self._threads:
            t.join(5)
        return rc

    def stop(self, timeout=DEADLINE):
        """SIGINT the process group, wait, then SIGKILL whatever is left; returns the status."""
        pgid = self.popen.pid                   # own session: group id = pid
        if self.popen.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(pgid, signal.SIGINT)
            try:
                self.popen.wait(timeout)
            except subprocess.TimeoutExpired:
                pass
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(pgid, signal.SIGKILL)
        rc = self.popen.wait(5)
        for t in self._threads:
            t.join(5)
        return rc

    def describe(self):
        """Command, status and output, for assertion messages."""
        return (f'$ {" ".join(self.cmd)}\nexit {self.popen.poll()}\n'
                f'--- stdout\n{self.stdout}--- stderr\n{self.stderr}')


@contextlib.contextmanager
def spawn(cmd, env, cwd=None):
    """Start ``cmd`` (own session) and always stop it (SIGINT, wait, kill group) at the end."""
    proc = Proc(cmd, env, cwd)
    try:
        yield proc
    finally:
        proc.stop()


def reliable_qos(depth=1000):
    """
    Reliable, volatile, keep-last ``depth``; ``depth=None``: keep-all.

    A keep-last publisher drops a sample a reader has not acknowledged once ``depth``
    newer ones are queued; a keep-all one keeps it until it is repaired.
    """
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    if depth is None:
        return QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.VOLATILE)
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=depth,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)


class TestNode:
    """An in-test rclpy node with its own executor; spin it with :meth:`spin_until`."""

    __test__ = False                            # not a pytest test class

    def __init__(self, node, executor):
        self.node = node
        self.executor = executor

    def spin_until(self, predicate, timeout=DEADLINE):
        """Spin until ``predicate()`` is true; returns its last value."""
        t_end = time.monotonic() + timeout
        while not predicate():
            if time.monotonic() > t_end:
                return predicate()
            self.executor.spin_once(timeout_sec=0.02)
        return True

    def repeat_until(self, action, predicate, period=0.2, timeout=DEADLINE):
        """
        Call ``action()`` every ``period`` s, spinning, until ``predicate()``; returns its value.

        For the first sample on a new connection: a publisher may see a
        subscriber before the subscriber has matched it, and a sample sent in
        that moment is lost to it; repeating it until it is answered is a
        condition, where a pause would be a guess.
        """
        t_end = time.monotonic() + timeout
        while True:
            action()
            if self.spin_until(predicate, min(period, max(0.0, t_end - time.monotonic()))):
                return True
            if time.monotonic() > t_end:
                return predicate()

    def spin_for(self, seconds):
        """Spin for ``seconds`` (to serve callbacks; never to wait for something to happen)."""
        t_end = time.monotonic() + seconds
        while time.monotonic() < t_end:
            self.executor.spin_once(timeout_sec=min(0.02, max(0.0, t_end - time.monotonic())))

    def wait_for_subscribers(self, publisher, count=1, timeout=DEADLINE):
        """Wait until ``publisher`` has ``count`` matched subscriptions."""
        return self.spin_until(lambda: publisher.get_subscription_count() >= count, timeout)

    def wait_for_publishers(self, subscription, count=1, timeout=DEADLINE):
        """Wait until ``subscription`` has ``count`` matched publishers."""
        return self.spin_until(lambda: subscription.get_publisher_count() >= count, timeout)


@contextlib.contextmanager
def ros_node(name, domain):
    """
    Yield a :class:`TestNode` on its own rclpy context in ``domain`` (no signal handlers).

    ``ROS_AUTOMATIC_DISCOVERY_RANGE`` is read from ``os.environ`` at init.
    """
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.signals import SignalHandlerOptions

    context = Context()
    rclpy.init(context=context, domain_id=int(domain),
               signal_handler_options=SignalHandlerOptions.NO)
    node = executor = None
    try:
        node = rclpy.create_node(name, context=context, start_parameter_services=False)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        yield TestNode(node, executor)
    finally:
        if executor is not None:
            executor.shutdown(timeout_sec=1.0)
        if node is not None:
            node.destroy_node()
        context.try_shutdown()
