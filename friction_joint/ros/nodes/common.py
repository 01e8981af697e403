# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Shared pieces of the nodes: message helpers, stamp pairing, the input gate, the main loop.

The input gate (:class:`Rejects`, :class:`PairedInput`): every message a node
takes in is checked before it touches any state.  A message is refused when
it lacks the node's joint or a field for it, when a value is not finite or
beyond what is physically plausible for the node's gear
(:class:`~friction_joint.testbed.plant.InputLimits`: position, velocity,
torque, temperature), or when its stamp lies more than ``MAX_STAMP_LEAD``
seconds ahead of the node's (wall) clock.  Refused messages are counted by
reason, logged at most once per ``REJECT_LOG_PERIOD`` seconds (rclpy's
``throttle_duration_sec``, behind a monotonic-clock check: rclpy's logger
inspects the caller's module on every call, about 0.7 ms, even when it then
throttles), and the count is logged when the node is destroyed
(``rejected N input messages (...)``).  An exception raised while a message
is processed is counted and logged the same way; it never ends the node
(except the types a node names in ``fatal``).
"""
from __future__ import annotations

import collections
from collections.abc import Callable
import contextlib
import math
import time
from typing import Any, TYPE_CHECKING

from .usage import exit_on_help
from .._rclpy import guard_clock, RCLError, take_all, Waiter
from ..parameters import declare_follower_params, MODES, prepare_ros_args, REJECT_LOG_PERIOD
from ..qos import dds_environ
from ..startup import check_domain_id, check_overrides_used, one_line, rcl_init

if TYPE_CHECKING:
    from builtin_interfaces.msg import Time
    from rclpy.subscription import Subscription
    from sensor_msgs.msg import JointState

__all__ = ['stamp_to_ns', 'ns_to_stamp', 'joint_index', 'finite', 'take_queued', 'StampPairing',
           'StampOrder', 'Rejects', 'PairedInput', 'run_node', 'REJECT_LOG_PERIOD', 'MODES',
           'STAMP_HORIZON', 'Lossless', 'PUBLISH_WAIT', 'MAX_STAMP_LEAD', 'EXECUTOR_EVERY',
           'declare_follower_params']

#: s a node that ended its run waits for reliable subscribers (a loaded recorder) to acknowledge
#: its last samples; one stopped by a signal waits STOP_ACK_TIMEOUT s (a killed peer never does)
ACK_TIMEOUT, STOP_ACK_TIMEOUT = 15.0, 0.5

#: s between the executor turns (parameter services) of a node that takes its input directly
EXECUTOR_EVERY = 0.05
#: seconds a state's stamp may lie ahead of the node's wall clock (checked without sim time)
MAX_STAMP_LEAD = 1.0
#: s: a state newer than the last answered one by at most this continues the stream (a
#: pause of a stream is seconds; a stamp from another clock is hours or years away)
STAMP_HORIZON = 10.0
#: s a lossless publisher retries a sample its full history refuses before giving up
PUBLISH_WAIT = 60.0


def take_queued(sub: Subscription, cls: type) -> list[Any]:
    """
    Return the messages already queued on subscription ``sub`` (oldest first).

    Taken straight from the subscription, without a turn of the executor (which
    costs about 0.2 ms in rclpy); ``cls`` is the subscription's message type.
    """
    return [msg for msg, _ in take_all(sub, cls)]


def stamp_to_ns(stamp: Time) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def ns_to_stamp(ns: int, stamp: Time) -> Time:
    """Fill a builtin_interfaces/Time from integer nanoseconds."""
    stamp.sec, stamp.nanosec = divmod(int(ns), 1_000_000_000)
    return stamp


def joint_index(msg: JointState, joint: str) -> int | None:
    """Index of ``joint`` in a JointState's name list, or None."""
    try:
        return list(msg.name).index(joint)
    except ValueError:
        return None


def finite(*values: float) -> bool:
    return all(math.isfinite(v) for v in values)


