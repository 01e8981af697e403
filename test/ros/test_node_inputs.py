# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Bad input into the nodes: refused, counted, logged; the nodes go on and recover.

* one poisoned message (1e308 rad/s, 1e308 Nm) into the estimator or the
  simulator (processes);
* a refused command in lockstep still advances the simulation;
* an exception inside a callback does not end a node (nodes in this process);
* the acceptance test: a 10 s storm of random finite and non-finite messages
  into the estimator and the real-time simulator at once; afterwards the
  estimator agrees with an offline observer on the clean data and the
  simulator follows a sane command.

The tests hold on a loaded machine: they wait for conditions (an answer to
every stamp, a state computed after a command was sent) with the generous
deadline ``roshelpers.DEADLINE`` and assert what arrived and what it
contains, never how much arrived in a fixed time (rates: ``bench_nodes.py``).
"""
import collections
import contextlib
import math
import os
import re
import signal
import subprocess
import sys
import time

from friction_joint import load_gear
from friction_joint.control.observer import DisturbanceObserver
import numpy as np
import pytest
from roshelpers import DEADLINE, param_if_declared, stamp_ns

pytestmark = pytest.mark.ros

PY = sys.executable
MODEL = 'config/csd25.yaml'
TRUTH = 'config/csd25_truth.yaml'
NAN, INF = float('nan'), float('inf')
BASE_NS = 1000 * 10 ** 9                 # stamps of the test data start at 1000 s (the past)


def no_watchdog():
    """
    Return the parameters that turn the simulator's command watchdog off (where it has one).

    These tests are about refused input, which keeps the last valid command;
    the watchdog (its own tests) would take the drive's torque off when the
    test sends no valid command for a while, or stalls on a loaded machine.
    """
    return param_if_declared('friction_joint.ros.nodes.joint_sim', 'command_timeout', 0.0)


def node_cmd(node, gear, *ros_args, **params):
    cmd = [PY, '-m', f'friction_joint.ros.nodes.{node}', '--ros-args', '--params-file', gear]
    for k, v in params.items():
        cmd += ['-p', f'{k}:={v}']
    return cmd + list(ros_args)


def set_stamp(stamp, ns):
    stamp.sec, stamp.nanosec = divmod(int(ns), 1_000_000_000)


def joint_state(ns, q, qd, effort, names=('joint',)):
    from sensor_msgs.msg import JointState
    m = JointState()
    set_stamp(m.header.stamp, ns)
    m.name = list(names)
    m.position, m.velocity, m.effort = list(q), list(qd), list(effort)
    return m


def temperature(ns, xi):
    from sensor_msgs.msg import Temperature
    m = Temperature()
    set_stamp(m.header.stamp, ns)
    m.header.frame_id = 'joint'
    m.temperature = xi
    return m


def wrench(tz):
    from geometry_msgs.msg import WrenchStamped
    m = WrenchStamped()
    m.wrench.torque.z = tz
    return m


def clean_motion(n, dt, t0=0.3):
    """(tau, q, qd) of a sliding sine motion, as a joint on the test bed makes it."""
    t = t0 + dt * np.arange(n)
    q = 0.4 * np.sin(1.5 * t)
    qd = 0.6 * np.cos(1.5 * t)
    tau = 10.99 * np.sin(q) + 3.0 * np.tanh(50 * qd) + 0.5 * np.sin(7.0 * t)
    return tau, q, qd


def rejected_count(proc):
    """Return the count a node reports at shutdown (None if it reported none)."""
    found = re.findall(r'rejected (\d+) input messages', proc.stdout + proc.stderr)
    return int(found[-1]) if found else None


def stop_together(*procs, timeout=DEADLINE):
    """SIGINT all processes at once, wait for them, then tidy up; returns their exit statuses."""
    for p in procs:
        if p.popen.poll() is None:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(p.popen.pid, signal.SIGINT)
    t_end = time.monotonic() + timeout
    for p in procs:
        with contextlib.suppress(subprocess.TimeoutExpired):
            p.popen.wait(max(0.1, t_end - time.monotonic()))
    return [p.stop() for p in procs]


def drain(sub, cls):
    from friction_joint.ros._rclpy import take_all
    return [m for m, _ in take_all(sub, cls)]


# ------------------------------------------------------------ single poisoned messages

def test_estimators_outlive_poisoned_states(spawn, ros_node):
    """
    One 1e308 rad/s or 1e308 Nm state poisoned the observer (NaN for good, or 1e306 Nm).

    Two estimators (sync off with the static model, sync on with GMS) get the
    same clean samples with poisoned ones in between; every clean sample is
    answered exactly as an offline observer that never saw the poison answers
    it, and the poisoned ones are refused and counted.
    """
    from sensor_msgs.msg import JointState, Temperature
    import roshelpers
    a = spawn(node_cmd('estimator', MODEL, '-r', '__node:=est_a', '-r', 'external_torque:=ext_a',
                       sync='false', friction='static'))
    b = spawn(node_cmd('estimator', MODEL, '-r', '__node:=est_b', '-r', 'external_torque:=ext_b',
                       sync='true', friction='gms'))
    assert a.wait_for('external torque observer'), a.describe()
    assert b.wait_for('external torque observer'), b.describe()
    qos = roshelpers.reliable_qos()
    pub_js = ros_node.node.create_publisher(JointState, '/joint_states', qos)
    pub_t = ros_node.node.create_publisher(Temperature, '/joint_temperature', qos)
    got = {'a': {}, 'b': {}}
    subs = [ros_node.node.create_subscription(
        JointState, f'/ext_{key}',
        lambda m, key=key: got[key].setdefault(stamp_ns(m), m.effort[0]), qos)
        for key in got]
    assert ros_node.wait_for_subscribers(pub_js, 2)
    assert ros_node.wait_for_subscribers(pub_t, 2)
    assert all(ros_node.wait_for_publishers(s) for s in subs)
    dt_ns = 1_000_000_000 // 3000
    n = 600
    tau, q, qd = clean_motion(n, dt_ns * 1e-9)

    # A publisher may see a subscriber before the subscriber has matched it (samples sent
    # in that moment are lost to it): the first sample is repeated until both estimators
    # answer it; a repeated stamp gets the same answer and leaves the observer alone.
    def first_sample():
        pub_t.publish(temperature(BASE_NS, 30.0))
        pub_js.publish(joint_state(BASE_NS, [q[0]], [qd[0]], [tau[0]]))

    assert ros_node.repeat_until(first_sample, lambda: all(BASE_NS in g for g in got.values())), \
        f'no answer to the first sample: {got}\n' + a.describe() + b.describe()
    # (q, qd, effort): effort 1e308 first (old code: 1e306 Nm for seconds), then 1e308 rad/s
    # (old code: NaN for good), then a huge position and non-finite values
    poison = {150: (0.1, 0.2, 1e308), 250: (0.1, 1e308, 1.0), 350: (1e308, 0.2, 1.0),
              420: (0.1, -INF, 1.0), 480: (0.1, 0.2, NAN)}
    clean = [BASE_NS]
    for k in range(1, n):
        ns = BASE_NS + k * dt_ns
        if k in poison:
            bad = ns - dt_ns // 2                           # between two clean samples
            pub_t.publish(temperature(bad, 30.0))
            pub_js.publish(joint_state(bad, *([v] for v in poison[k])))
        pub_t.publish(temperature(ns, 30.0))
        pub_js.publish(joint_state(ns, [q[k]], [qd[k]], [tau[k]]))
        clean.append(ns)
        if k % 50 == 49:
            ros_node.spin_for(0.05)                         # serve the answers as they come
    done = ros_node.spin_until(lambda: all(set(clean) <= set(g) for g in got.values()))
    assert done, (f'answers: a {len(got["a"])}, b {len(got["b"])} of {n}\n' + a.describe()
                  + b.describe())
    for key, kind in (('a', 'static'), ('b', 'gms')):
        model = load_gear(MODEL)
        obs = DisturbanceObserver(model, beta=60.0, dt=1.0 / 3000.0, friction=kind)
        expected = [obs(tau[k], q[k], qd[k], 30.0) for k in range(n)]
        live = np.array([got[key][ns] for ns in clean])
        np.testing.assert_allclose(live[:250], expected[:250], rtol=0, atol=1e-9,
                                   err_msg=f'estimator {key} after the 1e308 Nm effort')
        assert np.all(np.isfinite(live)), f'estimator {key}: non-finite estimates'
        np.testing.assert_allclose(live, expected, rtol=0, atol=1e-9)
        assert sorted(got[key]) == clean                    # the poisoned states got no answer
    assert a.popen.poll() is None and b.popen.poll() is None
    assert stop_together(a, b) == [0, 0]
    assert rejected_count(a) == len(poison) and rejected_count(b) == len(poison), \
        a.describe() + b.describe()
    log = a.stderr + a.stdout                               # the first is logged, the rest
    assert 'torque 1e+308 Nm is beyond the plausible' in log     # are throttled, then counted
    assert '2 x an implausible /joint_states velocity' in log


def test_joint_sim_outlives_implausible_command_and_contact(spawn, ros_node):
    """
    A 1e308 Nm command or contact torque stopped the simulator; now it keeps the last one.

    After each bad message the test waits until the simulator has published
    states it computed after the message was sent (their stamps are later);
    every state from the sane command of 3 Nm until the next sane command is
    then checked: the drive applied 3 Nm throughout (a bad command the
    simulator took would stay applied until the next sane one) and the state
    stayed finite; at the end the simulator reports each bad message refused.
    """
    from geometry_msgs.msg import WrenchStamped
    from sensor_msgs.msg import JointState
    import roshelpers
    sim = spawn(node_cmd('joint_sim', TRUTH, mode='realtime', **no_watchdog()))
    assert sim.wait_for('realtime simulation'), sim.describe()
    qos = roshelpers.reliable_qos()
    pub_cmd = ros_node.node.create_publisher(JointState, '/joint_command', qos)
    pub_contact = ros_node.node.create_publisher(WrenchStamped, '/contact_torque', qos)
    states = []
    sub = ros_node.node.create_subscription(JointState, '/joint_states', states.append, qos)
    assert ros_node.wait_for_subscribers(pub_cmd)
    assert ros_node.wait_for_subscribers(pub_contact)
    assert ros_node.wait_for_publishers(sub)

    def command(effort):
        pub_cmd.publish(joint_state(0, [0.0], [0.0], [effort]))

    def applied(effort):
        return bool(states) and abs(states[-1].effort[0] - effort) < 0.05

    def states_after(sent_ns, count=30):
        """Wait until ``count`` states stamped after ``sent_ns`` (wall clock) have arrived."""
        return ros_node.spin_until(
            lambda: sum(stamp_ns(m) > sent_ns for m in states[-count:]) >= count
            or sim.popen.poll() is not None)

    # repeated until applied: the first command may go out before the simulator has matched
    assert ros_node.repeat_until(lambda: command(3.0), lambda: applied(3.0)), sim.describe()
    first = len(states) - 1
    for bad in (1e308, -1e308, NAN, INF, 1e5):
        command(bad)
        assert states_after(time.time_ns()), sim.describe()
        assert sim.popen.poll() is None, sim.describe()
    for bad in (1e308, NAN, -INF, -1e5):
        pub_contact.publish(wrench(bad))
        assert states_after(time.time_ns()), sim.describe()
        assert sim.popen.poll() is None, sim.describe()
    held = states[first:]                                   # all computed before the next command
    command(-2.0)                                           # still follows a sane command
    assert ros_node.spin_until(lambda: applied(-2.0)), sim.describe()
    # (this test's executor may fall behind 1 kHz and its queue drop some states: a bad
    # command taken would stay applied until the next sane one, so it shows in every later one)
    effort = np.array([m.effort[0] for m in held])
    assert np.all(np.abs(effort - 3.0) < 0.1), (len(held), effort[np.abs(effort - 3.0) >= 0.1][:5])
    assert all(math.isfinite(m.position[0]) and math.isfinite(m.velocity[0]) for m in states)
    assert sim.stop() == 0
    out = sim.stdout + sim.stderr
    assert rejected_count(sim) == 9, out
    assert 'command 1e+308 Nm is beyond the plausible' in out or \
        'torque 1e+308 Nm is beyond the plausible' in out
    assert 'command 0.0 Nm' not in out and 'SimulationError' not in out


def test_lockstep_advances_with_the_last_command_when_one_is_refused(spawn, ros_node):
    """A refused command answering step k used to stall the lockstep loop for good."""
    from sensor_msgs.msg import JointState, Temperature
    import roshelpers
    steps = 30
    sim = spawn(node_cmd('joint_sim', TRUTH, mode='lockstep', duration=steps / 3000.0,
                         start_delay=0.1))
    assert sim.wait_for('lockstep simulation'), sim.describe()
    qos = roshelpers.reliable_qos()
    pub = ros_node.node.create_publisher(JointState, '/joint_command', qos)
    seen = {}
    bad = {8: NAN, 12: 1e308, 13: -INF}

    def answer(m):
        # every state is answered, a re-sent one too: the simulator re-sends the first state
        # until a command for it arrives (the first answer may go out before it has matched)
        ns = stamp_ns(m)
        k = round(ns * 3e-6)
        seen.setdefault(ns, m.effort[0])
        pub.publish(joint_state(ns, [0.0], [0.0], [bad.get(k, 2.0)]))

    sub = ros_node.node.create_subscription(JointState, '/joint_states', answer, qos)
    ros_node.node.create_subscription(Temperature, '/joint_temperature', lambda m: None, qos)
    assert ros_node.wait_for_publishers(sub)
    assert ros_node.wait_for_subscribers(pub)
    assert ros_node.spin_until(lambda: sim.popen.poll() is not None), \
        f'{len(seen)} of {steps + 1} steps\n' + sim.describe()
    assert sim.wait() == 0, sim.describe()
    assert sorted(round(ns * 3e-6) for ns in seen) == list(range(steps + 1))   # none stalled
    assert all(math.isfinite(e) for e in seen.values())
    assert rejected_count(sim) == len(bad)


# ------------------------------------------------------------ nodes in this process

@contextlib.contextmanager
def node_here(cls, gear, **params):
    """Construct a node of ``cls`` in this process (default context) with gear and params."""
    import rclpy
    from rclpy.signals import SignalHandlerOptions
    args = ['--ros-args', '--params-file', gear]
    for k, v in params.items():
        args += ['-p', f'{k}:={v}']
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        node = cls()
        yield node
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.shutdown()


def failing(*args, **kwargs):
    raise RuntimeError('a bug in the processing')


def test_an_exception_in_a_callback_does_not_end_the_node(ros_env, monkeypatch):
    from friction_joint.ros.nodes.controller import ControllerNode
    from friction_joint.ros.nodes.estimator import EstimatorNode
    from friction_joint.ros.nodes.joint_sim import JointSimNode
    with node_here(EstimatorNode, MODEL, sync='false') as node:
        sent = []
        monkeypatch.setattr(node.pub, 'publish', sent.append)
        node.on_temperature(temperature(BASE_NS, 30.0))
        monkeypatch.setattr(node, 'observer', failing)
        node.on_state(joint_state(BASE_NS, [0.1], [0.2], [1.0]))      # must not raise
        assert node.rejected == 1 and not sent
        monkeypatch.setattr(node, 'observer', DisturbanceObserver(node.gear, dt=node.dt))
        node.on_state(joint_state(BASE_NS + 1000, [0.1], [0.2], [1.0]))
        assert len(sent) == 1 and math.isfinite(sent[0].effort[0])
    with node_here(ControllerNode, MODEL) as node:
        sent = []
        monkeypatch.setattr(node.pub, 'publish', sent.append)
        monkeypatch.setattr(node, 'ctrl', failing)
        node.on_temperature(temperature(BASE_NS, 30.0))
        node.on_state(joint_state(BASE_NS, [0.1], [0.2], [1.0]))
        assert node.rejected == 1 and not sent
    with node_here(JointSimNode, TRUTH, mode='lockstep') as node:
        monkeypatch.setattr(node, 'advance', failing)
        node.on_command(joint_state(0, [0.0], [0.0], [1.0]))
        node.on_contact(wrench(2.0))
        assert node.rejected == 1 and node.tau_cmd == 1.0 and node.contact == 2.0


def test_states_before_the_first_temperature_wait_for_it(ros_env, monkeypatch):
    """
    A state that came before any temperature was dropped without a word (sync off).

    The temperature topic may match a moment after the state topic; the states
    are now held in order and answered with the first temperature, exactly as an
    observer that had the temperature from the start answers them.  A node
    holding too many counts the oldest as refused.
    """
    from friction_joint.ros.nodes.estimator import EstimatorNode
    dt = 1.0 / 3000.0
    tau, q, qd = clean_motion(40, dt)
    with node_here(EstimatorNode, MODEL, sync='false', friction='lugre') as node:
        sent = []
        monkeypatch.setattr(node.pub, 'publish', sent.append)
        stamps = [BASE_NS + k * 333_333 for k in range(40)]
        for k in range(30):
            node.on_state(joint_state(stamps[k], [q[k]], [qd[k]], [tau[k]]))
        assert sent == [] and node.rejected == 0
        node.on_temperature(temperature(stamps[0], 30.0))
        assert [stamp_ns(m) for m in sent] == stamps[:30]
        for k in range(30, 40):
            node.on_state(joint_state(stamps[k], [q[k]], [qd[k]], [tau[k]]))
        obs = DisturbanceObserver(load_gear(MODEL), beta=60.0, dt=dt, friction='lugre')
        expected = [obs(tau[k], q[k], qd[k], 30.0) for k in range(40)]
        np.testing.assert_allclose([m.effort[0] for m in sent], expected, rtol=0, atol=1e-12)
    with node_here(EstimatorNode, MODEL, sync='false') as node:
        sent = []
        monkeypatch.setattr(node.pub, 'publish', sent.append)
        node.pair.max_pending = 5
        for k in range(8):
            node.on_state(joint_state(stamps[k], [q[k]], [qd[k]], [tau[k]]))
        assert node.rejected == 3 and node.pair.dropped == 3
        node.on_temperature(temperature(stamps[0], 30.0))
        assert [stamp_ns(m) for m in sent] == stamps[3:8]


def test_use_sim_time_checks_stamps_against_clock(ros_env, monkeypatch):
    """``use_sim_time`` was accepted and changed nothing; stamps are now checked against /clock."""
    from rclpy.time import Time
    from friction_joint.ros.nodes.estimator import EstimatorNode
    with node_here(EstimatorNode, MODEL, sync='false', use_sim_time='true') as node:
        sent = []
        monkeypatch.setattr(node.pub, 'publish', sent.append)
        clock = node.get_clock()
        assert clock.ros_time_is_active
        node.on_temperature(temperature(1_000_000, 30.0))
        node.on_state(joint_state(5_000_000_000, [0.1], [0.2], [1.0]))   # no /clock yet
        assert len(sent) == 1 and node.rejected == 0
        clock.set_ros_time_override(Time(nanoseconds=6_000_000_000))
        node.on_state(joint_state(6_500_000_000, [0.1], [0.2], [1.0]))   # 0.5 s ahead: ok
        node.on_state(joint_state(9_000_000_000, [0.1], [0.2], [1.0]))   # 3 s ahead of /clock
        assert len(sent) == 2 and node.rejected == 1
        node.on_state(joint_state(6_800_000_000, [0.1], [0.2], [1.0]))
        assert len(sent) == 3 and node.rejected == 1


def test_the_gate_uses_the_gear_limits(ros_env, monkeypatch):
    """Values just inside the gear's limits are used, just outside refused, stamps too."""
    from friction_joint.ros.nodes.estimator import EstimatorNode
    from friction_joint.ros.nodes.joint_sim import JointSimNode
    from friction_joint.testbed.plant import InputLimits
    lim = InputLimits(load_gear(MODEL))
    with node_here(EstimatorNode, MODEL, sync='false') as node:
        sent = []
        monkeypatch.setattr(node.pub, 'publish', sent.append)
        node.on_temperature(temperature(BASE_NS, 30.0))
        ns = BASE_NS
        for q, qd, eff, ok in ((0.1, 0.99 * lim.velocity, 0.99 * lim.torque, True),
                               (0.1, 1.01 * lim.velocity, 1.0, False),
                               (0.1, 0.2, -1.01 * lim.torque, False),
                               (1.01 * lim.position, 0.2, 1.0, False),
                               (0.1, 0.2, 1.0, True)):
            ns += 1_000_000
            n = len(sent)
            node.on_state(joint_state(ns, [q], [qd], [eff]))
            assert len(sent) == n + ok, (q, qd, eff)
        for xi in (lim.temperature[1] + 1.0, lim.temperature[0] - 1.0, NAN):
            node.on_temperature(temperature(ns, xi))
        assert node.pair.latest == 30.0
        future = time.time_ns() + 60 * 10 ** 9                # a stamp a minute ahead
        node.on_state(joint_state(future, [0.1], [0.2], [1.0]))
        node.on_state(joint_state(ns + 1_000_000, [0.1], [0.2], [1.0]))
        assert len(sent) == 3 and stamp_ns(sent[-1]) == ns + 1_000_000
        assert node.rejected == 7
    truth = InputLimits(load_gear(TRUTH))
    with node_here(JointSimNode, TRUTH) as node:
        for effort, held in ((0.99 * truth.torque, 0.99 * truth.torque),
                             (1.01 * truth.torque, 0.99 * truth.torque), (5.0, 5.0)):
            node.on_command(joint_state(0, [0.0], [0.0], [effort]))
            assert node.tau_cmd == held
        node.on_contact(wrench(-1.01 * truth.torque))
        assert node.contact == 0.0 and node.rejected == 2


