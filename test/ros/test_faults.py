# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Faults the nodes must survive: poisoned stamps, a bad /clock, killed and restarted peers.

Each test reproduces a fault that silenced or ended a node before: one state
stamped far ahead of the stream (every later state was refused as "older"),
a stamp with ``nanosec >= 1e9``, a stream whose stamps start over (a replay
that loops), a ``/clock`` with negative seconds (rclpy's callback raised and
ended every node on sim time), ``use_sim_time`` set at run time on the
simulator, and, in lockstep, the controller, the estimator and the recorder
killed (SIGKILL) and restarted during a run.  Conditions are waited for with
``roshelpers.DEADLINE``.
"""
import os
import signal
import time

from friction_joint.bag import read_recording
import numpy as np
import pytest
from roshelpers import DEADLINE, PYTHON, reliable_qos, stamp_ns
from test_node_inputs import joint_state, MODEL, node_cmd, temperature, TRUTH

pytestmark = pytest.mark.ros

DT_NS = 1_000_000_000 // 1000


def test_outlier_stamps_and_a_looping_stream_do_not_silence_the_followers(spawn, ros_node):
    """
    Before: one state stamped ahead of the stream silenced both nodes for good.

    The estimator must answer every clean state: 200, then (after a state
    3500 s ahead and one with nanosec 1.5e9, both refused) 200 more, then a
    stream that starts over at the first stamp (a replay loop): it restarts
    and answers those too, from the first.  The controller (answering the
    newest state) must answer the last state of each stretch.
    """
    from sensor_msgs.msg import JointState
    est = spawn(node_cmd('estimator', MODEL, friction='static'))
    ctl = spawn(node_cmd('controller', MODEL))
    node = ros_node.node
    qos = reliable_qos()
    pub_js = node.create_publisher(JointState, '/joint_states', qos)
    pub_t = node.create_publisher(type(temperature(0, 30.0)), '/joint_temperature', qos)
    got = {'est': [], 'ctl': []}
    for key, topic in (('est', '/external_torque'), ('ctl', '/joint_command')):
        node.create_subscription(JointState, topic,
                                 lambda m, key=key: got[key].append(stamp_ns(m)), qos)
    assert ros_node.wait_for_subscribers(pub_js, 2, timeout=DEADLINE)
    base = time.time_ns() - 3600 * 10 ** 9            # a stream from an hour ago

    def state(k):
        q = 0.3 * np.sin(0.01 * k)
        return joint_state(base + k * DT_NS, [q], [0.003 * np.cos(0.01 * k)], [2.0 + q])

    def first():
        pub_t.publish(temperature(base, 30.0))
        pub_js.publish(state(0))

    assert ros_node.repeat_until(first, lambda: base in got['est'] and base in got['ctl']), \
        est.describe() + ctl.describe()

    def stretch(ks):
        last = base + ks[-1] * DT_NS
        n_est, n_ctl = got['est'].count(last), got['ctl'].count(last)
        for k in ks:
            pub_js.publish(state(k))
            if k % 50 == 0:
                ros_node.spin_for(0.01)
        assert ros_node.spin_until(lambda: got['est'].count(last) > n_est
                                   and got['ctl'].count(last) > n_ctl,
                                   timeout=DEADLINE), (len(got['est']), est.describe(),
                                                       ctl.describe())

    stretch(range(1, 200))
    ahead = joint_state(base + 3500 * 10 ** 9, [0.1], [0.0], [1.0])
    pub_js.publish(ahead)
    bad = state(200)
    bad.header.stamp.nanosec = 1_500_000_000
    pub_js.publish(bad)
    stretch(range(200, 400))
    clean = {base + k * DT_NS for k in range(400)}
    assert clean <= set(got['est'])
    assert base + 3500 * 10 ** 9 not in got['est'] + got['ctl']
    # the stream starts over (a replay that loops): answered again from its first state
    n_first = len(got['est'])
    stretch(range(0, 100))
    again = got['est'][n_first:]
    assert again[:100] == [base + k * DT_NS for k in range(100)], again[:5]
    assert 'restarting on the new timeline' in est.stdout + est.stderr
    assert est.popen.poll() is None and ctl.popen.poll() is None


def test_a_held_up_realtime_controller_follows_a_restarted_stream_queued_at_once(spawn,
                                                                                 ros_node):
    """
    Before: a realtime controller fell silent for good on a restart queued in one batch.

    It offered only the newest of its queued states to the stamp order, so a restarted
    stream that a loaded machine queued at once was never confirmed (three states in a row
    are needed).

    The controller is stopped (SIGSTOP) while the stream starts over, so that every state
    of the new stretch is queued at once; resumed, it must answer the stretch's newest.
    """
    from sensor_msgs.msg import JointState
    ctl = spawn(node_cmd('controller', MODEL))
    node = ros_node.node
    qos = reliable_qos()
    pub_js = node.create_publisher(JointState, '/joint_states', qos)
    pub_t = node.create_publisher(type(temperature(0, 30.0)), '/joint_temperature', qos)
    got = []
    node.create_subscription(JointState, '/joint_command', lambda m: got.append(stamp_ns(m)),
                             qos)
    assert ros_node.wait_for_subscribers(pub_js, 1, timeout=DEADLINE)
    rng = np.random.default_rng(11)
    base = time.time_ns() - int(rng.uniform(600, 7200)) * 10 ** 9

    def state(k):
        return joint_state(base + k * DT_NS, [0.1 * np.sin(0.01 * k)], [0.0], [2.0])

    def first():
        pub_t.publish(temperature(base, 30.0))
        pub_js.publish(state(0))

    assert ros_node.repeat_until(first, lambda: base in got), ctl.describe()
    n = int(rng.integers(150, 400))
    for k in range(1, n):
        pub_js.publish(state(k))
    last = base + (n - 1) * DT_NS
    assert ros_node.spin_until(lambda: last in got, timeout=DEADLINE), ctl.describe()
    restart = int(rng.integers(5, 100))                 # the stream starts over, all queued
    os.kill(ctl.popen.pid, signal.SIGSTOP)
    try:
        for k in range(restart):
            pub_js.publish(state(k))
        ros_node.spin_for(0.5)
    finally:
        os.kill(ctl.popen.pid, signal.SIGCONT)
    newest = base + (restart - 1) * DT_NS
    assert ros_node.spin_until(lambda: got[-1] == newest, timeout=DEADLINE), (
        got[-3:], newest, ctl.describe())
    assert ctl.wait_for('restarting on the new timeline'), ctl.describe()   # the log arrives late


def test_a_bad_clock_is_refused_not_fatal(spawn, ros_node):
    """Before: a /clock with negative seconds ended every node on sim time (ValueError)."""
    from rosgraph_msgs.msg import Clock
    procs = [spawn(node_cmd('estimator', MODEL, use_sim_time='true')),
             spawn(node_cmd('controller', MODEL, use_sim_time='true')),
             spawn(node_cmd('joint_sim', TRUTH, use_sim_time='true', wait_subscribers=0,
                            command_timeout=0.0))]
    pub = ros_node.node.create_publisher(Clock, '/clock', reliable_qos())
    assert ros_node.wait_for_subscribers(pub, 3, timeout=DEADLINE)

    def clock(sec, nanosec=0):
        msg = Clock()
        msg.clock.sec, msg.clock.nanosec = sec, nanosec
        pub.publish(msg)

    def refused_everywhere():
        return all('cannot represent' in p.stdout + p.stderr for p in procs)

    # one message per period: rclpy's /clock subscription keeps only the newest sample
    clock(100)
    assert ros_node.repeat_until(lambda: clock(-5), refused_everywhere), \
        [p.describe()[-1500:] for p in procs]
    clock(101)
    ros_node.spin_for(0.2)
    clock(102)
    ros_node.spin_for(1.0)
    assert all(p.popen.poll() is None for p in procs), [p.describe() for p in procs]


def test_joint_sim_refuses_use_sim_time_at_run_time(spawn, ros_node):
    """Before: joint_sim took use_sim_time at run time and stamped 3003 states 0.0."""
    from rcl_interfaces.srv import SetParameters
    from rclpy.parameter import Parameter
    spawn(node_cmd('joint_sim', TRUTH, wait_subscribers=0))
    client = ros_node.node.create_client(SetParameters, '/joint_sim/set_parameters')
    assert ros_node.spin_until(client.service_is_ready, timeout=DEADLINE)
    request = SetParameters.Request()
    request.parameters = [Parameter('use_sim_time', value=True).to_parameter_msg()]
    future = client.call_async(request)
    assert ros_node.spin_until(future.done, timeout=DEADLINE)
    result = future.result().results[0]
    assert not result.successful and 'use_sim_time' in result.reason


def _kill_and_restart(spawn, proc, cmd):
    os.killpg(proc.popen.pid, signal.SIGKILL)
    proc.popen.wait(30)
    return spawn(cmd)


@pytest.mark.slow
def test_lockstep_survives_killed_and_restarted_peers(spawn, ros_node, tmp_path):
    """
    Before: kill -9 of the controller stalled the lockstep simulator for good, silently.

    A lockstep run (recorder, estimator with flow control, controller) whose
    controller, estimator and recorder are each killed with SIGKILL and
    restarted once: the simulator re-sends the state it waits on, so the run
    completes; it logs each stall; the restarted recorder's recording has
    every step on every loop topic from the moment it matched to the end.
    """
    from sensor_msgs.msg import JointState
    duration = 5.0
    n = int(duration * 3000)
    rec_cmd = [PYTHON, '-m', 'friction_joint', 'record', str(tmp_path / 'rec1'), '--use-sim-time']
    est_cmd = node_cmd('estimator', MODEL, mode='lockstep')
    ctl_cmd = node_cmd('controller', MODEL, mode='lockstep')
    rec = spawn(rec_cmd)
    est = spawn(est_cmd)
    ctl = spawn(ctl_cmd)
    sim = spawn(node_cmd('joint_sim', TRUTH, mode='lockstep', duration=duration,
                         wait_subscribers=3, wait_recorder='loop', follow='external_torque'))
    steps = []
    # best effort: a watcher that never holds the lockstep publisher back
    from rclpy.qos import qos_profile_sensor_data
    ros_node.node.create_subscription(
        JointState, '/joint_states', lambda m: steps.append(stamp_ns(m) * 3000 // 10 ** 9),
        qos_profile_sensor_data)

    def reach(k):
        assert ros_node.spin_until(lambda: steps and steps[-1] >= k, timeout=DEADLINE * 6), (
            steps[-1:], sim.describe())

    reach(n // 8)
    ctl = _kill_and_restart(spawn, ctl, ctl_cmd)
    reach(3 * n // 8)
    est = _kill_and_restart(spawn, est, est_cmd)
    reach(5 * n // 8)
    rec = _kill_and_restart(spawn, rec, [PYTHON, '-m', 'friction_joint', 'record',
                                         str(tmp_path / 'rec2'), '--use-sim-time'])
    k_restart = steps[-1]
    assert sim.wait(timeout=DEADLINE * 10) == 0, sim.describe()
    for proc in (ctl, est, rec):
        proc.stop(timeout=DEADLINE)
    log = sim.stdout + sim.stderr
    # a killed controller sends no command, a killed estimator echoes nothing (flow control):
    # both stall the loop, and every stall is logged at its first re-send, however short
    # the machine's load makes it (a killed recorder stalls it only while its keep-all
    # history is full: it may or may not)
    stalls = [line for line in log.splitlines() if 're-sending the state' in line]
    assert any('waiting for the command of step' in line for line in stalls), log
    assert any('waiting for the followers' in line for line in stalls), log
    bag = read_recording(str(tmp_path / 'rec2'))
    for topic in ('joint_states', 'joint_command', 'external_torque', 'link_torque'):
        k = np.unique(np.round(getattr(bag, topic).t * 3000).astype(np.int64))
        assert k[-1] == n, (topic, k[-1])
        assert np.all(np.diff(k) == 1), (topic, np.flatnonzero(np.diff(k) != 1)[:5])
        # it joined a running loop (a few thousand steps pass while it starts), then
        # kept every step to the end
        assert k_restart <= k[0] <= n - 1500, (topic, k[0], k_restart)


def test_replay_loop_into_an_estimator_on_sim_time_is_answered_every_loop(
        spawn, ros_node, tmp_path):
    """
    Before: ``replay REC --loop`` into an estimator on sim time: 0 answers after the first loop.

    The second loop starts the stamps (and /clock) over: the estimator
    restarts on the new timeline and answers the states of every loop.
    """
    from friction_joint.bag import write_recording
    from sensor_msgs.msg import JointState
    n, t0 = 1500, 100.0
    t = t0 + 1e-3 * np.arange(n)
    q = 0.3 * np.sin(2.0 * (t - t0))
    bag = write_recording(str(tmp_path / 'loop'), {
        '/joint_states': {'t': t, 'q': q, 'qd': 0.6 * np.cos(2.0 * (t - t0)), 'effort': 2.0 + q},
        '/joint_temperature': {'t': t[::100], 'xi': np.full(len(t[::100]), 30.0)}})
    answers = []
    ros_node.node.create_subscription(JointState, '/external_torque',
                                      lambda m: answers.append(stamp_ns(m)), reliable_qos())
    est = spawn(node_cmd('estimator', MODEL, use_sim_time='true', friction='static'))
    assert est.wait_for('external torque observer', timeout=DEADLINE), est.describe()
    spawn([PYTHON, '-m', 'friction_joint', 'replay', bag, '--loop', '--wait', '30'])
    last = int(round(t[-1] * 1e9))

    def loops():
        return answers.count(last)

    assert ros_node.spin_until(lambda: loops() >= 2, timeout=DEADLINE * 2), (
        len(answers), est.describe())
    second = answers[answers.index(last) + 1:]
    assert len(set(second)) >= 0.9 * n, len(set(second))       # the second loop answered
    assert 'restarting on the new timeline' in est.stdout + est.stderr


def test_a_flood_of_rejected_parameter_requests_is_logged_throttled(spawn, ros_node):
    """
    Before: every rejected request logged a warning; a flood kept the node busy for minutes.

    400 requests the controller must refuse: it logs a handful of lines, not
    400, and still stops promptly on SIGINT.
    """
    from rcl_interfaces.srv import SetParameters
    from rclpy.parameter import Parameter
    ctl = spawn(node_cmd('controller', MODEL))
    client = ros_node.node.create_client(SetParameters, '/controller/set_parameters')
    assert ros_node.spin_until(client.service_is_ready, timeout=DEADLINE)
    futures = []
    for k in range(400):                    # (a service queue keeps 10 requests: 5 in flight)
        assert ros_node.spin_until(lambda: sum(not f.done() for f in futures) < 5,
                                   timeout=DEADLINE)
        request = SetParameters.Request()
        request.parameters = [Parameter('friction_ff', value=f'bogus{k}').to_parameter_msg()]
        futures.append(client.call_async(request))
    assert ros_node.spin_until(lambda: all(f.done() for f in futures), timeout=DEADLINE)
    assert not any(f.result().results[0].successful for f in futures)
    t0 = time.monotonic()
    assert ctl.stop(timeout=DEADLINE) in (0, -signal.SIGINT, 130), ctl.describe()
    assert time.monotonic() - t0 < 20.0, 'the controller did not stop promptly'
    lines = [line for line in (ctl.stdout + ctl.stderr).splitlines()
             if 'rejected a parameter change' in line]
    assert 1 <= len(lines) <= 40, len(lines)
    assert '400 rejected so far' in ctl.stdout + ctl.stderr or len(lines) < 400
