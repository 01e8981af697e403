# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``joint_sim``: the simulated Harmonic Drive joint (the plant) as a ROS 2 node.

    ros2 run friction_joint joint_sim --ros-args --params-file config/csd25_truth.yaml \
        -p mode:=lockstep

Publishes ``/joint_states`` (q, qd, effort = applied drive torque),
``/joint_temperature``, ``/link_torque`` and, in lockstep mode, ``/clock``;
subscribes ``/joint_command`` (effort = commanded torque) and
``/contact_torque`` (geometry_msgs/WrenchStamped, torque.z added to tau_ext:
an injected contact for estimator tests).

Modes (parameter ``mode``):

``realtime``
    Ticks at ``publish_rate`` (default 1 kHz) on the monotonic clock: each tick
    takes the newest ``/joint_command`` and ``/contact_torque``, advances the
    plant by ``simulation.rate / publish_rate`` steps with that command held
    and publishes the state stamped with the ROS time of the first tick plus
    the simulated time (regular stamps, ``k / simulation.rate``, whatever the
    machine's load); temperature at ``simulation.temperature_rate``.  The
    node runs its own loop (sleep to the
    tick's due time, take the inputs straight from the subscriptions) instead
    of an rclpy timer: a turn of the rclpy executor costs about 0.2 ms, so a
    timer-driven loop cannot hold 1 kHz on a busy machine.  The executor is
    turned every ``SPIN_EVERY`` ticks for parameter services.  A tick that is
    late is run at once (at most ``MAX_CATCH_UP`` in a row, then the schedule
    restarts from now: the simulated time slips behind the wall clock, which
    is counted and logged; no sample is skipped and the stamps stay regular).
    **Pacing**: the joint runs at most ``max_lead`` s ahead of the controller's
    answers, then waits up to ``lead_wait`` s for it (the simulated clock slows)
    (:class:`~friction_joint.testbed.pacing.Pacing`).  The closing log line
    gives the achieved rate, answered share, waits, slip and watchdog trips.
``lockstep``
    Simulated time.  The node publishes the state of step k (stamp k dt,
    plus /clock and the temperature sample with the same stamp) and advances
    only when the command stamped k arrives, so a closed loop across
    processes is deterministic and independent of machine load.  Until the
    first command arrives the current state is re-sent every
    ``resend_period`` s (peers may still be starting).  The first state is
    sent once ``wait_subscribers`` subscribers are matched on /joint_states
    and /joint_temperature and ``start_delay`` s have passed since, so that
    every peer (a recorder too) has discovered every other before the loop
    starts.  With
    ``duration`` > 0 the node stops after that much simulated time and exits.

    **Flow control** (``follow``, ``window``): the controller is in the loop,
    so it can never fall behind; a node that only listens (the estimator)
    could, until its input queue overflows.  ``follow`` names topics (comma-separated,
    resolved like the node's own) on which followers echo the state stamps they have
    processed (the estimator's ``external_torque``).  The node does not advance past step k while a
    follower's newest echo is older than step k - ``window``; it waits for it
    (logged after 5 s, then every 5 s), so no follower holds more than
    ``window`` unprocessed states and none is lost by construction.  At the
    end the node waits up to ``FINAL_WAIT`` s for every follower to echo the
    last state.  The time spent waiting is logged at the end.

Own parameters: mode, publish_rate, duration, xi0 (NaN: the gear file's
thermal.initial), q0, seed (-1: simulation.seed), friction_model ('' : the
gear file's friction.model), resend_period, wait_subscribers, start_delay,
follow, window, wait_recorder, command_timeout, timeout_reaction, max_lead,
lead_wait.
``wait_subscribers`` and ``start_delay`` hold the first tick in realtime
mode too (a state published before its subscribers have matched is lost to
them).  In lockstep the state the loop waits on is re-sent every
``resend_period`` while the loop stalls (a controller or estimator killed
and restarted has never seen it; logged after 5 s).
``wait_recorder`` (comma-separated topics, or ``loop`` for
``LOOP_TOPIC_NAMES`` and, in lockstep, ``/clock``) holds the first state until a
recorder has announced on ``recorder_ready`` that it has matched a publisher
on each of them (``friction_joint record`` does; see
:mod:`~friction_joint.ros.qos`), so a recording started before the nodes
has every message from the first.

**Command watchdog** (``command_timeout``, default 0.05 s of simulated time;
0 turns it off): once the first valid command has arrived, the drive
applies the newest valid command only while it is younger than
``command_timeout``; after that (the controller stopped, or every command
is refused) it applies ``timeout_reaction``.  In realtime a command that
answers a state older than ``command_timeout`` is refused as stale (a
starved controller's delayed loop would go unstable).  The reactions: ``zero`` torque (default; the
drive's safe torque off: the joint coasts and hangs) or ``brake`` (a
damping torque J q̇ / ``BRAKE_TIME`` that stops it; see
:mod:`~friction_joint.testbed.watchdog`).  The trip and the
return of valid commands are logged.

Implausible input is **rejected, keeping the last valid value**: a ``/joint_command`` effort or
a ``/contact_torque`` that is not finite or beyond the plausible torque of the gear
(:class:`~friction_joint.testbed.plant.InputLimits`: 10 x (m g l + peak friction + J V / 0.1
s), about 600 Nm for the CSD-25; logged at start) is counted, logged (throttled) and not
applied: the plant goes on with the last valid command (until the watchdog trips) and contact
torque. In lockstep a refused command stamped for the current step still advances the step
(with the last valid command), so the loop never stalls on it. The count is logged at shutdown
(see :mod:`~friction_joint.ros.nodes.common`). Only a finite state leaving the finite range (an
unstable closed loop) ends the node, with :class:`~friction_joint.exceptions.SimulationError`.
"""
import math
import sys
import time

from geometry_msgs.msg import WrenchStamped
from rclpy.executors import Executor
from rclpy.node import Node
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState, Temperature
from std_msgs.msg import String

from .common import (EXECUTOR_EVERY, joint_index, Lossless, ns_to_stamp, Rejects, run_node,
                     stamp_to_ns, take_queued)
from .sim_params import check_sim_params, DEFAULTS, DESCRIPTORS, VALIDATORS
from .._rclpy import Waiter
from ..parameters import declare_gear, declare_node_params, parameter_guard
from ..qos import CLOCK_QOS, overridable, READY_QOS, READY_TOPIC, stream_qos
from ..startup import check_overrides_used
from ...exceptions import SimulationError
from ...testbed import CommandWatchdog, InputLimits, Pacing, Plant, Sample

__all__ = ['JointSimNode', 'main']

#: realtime: ticks run back to back when late before the schedule restarts
MAX_CATCH_UP = 20
#: realtime: ticks between turns of the executor (parameter services)
SPIN_EVERY = 20
#: lockstep: seconds to wait at the end for the followers to echo the last state
FINAL_WAIT = 20.0
#: realtime pacing: s between looks at the command queue while waiting for the controller
PACE_POLL = 0.002

#: ``wait_recorder:=loop``: the topics of the closed loop a recording must have from its start
LOOP_TOPIC_NAMES = ('joint_states', 'joint_temperature', 'link_torque', 'joint_command',
                    'external_torque')


class JointSimNode(Rejects, Node):
    """Wires the :class:`~friction_joint.testbed.plant.Plant` to topics and a timer."""

    #: an unstable closed loop ends the node (a refused input never gets that far)
    fatal = (SimulationError,)
    commanded = False                # lockstep: the command of the current step has come
    progress = 0.0                   # lockstep: monotonic time of the last step
    resent = 0                       # lockstep: states re-sent while the loop stalled
    stall_at: float | None = None    # lockstep: the progress time of the last stall logged
    _messages: tuple[Clock, Temperature, WrenchStamped, JointState] | None = None  # messages()

    def __init__(self):
        super().__init__('joint_sim')
        self.p = declare_node_params(self, DEFAULTS, VALIDATORS, DESCRIPTORS)
        xi0 = self.p['xi0']
        self.gear = declare_gear(self, own=list(DEFAULTS))
        self.limits = InputLimits(self.gear)
        check_sim_params(self.p, xi0, self.gear, self.limits)     # before any allocation

        def plant():
            return Plant(self.gear, model=self.p['friction_model'] or None,
                         xi0=None if math.isnan(xi0) else xi0,
                         seed=None if self.p['seed'] < 0 else self.p['seed'], q0=self.p['q0'])
        plant().step(0.0)                           # compile the kernels before data flows
        self.plant = plant()
        self.joint = self.gear.joint_name
        self.lockstep = self.p['mode'] == 'lockstep'
        self.temperature_variance = (self.gear.section('sensors')['temperature_resolution'] ** 2
                                     / 12.0)
        self.tau_cmd = 0.0
        self.contact = 0.0
        self.done = False
        self.n_end = (int(round(self.p['duration'] * self.plant.rate))
                      if self.p['duration'] > 0 else 0)
        qos, out, opts = stream_qos(), stream_qos(lossless=self.lockstep), overridable()
        keep = (lambda pub: Lossless(self, pub)) if self.lockstep else (lambda pub: pub)
        self.pub_state = keep(self.create_publisher(JointState, 'joint_states', out,
                                                    qos_overriding_options=opts))
        self.pub_temp = keep(self.create_publisher(Temperature, 'joint_temperature', out,
                                                   qos_overriding_options=opts))
        self.pub_link = keep(self.create_publisher(WrenchStamped, 'link_torque', out,
                                                   qos_overriding_options=opts))
        # /clock is global by convention: every node of the system follows one clock
        self.pub_clock = (keep(self.create_publisher(Clock, '/clock', CLOCK_QOS))
                          if self.lockstep else None)
        self.sub_command = self.create_subscription(JointState, 'joint_command',
                                                    self.on_command, qos,
                                                    qos_overriding_options=opts)
        self.sub_contact = self.create_subscription(WrenchStamped, 'contact_torque',
                                                    self.on_contact, qos,
                                                    qos_overriding_options=opts)
        self.started = False
        self.ready_since = None
        self.recorded = None
        self.recorder_needs = self.recorder_topics()
        if self.recorder_needs:
            self.sub_ready = self.create_subscription(String, READY_TOPIC, self.on_ready,
                                                      READY_QOS)
        self.watchdog = CommandWatchdog(self.plant.rate, self.p['command_timeout'],
                                        self.p['timeout_reaction'], inertia=self.gear.inertia,
                                        torque_limit=self.limits.torque)
        self.followers = {}
        self.echo_subs = []
        self.waiter = None
        self.next_turn = 0.0
        # nothing of this node changes at run time (use_sim_time included: states would
        # be stamped with a clock that has not started)
        parameter_guard(self, {}, {}, None)
        if self.lockstep:
            for topic in (t.strip() for t in self.p['follow'].split(',') if t.strip()):
                name = {}
                sub = self.create_subscription(JointState, topic,
                                               lambda m, n=name: self.on_echo(n['topic'], m), qos)
                name['topic'] = sub.topic_name
                self.followers[sub.topic_name] = -1
                self.echo_subs.append(sub)
            self.blocked_since = None
            self.waited = 0.0
            self.final_since = None
            self.resend = self.create_timer(min(0.05, self.p['resend_period']), self.on_resend)
            self.last_sent = None
        else:
            self.per_tick = max(1, int(round(self.plant.rate / self.p['publish_rate'])))
            temperature_rate = self.gear.section('simulation')['temperature_rate']
            self.temp_every = max(1, int(round(self.p['publish_rate'] / temperature_rate)))
            self.ticks = 0
            self.period = 1.0 / self.p['publish_rate']
            self.next_tick = None
            self.slipped = 0
            self.t0_ns = None                       # ROS time of step 0 (realtime stamps)
            self.pace = Pacing(round(self.p['max_lead'] * self.plant.rate), self.p['lead_wait'])
            self.cmd_waiter = None
            self.wall_start = None
        check_overrides_used(self)                  # a qos_overrides.* naming no entity
        self.get_logger().info(
            f'{self.p["mode"]} simulation of {self.joint} ({self.plant.joint.model} friction, '
            f'{self.plant.rate:g} Hz, xi0 {self.plant.thermal.xi:.2f} degC); plausible '
            f'command and contact torque: |torque| <= {self.limits.torque:.4g} Nm')

    # ---------------------------------------------------------------- input
    def on_command(self, msg: JointState) -> None:
        """Take a /joint_command message (gated; never raises but ``fatal``)."""
        self.guarded('a /joint_command message', self.handle_command, msg)

    def on_contact(self, msg: WrenchStamped) -> None:
        """Take a /contact_torque message (gated; never raises)."""
        self.guarded('a /contact_torque message', self.handle_contact, msg)

    def handle_command(self, msg: JointState) -> None:
        i = joint_index(msg, self.joint)
        if i is None:
            self._reject('a /joint_command not naming ' + self.joint)
            return
        why = (f'no effort for {self.joint}' if i >= len(msg.effort)
               else self.limits.check('torque', msg.effort[i]))
        age = self.command_age(msg)
        if not why and age is not None and age > self.p['command_timeout'] > 0:
            self._reject('a stale /joint_command',
                         f'it answers the state of {age:.3f} s ago (command_timeout '
                         f'{self.p["command_timeout"]:g} s)')
        elif why:
            self._reject('a refused /joint_command effort',
                         f'command {why}; keeping {self.tau_cmd:.6g} Nm')
        else:
            self.tau_cmd = float(msg.effort[i])
            self.watchdog.command(self.plant.k)
            if not self.lockstep:
                self.pace.answered(self.command_step(msg))
        if self.lockstep and not self.done:
            if stamp_to_ns(msg.header.stamp) != self.stamp_ns(self.plant.k):
                return                          # a stale or duplicate command
            self.started = True
            self.commanded = True
            self.try_advance()

    def command_age(self, msg: JointState) -> float | None:
        """Return the age (s) of the state a realtime command answers (None: unstamped)."""
        ns = stamp_to_ns(msg.header.stamp)
        if self.lockstep or ns <= 0 or self.t0_ns is None:
            return None
        return (self.t0_ns + self.stamp_ns(self.plant.k) - ns) * 1e-9

    def command_step(self, msg: JointState) -> int:
        """Return the step of the state a realtime command answers (unstamped: the current)."""
        ns = stamp_to_ns(msg.header.stamp)
        if ns <= 0 or self.t0_ns is None:
            return self.plant.k
        return round((ns - self.t0_ns) * self.plant.rate * 1e-9)

    def on_echo(self, topic: str, msg: JointState) -> None:
        """Take a follower's echo (flow control): its newest processed state stamp."""
        self.followers[topic] = max(self.followers[topic], stamp_to_ns(msg.header.stamp))
        if self.blocked_since is not None:
            self.try_advance()

    def lagging(self, k: int) -> list[str]:
        """Return the followers whose newest echo is older than step ``k - window``."""
        need = self.stamp_ns(k - self.p['window'])
        return [t for t, ns in self.followers.items() if ns < need]

    def handle_contact(self, msg: WrenchStamped) -> None:
        tz = msg.wrench.torque.z
        why = self.limits.check('torque', tz)
        if why:
            self._reject('a refused /contact_torque',
                         f'contact {why}; keeping {self.contact:.6g} Nm')
            return
        self.contact = float(tz)

    def on_ready(self, msg: String) -> None:
        """Take the recorder's readiness announcement (the topics it has matched)."""
        self.recorded = {t for t in msg.data.split(',') if t}

    def recorder_topics(self) -> set[str]:
        """Return the resolved topics of ``wait_recorder`` ('loop': the loop's topics)."""
        spec = self.p['wait_recorder'].strip()
        names = LOOP_TOPIC_NAMES if spec == 'loop' else [t.strip() for t in spec.split(',')]
        topics = {self.resolve_topic_name(t) for t in names if t}
        if spec == 'loop' and self.lockstep:
            topics.add('/clock')
        return topics

    # ---------------------------------------------------------------- watchdog
    def drive_torque(self, qd: float) -> float:
        """Return the drive's torque (:class:`CommandWatchdog`); log a trip and a resume."""
        tau, event = self.watchdog.torque(self.plant.k, self.tau_cmd, qd)
        if event == 'tripped':
            self.get_logger().warning(
                f'no valid /joint_command for {self.p["command_timeout"]:g} s at t = '
                f'{self.plant.t:.3f} s (rejected so far: {self.rejected}): '
                f'{self.p["timeout_reaction"]} torque until a valid command arrives '
                f'(trip {self.watchdog.trips})')
        elif event == 'resumed':
            self.get_logger().info(f'valid /joint_command again at t = {self.plant.t:.3f} s: '
                                   'the drive follows it')
        return tau

    # ---------------------------------------------------------------- output
    def stamp_ns(self, k: int) -> int:
        """Return the simulated time of step k in ns, rounded per step (no drift)."""
        return round(k * 1e9 / self.plant.rate)

    def messages(self) -> tuple[Clock, Temperature, WrenchStamped, JointState]:
        """Return the four outgoing messages, built once (a publish serializes at once)."""
        if self._messages is None:
            t = Temperature()
            t.header.frame_id = self.joint
            t.variance = self.temperature_variance
            w = WrenchStamped()
            w.header.frame_id = self.joint
            js = JointState()
            js.name = [self.joint]
            self._messages = (Clock(), t, w, js)
        return self._messages

    def publish(self, s: Sample, temperature: float) -> None:
        ns = self.stamp_ns(self.plant.k)
        if not self.lockstep:
            if self.t0_ns is None:
                self.t0_ns = self.get_clock().now().nanoseconds - ns
            ns += self.t0_ns
        c, t, w, js = self.messages()
        if self.pub_clock is not None:
            ns_to_stamp(ns, c.clock)
            self.pub_clock.publish(c)
        if temperature:
            ns_to_stamp(ns, t.header.stamp)
            t.temperature = s.xi
            self.pub_temp.publish(t)
        ns_to_stamp(ns, w.header.stamp)
        w.wrench.torque.z = s.tau_link
        self.pub_link.publish(w)
        ns_to_stamp(ns, js.header.stamp)
        js.position = [s.q]
        js.velocity = [s.qd]
        js.effort = [s.effort]
        self.pub_state.publish(js)

    # ---------------------------------------------------------------- stepping
    def try_advance(self) -> None:
        """Advance on the command of the current step unless a follower lags (flow control)."""
        if not self.commanded:
            return
        now = time.monotonic()
        if self.followers and self.lagging(self.plant.k):
            if self.blocked_since is None:
                self.blocked_since = now
            return
        if self.blocked_since is not None:
            self.waited += now - self.blocked_since
            self.blocked_since = None
        self.commanded = False
        self.advance()

    def advance(self) -> None:
        self.progress = time.monotonic()
        s = self.plant.step(self.drive_torque(self.plant.last.qd), tau_contact=self.contact)
        if self.n_end and self.plant.k >= self.n_end:
            self.done = True
        self.publish(s, temperature=True)
        if self.done:
            self.get_logger().info(f'simulated {self.plant.t:.3f} s; done')

    def ready(self) -> bool:
        """Return whether ``wait_subscribers`` have matched ``start_delay`` s ago."""
        now = time.monotonic()
        if self.ready_since is None:
            need = self.p['wait_subscribers']
            pubs = (self.pub_state, self.pub_temp) if self.lockstep else (self.pub_state,)
            if min(p.get_subscription_count() for p in pubs) < need:
                return False
            if self.recorder_needs - (self.recorded or set()):
                if self._log_due('recorder', 5.0):
                    missing = sorted(self.recorder_needs - (self.recorded or set()))
                    self.get_logger().info(f'waiting for a recorder to announce '
                                           f'{", ".join(missing)} on {READY_TOPIC}')
                return False
            self.ready_since = now
            self.get_logger().info(f'{need} subscriber(s) matched; starting in '
                                   f'{self.p["start_delay"]:g} s')
        return now - self.ready_since >= self.p['start_delay']

    def on_resend(self) -> None:
        if self.done:
            self.finish()
        if self.blocked_since is not None:
            self.warn_blocked()
        if self.started:
            self.resend_stalled()
            return
        if not self.ready():
            return
        now = time.monotonic()
        if self.last_sent is None or now - self.last_sent >= self.p['resend_period']:
            self.last_sent = now
            self.publish(self.plant.last, temperature=True)

    def resend_stalled(self) -> None:
        """Re-send the current state every ``resend_period`` while the loop stalls."""
        now = time.monotonic()
        stalled = now - max(self.progress, self.last_sent or 0.0)
        if stalled < self.p['resend_period']:
            return
        self.last_sent = now
        self.resent += 1
        self.publish(self.plant.last, temperature=True)
        waiting, first = now - self.progress, self.stall_at != self.progress
        if first or (waiting > 5.0 and self._log_due('stalled', 5.0)):   # each stall's first
            self.stall_at = self.progress
            what = ('the followers' if self.blocked_since is not None
                    else f'the command of step {self.plant.k}')
            self.get_logger().warning(
                f'no progress for {waiting:.1f} s: waiting for {what}; re-sending the state '
                f'every {self.p["resend_period"]:g} s ({self.resent} re-sent so far)')

    def warn_blocked(self):
        """Log (throttled) which followers the simulation is waiting for."""
        waiting = time.monotonic() - self.blocked_since
        if waiting > 5.0 and self._log_due('blocked', 5.0):
            lag = ', '.join(f'{t} (newest echo {ns * 1e-9:.4f} s)'
                            for t, ns in self.followers.items())
            self.get_logger().warning(
                f'step {self.plant.k} waits {waiting:.0f} s for {lag}', throttle_duration_sec=2.5)

    def interrupted(self) -> bool:
        """Whether a run of finite ``duration`` has not reached it (see ``run_node``)."""
        return bool(self.n_end) and not self.done

    def finish(self) -> None:
        """End the node once every follower has echoed the last state (or FINAL_WAIT)."""
        now = time.monotonic()
        self.final_since = self.final_since or now
        behind = [t for t, ns in self.followers.items() if ns < self.stamp_ns(self.plant.k)]
        if behind and now - self.final_since < FINAL_WAIT:
            return
        if behind:
            self.get_logger().warning(f'{", ".join(behind)}: the last state was not echoed '
                                      f'within {FINAL_WAIT:g} s')
        if self.followers:
            self.get_logger().info(f'flow control: waited {self.waited:.2f} s for '
                                   f'{", ".join(self.followers)}')
        raise SystemExit(0)

    def spin_step(self, executor: Executor) -> None:
        """One turn of the node's main loop (called by ``run_node``)."""
        if self.lockstep:
            self.lockstep_turn(executor)
            return
        if not self.started:
            executor.spin_once(timeout_sec=0.02)
            self.started = self.ready()
            return
        now = time.monotonic()
        if self.next_tick is None:
            self.next_tick = self.wall_start = now
            if self.count_publishers(self.sub_command.topic_name):
                self.pace.expect(self.plant.k)      # a controller is there: wait for it
        if self.hold_for_controller(now):
            return
        if now < self.next_tick:
            time.sleep(min(self.next_tick - now, 0.1))
            return
        if now - self.next_tick > MAX_CATCH_UP * self.period:
            late = int((now - self.next_tick) / self.period)
            self.slipped += late
            self.next_tick = now
            if self._log_due('late', 5.0):
                self.get_logger().warning(
                    f'{late} ticks late: the simulated time slips {self.slipped * self.period:.3f}'
                    ' s behind the wall clock in all (stamps stay regular); the machine '
                    'does not keep up with publish_rate', throttle_duration_sec=2.5)
        self.next_tick += self.period
        for msg in take_queued(self.sub_command, JointState):
            self.on_command(msg)
        for msg in take_queued(self.sub_contact, WrenchStamped):
            self.on_contact(msg)
        self.on_tick()
        if self.ticks % SPIN_EVERY == 0:
            executor.spin_once(timeout_sec=0.0)

    def hold_for_controller(self, now):
        """Return whether the tick waits for a lagging controller (realtime pacing)."""
        held, waited, gave_up = self.pace.hold(self.plant.k + self.per_tick, now)
        if waited:
            self.next_tick += waited
        if gave_up:
            self.get_logger().warning(
                f'the controller answered no state for {self.p["lead_wait"]:g} s at t = '
                f'{self.plant.t:.3f} s: running on without it (the watchdog decides) until a '
                'command answers a recent state')
        if not held:
            return False
        self.cmd_waiter = self.cmd_waiter or Waiter(self, [self.sub_command])
        self.cmd_waiter.wait(PACE_POLL)
        for msg in take_queued(self.sub_command, JointState):
            self.on_command(msg)
        return True

    def run_summary(self) -> str:
        """Return the closing line: achieved rate, answered share, waits, slips, trips."""
        trips = f'watchdog trips {self.watchdog.trips}'
        if self.lockstep:
            return (f'lockstep run: {self.plant.k} steps ({self.plant.t:.3f} s simulated), '
                    f'{self.resent} states re-sent while the loop stalled, {trips}')
        wall = time.monotonic() - self.wall_start if self.wall_start is not None else 0.0
        return (f'realtime run: {self.ticks} states in {wall:.2f} s of wall time '
                f'({self.ticks / max(wall, 1e-9):.0f} Hz of publish_rate '
                f'{self.p["publish_rate"]:g} Hz), {self.plant.t:.3f} s simulated; '
                f'{self.pace.describe(self.ticks)}; slipped {self.slipped * self.period:.3f} s '
                f'behind the wall clock; {trips}')

    def lockstep_turn(self, executor: Executor) -> None:
        """
        Lockstep: wait on the subscriptions, take the messages without an executor turn.

        (A turn costs about 0.2 ms in rclpy.)  The executor turns before the
        loop runs and every ``EXECUTOR_EVERY`` s (timer, parameter services).
        """
        if not self.started or self.done:
            executor.spin_once(timeout_sec=0.05)
            return
        if self.waiter is None:
            self.waiter = Waiter(self, [self.sub_command, self.sub_contact] + self.echo_subs)
        self.waiter.wait(EXECUTOR_EVERY)
        for msg in take_queued(self.sub_contact, WrenchStamped):
            self.on_contact(msg)
        for sub in self.echo_subs:
            for msg in take_queued(sub, JointState):
                self.on_echo(sub.topic_name, msg)
        for msg in take_queued(self.sub_command, JointState):
            self.on_command(msg)
        now = time.monotonic()
        if now >= self.next_turn:
            self.next_turn = now + EXECUTOR_EVERY
            executor.spin_once(timeout_sec=0.0)

    def on_tick(self) -> None:
        s = self.plant.last
        for _ in range(self.per_tick):
            s = self.plant.step(self.drive_torque(self.plant.last.qd), tau_contact=self.contact)
        self.ticks += 1
        self.publish(s, temperature=(self.ticks % self.temp_every == 0))
        if self.n_end and self.plant.k >= self.n_end:
            self.done = True
            raise SystemExit(0)


def main(args: list[str] | None = None) -> int | str:
    return run_node(JointSimNode, 'joint_sim', args, drain=False)


if __name__ == '__main__':
    sys.exit(main())