# ------------------------------------------------------------ the storm (acceptance test)

STORM_S = 10.0                           # of storm messages at RATE (longer in wall time if late)
CLEAN_S = 1.5                            # of clean data at least (longer until the checks can run)
SETTLE_S = 1.0                           # the checks look at what comes 1 s after the storm
FOLLOW_STATES = 225                      # simulator states checked (0.225 s of its time)
RATE = 500.0                             # Hz of the storm and of the clean data after it
SEED = 12


class Storm:
    """Random messages: finite and non-finite, plausible and not, malformed; seeded."""

    def __init__(self, seed):
        self.rng = np.random.default_rng(seed)
        self.expected = collections.Counter()          # messages each node must refuse

    def huge(self):
        return float(self.rng.choice([-1, 1]) * 10 ** self.rng.uniform(9.5, 308))

    def nonfinite(self):
        return float(self.rng.choice([NAN, INF, -INF]))

    def state(self, ns):
        """Return a random /joint_states message for the estimator."""
        r = self.rng
        values = [r.uniform(-3, 3), r.uniform(-10, 10), r.uniform(-30, 30)]
        kind = r.integers(6)
        names = ['joint']
        self.expected['estimator'] += kind in (1, 2, 3, 4)
        if kind == 1:
            values[r.integers(3)] = self.nonfinite()
        elif kind == 2:
            values[r.integers(3)] = self.huge()
        elif kind == 3:                                 # malformed
            shape = r.integers(3)
            if shape == 0:
                return joint_state(ns, [], [], [])
            if shape == 1:
                names = ['other']
            else:
                return joint_state(ns, values, values[:1], [])
        elif kind == 4:                                 # stamped in the future
            ns = (2 ** 31 - 1) * 10 ** 9
        return joint_state(ns, [values[0]], [values[1]], [values[2]], names)

    def temperature(self, ns):
        kind = self.rng.integers(4)
        xi = {0: self.nonfinite, 1: self.huge}.get(kind, lambda: self.rng.uniform(0, 80))()
        self.expected['estimator'] += kind in (0, 1)
        return temperature(ns, xi)

    def command(self):
        r = self.rng
        kind = r.integers(5)
        effort = {0: self.nonfinite, 1: self.huge}.get(kind, lambda: r.uniform(-16, 16))()
        self.expected['joint_sim'] += kind in (0, 1, 2)
        if kind == 2:                                   # malformed: no effort
            return joint_state(0, [0.0], [0.0], [])
        return joint_state(0, [0.0], [0.0], [effort])

    def contact(self):
        kind = self.rng.integers(4)
        tz = {0: self.nonfinite, 1: self.huge}.get(kind, lambda: self.rng.uniform(-5, 5))()
        self.expected['joint_sim'] += kind in (0, 1)
        return wrench(tz)