class StampPairing:
    """
    Pair joint states with the temperature sample of the same stamp (lockstep).

    In ``sync`` mode a state is processed only once the temperature with its
    stamp has arrived (the simulator publishes one with every state), which
    makes processing independent of the order in which the two topics are
    delivered.  Otherwise the latest temperature is used; states that arrive
    before any temperature are held (in order) until the first one does, so a
    temperature topic that matches a moment later than the state topic loses
    nothing.  At most ``max_pending`` states are held; older ones are dropped
    and counted in ``dropped``.
    """

    def __init__(self, sync: bool, max_pending: int = 10000) -> None:
        self.sync = sync
        self.temps: dict[int, float] = {}
        self.latest: float | None = None
        self.pending: dict[int, Any] = {}
        self.max_pending = max_pending
        self.dropped = 0

    def temperature(self, ns: int, xi: float) -> list[tuple[int, Any, float]]:
        """Record a temperature; returns states now ready [(ns, payload, xi)]."""
        self.latest = xi
        if not self.sync:
            ready = [(k, payload, xi) for k, payload in self.pending.items()]
            self.pending.clear()
            return ready
        self.temps[ns] = xi
        ready = []
        if ns in self.pending:
            ready.append((ns, self.pending.pop(ns), xi))
        self._trim()
        return ready

    def state(self, ns: int, payload: Any) -> list[tuple[int, Any, float]]:
        """Offer a state; returns [(ns, payload, xi)] ready to process."""
        if not self.sync and self.latest is not None:
            return [(ns, payload, self.latest)]
        if self.sync and ns in self.temps:
            return [(ns, payload, self.temps.pop(ns))]
        self.pending[ns] = payload
        self._trim()
        return []

    def _trim(self):
        while len(self.temps) > self.max_pending:
            self.temps.pop(next(iter(self.temps)))
        while len(self.pending) > self.max_pending:
            self.pending.pop(next(iter(self.pending)))
            self.dropped += 1


class Lossless:
    """
    A keep-all publisher that waits instead of failing when its history is full.

    A subscriber killed with SIGKILL stays matched until DDS drops it at the
    end of its participant's lease (about 20 s with Fast DDS); a keep-all
    publisher keeps every sample it has not acknowledged, and once the
    history's resource limit is reached rcl refuses the next publish
    (``RCLError``).  The sample is then retried every 0.05 s (logged, at most
    once per ``REJECT_LOG_PERIOD``) until the dead subscriber is dropped, so
    nothing is lost to the live ones; after ``PUBLISH_WAIT`` s the error is
    raised.
    """

    def __init__(self, node, publisher):
        self.node = node
        self.publisher = publisher
        self.retried = 0

    def publish(self, msg):
        t_end = None
        while True:
            try:
                self.publisher.publish(msg)
                return
            except RCLError as exc:
                now = time.monotonic()
                t_end = t_end or now + PUBLISH_WAIT
                if now > t_end:
                    raise
                self.retried += 1
                if self.node._log_due(f'full {self.publisher.topic_name}', REJECT_LOG_PERIOD):
                    self.node.get_logger().warning(
                        f'{self.publisher.topic_name}: a subscriber does not acknowledge (a '
                        f'killed peer, until its lease ends?); retrying ({exc})'.splitlines()[0])
                time.sleep(0.05)

    def __getattr__(self, name):
        return getattr(self.publisher, name)


class StampOrder:
    """
    Answer states in stamp order; refuse a lone outlier, follow a new timeline.

    A state continues the stream when its stamp equals the last answered one (answered
    again) or is newer by at most ``horizon`` ns.  Any other state (older, or far ahead) is
    held as a candidate: ``confirm`` candidates that continue one another are a new timeline
    (a replay that loops, a restarted simulator, a clock that jumped): the node restarts on
    it and answers them; a state that continues the old stream instead refuses the
    candidates as outliers.  One state stamped far ahead therefore never silences a node.
    """

    def __init__(self, horizon: float = STAMP_HORIZON, confirm: int = 3) -> None:
        self.horizon = int(horizon * 1e9)
        self.confirm = confirm
        self.last: int | None = None
        self.held: list[Any] = []
        self.held_last: int | None = None

    def _continues(self, last, ns):
        return last is None or last <= ns <= last + self.horizon

    def offer(self, ns: int, item: Any) -> tuple[bool, list[Any], int]:
        """Return ``(restart, ready items, refused count)`` for the state ``item`` at ``ns``."""
        refused = 0
        if self._continues(self.last, ns):
            refused, self.held = len(self.held), []
            self.last = ns
            return False, [item], refused
        if self.held and self.held_last is not None and \
                not (self.held_last < ns <= self.held_last + self.horizon):
            refused, self.held = len(self.held), []
        self.held.append(item)
        self.held_last = ns
        if len(self.held) < self.confirm:
            return False, [], refused
        ready, self.held = self.held, []
        self.last = ns
        return True, ready, refused


