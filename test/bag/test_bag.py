# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Reading and writing recordings (friction_joint.bag.reader): offline, no ROS processes."""
import os
from pathlib import Path
import shutil

from friction_joint.bag import _cdr as bagmod
from friction_joint.bag import (iter_messages, JointStates, read_recording, Recording,
                                recording_topics, write_recording, zero_order_hold)
from friction_joint.exceptions import FrictionJointError, RecordingError
import numpy as np
import pytest
import sourcetree


def _topics(n=2000, rate=1000.0, t0=5.0, seed=0):
    rng = np.random.default_rng(seed)
    t = t0 + np.arange(n) / rate
    nt = max(2, int(n / rate) + 1)
    return {
        '/joint_states': {'t': t, 'q': rng.normal(size=n), 'qd': rng.normal(size=n),
                          'effort': rng.normal(size=n), 't_recv': t + 2e-4},
        '/joint_temperature': {'t': t0 + np.arange(nt), 'xi': 25.0 + 0.5 * np.arange(nt),
                               'variance': 0.01},
        '/link_torque': {'t': t, 'tau': np.sin(t)},
        '/joint_command': {'t': t, 'effort': np.cos(t), 'q_d': np.sin(t)},
        '/external_torque': {'t': t[::2], 'effort': rng.normal(size=len(t[::2]))},
        '/clock': {'t': t},
    }


def _mcap_file(path):
    return next(Path(path).glob('*.mcap'))