def run_storm(node, est, sim):
    """
    Publish the storm, then clean data; return what came back (see the ``storm`` fixture).

    Publishing is paced at ``RATE`` and never catches up in a burst (a loaded
    machine stretches the storm in wall time; its messages stay the same).  The
    clean data and the sane command go on until the simulator has published
    ``FOLLOW_STATES`` states stamped ``SETTLE_S`` or more after the first state
    in which it applied the command (``DEADLINE`` at most); then the test waits
    until every clean sample has been answered by the estimator.
    """
    from geometry_msgs.msg import WrenchStamped
    from sensor_msgs.msg import JointState, Temperature
    import roshelpers
    n = node.node
    qos = roshelpers.reliable_qos()
    pubs = {'js': n.create_publisher(JointState, '/joint_states', qos),
            'temp': n.create_publisher(Temperature, '/joint_temperature', qos),
            'cmd': n.create_publisher(JointState, '/sim/joint_command', qos),
            'contact': n.create_publisher(WrenchStamped, '/sim/contact_torque', qos)}
    sub_ext = n.create_subscription(JointState, '/external_torque', lambda m: None, qos)
    sub_sim = n.create_subscription(JointState, '/sim/joint_states', lambda m: None, qos)
    assert est.wait_for('external torque observer'), est.describe()
    assert sim.wait_for('realtime simulation'), sim.describe()
    assert all(node.wait_for_subscribers(p) for p in pubs.values())
    assert node.wait_for_publishers(sub_ext)
    assert node.wait_for_publishers(sub_sim)
    storm = Storm(SEED)
    step_ns = int(1e9 / RATE)
    n_storm, n_clean = int(STORM_S * RATE), int(CLEAN_S * RATE)
    n_max = n_clean + int(DEADLINE * RATE)
    tau, q, qd = clean_motion(n_max, 1.0 / RATE)
    truth = load_gear(TRUTH)
    command = 1.5 * (truth.mgl + 4.7)       # beats the lever and the break-away torque
    sim_storm, sim_after, ext = [], [], {}
    t_start = t_next = time.monotonic()
    k = 0
    while True:
        pause = t_next - time.monotonic()
        if pause > 0:
            time.sleep(pause)
        t_next = max(t_next, time.monotonic() - 0.5 / RATE) + 1.0 / RATE
        ns = BASE_NS + k * step_ns
        if k < n_storm:
            pubs['temp'].publish(storm.temperature(ns))
            pubs['js'].publish(storm.state(ns))
            pubs['cmd'].publish(storm.command())
            pubs['contact'].publish(storm.contact())
        else:
            j = k - n_storm
            pubs['temp'].publish(temperature(ns, 30.0))
            pubs['js'].publish(joint_state(ns, [q[j]], [qd[j]], [tau[j]]))
            pubs['cmd'].publish(joint_state(0, [0.0], [0.0], [command]))
            pubs['contact'].publish(wrench(0.0))
        k += 1
        if k % 10 == 0:
            (sim_storm if k <= n_storm else sim_after).extend(drain(sub_sim, JointState))
            if k > n_storm:
                ext.update((stamp_ns(m), m.effort[0]) for m in drain(sub_ext, JointState))
                j = k - n_storm
                if j >= n_max or (j >= n_clean and
                                  len(following(sim_after, command)) >= FOLLOW_STATES):
                    break
    clean = [BASE_NS + (n_storm + j) * step_ns for j in range(k - n_storm)]

    def answered():
        ext.update((stamp_ns(m), m.effort[0]) for m in drain(sub_ext, JointState))
        return set(clean) <= set(ext)

    roshelpers.wait_until(answered)
    t_answered = time.monotonic()
    m = len(clean)
    return {'clean': clean, 'ext': ext, 'tau': tau[:m], 'q': q[:m], 'qd': qd[:m],
            'sim_storm': sim_storm, 'sim_after': sim_after, 'command': command,
            'expected': storm.expected, 'wall_s': t_answered - t_start,
            'alive': (est.popen.poll() is None, sim.popen.poll() is None)}