class Rejects:
    """
    Mixin: count, log (throttled) and report at shutdown the messages a node refuses.

    ``fatal`` names the exception types a guarded callback lets through (they
    end the node, as the node documents); every other exception is counted as
    a refused message.
    """

    rejected = 0
    fatal: tuple[type[BaseException], ...] = ()

    def _log_due(self, key, period):
        """Return whether the throttled log line ``key`` is due (checked before rclpy's)."""
        now, due = time.monotonic(), self.__dict__.setdefault('_log_next', {})
        if now < due.get(key, -math.inf):
            return False
        due[key] = now + period
        return True

    def _reject(self, what, why=''):
        """Count a refused message under ``what`` (a fixed reason); ``why`` adds the detail."""
        self.rejected += 1
        counts = self.__dict__.setdefault('_reject_counts', collections.Counter())
        counts[what] += 1
        line = f'ignored {what}{": " + why if why else ""} (rejected so far: {self.rejected})'
        if counts[what] == 1:              # the first of each kind, whatever came before it
            self.get_logger().warning(line)
        elif self._log_due('rejected', REJECT_LOG_PERIOD):
            # rclpy's own throttle stays as a second guard (half the period: never in the way)
            self.get_logger().warning(line, throttle_duration_sec=0.5 * REJECT_LOG_PERIOD)

    def guarded(self, what: str, handler: Callable[[Any], None], msg: Any) -> None:
        """Run ``handler(msg)``; an exception (not in ``fatal``) is counted, logged, survived."""
        try:
            handler(msg)
        except self.fatal:
            raise
        except Exception as exc:                # noqa: BLE001 - no message may end the node
            self._reject(f'{what} whose processing failed', f'{type(exc).__name__}: {exc}')

    def rejects_report(self) -> str:
        """Return the one-line summary of the refused messages."""
        counts = self.__dict__.get('_reject_counts') or collections.Counter()
        detail = '; '.join(f'{n} x {what}' for what, n in counts.most_common())
        return f'rejected {self.rejected} input messages' + (f' ({detail})' if detail else '')

    def destroy_node(self):
        """Log the run's summary and the count of refused messages, then destroy the node."""
        for line in (getattr(self, 'run_summary', str)(), self.rejects_report()):
            if line:
                self.get_logger().info(line)
        return super().destroy_node()