def _write_messages(path, messages):
    """Low-level bag: ``messages`` = [(topic, msgtype, bag_time_ns, make(T) -> message)]."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        conns = {}
        for topic, msgtype, stamp, make in messages:
            if topic not in conns:
                conns[topic] = w.add_connection(topic, msgtype, typestore=ts)
            w.write(conns[topic], stamp, ts.serialize_cdr(make(ts.types), msgtype))
    return path


def _header(T, ns, frame=''):
    return T['std_msgs/msg/Header'](
        stamp=T['builtin_interfaces/msg/Time'](sec=ns // 10**9, nanosec=ns % 10**9),
        frame_id=frame)


def _js(names, pos, ns, frame=''):
    def make(T):
        k = len(pos)
        return T['sensor_msgs/msg/JointState'](
            header=_header(T, ns, frame), name=list(names), position=np.array(pos, float),
            velocity=np.full(k, 0.5), effort=np.full(k, -1.0))
    return make


def _temp(xi, ns):
    def make(T):
        return T['sensor_msgs/msg/Temperature'](header=_header(T, ns), temperature=xi,
                                                variance=0.0)
    return make


# --------------------------------------------------------------------------- round trips

def test_round_trip_directory(tmp_path):
    topics = _topics()
    out = write_recording(tmp_path / 'rec', topics)
    assert out == str(tmp_path / 'rec')
    assert (tmp_path / 'rec' / 'metadata.yaml').exists()
    assert [p.name for p in tmp_path.iterdir()] == ['rec']      # no temporary left
    rec = read_recording(tmp_path / 'rec')
    js = topics['/joint_states']
    assert rec.joint_name == 'joint'
    np.testing.assert_array_equal(rec.joint_states.q, js['q'])
    np.testing.assert_array_equal(rec.joint_states.qd, js['qd'])
    np.testing.assert_array_equal(rec.joint_states.effort, js['effort'])
    np.testing.assert_allclose(rec.joint_states.t, js['t'], atol=1e-9)
    np.testing.assert_allclose(rec.joint_states.t_recv, js['t_recv'], atol=1e-9)
    np.testing.assert_array_equal(rec.temperature.xi, topics['/joint_temperature']['xi'])
    np.testing.assert_array_equal(rec.temperature.variance, 0.01)
    np.testing.assert_array_equal(rec.link_torque.tau, topics['/link_torque']['tau'])
    np.testing.assert_array_equal(rec.joint_command.effort, topics['/joint_command']['effort'])
    np.testing.assert_array_equal(rec.joint_command.q_d, topics['/joint_command']['q_d'])
    assert np.isnan(rec.joint_command.qd_d).all()          # no velocity reference
    np.testing.assert_array_equal(rec.external_torque.effort,
                                  topics['/external_torque']['effort'])
    assert rec.topics['/clock'] == ('rosgraph_msgs/msg/Clock', 2000)
    assert rec.t0 == pytest.approx(5.0) and rec.duration == pytest.approx(1.999)
    s = rec.summary()
    assert s['topics']['/joint_states']['count'] == 2000
    assert s['topics']['/joint_states']['rate'] == pytest.approx(1000.0)
    assert s['topics']['/external_torque']['rate'] == pytest.approx(500.0)
    assert s['other_topics'] == {'/clock': {'type': 'rosgraph_msgs/msg/Clock', 'count': 2000}}
    assert '/joint_states: 2000 messages, 1000.0 Hz' in str(rec)


def test_bag_messages_in_receive_time_order(tmp_path):
    write_recording(tmp_path / 'rec', _topics(n=300))
    stamps = [s for _, _, s, _ in iter_messages(tmp_path / 'rec')]
    assert stamps == sorted(stamps) and len(stamps) == 300 * 4 + 150 + 2
    only = list(iter_messages(tmp_path / 'rec', topics=['/joint_temperature']))
    assert [m[:2] for m in only] == [('/joint_temperature', 'sensor_msgs/msg/Temperature')] * 2
    with pytest.raises(RecordingError, match='/nope'):
        list(iter_messages(tmp_path / 'rec', topics=['/nope']))


def test_single_mcap_file_and_recording_round_trip(tmp_path):
    topics = _topics(n=500)
    write_recording(tmp_path / 'one.mcap', topics)
    assert (tmp_path / 'one.mcap').is_file()
    assert sorted(os.listdir(tmp_path)) == ['one.mcap']
    rec = read_recording(tmp_path / 'one.mcap')
    np.testing.assert_array_equal(rec.joint_states.q, topics['/joint_states']['q'])
    assert recording_topics(tmp_path / 'one.mcap')['/joint_states'] == \
        ('sensor_msgs/msg/JointState', 500)
    # a Recording is valid input to write_recording: everything survives a second trip
    write_recording(tmp_path / 'again', rec)
    rec2 = read_recording(tmp_path / 'again')
    for name, series in rec.series().items():
        other = rec2.series()[name]
        for f in ('t', 't_recv'):
            np.testing.assert_array_equal(getattr(other, f), getattr(series, f))
    np.testing.assert_array_equal(rec2.joint_command.qd_d, rec.joint_command.qd_d)


def test_readable_by_anyreader_and_mcap(tmp_path):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rosbags.highlevel import AnyReader

    topics = _topics(n=50)
    write_recording(tmp_path / 'rec', topics)
    with AnyReader([tmp_path / 'rec']) as reader:
        conns = [c for c in reader.connections if c.topic == '/link_torque']
        taus = [reader.deserialize(raw, c.msgtype).wrench.torque.z
                for c, _, raw in reader.messages(connections=conns)]
    np.testing.assert_array_equal(taus, topics['/link_torque']['tau'])
    with open(_mcap_file(tmp_path / 'rec'), 'rb') as fh:
        msgs = [(ch.topic, m) for _, ch, _, m in make_reader(
            fh, decoder_factories=[DecoderFactory()]).iter_decoded_messages()]
    pos = [m.position[0] for topic, m in msgs if topic == '/joint_states']
    np.testing.assert_array_equal(pos, topics['/joint_states']['q'])


def test_joint_picked_by_name_among_several(tmp_path):
    n = 100
    t = np.arange(n) * 1e-3
    q = np.stack([t, 10 + t, 20 + t], axis=1)
    write_recording(tmp_path / 'rec', {
        '/joint_states': {'t': t, 'q': q, 'qd': np.ones_like(q), 'effort': 2 * q,
                          'name': ['a', 'joint', 'b']},
        '/joint_temperature': {'t': [0.0], 'xi': [30.0]},
        '/external_torque': {'t': t, 'effort': q[:, ::-1], 'name': ['b', 'joint', 'a']}})
    rec = read_recording(tmp_path / 'rec', joint_name='joint')
    np.testing.assert_array_equal(rec.joint_states.q, q[:, 1])
    np.testing.assert_array_equal(rec.joint_states.qd, np.ones(n))
    np.testing.assert_array_equal(rec.joint_states.effort, 2 * q[:, 1])
    np.testing.assert_array_equal(rec.external_torque.effort, q[:, 1])
    rec_b = read_recording(tmp_path / 'rec', joint_name='b')
    np.testing.assert_array_equal(rec_b.joint_states.q, q[:, 2])
    np.testing.assert_array_equal(rec_b.external_torque.effort, q[:, 2])
    assert read_recording(tmp_path / 'rec').joint_name == 'a'     # default: first name
    with pytest.raises(RecordingError, match="no /joint_states message names joint 'c'"):
        read_recording(tmp_path / 'rec', joint_name='c')


def test_varying_layouts_skipped_messages_and_order(tmp_path):
    ms = 1_000_000
    js, tp = 'sensor_msgs/msg/JointState', 'sensor_msgs/msg/Temperature'
    msgs = [('/joint_states', js, 1 * ms, _js(['joint'], [1.0], 1 * ms)),
            ('/joint_states', js, 2 * ms, _js(['x', 'joint'], [9.0, 2.0], 2 * ms, 'base')),
            ('/joint_states', js, 3 * ms, _js(['x'], [9.0], 3 * ms)),            # skipped
            ('/joint_states', js, 4 * ms, _js(['joint', 'x'], [4.0, 9.0], 5 * ms)),
            ('/joint_states', js, 5 * ms, _js(['joint'], [3.0], 4 * ms)),       # stamp earlier
            ('/joint_states', js, 6 * ms, _js([], [6.0], 6 * ms)),              # anonymous
            ('/joint_temperature', tp, 6 * ms, _temp(40.0, 2 * ms))]
    _write_messages(tmp_path / 'rec', msgs)
    rec = read_recording(tmp_path / 'rec', joint_name='joint')
    np.testing.assert_array_equal(rec.joint_states.q, [1.0, 2.0, 3.0, 4.0, 6.0])
    np.testing.assert_allclose(rec.joint_states.t, [1e-3, 2e-3, 4e-3, 5e-3, 6e-3])
    np.testing.assert_allclose(rec.joint_states.t_recv, [1e-3, 2e-3, 5e-3, 4e-3, 6e-3])
    np.testing.assert_array_equal(rec.joint_states.qd, 0.5)
    assert rec.joint_states.skipped == 1
    assert rec.unordered == {'/joint_states': 1}
    assert rec.summary()['topics']['/joint_states']['skipped'] == 1


def test_many_layouts_decode_one_by_one(tmp_path, monkeypatch):
    monkeypatch.setattr(bagmod, 'MAX_LAYOUTS', 3)
    monkeypatch.setattr(bagmod, 'DECODE_BLOCK', 7)
    js = 'sensor_msgs/msg/JointState'
    msgs = [('/joint_states', js, i, _js(['joint'], [float(i)], i, 'f' * (i % 5)))
            for i in range(1, 40)]
    msgs.append(('/joint_temperature', 'sensor_msgs/msg/Temperature', 50, _temp(1.0, 50)))
    _write_messages(tmp_path / 'rec', msgs)
    rec = read_recording(tmp_path / 'rec')
    np.testing.assert_array_equal(rec.joint_states.q, np.arange(1, 40))


def test_zero_order_hold():
    rec_t = np.array([1.0, 2.0, 3.0])
    np.testing.assert_array_equal(zero_order_hold(rec_t, [10, 20, 30], [0.5, 1.0, 1.9, 2.0, 9]),
                                  [10, 10, 10, 20, 30])
    with pytest.raises(RecordingError):
        zero_order_hold([], [], [1.0])


def test_temperature_on_joint_state_times(tmp_path):
    t = np.arange(0, 3, 0.25)
    write_recording(tmp_path / 'rec', {
        '/joint_states': {'t': t + 10, 'q': t, 'qd': t, 'effort': t},
        '/joint_temperature': {'t': [10.5, 11.5, 12.5], 'xi': [20.0, 21.0, 22.0]}})
    rec = read_recording(tmp_path / 'rec')
    np.testing.assert_array_equal(rec.temperature_at(),
                                  [20, 20, 20, 20, 20, 20, 21, 21, 21, 21, 22, 22])
    assert rec.temperature_at(t=[100.0]) == [22.0]


# --------------------------------------------------------------------------- bad input

def _bad(path, match, **kw):
    with pytest.raises(RecordingError, match=match) as info:
        read_recording(path, **kw)
    assert isinstance(info.value, FrictionJointError)
    return str(info.value)


def test_missing_path_and_not_a_bag(tmp_path):
    _bad(tmp_path / 'nothing', 'does not exist')
    (tmp_path / 'empty').mkdir()
    _bad(tmp_path / 'empty', 'not a rosbag2 recording: no metadata.yaml')
    (tmp_path / 'notes.txt').write_text('hello')
    _bad(tmp_path / 'notes.txt', 'not a recording')
    (tmp_path / 'fake.mcap').write_bytes(b'this is not an mcap file at all' * 10)
    _bad(tmp_path / 'fake.mcap', 'truncated or corrupt')
    (tmp_path / 'zero.mcap').write_bytes(b'')
    _bad(tmp_path / 'zero.mcap', 'truncated or corrupt')


@pytest.mark.parametrize('fraction', [0.5, 0.99])
def test_truncated_file(tmp_path, fraction):
    write_recording(tmp_path / 'rec', _topics(n=3000))
    write_recording(tmp_path / 'one.mcap', _topics(n=3000))
    for path in (_mcap_file(tmp_path / 'rec'), tmp_path / 'one.mcap'):
        with open(path, 'r+b') as fh:
            fh.truncate(int(os.path.getsize(path) * fraction))
    _bad(tmp_path / 'rec', 'truncated or corrupt')
    _bad(tmp_path / 'one.mcap', 'truncated or corrupt')


@pytest.mark.parametrize('offset', [8, 100])      # first record header; inside first chunk
def test_corrupt_structure(tmp_path, offset):
    write_recording(tmp_path / 'rec', _topics(n=3000))
    path = _mcap_file(tmp_path / 'rec')
    with open(path, 'r+b') as fh:
        fh.seek(offset)
        fh.write(b'\xff' * 16)
    _bad(tmp_path / 'rec', 'truncated or corrupt')
    shutil.rmtree(tmp_path / 'rec')
    write_recording(tmp_path / 'rec', _topics(n=300))
    os.remove(_mcap_file(tmp_path / 'rec'))            # metadata without its data file
    _bad(tmp_path / 'rec', 'truncated or corrupt')


def test_missing_required_topics(tmp_path):
    topics = _topics(n=100)
    write_recording(tmp_path / 'b', {'/joint_temperature': topics['/joint_temperature']})
    msg = _bad(tmp_path / 'b', 'no /joint_states topic')
    assert '/joint_temperature' in msg             # lists what is there
    empty = dict(topics, **{'/joint_states': {'t': [], 'q': [], 'qd': [], 'effort': []}})
    write_recording(tmp_path / 'c', empty)
    _bad(tmp_path / 'c', '/joint_states has no messages')


@pytest.mark.parametrize('how', ['absent', 'empty'])
def test_temperature_is_optional(tmp_path, how):
    """No /joint_temperature (or no message on it): read, with ``temperature`` None."""
    topics = _topics(n=100)
    if how == 'absent':
        del topics['/joint_temperature']
    else:
        topics['/joint_temperature'] = {'t': [], 'xi': []}
    write_recording(tmp_path / 'a', topics)
    rec = read_recording(tmp_path / 'a')
    assert rec.temperature is None
    assert len(rec.joint_states) == 100 and rec.link_torque is not None
    assert '/joint_temperature' not in rec.series()
    assert '/joint_temperature' not in rec.summary()['topics']
    with pytest.raises(RecordingError, match='no /joint_temperature topic'):
        rec.temperature_at()
    write_recording(tmp_path / 'copy', rec)            # round trip without the topic
    assert read_recording(tmp_path / 'copy').temperature is None


def test_nan_named_by_topic_and_count(tmp_path):
    topics = _topics(n=100)
    topics['/joint_states']['qd'][[3, 7]] = np.nan
    topics['/joint_states']['effort'][5] = np.inf
    write_recording(tmp_path / 'a', topics)
    msg = _bad(tmp_path / 'a', '/joint_states: 3 NaN/inf values')
    assert 'qd 2' in msg and 'effort 1' in msg
    topics = _topics(n=100)
    topics['/joint_temperature']['xi'] = np.full(1, np.nan)
    topics['/joint_temperature']['t'] = [5.0]
    write_recording(tmp_path / 'b', topics)
    _bad(tmp_path / 'b', '/joint_temperature: 1 NaN/inf values')
    topics = _topics(n=100)
    topics['/link_torque']['tau'][0] = np.nan
    write_recording(tmp_path / 'c', topics)
    _bad(tmp_path / 'c', '/link_torque: 1 NaN/inf')


def test_wrong_message_type(tmp_path):
    ms = 1_000_000
    msgs = [('/joint_states', 'sensor_msgs/msg/JointState', ms, _js(['joint'], [1.0], ms)),
            ('/joint_temperature', 'std_msgs/msg/Float64', ms,
             lambda T: T['std_msgs/msg/Float64'](data=25.0))]
    _write_messages(tmp_path / 'rec', msgs)
    _bad(tmp_path / 'rec', '/joint_temperature has message type std_msgs/msg/Float64, '
                           'expected sensor_msgs/msg/Temperature')


def test_joint_states_lacking_a_field(tmp_path):
    ms = 1_000_000

    def no_velocity(T):
        return T['sensor_msgs/msg/JointState'](
            header=_header(T, ms), name=['joint'], position=np.array([1.0]),
            velocity=np.zeros(0), effort=np.array([1.0]))
    _write_messages(tmp_path / 'rec', [
        ('/joint_states', 'sensor_msgs/msg/JointState', ms, no_velocity),
        ('/joint_temperature', 'sensor_msgs/msg/Temperature', ms, _temp(1.0, ms))])
    _bad(tmp_path / 'rec', '/joint_states: 1 messages have no velocity')


def test_write_errors_and_atomicity(tmp_path, monkeypatch):
    topics = _topics(n=50)
    write_recording(tmp_path / 'rec', topics)
    with pytest.raises(RecordingError, match='exists already'):
        write_recording(tmp_path / 'rec', topics)
    with pytest.raises(RecordingError, match='not contract topics'):
        write_recording(tmp_path / 'x', {'/foo': {'t': [0.0]}})
    with pytest.raises(RecordingError, match='unknown field.*position'):
        write_recording(tmp_path / 'x', {'/joint_states': {'t': [0.0], 'position': [1.0]}})
    with pytest.raises(RecordingError, match='missing field.*qd'):
        write_recording(tmp_path / 'x', {'/joint_states': {'t': [0.0], 'q': [1.0],
                                                           'effort': [1]}})
    with pytest.raises(RecordingError, match='q has shape'):
        write_recording(tmp_path / 'x', {'/joint_states': {'t': [0.0, 1.0], 'q': [1.0],
                                                           'qd': [1, 2], 'effort': [1, 2]}})
    with pytest.raises(RecordingError, match='finite times'):
        write_recording(tmp_path / 'x', {'/joint_temperature': {'t': [-1.0], 'xi': [1.0]}})
    # a failure half way leaves neither the target nor a temporary directory
    from friction_joint.bag.mcap_stream import McapStream

    def failing_add(self, groups, which):
        raise OSError('disk full')
    monkeypatch.setattr(McapStream, 'add_messages', failing_add)
    before = sorted(os.listdir(tmp_path))
    with pytest.raises(OSError, match='disk full'):
        write_recording(tmp_path / 'half', topics)
    assert sorted(os.listdir(tmp_path)) == before


def test_dataclass_input(tmp_path):
    t = np.arange(10) * 0.1
    js = JointStates(t=t, t_recv=t, q=t, qd=t, effort=t)
    write_recording(tmp_path / 'rec', {'/joint_states': js,
                                       '/joint_temperature': {'t': [0.0], 'xi': [1.0]}},
                    joint_name='j2')
    rec = read_recording(tmp_path / 'rec')
    assert isinstance(rec, Recording) and rec.joint_name == 'j2'
    np.testing.assert_array_equal(rec.joint_states.q, t)


# --------------------------------------------------------------------------- rosbag2 metadata

MCAP_CLI = Path(sourcetree.MCAP_CLI)
SAMPLE = Path(__file__).resolve().parents[2] / 'bags' / 'csd25_sample'


def _mcap_doctor(path):
    import subprocess
    if MCAP_CLI.exists():
        res = subprocess.run([str(MCAP_CLI), 'doctor', '--strict-message-order', str(path)],
                             capture_output=True, text=True, timeout=120)
        assert res.returncode == 0, res.stdout + res.stderr


def test_seal_rosbag2_writes_distro_and_offered_qos(tmp_path):
    from mcap.reader import make_reader
    from rosbags.highlevel import AnyReader
    from rosbags.interfaces import QosDurability, QosHistory
    from ruamel.yaml import YAML

    from friction_joint.bag.checksums import seal_rosbag2, verify_checksums

    topics = _topics(n=300)
    write_recording(tmp_path / 'rec', topics)
    profile = {'history': 'keep_last', 'depth': 10, 'reliability': 'reliable',
               'durability': 'transient_local', 'deadline': {'sec': 1, 'nsec': 5},
               'lifespan': {'sec': 0, 'nsec': 0}, 'liveliness': 'automatic',
               'liveliness_lease_duration': {'sec': 0, 'nsec': 0},
               'avoid_ros_namespace_conventions': False}
    seal_rosbag2(tmp_path / 'rec', ros_distro='jazzy',
                 offered_qos={'/joint_states': [profile]})
    info = YAML(typ='safe').load((tmp_path / 'rec' / 'metadata.yaml').read_text())[
        'rosbag2_bagfile_information']
    assert info['ros_distro'] == 'jazzy'
    qos = {t['topic_metadata']['name']: t['topic_metadata']['offered_qos_profiles']
           for t in info['topics_with_message_count']}
    assert qos['/joint_states'] == [profile] and qos['/link_torque'] == []
    with AnyReader([tmp_path / 'rec']) as reader:
        (conn,) = [c for c in reader.connections if c.topic == '/joint_states']
        (got,) = conn.ext.offered_qos_profiles
        assert got.history == QosHistory.KEEP_LAST and got.depth == 10
        assert got.durability == QosDurability.TRANSIENT_LOCAL and got.deadline.nsec == 5
        assert sum(1 for _ in reader.messages([conn])) == 300
    mcap = _mcap_file(tmp_path / 'rec')
    verify_checksums(mcap)
    with open(mcap, 'rb') as fh:
        reader = make_reader(fh)
        channels = {c.topic: c.metadata for c in reader.get_summary().channels.values()}
        (meta,) = list(reader.iter_metadata())
    assert 'transient_local' in channels['/joint_states']['offered_qos_profiles']
    assert meta.name == 'rosbag2' and meta.metadata['ROS_DISTRO'] == 'jazzy'
    assert 'ros_distro: jazzy' in meta.metadata['serialized_metadata']
    rec = read_recording(tmp_path / 'rec')
    np.testing.assert_array_equal(rec.joint_states.q, topics['/joint_states']['q'])
    _mcap_doctor(mcap)


def _chunk_compressions(path):
    from mcap.reader import make_reader
    with open(path, 'rb') as fh:
        summary = make_reader(fh).get_summary()
    return {c.compression for c in summary.chunk_indexes}


def test_shipped_sample_is_plain_mcap_with_zstd_chunks_and_crcs():
    from ruamel.yaml import YAML

    from friction_joint.bag.checksums import verify_checksums

    files = sorted(p.name for p in SAMPLE.iterdir())
    assert files == ['csd25_sample.mcap', 'metadata.yaml']
    mcap = SAMPLE / 'csd25_sample.mcap'
    assert mcap.stat().st_size < 5_000_000
    with open(mcap, 'rb') as fh:
        assert fh.read(8) == b'\x89MCAP0\r\n'                   # not whole-file compressed
    assert _chunk_compressions(mcap) == {'zstd'}
    verify_checksums(mcap)
    info = YAML(typ='safe').load((SAMPLE / 'metadata.yaml').read_text())[
        'rosbag2_bagfile_information']
    assert info['compression_mode'] == '' and info['compression_format'] == ''
    assert info['relative_file_paths'] == ['csd25_sample.mcap']
    assert info['ros_distro'] == 'jazzy' and info['message_count'] == 90783
    _mcap_doctor(mcap)


def test_simulated_compressed_recording_has_the_sample_layout(tmp_path):
    from friction_joint import load_gear
    from friction_joint.experiments.hidden import RecordingOptions, simulate_recording

    base = load_gear(Path(__file__).resolve().parents[2] / 'config' / 'csd25_base.yaml')
    simulate_recording(base, tmp_path / 'sim', options=RecordingOptions(
        duration=4.0, seed=5, n_segments=2, link_torque=False, compress=True))
    assert sorted(p.name for p in (tmp_path / 'sim').iterdir()) == ['metadata.yaml',
                                                                    'sim.mcap']
    assert _chunk_compressions(tmp_path / 'sim' / 'sim.mcap') == {'zstd'}
    text = (tmp_path / 'sim' / 'metadata.yaml').read_text()
    assert 'ros_distro: jazzy' in text and 'compression_mode: file' not in text
    rec = read_recording(tmp_path / 'sim', joint_name=base.joint_name)
    assert rec.duration > 3.0 and rec.unordered == {}