def following(states, command):
    """
    Return the states stamped ``SETTLE_S`` or more after the first one that applies ``command``.

    ``command`` lies outside the storm's range of plausible commands, so the
    first state whose effort is ``command`` is the first after the storm that
    the simulator computed with the sane command.
    """
    applied = [stamp_ns(m) for m in states if abs(m.effort[0] - command) < 0.1]
    if not applied:
        return []
    t_cmd = applied[0]
    return [m for m in states if stamp_ns(m) >= t_cmd + SETTLE_S * 1e9]


@pytest.fixture(scope='module')
def storm():
    """
    Run estimator and real-time simulator (namespace /sim) through one storm.

    The estimator pairs states and temperatures by stamp (``sync``, as the storm
    was written for); the simulator's command watchdog is off (see ``no_watchdog``).
    """
    import roshelpers
    env = roshelpers.ros_environ()
    with pytest.MonkeyPatch.context() as mp:
        for key in ('ROS_DOMAIN_ID', 'ROS_AUTOMATIC_DISCOVERY_RANGE'):
            mp.setenv(key, env[key])
        mp.delenv('ROS_LOCALHOST_ONLY', raising=False)
        est = roshelpers.Proc(node_cmd('estimator', MODEL, rate=RATE, friction='lugre',
                                       sync='true'), env)
        sim = roshelpers.Proc(node_cmd('joint_sim', TRUTH, '-r', '__ns:=/sim',
                                       mode='realtime', **no_watchdog()), env)
        try:
            with roshelpers.ros_node('storm', env['ROS_DOMAIN_ID']) as node:
                result = run_storm(node, est, sim)
                rc = stop_together(est, sim)          # while this node still acknowledges
        finally:
            stop_together(est, sim)
    result.update(est=est, sim=sim, rc=rc)
    return result