class PairedInput(Rejects):
    """
    Mixin: gated /joint_states + /joint_temperature input, paired by stamp.

    The node sets ``joint``, ``pair`` (:class:`StampPairing`), ``limits``
    (:class:`~friction_joint.testbed.plant.InputLimits` of its gear),
    ``state_fields`` (JointState fields it needs), ``sub_state`` and
    ``sub_temp`` (its two subscriptions) and implements
    ``process(ns, values, xi)``.  ``on_state`` and ``on_temperature`` are the
    subscription callbacks; they never raise.
    """

    state_fields: tuple[str, ...] = ('position', 'velocity')
    #: the InputLimits quantity of each JointState field
    QUANTITY = {'position': 'position', 'velocity': 'velocity', 'effort': 'torque'}

    _waiter = None
    _next_turn = 0.0

    def spin_step(self, executor):
        """
        One turn of the node's main loop (called by ``run_node``).

        Synchronised (``sync``, lockstep) nodes wait on their two input
        subscriptions directly and take every queued message without an
        executor turn (about 0.2 ms each in rclpy, twice per lockstep step);
        the executor is turned every ``EXECUTOR_EVERY`` s for parameter
        services.  Other nodes spin the executor.
        """
        if not self.pair.sync:
            executor.spin_once(timeout_sec=0.1)
            return
        if self._waiter is None:
            self._waiter = Waiter(self, (self.sub_state, self.sub_temp))
        self._waiter.wait(EXECUTOR_EVERY)
        for msg in take_queued(self.sub_temp, self.sub_temp.msg_type):
            self.on_temperature(msg)
        for msg in take_queued(self.sub_state, self.sub_state.msg_type):
            self.on_state(msg)
        now = time.monotonic()
        if now >= self._next_turn:
            self._next_turn = now + EXECUTOR_EVERY
            executor.spin_once(timeout_sec=0.0)

    def on_temperature(self, msg):
        """Take a /joint_temperature message (gated; never raises)."""
        self.guarded('a /joint_temperature message', self.handle_temperature, msg)

    def on_state(self, msg):
        """Take a /joint_states message (gated; never raises)."""
        self.guarded('a /joint_states message', self.handle_state, msg)

    def handle_temperature(self, msg):
        why = self.limits.check('temperature', msg.temperature)
        if why:
            self._reject('an implausible /joint_temperature', why)
            return
        for item in self.pair.temperature(stamp_to_ns(msg.header.stamp), msg.temperature):
            self.dispatch(*item)

    def handle_state(self, msg):
        state = self.gate_state(msg)
        if state is None:
            return
        dropped = self.pair.dropped
        ready = self.pair.state(*state)
        if self.pair.dropped > dropped:
            self._reject('a joint state that waited too long for its temperature',
                         f'{self.pair.max_pending} states were waiting')
        for item in ready:
            self.dispatch(*item)

    order = None

    def dispatch(self, ns, state, xi, answer=True):
        """Hand a paired state to ``process`` in stamp order (:class:`StampOrder`); return it."""
        if self.order is None:
            self.order = StampOrder()
        last = self.order.last
        restart, ready, refused = self.order.offer(ns, (ns, state, xi))
        for _ in range(refused):
            self._reject('a joint state off the timeline of the stream',
                         f'stamp not within {STAMP_HORIZON:g} s after {last * 1e-9:.6f} s '
                         'and not followed by states continuing it')
        if restart:
            self.get_logger().warning(
                f'the state stamps jumped from {last * 1e-9:.6f} s to {ready[0][0] * 1e-9:.6f} s '
                f'and continue there ({len(ready)} states): restarting on the new timeline')
            self.restart()
        for item in ready if answer else ():    # answer False: the caller picks what to answer
            self.process(*item)
        return ready

    def restart(self):
        """Start afresh on a new timeline of stamps (override: reset the node's state)."""

    def gate_state(self, msg):
        """Return ``(ns, values)`` of a state that passes the gate, else count it and None."""
        i = joint_index(msg, self.joint)
        arrays = [getattr(msg, f) for f in self.state_fields]
        if i is None or i >= min(len(a) for a in arrays):
            self._reject(f'a joint state without {"/".join(self.state_fields)} for {self.joint}')
            return None
        values = tuple(float(a[i]) for a in arrays)
        for field, value in zip(self.state_fields, values, strict=True):
            why = self.limits.check(self.QUANTITY[field], value)
            if why:
                self._reject(f'an implausible /joint_states {field}', why)
                return None
        if not 0 <= msg.header.stamp.nanosec < 1_000_000_000:
            self._reject('a /joint_states stamp with nanosec out of range',
                         f'nanosec {msg.header.stamp.nanosec} is not below 1e9')
            return None
        ns = stamp_to_ns(msg.header.stamp)
        why = self.stamp_problem(ns)
        if why:
            self._reject('a /joint_states stamp in the future', why)
            return None
        return ns, values

    def stamp_problem(self, ns):
        """
        Return why stamp ``ns`` is implausible (negative, or ahead of the node's clock).

        The clock is the wall clock, or with ``use_sim_time`` the ``/clock`` time
        (no check before the first ``/clock`` message); a stamp more than
        ``MAX_STAMP_LEAD`` s ahead of it is refused.
        """
        if ns < 0:
            return f'stamp {ns * 1e-9:.9f} s is negative'
        clock = self.get_clock()
        now = clock.now().nanoseconds
        if clock.ros_time_is_active and now == 0:       # no /clock yet: no reference
            return None
        lead = ns - now
        if lead > MAX_STAMP_LEAD * 1e9:
            kind = '/clock' if clock.ros_time_is_active else 'the clock'
            return f'stamp {ns * 1e-9:.3f} s is {lead * 1e-9:.3g} s ahead of {kind}'
        return None


class _ClockCheck:
    """
    Check a ``/clock`` message before rclpy's time source sees it (``use_sim_time``).

    A time rclpy cannot represent (negative seconds, nanoseconds of a second or
    more) is refused, counted and logged (throttled): it used to raise in
    rclpy's callback and end the node.  A jump backwards (a replay that loops)
    or forward by more than ``STAMP_HORIZON`` is logged and followed.
    """

    def __init__(self, node):
        self.node = node
        self.last = None

    def __call__(self, msg):
        clock = msg.clock
        if clock.sec < 0 or not 0 <= clock.nanosec < 1_000_000_000:
            self.node._reject('a /clock message rclpy cannot represent',
                              f'sec {clock.sec}, nanosec {clock.nanosec}')
            return False
        ns = stamp_to_ns(clock)
        if self.last is not None and not self.last <= ns <= self.last + STAMP_HORIZON * 1e9:
            if self.node._log_due('clock jump', REJECT_LOG_PERIOD):
                self.node.get_logger().warning(f'/clock jumped from {self.last * 1e-9:.6f} s to '
                                               f'{ns * 1e-9:.6f} s: following it')
        self.last = ns
        return True


