# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint record`` / ``replay`` as processes on an isolated ROS 2 domain.

The tests hold on a loaded machine: they wait for conditions (a line of the
recorder, every message arrived, the replay ended) with the generous deadline
``roshelpers.DEADLINE``.  Replay timing is checked from the replayer's own
publish times (the DDS source timestamps) and only in the direction a busy
machine cannot break (replay never publishes before a message's log time);
how closely it keeps the log times is measured by ``benchmarks/bench_nodes.py``.
"""
from pathlib import Path
import re
import subprocess
import time

from friction_joint.bag import read_recording, write_recording
import numpy as np
import pytest
from roshelpers import DEADLINE, PYTHON, reliable_qos
import sourcetree

pytestmark = pytest.mark.ros

pytest.importorskip('rclpy')

CLI = [PYTHON, '-m', 'friction_joint']
MCAP_CLI = Path(sourcetree.MCAP_CLI)


def _joint_state(i, names=('joint',)):
    from sensor_msgs.msg import JointState
    m = JointState()
    m.header.stamp.sec, m.header.stamp.nanosec = 100 + i // 1000, (i % 1000) * 1_000_000
    m.name = list(names)
    k = len(names)
    m.position = [float(i) + j for j in range(k)]
    m.velocity = [1000.0] * k                   # the position rises by 1 per 1 ms stamp
    m.effort = [-float(i)] * k
    return m


def _publish(node, pub, msgs, rate=2000.0):
    period = 1.0 / rate
    t0 = time.perf_counter()
    for i, m in enumerate(msgs):
        pub.publish(m)
        while time.perf_counter() < t0 + (i + 1) * period:
            pass
    from rclpy.duration import Duration
    assert pub.wait_for_all_acked(Duration(seconds=DEADLINE))


def test_record_counts_every_message(ros_node, spawn, tmp_path):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rosbags.highlevel import AnyReader
    from sensor_msgs.msg import JointState

    n = 1500
    out = tmp_path / 'rec'
    rec = spawn(CLI + ['record', out, '--topics', '/joint_states'])
    assert rec.wait_for('recording /joint_states'), rec.describe()
    pub = ros_node.node.create_publisher(JointState, '/joint_states', reliable_qos(None))
    assert ros_node.wait_for_subscribers(pub), rec.describe()
    assert rec.wait_for('/joint_states: 1 publisher matched'), rec.describe()
    t_sent = time.time()
    _publish(ros_node, pub, [_joint_state(i) for i in range(n)], rate=3000.0)
    assert rec.stop() == 0, rec.describe()
    assert f'recorded {n} messages (/joint_states: {n}) to {out}' in rec.stdout, rec.describe()
    assert sorted(p.name for p in tmp_path.iterdir()) == ['rec']

    with AnyReader([out]) as reader:
        msgs = [(t, reader.deserialize(raw, c.msgtype)) for c, t, raw in reader.messages()]
    assert len(msgs) == n
    assert [m.position[0] for _, m in msgs] == list(range(n))
    assert [m.header.stamp.nanosec for _, m in msgs[:3]] == [0, 1_000_000, 2_000_000]
    assert msgs[0][1].name == ['joint'] and msgs[5][1].effort[0] == -5.0
    bag_times = np.array([t for t, _ in msgs])
    assert np.all(np.diff(bag_times) >= 0)
    assert t_sent - 1.0 < bag_times[0] / 1e9 <= time.time()       # receive (wall) time

    with open(next(out.glob('*.mcap')), 'rb') as fh:
        decoded = [m for _, _, _, m in make_reader(
            fh, decoder_factories=[DecoderFactory()]).iter_decoded_messages()]
    assert [m.position[0] for m in decoded] == list(range(n))


def test_record_duration_default_topics_read_back(ros_node, spawn, tmp_path):
    from sensor_msgs.msg import JointState, Temperature

    out = tmp_path / 'rec'
    duration = 20.0             # wall s from start-up: discovery on a busy machine, then 0.2 s
    rec = spawn(CLI + ['record', out, '--duration', f'{duration:g}'])
    assert rec.wait_for('recording'), rec.describe()
    js = ros_node.node.create_publisher(JointState, '/joint_states', reliable_qos(None))
    tp = ros_node.node.create_publisher(Temperature, '/joint_temperature', reliable_qos())
    assert ros_node.wait_for_subscribers(js) and ros_node.wait_for_subscribers(tp)
    assert rec.wait_for('/joint_states: 1 publisher matched'), rec.describe()
    assert rec.wait_for('/joint_temperature: 1 publisher matched'), rec.describe()
    for i in range(5):
        m = Temperature()
        m.header.stamp.sec = 100 + i // 2
        m.header.stamp.nanosec = (i % 2) * 500_000_000
        m.temperature, m.variance = 30.0 + i, 0.1
        tp.publish(m)
    _publish(ros_node, js, [_joint_state(i, ('other', 'joint')) for i in range(300)])
    _publish(ros_node, tp, [])                                 # the temperatures acknowledged
    assert rec.wait(timeout=duration + DEADLINE) == 0, rec.describe()
    assert re.search(r'recorded 305 messages \(/joint_states: 300, /joint_temperature: 5, '
                     r'/link_torque: 0, .*/clock: 0\)', rec.stdout), rec.describe()

    data = read_recording(out, joint_name='joint')
    np.testing.assert_array_equal(data.joint_states.q, np.arange(300) + 1.0)
    np.testing.assert_array_equal(data.joint_states.effort, -np.arange(300.0))
    np.testing.assert_allclose(data.joint_states.t, 100 + np.arange(300) * 1e-3)
    np.testing.assert_array_equal(data.temperature.xi, [30, 31, 32, 33, 34])
    np.testing.assert_array_equal(data.temperature_at(t=[100.7, 101.2]), [31, 32])
    assert data.link_torque is None and data.joint_command is None
    assert read_recording(out).joint_name == 'other'


def test_record_refuses_existing_output(spawn, tmp_path):
    (tmp_path / 'rec').mkdir()
    rec = spawn(CLI + ['record', tmp_path / 'rec'])
    assert rec.wait() == 2, rec.describe()
    assert 'exists already' in rec.stderr
    rec = spawn(CLI + ['record', tmp_path / 'x', '--topics', '/unknown'])
    assert rec.wait() == 2, rec.describe()
    assert '/unknown is not a contract topic' in rec.stderr


def _replay_bag(path, n=300):
    t = 10.0 + np.arange(n) * 1e-3
    write_recording(path, {
        '/joint_states': {'t': t, 'q': np.arange(n, dtype=float), 'qd': np.zeros(n),
                          'effort': np.ones(n)},
        '/joint_temperature': {'t': [10.0, 10.2], 'xi': [25.0, 26.0]},
        '/clock': {'t': t + 1000.0}})              # the bag's own clock, to be skipped
    return t


class _Collector:
    """Every message of some topics, with the time the publisher sent it (source timestamp)."""

    def __init__(self, node, topics):
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import JointState, Temperature
        types = {'/joint_states': JointState, '/joint_temperature': Temperature, '/clock': Clock}
        self.got = {t: [] for t in topics}
        self.sent = {t: [] for t in topics}
        self.subs = [node.create_subscription(types[t], t, self._cb(t), reliable_qos(None))
                     for t in topics]

    def _cb(self, topic):
        def cb(msg, info):
            self.got[topic].append(msg)
            self.sent[topic].append(info['source_timestamp'] * 1e-9)
        return cb

    def has(self, counts):
        """Return whether at least ``counts[topic]`` messages of each topic have arrived."""
        return all(len(self.got[t]) >= n for t, n in counts.items())


def test_replay_publishes_in_order_with_clock(ros_node, spawn, tmp_path):
    n = 300
    t = _replay_bag(tmp_path / 'bag', n)
    col = _Collector(ros_node.node, ['/joint_states', '/joint_temperature', '/clock'])
    rep = spawn(CLI + ['replay', tmp_path / 'bag', '--rate', '1', '--wait', '60'])
    expected = {'/joint_states': n, '/joint_temperature': 2, '/clock': n}
    assert ros_node.spin_until(lambda: rep.popen.poll() is not None and col.has(expected)), \
        ({t: len(m) for t, m in col.got.items()}, rep.describe())
    assert rep.wait() == 0, rep.describe()
    assert f'replayed {2 * n + 2} messages (/joint_states: {n}, /joint_temperature: 2, ' \
           f'/clock: {n}) from' in rep.stdout, rep.describe()
    js = col.got['/joint_states']
    assert [m.position[0] for m in js] == list(range(n))
    assert len(col.got['/joint_temperature']) == 2
    clock = np.array([c.clock.sec + c.clock.nanosec * 1e-9 for c in col.got['/clock']])
    assert len(clock) == n and np.all(np.diff(clock) > 0)
    np.testing.assert_allclose(clock, t, atol=1e-9)           # from the stamps, not the bag's
    span = col.sent['/joint_states'][-1] - col.sent['/joint_states'][0]
    assert span > 0.9 * (t[-1] - t[0]), span                     # 0.3 s of data at rate 1


def test_replay_single_mcap_fast_without_clock(ros_node, spawn, tmp_path):
    n = 300
    _replay_bag(tmp_path / 'one.mcap', n)
    col = _Collector(ros_node.node, ['/joint_states', '/clock'])
    rep = spawn(CLI + ['replay', tmp_path / 'one.mcap', '--rate', 'max', '--no-clock', '--wait',
                       '60', '--topics', '/joint_states', '/clock'])
    assert ros_node.spin_until(lambda: rep.popen.poll() is not None and
                               col.has({'/joint_states': n, '/clock': n})), rep.describe()
    assert rep.wait() == 0, rep.describe()
    assert [m.position[0] for m in col.got['/joint_states']] == list(range(n))
    clock = [c.clock.sec + c.clock.nanosec * 1e-9 for c in col.got['/clock']]
    assert clock[0] == pytest.approx(1010.0)                    # the bag's own /clock
    rep = spawn(CLI + ['replay', tmp_path / 'one.mcap', '--topics', '/nope'])
    assert rep.wait() == 2 and 'no /nope topic' in rep.stderr, rep.describe()


def test_replay_ends_with_an_error_when_a_subscriber_stops_taking(ros_node, spawn, tmp_path):
    from sensor_msgs.msg import JointState
    n = int(np.random.default_rng(5).integers(20_000, 25_000))
    _replay_bag(tmp_path / 'bag', n)
    ros_node.node.create_subscription(JointState, '/joint_states', lambda m: None,
                                      reliable_qos(None))      # keep-all, never spun
    rep = spawn(CLI + ['replay', tmp_path / 'bag', '--rate', 'max', '--no-clock', '--wait', '60',
                       '--topics', '/joint_states'])
    assert rep.wait(timeout=2 * DEADLINE) == 2, rep.describe()
    m = re.search(r'/joint_states: publishing failed after (\d+) messages .* a subscriber has '
                  r'stopped taking messages', rep.stderr)
    assert m and 0 < int(m.group(1)) < n, rep.describe()
    assert 'replayed' not in rep.stdout


def _sim_stream(ros_node, js_pub, clock_pub, phases):
    """
    Publish ``/clock`` then a JointState stamped with it, step by step; return the times.

    ``phases``: ``(steps, sim dt, wall period)``; the clock runs faster or slower
    than wall time as a lockstep simulator's does.
    """
    from rosgraph_msgs.msg import Clock
    sim, stamps = 50_000_000_000, []
    t_next = time.perf_counter()
    for steps, dt, period in phases:
        for _ in range(steps):
            sim += int(round(dt * 1e9))
            clock = Clock()
            clock.clock.sec, clock.clock.nanosec = divmod(sim, 1_000_000_000)
            clock_pub.publish(clock)
            m = _joint_state(len(stamps))
            m.header.stamp = clock.clock
            js_pub.publish(m)
            stamps.append(sim)
            t_next += period
            while time.perf_counter() < t_next:
                pass
    from rclpy.duration import Duration
    assert js_pub.wait_for_all_acked(Duration(seconds=DEADLINE))
    assert clock_pub.wait_for_all_acked(Duration(seconds=DEADLINE))
    return np.array(stamps)


@pytest.mark.slow
def test_record_sim_time_logs_clock_times_and_replay_spans_sim_time(ros_node, spawn, tmp_path):
    from rosbags.highlevel import AnyReader
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import JointState

    out = tmp_path / 'rec'
    rec = spawn(CLI + ['record', out, '--use-sim-time', '--topics', '/joint_states', '/clock'])
    assert rec.wait_for('log times from /clock'), rec.describe()
    js = ros_node.node.create_publisher(JointState, '/joint_states', reliable_qos(None))
    clock = ros_node.node.create_publisher(Clock, '/clock', reliable_qos(None))
    assert ros_node.wait_for_subscribers(js) and ros_node.wait_for_subscribers(clock)
    assert rec.wait_for('/joint_states: 1 publisher matched'), rec.describe()
    assert rec.wait_for('/clock: 1 publisher matched'), rec.describe()
    wall0 = time.monotonic()
    # 1.5 s of sim time in about 0.15 s, then 0.1 s of sim time in about 0.5 s
    stamps = _sim_stream(ros_node, js, clock, [(150, 0.01, 0.001), (100, 0.001, 0.005)])
    wall = time.monotonic() - wall0                 # every message acknowledged by the recorder
    assert rec.stop() == 0, rec.describe()
    n = len(stamps)
    assert f'recorded {2 * n} messages (/joint_states: {n}, /clock: {n})' in rec.stdout, \
        rec.describe()

    with AnyReader([out]) as reader:
        rows = [(c.topic, t, reader.deserialize(raw, c.msgtype)) for c, t, raw in
                reader.messages()]
    js_log = np.array([t for topic, t, _ in rows if topic == '/joint_states'])
    js_stamp = np.array([m.header.stamp.sec * 10**9 + m.header.stamp.nanosec
                         for topic, _, m in rows if topic == '/joint_states'])
    clock_log = np.array([t for topic, t, _ in rows if topic == '/clock'])
    clock_val = np.array([m.clock.sec * 10**9 + m.clock.nanosec
                          for topic, _, m in rows if topic == '/clock'])
    np.testing.assert_array_equal(js_stamp, stamps)
    np.testing.assert_array_equal(js_log, stamps)                # the /clock time, exactly
    np.testing.assert_array_equal(clock_log, stamps)
    np.testing.assert_array_equal(clock_val, stamps)
    assert np.all(np.diff([t for _, t, _ in rows]) >= 0)
    span = (js_log[-1] - js_log[0]) * 1e-9
    assert span == pytest.approx(1.599 - 0.0, abs=0.011)        # sim time, not wall time
    if MCAP_CLI.exists():
        res = subprocess.run([str(MCAP_CLI), 'doctor', '--strict-message-order',
                              str(next(out.glob('*.mcap')))], capture_output=True, text=True)
        assert res.returncode == 0, res.stdout + res.stderr

    # replay follows log times: it spans the recording's sim time, not its wall time
    col = _Collector(ros_node.node, ['/joint_states'])
    rep = spawn(CLI + ['replay', out, '--rate', '1', '--wait', '60', '--no-clock', '--topics',
                       '/joint_states'])
    assert ros_node.spin_until(lambda: rep.popen.poll() is not None and
                               col.has({'/joint_states': n})), rep.describe()
    assert rep.wait() == 0, rep.describe()
    got = col.got['/joint_states']
    assert [m.position[0] for m in got] == list(range(n))
    sent = np.array(col.sent['/joint_states'])
    replay_span = sent[-1] - sent[0]
    assert replay_span > 0.9 * span, (replay_span, span, wall)
    # the fast sim phase (1.5 s of sim time published in about 0.15 s) replays over 1.5 s or
    # more; the slow one (0.1 s of sim time published over 0.5 s or more) in about 0.1 s:
    # replay follows the log (sim) times, so the order of the two is the reverse of the wall
    # time's (how closely it keeps them: bench_nodes.py)
    fast, slow = sent[149] - sent[0], sent[-1] - sent[150]
    assert fast > 0.9 * (stamps[149] - stamps[0]) * 1e-9, (fast, slow, wall)
    assert slow < fast, (fast, slow, wall)


def test_record_metadata_has_ros_distro_and_offered_qos(ros_node, spawn, ros_env, tmp_path):
    from mcap.reader import make_reader
    from rclpy.duration import Duration
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    from rosbags.highlevel import AnyReader
    from rosbags.interfaces import QosDurability, QosReliability
    from ruamel.yaml import YAML
    from sensor_msgs.msg import JointState, Temperature

    out = tmp_path / 'rec'
    env = dict(ros_env)
    env.pop('ROS_DISTRO', None)                                 # default: jazzy
    rec = spawn(CLI + ['record', out, '--topics', '/joint_states', '/joint_temperature'],
                env=env)
    assert rec.wait_for('recording'), rec.describe()
    qos = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=50,
                     reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     deadline=Duration(seconds=2, nanoseconds=500), lifespan=Duration(seconds=7))
    js = ros_node.node.create_publisher(JointState, '/joint_states', qos)
    tp = ros_node.node.create_publisher(Temperature, '/joint_temperature', reliable_qos())
    assert ros_node.wait_for_subscribers(js) and ros_node.wait_for_subscribers(tp)
    assert rec.wait_for('/joint_states: 1 publisher matched'), rec.describe()
    assert rec.wait_for('/joint_temperature: 1 publisher matched'), rec.describe()
    temp = Temperature()
    temp.header.stamp.sec, temp.temperature = 100, 30.0
    _publish(ros_node, tp, [temp])
    _publish(ros_node, js, [_joint_state(i) for i in range(20)], rate=500.0)
    assert rec.stop() == 0, rec.describe()
    assert 'recorded 21 messages (/joint_states: 20, /joint_temperature: 1)' in rec.stdout

    info = YAML(typ='safe').load((out / 'metadata.yaml').read_text())[
        'rosbag2_bagfile_information']
    assert info['ros_distro'] == 'jazzy' and info['version'] == 9
    topics = {t['topic_metadata']['name']: t['topic_metadata']
              for t in info['topics_with_message_count']}
    infinite = {'sec': 9223372036, 'nsec': 854775807}
    assert topics['/joint_states']['offered_qos_profiles'] == [{
        'history': 'unknown', 'depth': 0,              # DDS discovery does not carry these
        'reliability': 'reliable', 'durability': 'transient_local',
        'deadline': {'sec': 2, 'nsec': 500}, 'lifespan': {'sec': 7, 'nsec': 0},
        'liveliness': 'automatic', 'liveliness_lease_duration': infinite,
        'avoid_ros_namespace_conventions': False}]
    (temp_qos,) = topics['/joint_temperature']['offered_qos_profiles']
    assert temp_qos['durability'] == 'volatile' and temp_qos['deadline'] == infinite

    with AnyReader([out]) as reader:
        (conn,) = [c for c in reader.connections if c.topic == '/joint_states']
        (profile,) = conn.ext.offered_qos_profiles
        assert profile.reliability == QosReliability.RELIABLE
        assert profile.durability == QosDurability.TRANSIENT_LOCAL
        assert profile.deadline.sec == 2 and profile.deadline.nsec == 500
        msgs = [reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages([conn])]
    assert [m.position[0] for m in msgs] == list(range(20))
    assert np.array_equal(read_recording(out).joint_states.q, np.arange(20.0))

    with open(next(out.glob('*.mcap')), 'rb') as fh:
        reader = make_reader(fh)
        channels = {c.topic: c.metadata for c in reader.get_summary().channels.values()}
        (meta,) = [m.metadata for m in reader.iter_metadata() if m.name == 'rosbag2']
    assert 'transient_local' in channels['/joint_states']['offered_qos_profiles']
    assert meta['ROS_DISTRO'] == 'jazzy'
    assert 'ros_distro: jazzy' in meta['serialized_metadata']
    assert 'transient_local' in meta['serialized_metadata']