def test_estimator_survives_the_storm_and_agrees_with_offline_after_1_s(storm):
    est = storm['est']
    assert storm['alive'][0] and storm['rc'][0] == 0, est.describe()
    clean, ext = storm['clean'], storm['ext']
    missing = [ns for ns in clean if ns not in ext]
    assert not missing, f'{len(missing)} of {len(clean)} clean samples unanswered\n' + \
        est.describe()[-3000:]
    live = np.array([ext[ns] for ns in clean])
    assert np.all(np.isfinite(live))
    obs = DisturbanceObserver(load_gear(MODEL), beta=60.0, dt=1.0 / RATE, friction='lugre')
    offline = np.array([obs(t, q, qd, 30.0) for t, q, qd in zip(storm['tau'], storm['q'],
                                                                storm['qd'], strict=True)])
    after = int(RATE * SETTLE_S)                            # 1 s after the storm
    err = np.abs(live - offline)
    assert np.max(err[after:]) < 1e-9, f'max deviation {np.max(err[after:]):.3g} Nm'
    assert rejected_count(est) == storm['expected']['estimator'], est.describe()[-3000:]
    log = est.stdout + est.stderr
    warnings = log.count('ignored ')
    kinds = re.findall(r'rejected \d+ input messages \(([^\n]*)\)', log)[-1].count(' x ')
    # throttled: the first of each kind, then one line per 2 s while storm messages came in
    assert 1 <= warnings <= kinds + storm['wall_s'] / 2.0 + 3, (warnings, kinds, storm['wall_s'])


def test_joint_sim_survives_the_storm_and_follows_the_command_after_1_s(storm):
    sim = storm['sim']
    assert storm['alive'][1] and storm['rc'][1] == 0, sim.describe()
    during, after = storm['sim_storm'], storm['sim_after']
    assert during, sim.describe()                             # published through the storm
    assert all(math.isfinite(m.position[0]) and math.isfinite(m.velocity[0])
               for m in during + after)
    stamps = [stamp_ns(m) for m in during + after]
    assert all(b > a for a, b in zip(stamps, stamps[1:], strict=False))      # one run, in order
    window = following(after, storm['command'])
    assert len(window) >= FOLLOW_STATES, (len(window), len(after), sim.describe()[-3000:])
    q = np.array([m.position[0] for m in window])
    qd = np.array([m.velocity[0] for m in window])
    effort = np.array([m.effort[0] for m in window])
    assert np.max(np.abs(effort - storm['command'])) < 0.1     # applies the sane command
    assert np.all(qd > 0) and np.all(np.diff(q) >= 0)         # and turns the way it pushes
    assert rejected_count(sim) == storm['expected']['joint_sim'], sim.describe()[-3000:]