def run_node(factory: Callable[[], Any], name: str, args: list[str] | None = None,
             drain: bool = True) -> int | str:
    """
    Run a node as the ``main()`` body: init, spin, quiet end on Ctrl-C / SIGTERM.

    ``-h``/``--help`` before ``--ros-args`` prints the usage and exits 0 (no gear file needed,
    :mod:`~friction_joint.ros.nodes.usage`). The first SIGINT/SIGTERM stops the node *after* it
    has processed what is already queued (``drain``; e.g. an estimator behind a simulator that
    has finished), so no answer is lost; a second signal exits at once; the node ends within
    about ``STOP_ACK_TIMEOUT`` s more, with status 0, or 128 + the signal's number when it cut
    short a run of finite length (the node's ``interrupted()`` says so). Every start-up failure
    (a bad parameter or ROS argument, an rcl error, anything the node's constructor raises; see
    :mod:`~friction_joint.ros.startup`) and any error that ends the loop is one line on stderr
    and exit status 2. A node may end itself by raising ``SystemExit(0)`` from a callback. A
    node with a ``spin_step(executor)`` method runs its own loop: it is called instead of
    ``executor.spin_once``. ``factory`` may also return a composition: an object with ``nodes``
    (the nodes, all added to the one executor) and ``spin_step`` (see
    :mod:`~friction_joint.ros.nodes.composed`). The executor is single-threaded
    (``rclpy.experimental.EventsExecutor``, faster, lost one of two subscriptions here).
    """
    exit_on_help(factory, name, args)     # before rclpy.init: no gear file needed
    import signal
    import sys

    import rclpy
    from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.signals import SignalHandlerOptions

    from ...exceptions import FrictionJointError

    stop = []

    def on_signal(signum, frame):
        stop.append(signum)
        if len(stop) > 1:
            raise KeyboardInterrupt

    cleanup = None
    try:
        # files rcl opens checked, the gear file by the package's reader; rcl parses a copy
        check_domain_id()
        args, cleanup = prepare_ros_args(args)
        dds_environ()                     # the package's DDS profile, unless one is set
        rcl_init(lambda: rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO))
    except Exception as exc:              # noqa: BLE001 - one line, never a traceback
        print(f'{name}: error: {one_line(exc)}', file=sys.stderr)
        return 2
    finally:
        if cleanup is not None:
            cleanup()                     # rcl has parsed the copies at init
    old = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
    node = executor = None
    status: int | str = 0
    started = False
    try:
        try:
            node = factory()
            nodes = list(getattr(node, 'nodes', [node]))
            for member in nodes:          # a qos_overrides.* naming no entity of the node
                check_overrides_used(member)
        except Exception as exc:          # noqa: BLE001 - any start-up failure: one line
            print(f'{name}: error: {one_line(exc)}', file=sys.stderr)
            raise SystemExit(2) from None
        started = True
        executor = SingleThreadedExecutor()
        for member in nodes:
            executor.add_node(member)
            guard_clock(member, _ClockCheck(member))
        spin = getattr(node, 'spin_step', None) or (lambda ex: ex.spin_once(timeout_sec=0.1))
        while not stop and rclpy.ok():
            spin(executor)
        if stop and getattr(node, 'interrupted', lambda: False)():
            status = 128 + stop[0]
        t_end = time.monotonic() + 30.0
        if drain:                          # the input only: a flood of parameter requests
            for member in nodes:           # must not hold a stopping node
                for srv in list(member.services):
                    member.destroy_service(srv)
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
    except Exception as exc:              # noqa: BLE001 - e.g. a gear the plant cannot run
        print(f'{name}: error: {type(exc).__name__}: {" ".join(str(exc).split())}',
              file=sys.stderr)
        status = 2
    finally:
        for sig, handler in old.items():
            signal.signal(sig, handler)
        nodes = list(getattr(node, 'nodes', [node])) if node is not None else []
        if not started:                   # refused at start-up: the one line only
            for member in nodes:
                Node.destroy_node(member)
            nodes = []
        wait = STOP_ACK_TIMEOUT if stop else ACK_TIMEOUT
        t_end, late = time.monotonic() + wait, []     # one deadline for all the publishers
        for pub in (p for member in nodes for p in member.publishers if rclpy.ok()):
            from rclpy.duration import Duration       # reliable peers take the last samples
            with contextlib.suppress(Exception):      # best effort on the way out
                left = Duration(seconds=max(0.0, t_end - time.monotonic()))
                late += [] if pub.wait_for_all_acked(left) else [pub.topic_name]
        if late:
            print(f'{name}: {", ".join(late)}: samples not acknowledged by every subscriber '
                  f'within {wait:g} s of stopping', file=sys.stderr)
        if executor is not None:
            executor.shutdown()
        for member in nodes:
            member.destroy_node()
        rclpy.try_shutdown()
    return status
