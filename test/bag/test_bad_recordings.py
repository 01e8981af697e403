# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Corrupt recordings are rejected by name; odd but valid ones (gaps, late messages) are read.

Time stamps (header stamps per topic), physically absurd values, bit flips (checksums)
and the joint name.  Small synthetic recordings, no ROS processes.
"""
import os
from pathlib import Path
import re
import subprocess

from friction_joint.bag import read_recording, write_recording
from friction_joint.exceptions import RecordingError
import numpy as np
import pytest
import sourcetree

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / 'bags' / 'csd25_sample'
MCAP_CLI = Path(sourcetree.MCAP_CLI)


def _smooth(n=3000, rate=1000.0, t0=2.0, seed=0):
    """Topics of a plausible 1 kHz joint: a sine motion with noise, temperature at 4 Hz."""
    rng = np.random.default_rng(seed)
    t = t0 + np.arange(n) / rate
    q = 0.8 * np.sin(1.3 * t)
    qd = 0.8 * 1.3 * np.cos(1.3 * t) + 1e-3 * rng.normal(size=n)
    effort = 2.0 * np.tanh(qd / 0.01) + 0.5 * qd + 0.01 * rng.normal(size=n)
    tt = np.arange(t0, t[-1], 0.25)
    return {
        '/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
        '/joint_temperature': {'t': tt, 'xi': 30.0 + 0.01 * np.arange(len(tt))},
        '/link_torque': {'t': t, 'tau': 3.0 * np.sin(q)},
    }


def _bad(path, *words, **kw):
    """read_recording raises RecordingError naming ``path`` and every word (regex)."""
    with pytest.raises(RecordingError) as info:
        read_recording(path, **kw)
    msg = str(info.value)
    assert str(path) in msg, f'the error does not name the file: {msg}'
    for w in words:
        assert re.search(w, msg), f'{w!r} not in: {msg}'
    assert '\n' not in msg
    return msg


# --------------------------------------------------------------------------- time stamps

def test_reversed_stretch_of_stamps_is_an_error(tmp_path):
    topics = _smooth()
    js = topics['/joint_states']
    js['t_recv'] = js['t'].copy()                  # bag (receive) order stays forward
    w = (js['t'] >= 3.0) & (js['t'] < 3.5)         # header stamps reversed over 0.5 s
    js['t'][w] = js['t'][w][::-1]
    write_recording(tmp_path / 'rec', topics)
    msg = _bad(tmp_path / 'rec', '/joint_states', 'backwards', r'message 100[0-9]',
               r't = 3\.')
    assert 'reversed' in msg


def test_overlapping_runs_are_an_error(tmp_path):
    """Two runs glued with overlapping time bases: the second restarts 0.4 s back."""
    a, b = _smooth(n=1500, seed=1), _smooth(n=1500, t0=3.1, seed=2)
    topics = {k: {f: np.concatenate([a[k][f], b[k][f]]) for f in a[k]} for k in a}
    js = topics['/joint_states']
    js['t_recv'] = 2.0 + np.arange(len(js['t'])) * 1e-3
    for k in ('/joint_temperature', '/link_torque'):
        topics[k] = a[k]
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_states', 'overlap', r'message 1500', r't = 3\.1')


def test_same_stamp_with_other_values_is_an_error(tmp_path):
    topics = _smooth()
    topics['/joint_states']['t'][2000] = topics['/joint_states']['t'][1999]
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_states', 'same (header )?stamp', r'message 2000',
         r't = 3\.999')


def test_identical_duplicates_are_dropped_and_counted(tmp_path):
    """A message sent twice (lockstep resend: same stamp, same bytes) is read once."""
    topics = _smooth()
    idx = np.r_[np.arange(10), 9, 9, np.arange(10, 3000)]
    topics['/joint_states'] = {k: v[idx] for k, v in topics['/joint_states'].items()}
    write_recording(tmp_path / 'rec', topics)
    rec = read_recording(tmp_path / 'rec')
    assert len(rec.joint_states) == 3000
    np.testing.assert_array_equal(np.diff(rec.joint_states.t) > 0, True)
    assert rec.duplicates == {'/joint_states': 2}
    assert rec.summary()['topics']['/joint_states']['duplicates'] == 2
    assert 'duplicates 2' in str(rec)


def test_late_delivery_is_sorted_not_rejected(tmp_path):
    """A message delivered 20 ms late (a DDS resend) fills its hole in the stamps."""
    topics = _smooth()
    js = topics['/joint_states']
    recv = js['t'].copy()
    recv[1500] += 0.0205                           # bag order: 1499, 1501..1520, 1500, ...
    js['t_recv'] = recv
    write_recording(tmp_path / 'rec', topics)
    rec = read_recording(tmp_path / 'rec')
    np.testing.assert_allclose(rec.joint_states.t, js['t'], atol=1e-9)
    np.testing.assert_array_equal(rec.joint_states.q, js['q'])
    assert rec.unordered == {'/joint_states': 1}


def test_gaps_and_irregular_sampling_are_read(tmp_path):
    topics = _smooth(n=4000)
    js = topics['/joint_states']
    rng = np.random.default_rng(3)
    js['t'] = js['t'] + rng.uniform(-3e-4, 3e-4, len(js['t']))      # jitter
    js['t'][2000:] += 1.5                                           # a 1.5 s pause
    topics['/link_torque']['t'] = js['t']
    write_recording(tmp_path / 'rec', topics)
    rec = read_recording(tmp_path / 'rec')
    assert len(rec.joint_states) == 4000 and rec.unordered == {} and rec.duplicates == {}


def test_shipped_sample_and_simulator_recordings_read(tmp_path):
    from friction_joint import load_gear
    from friction_joint.experiments.hidden import RecordingOptions, simulate_recording
    rec = read_recording(SAMPLE)
    assert len(rec.joint_states) == 45300 and rec.unordered == {}
    base = load_gear(ROOT / 'config' / 'csd25_base.yaml')
    simulate_recording(base, tmp_path / 'sim', options=RecordingOptions(
        duration=6.0, seed=5, n_segments=2))
    sim = read_recording(tmp_path / 'sim', joint_name=base.joint_name)
    assert sim.duration > 5.0 and sim.unordered == {}


# --------------------------------------------------------------------------- values

def test_one_absurd_effort_is_named_with_its_time(tmp_path):
    topics = _smooth()
    topics['/joint_states']['effort'][1234] = 1e30
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_states', 'effort', r'1e\+30', r't = 3\.234')


def test_velocity_inconsistent_with_the_position_is_named(tmp_path):
    topics = _smooth()
    topics['/joint_states']['qd'][777] = 5e4              # the position moves at ~1 rad/s
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_states', r'\bqd\b|velocity', r't = 2\.777', 'position')


@pytest.mark.parametrize('topic,field', [('/joint_temperature', 'xi'), ('/link_torque', 'tau')])
def test_absurd_values_on_other_topics(tmp_path, topic, field):
    topics = _smooth()
    topics[topic][field][3] = -4e21
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', topic, field, r'-4e\+21')


def test_plausible_extremes_are_accepted(tmp_path):
    """Rest with one quick move, a short torque peak, a quantised constant temperature."""
    n = 20000
    t = np.arange(n) * 1e-3
    rng = np.random.default_rng(4)
    qd = 1e-6 * rng.normal(size=n)
    qd[10000:10015] += 3.0 * np.sin(np.linspace(0, np.pi, 15))      # 15 ms move, 3 rad/s
    q = np.cumsum(qd) * 1e-3
    effort = 1e-3 * rng.normal(size=n)
    effort[15000:15008] += 50.0                                       # 8 ms impact
    xi = np.full(80, 25.0)
    xi[40] = 25.0625                                                  # one sensor step
    write_recording(tmp_path / 'rec', {
        '/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
        '/joint_temperature': {'t': np.arange(80) * 0.25, 'xi': xi}})
    rec = read_recording(tmp_path / 'rec')
    assert rec.joint_states.effort.max() > 49 and rec.joint_states.qd.max() > 2.9


def test_tribometer_data_are_plausible(tmp_path):
    """Real measured data (200 Hz tribometer, see ../shared/real-data) read as they are."""
    src = Path(sourcetree.SHARED, 'real-data', 'tribometer', 'test_data_2.txt')
    if not src.exists():
        pytest.skip('real tribometer data not available')
    d = np.loadtxt(src, skiprows=1)
    t, pos, force = d[:, 0], d[:, 2] * 1e-3, d[:, 3] * 1e-6
    write_recording(tmp_path / 'rec', {
        '/joint_states': {'t': t, 'q': pos, 'qd': np.gradient(pos, t), 'effort': force},
        '/joint_temperature': {'t': t[:1], 'xi': [22.0]},
        '/link_torque': {'t': t, 'tau': d[:, 1] * 1e-6}})
    rec = read_recording(tmp_path / 'rec')
    assert len(rec.joint_states) == len(t)


def test_absurd_values_are_stopped_before_the_plateau_fit(tmp_path):
    """A Recording read without checks (or built by hand) is checked where fits take it."""
    from dataclasses import replace

    from friction_joint import load_gear
    from friction_joint.identification.plateaus import find_plateaus, plateaus_from_arrays
    gear = load_gear(ROOT / 'config' / 'csd25_base.yaml')
    topics = _smooth()
    topics['/joint_states']['effort'][2500] = 3e33
    write_recording(tmp_path / 'rec', topics)
    rec = read_recording(tmp_path / 'rec', check=False)
    with pytest.raises(RecordingError, match=r'/joint_states: implausible effort .*t = 4\.5'):
        find_plateaus(rec, gear)
    js = rec.joint_states
    with pytest.raises(RecordingError, match=r'^bench: implausible effort .*t = 4\.5'):
        plateaus_from_arrays(js.t, js.q, js.qd, js.effort, np.full(len(js), 30.0),
                             np.zeros(len(js)), inertia=0.1, source='bench')
    good = replace(rec, joint_states=replace(js, effort=np.where(js.effort > 1e9, 1.0,
                                                                 js.effort)))
    find_plateaus(good, gear)


# --------------------------------------------------------------------------- checksums

def _chunks_and_data_end(path):
    from mcap.records import Chunk, DataEnd
    from mcap.stream_reader import StreamReader
    with open(path, 'rb') as fh:
        recs = list(StreamReader(fh, skip_magic=False, emit_chunks=True).records)
    return [r for r in recs if isinstance(r, Chunk)], [r for r in recs if isinstance(r, DataEnd)]


def _mcap_of(path):
    path = Path(path)
    return path if path.suffix == '.mcap' else next(path.glob('*.mcap'))


def _rosbags_bag(path, topics):
    """Write a recording as other tools do: rosbags' MCAP writer, chunk CRCs 0."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types
    js, tp = topics['/joint_states'], topics['/joint_temperature']

    def header(t):
        ns = int(round(t * 1e9))
        return T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](
            sec=ns // 10**9, nanosec=ns % 10**9), frame_id='')
    rows = [(tj, 0, i) for i, tj in enumerate(js['t'])] + \
        [(tj, 1, i) for i, tj in enumerate(tp['t'])]
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        c0 = w.add_connection('/joint_states', 'sensor_msgs/msg/JointState', typestore=ts)
        c1 = w.add_connection('/joint_temperature', 'sensor_msgs/msg/Temperature',
                              typestore=ts)
        for tj, k, i in sorted(rows):
            if k == 0:
                msg = T['sensor_msgs/msg/JointState'](
                    header=header(tj), name=['joint'], position=np.array([js['q'][i]]),
                    velocity=np.array([js['qd'][i]]), effort=np.array([js['effort'][i]]))
                w.write(c0, int(round(tj * 1e9)),
                        ts.serialize_cdr(msg, 'sensor_msgs/msg/JointState'))
            else:
                msg = T['sensor_msgs/msg/Temperature'](header=header(tj),
                                                       temperature=tp['xi'][i], variance=0.0)
                w.write(c1, int(round(tj * 1e9)),
                        ts.serialize_cdr(msg, 'sensor_msgs/msg/Temperature'))
    return path


def _flip_bit_of_value(path, value, bit):
    data = bytearray(Path(path).read_bytes())
    raw = np.float64(value).tobytes()
    at = data.find(raw)
    assert at > 0 and data.find(raw, at + 1) < 0
    data[at + bit // 8] ^= 1 << (bit % 8)
    Path(path).write_bytes(bytes(data))


def test_written_recordings_carry_checksums(tmp_path):
    write_recording(tmp_path / 'rec', _smooth())
    write_recording(tmp_path / 'one.mcap', _smooth())
    for path in (tmp_path / 'rec', tmp_path / 'one.mcap'):
        chunks, data_end = _chunks_and_data_end(_mcap_of(path))
        assert chunks and all(c.uncompressed_crc != 0 for c in chunks)
        assert all(c.compression in ('zstd', 'lz4') for c in chunks)
        assert data_end[0].data_section_crc != 0
        read_recording(path)
    assert sorted(os.listdir(tmp_path)) == ['one.mcap', 'rec']
    assert sorted(os.listdir(tmp_path / 'rec')) == ['metadata.yaml', 'rec.mcap']


def test_checksummed_recording_stays_readable_by_other_tools(tmp_path):
    from rosbags.highlevel import AnyReader
    topics = _smooth()
    write_recording(tmp_path / 'rec', topics)
    with AnyReader([tmp_path / 'rec']) as reader:
        conns = [c for c in reader.connections if c.topic == '/joint_states']
        eff = [reader.deserialize(raw, c.msgtype).effort[0]
               for c, _, raw in reader.messages(connections=conns)]
    np.testing.assert_array_equal(eff, topics['/joint_states']['effort'])
    if not MCAP_CLI.exists():
        pytest.skip(f'{MCAP_CLI} not available')
    res = subprocess.run([str(MCAP_CLI), 'doctor', '--strict-message-order',
                          str(tmp_path / 'rec' / 'rec.mcap')], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert 'error' not in res.stderr.lower(), res.stderr


def test_sealing_orders_messages_by_log_time(tmp_path):
    """A recorder writes callbacks' bursts: seal_recording leaves them in log-time order."""
    from friction_joint.bag import seal_recording
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types
    bag = tmp_path / 'rec'
    with Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        c = w.add_connection('/clock', 'rosgraph_msgs/msg/Clock', typestore=ts)
        c2 = w.add_connection('/other', 'rosgraph_msgs/msg/Clock', typestore=ts)
        for k in range(50):                             # bursts of 10, topics interleaved
            for j in range(10):
                ns = (k // 2 * 10 + j) * 1000
                msg = T['rosgraph_msgs/msg/Clock'](clock=T['builtin_interfaces/msg/Time'](
                    sec=0, nanosec=ns))
                w.write(c if k % 2 else c2, ns, ts.serialize_cdr(msg, 'rosgraph_msgs/msg/Clock'))
    seal_recording(bag)
    from mcap.reader import make_reader
    with open(bag / 'rec.mcap', 'rb') as fh:
        reader = make_reader(fh)
        times = [m.log_time for _, _, m in reader.iter_messages(log_time_order=False)]
        meta = [m.name for m in reader.iter_metadata()]
    assert len(times) == 500 and times == sorted(times)
    assert meta == ['rosbag2']
    chunks, data_end = _chunks_and_data_end(bag / 'rec.mcap')
    assert all(ch.uncompressed_crc for ch in chunks) and data_end[0].data_section_crc
    from rosbags.highlevel import AnyReader
    with AnyReader([bag]) as reader:
        assert sum(1 for _ in reader.messages()) == 500
    if MCAP_CLI.exists():
        res = subprocess.run([str(MCAP_CLI), 'doctor', '--strict-message-order',
                              str(bag / 'rec.mcap')], capture_output=True, text=True)
        assert res.returncode == 0 and 'error' not in res.stderr.lower(), res.stderr


@pytest.mark.parametrize('where', [0.3, 0.5, 0.7])
def test_bit_flip_in_a_checksummed_recording_is_detected(tmp_path, where):
    write_recording(tmp_path / 'rec', _smooth())
    path = _mcap_of(tmp_path / 'rec')
    chunks, _ = _chunks_and_data_end(path)
    data = bytearray(path.read_bytes())
    data[int(len(data) * where * 0.8)] ^= 0x10                    # inside the data section
    path.write_bytes(bytes(data))
    _bad(tmp_path / 'rec', 'rec.mcap', r'(?i)checksum|crc|corrupt')


def test_bit_flip_in_a_recording_without_checksums_is_caught_as_absurd(tmp_path):
    """Other tools write CRC 0: the flipped exponent bit shows as an absurd effort."""
    topics = _smooth(n=1500)
    topics['/joint_states']['effort'][700] = 2.107092534866288
    _rosbags_bag(tmp_path / 'rec', topics)
    chunks, data_end = _chunks_and_data_end(_mcap_of(tmp_path / 'rec'))
    assert all(c.uncompressed_crc == 0 for c in chunks)
    assert read_recording(tmp_path / 'rec') is not None         # no CRCs: still reads
    _flip_bit_of_value(_mcap_of(tmp_path / 'rec'), 2.107092534866288, 59)
    _bad(tmp_path / 'rec', '/joint_states', 'effort', r't = 2\.7')


def test_chunk_crc_without_data_crc_is_checked(tmp_path):
    """Files with chunk CRCs only (as the C++ MCAP writer of ros2 bag makes them)."""
    from friction_joint.bag import seal_recording
    topics = _smooth(n=1500)
    topics['/joint_states']['effort'][700] = 2.107092534866288
    _rosbags_bag(tmp_path / 'rec', topics)
    seal_recording(tmp_path / 'rec', compression='none', data_crc=False)
    chunks, data_end = _chunks_and_data_end(_mcap_of(tmp_path / 'rec'))
    assert all(c.uncompressed_crc for c in chunks) and data_end[0].data_section_crc == 0
    read_recording(tmp_path / 'rec')
    _flip_bit_of_value(_mcap_of(tmp_path / 'rec'), 2.107092534866288, 20)   # a mantissa bit
    _bad(tmp_path / 'rec', r'(?i)checksum|crc')


# --------------------------------------------------------------------------- joint name

def test_missing_joint_names_file_joint_and_joints_present(tmp_path):
    """Two drivers publish one joint each on /joint_states; the gear's joint is neither."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types

    def js(name, ns):
        return T['sensor_msgs/msg/JointState'](
            header=T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](
                sec=0, nanosec=ns), frame_id=''),
            name=[name], position=np.array([1.0]), velocity=np.array([0.0]),
            effort=np.array([0.5]))
    with Writer(tmp_path / 'rec', version=9, storage_plugin=StoragePlugin.MCAP) as w:
        c = w.add_connection('/joint_states', 'sensor_msgs/msg/JointState', typestore=ts)
        c2 = w.add_connection('/joint_temperature', 'sensor_msgs/msg/Temperature',
                              typestore=ts)
        for i in range(40):
            ns = (i // 2 + 1) * 1_000_000
            w.write(c, ns, ts.serialize_cdr(js('shoulder' if i % 2 else 'elbow', ns),
                                            'sensor_msgs/msg/JointState'))
        w.write(c2, 50_000_000, ts.serialize_cdr(T['sensor_msgs/msg/Temperature'](
            header=T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](
                sec=0, nanosec=50_000_000), frame_id=''), temperature=30.0, variance=0.0),
            'sensor_msgs/msg/Temperature'))
    assert read_recording(tmp_path / 'rec', joint_name='shoulder').joint_states.skipped == 20
    msg = _bad(tmp_path / 'rec', 'wrist', 'shoulder', 'elbow', joint_name='wrist')
    assert 'joint' in msg
