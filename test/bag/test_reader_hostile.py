# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Hostile recordings (issue 23): special files, corrupt metadata, stamps, clocks, physics.

Every case ends in one line naming the file (and the topic), at once; the odd but
valid recordings beside them are read.  FIFO and device cases run the command in a
subprocess with a timeout (a regression would block in ``open()``).
"""
import json
import os
from pathlib import Path
import re
import shutil
import struct
import subprocess
import sys

from friction_joint.bag import read_recording, write_recording
from friction_joint.bag.consistency import MISMATCH, velocity_mismatch
from friction_joint.cli import main
from friction_joint.exceptions import RecordingError
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / 'bags' / 'csd25_sample'
MODEL = ROOT / 'config' / 'csd25_base.yaml'
FJ = [sys.executable, '-m', 'friction_joint']


def _smooth(n=3000, rate=1000.0, t0=2.0, seed=0):
    """Return a plausible 1 kHz joint (sine motion, noise), temperature at 4 Hz, link torque."""
    rng = np.random.default_rng(seed)
    t = t0 + np.arange(n) / rate
    q = 0.8 * np.sin(1.3 * t)
    qd = 0.8 * 1.3 * np.cos(1.3 * t) + 1e-3 * rng.normal(size=n)
    effort = 2.0 * np.tanh(qd / 0.01) + 0.5 * qd + 0.01 * rng.normal(size=n)
    tt = np.arange(t0, t[-1], 0.25)
    return {
        '/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
        '/joint_temperature': {'t': tt, 'xi': 23.0 + 12.5 * (tt - t0) / (tt[-1] - t0)},
        '/link_torque': {'t': t, 'tau': 3.0 * np.sin(q)},
    }


def _bad(path, *words, **kw):
    """read_recording raises one line naming ``path`` and every word (regex)."""
    with pytest.raises(RecordingError) as info:
        read_recording(path, **kw)
    msg = str(info.value)
    assert str(path) in msg, f'the error does not name the file: {msg}'
    for w in words:
        assert re.search(w, msg), f'{w!r} not in: {msg}'
    assert '\n' not in msg
    return msg


# --------------------------------------------------------------------------- special files

def _dir_with(tmp_path, which, make):
    rec = tmp_path / 'rec'
    rec.mkdir()
    for name in ('metadata.yaml', 'csd25_sample.mcap'):
        if name == which:
            make(rec / name)
        else:
            shutil.copy(SAMPLE / name, rec / name)
    return rec


def _zero(path):
    os.symlink('/dev/zero', path)


CASES = {
    'fifo recording': lambda d: (os.mkfifo(d / 'rec.mcap'), d / 'rec.mcap')[1],
    'fifo mcap in a directory': lambda d: (_dir_with(d, 'csd25_sample.mcap', os.mkfifo),
                                           d / 'rec' / 'csd25_sample.mcap'),
    'fifo metadata.yaml': lambda d: (_dir_with(d, 'metadata.yaml', os.mkfifo),
                                     d / 'rec' / 'metadata.yaml'),
    'metadata.yaml -> /dev/zero': lambda d: (_dir_with(d, 'metadata.yaml', _zero),
                                             d / 'rec' / 'metadata.yaml'),
    'mcap -> /dev/zero': lambda d: (_dir_with(d, 'csd25_sample.mcap', _zero),
                                    d / 'rec' / 'csd25_sample.mcap'),
}


_CHILD = """
import contextlib, io, json, sys
from friction_joint.cli import main
for args in json.loads(sys.argv[1]):
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        status = main(args)
    print(json.dumps([status, err.getvalue()]), flush=True)
"""


def test_special_files_in_a_recording_are_refused_at_once(tmp_path):
    """Refuse a FIFO or device anywhere in a recording: one line, exit 2, no hang, no output."""
    runs, culprits = [], []
    for k, case in enumerate(sorted(CASES)):
        d = tmp_path / f'case{k}'
        d.mkdir()
        made = CASES[case](d)
        if isinstance(made, tuple):
            rec, culprit = d / 'rec', made[1]
        else:
            rec, culprit = made, made
        runs.append(['identify', str(rec), '--model', str(MODEL), '--out', str(d / 'X')])
        culprits.append((case, culprit, d / 'X'))
    os.mkfifo(tmp_path / 'cut.mcap')                 # recover reads a recording too
    runs.append(['recover', str(tmp_path / 'cut.mcap'), str(tmp_path / 'OUT')])
    culprits.append(('recover a fifo', tmp_path / 'cut.mcap', tmp_path / 'OUT'))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.run([sys.executable, '-c', _CHILD, json.dumps(runs)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=180, env=env,
                          stdin=subprocess.DEVNULL)
    assert proc.returncode == 0, proc.stderr
    results = [json.loads(line) for line in proc.stdout.splitlines()]
    assert len(results) == len(runs)
    for (case, culprit, out), (status, err) in zip(culprits, results, strict=True):
        lines = err.strip().splitlines()
        assert status == 2, (case, err)
        assert len(lines) == 1, (case, err)
        assert str(culprit) in lines[0], (case, err)
        assert re.search('FIFO|device', lines[0]), (case, err)
        assert not out.exists()


@pytest.mark.skipif(os.geteuid() == 0, reason='root reads files of any mode')
def test_unreadable_recording_directory_and_mcap(tmp_path):
    rec = tmp_path / 'rec'
    shutil.copytree(SAMPLE, rec)
    os.chmod(rec / 'csd25_sample.mcap', 0)
    _bad(rec / 'csd25_sample.mcap', 'permission denied')
    _bad(rec, 'csd25_sample.mcap', 'permission denied')
    os.chmod(rec / 'csd25_sample.mcap', 0o644)
    os.chmod(rec, 0)
    try:
        _bad(rec, 'permission denied')
    finally:
        os.chmod(rec, 0o755)


def test_corrupt_metadata_is_one_line_naming_the_file(tmp_path):
    rec = tmp_path / 'rec'
    shutil.copytree(SAMPLE, rec)
    (rec / 'metadata.yaml').write_text('rosbag2_bagfile_information:\n  version: [9\n'
                                       '  : x: y\n')
    msg = _bad(rec, 'metadata.yaml', 'not valid YAML', 'line 3')
    assert 'Traceback' not in msg
    (rec / 'metadata.yaml').write_bytes(b'\xff\xfe\x00garbage')
    _bad(rec, 'metadata.yaml', 'UTF-8')
    (rec / 'metadata.yaml').write_text('- just\n- a list\n')
    _bad(rec, 'metadata.yaml', 'rosbag2_bagfile_information')
    (rec / 'metadata.yaml').write_text(
        (SAMPLE / 'metadata.yaml').read_text().replace('- csd25_sample.mcap', '- /dev/zero'))
    _bad(rec, 'metadata.yaml lists /dev/zero', 'character device')


# --------------------------------------------------------------------------- raw stamps

def _raw_bag(path, messages):
    """
    Write ``(topic, sec, nanosec, value)`` messages as they are (no checks, CRC 0).

    JointState: position = value, velocity 0, effort 0; Temperature: value.
    """
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types
    hdr = T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0),
                                   frame_id='')
    types = {'/joint_states': 'sensor_msgs/msg/JointState',
             '/joint_temperature': 'sensor_msgs/msg/Temperature'}
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        conns = {t: w.add_connection(t, m, typestore=ts) for t, m in types.items()}
        for k, (topic, sec, nsec, value) in enumerate(messages):
            if topic == '/joint_states':
                msg = T[types[topic]](header=hdr, name=['joint'], position=np.array([value]),
                                      velocity=np.array([0.0]), effort=np.array([0.0]))
            else:
                msg = T[types[topic]](header=hdr, temperature=value, variance=0.0)
            raw = bytearray(ts.serialize_cdr(msg, types[topic]))
            raw[4:12] = struct.pack('<iI', sec, nsec)
            w.write(conns[topic], 1000 + k, bytes(raw))
    return path


def test_nanosec_of_a_second_or_more_is_refused(tmp_path):
    msgs = [('/joint_states', 10, 1000 * i, 1.0) for i in range(50)]
    msgs[30] = ('/joint_states', 10, 1_500_000_000, 1.0)
    _raw_bag(tmp_path / 'rec', msgs)
    _bad(tmp_path / 'rec', '/joint_states', 'message 30', 'nanosec 1500000000', 'malformed')
    with pytest.raises(RecordingError, match='nanosec'):   # also when not checking values
        read_recording(tmp_path / 'rec', check=False)


def test_negative_stamps_are_refused(tmp_path):
    msgs = [('/joint_states', -5 + i // 1000, (i % 1000) * 1_000_000, 1.0)
            for i in range(3000)]
    _raw_bag(tmp_path / 'rec', msgs)
    _bad(tmp_path / 'rec', '/joint_states', 'negative', 'message 0', r't = -5\.0')


# --------------------------------------------------------------------------- clocks

def test_link_torque_stamped_1000_s_later_is_refused(tmp_path):
    topics = _smooth()
    topics['/link_torque']['t'] = topics['/link_torque']['t'] + 1000.0
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/link_torque', 'clock of /joint_states', 'no overlap')


def test_temperature_on_an_epoch_clock_is_refused(tmp_path):
    topics = _smooth()
    topics['/joint_temperature']['t'] = topics['/joint_temperature']['t'] + 1.7e9
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_temperature', 'clock of /joint_states')


def test_joint_states_on_another_clock_than_the_rest_are_refused(tmp_path):
    topics = _smooth(t0=1.7e9)
    for k in ('/joint_temperature', '/link_torque'):
        topics[k]['t'] = topics[k]['t'] - 1.7e9 + 3.0
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_temperature|/link_torque', 'clock')


def test_a_topic_mostly_elsewhere_touching_the_joint_states_is_refused(tmp_path):
    """Temperature over 1000 s of which 0.02 s overlap the 3 s of joint states."""
    topics = _smooth(t0=1002.0)
    tt = np.linspace(2.02, 1002.02, 4001)
    topics['/joint_temperature'] = {'t': tt, 'xi': np.full(len(tt), 30.0)}
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_temperature', 'covers', 'outside')


def test_slow_late_or_single_temperature_topics_are_read(tmp_path):
    """1 Hz starting 0.8 s late; one message at the start; 60 s of it before the joint."""
    cases = {'late': np.arange(2.8, 5.0, 1.0), 'single': np.array([2.0]),
             'before': np.arange(-58.0, 5.0, 0.25) + 60.0, 'one_after': np.array([5.3])}
    for name, tt in cases.items():
        topics = _smooth()
        topics['/joint_temperature'] = {'t': tt, 'xi': np.full(len(tt), 30.0)}
        write_recording(tmp_path / name, topics)
        rec = read_recording(tmp_path / name)
        assert len(rec.temperature) == len(tt)


# --------------------------------------------------------------------------- position/velocity

def test_frozen_position_with_a_moving_velocity_is_refused(tmp_path):
    topics = _smooth()
    js = topics['/joint_states']
    js['q'] = np.full(len(js['t']), js['q'][0])
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_states', 'velocity disagrees with the position')


def test_velocity_of_the_opposite_sign_is_refused(tmp_path):
    topics = _smooth()
    topics['/joint_states']['qd'] *= -1
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_states', 'velocity disagrees', r'mismatch (1\.[5-9]|2)')


def test_consistent_position_and_velocity_in_hard_forms_are_read(tmp_path):
    """Coarse encoder, noisy velocity, a velocity bias, jitter, a wrapping angle, rest."""
    rng = np.random.default_rng(7)
    base = _smooth(n=6000)
    t = base['/joint_states']['t']
    q = base['/joint_states']['q']
    qd = base['/joint_states']['qd']
    res = 2 * np.pi / 256
    spin_t = 2.0 + np.arange(6000) * 1e-3
    cases = {
        'coarse encoder (8 bit)': (t, np.round(q / res) * res, qd),
        'noisy velocity': (t, q, qd + 0.1 * rng.normal(size=len(t))),
        'velocity bias': (t, q, qd + 0.01),
        'jitter': (t + rng.uniform(-3e-4, 3e-4, len(t)), q, qd),
        'wrapping angle': (spin_t, (4.0 * spin_t + np.pi) % (2 * np.pi) - np.pi,
                           np.full(len(spin_t), 4.0)),
        'rest, filtered velocity noise': (t, np.zeros(len(t)), np.convolve(
            rng.normal(size=len(t)), np.ones(10) / 10, mode='same') * 1e-3),
    }
    for k, (tc, qc, qdc) in enumerate(cases.values()):
        m, _, _ = velocity_mismatch(tc, qc, qdc)
        assert not m > MISMATCH / 5, (list(cases)[k], m)
        if k not in (0, 4):                       # the coarse encoder, the wrapping angle
            continue
        topics = _smooth(n=6000)
        topics['/joint_states'] = {'t': tc, 'q': qc, 'qd': qdc,
                                   'effort': topics['/joint_states']['effort']}
        topics['/link_torque']['t'] = tc
        write_recording(tmp_path / f'r{k}', topics)
        read_recording(tmp_path / f'r{k}')


def test_mismatch_of_the_shipped_sample_and_its_defects():
    js = read_recording(SAMPLE).joint_states
    good, _, _ = velocity_mismatch(js.t, js.q, js.qd)
    frozen, _, _ = velocity_mismatch(js.t, np.full(len(js), js.q[0]), js.qd)
    degrees, _, _ = velocity_mismatch(js.t, js.q, np.degrees(js.qd))
    assert good < MISMATCH / 20
    assert frozen > 2 * MISMATCH and degrees > 2 * MISMATCH


# --------------------------------------------------------------------------- physical ranges

def test_temperature_below_absolute_zero_is_refused(tmp_path):
    topics = _smooth()
    topics['/joint_temperature']['xi'] = np.full(len(topics['/joint_temperature']['t']),
                                                 -300.0)
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_temperature', '-300', 'absolute zero')


def test_absurd_temperature_blames_the_recording_not_the_gear(tmp_path, capsys):
    topics = _smooth()
    topics['/joint_temperature']['xi'] = np.full(len(topics['/joint_temperature']['t']),
                                                 1e300)
    write_recording(tmp_path / 'rec', topics)
    _bad(tmp_path / 'rec', '/joint_temperature', '1e\\+300')
    assert main(['identify', str(tmp_path / 'rec'), '--model', str(MODEL), '--out',
                 str(tmp_path / 'X')]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(tmp_path / 'rec') in err[0], err
    assert '/joint_temperature' in err[0] and 'csd25_base' not in err[0]
    assert not (tmp_path / 'X').exists()


def test_temperature_spanning_its_range_is_read_whole(tmp_path):
    """The 23-35.5 °C ramp is read as such (not held at its first value)."""
    write_recording(tmp_path / 'rec', _smooth())
    xi = read_recording(tmp_path / 'rec').temperature_at()
    assert xi.min() == pytest.approx(23.0) and xi.max() > 35.0


# --------------------------------------------------------------------------- layouts

def _raw_states(frames):
    """Serialize JointState messages, one per frame id, position = index (ms stamps)."""
    from friction_joint.bag._cdr import walk_joint_state
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types
    templates = {}
    raws = []
    for i, frame in enumerate(frames):
        n = len(frame)
        if n not in templates:
            msg = T['sensor_msgs/msg/JointState'](
                header=T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](
                    sec=0, nanosec=0), frame_id='x' * n),
                name=['joint'], position=np.array([0.0]), velocity=np.array([0.0]),
                effort=np.array([0.0]))
            raw = ts.serialize_cdr(msg, 'sensor_msgs/msg/JointState')
            templates[n] = (bytes(raw), walk_joint_state(raw).fields['position'][0])
        raw, pos = templates[n]
        b = bytearray(raw)
        b[4:12] = struct.pack('<iI', i // 1000, (i % 1000) * 1_000_000)
        b[16:16 + n] = frame.encode()
        b[pos:pos + 8] = struct.pack('<d', float(i))
        raws.append(bytes(b))
    return raws


def test_distinct_frame_ids_do_not_multiply_layout_groups():
    """100 k messages, each with its own frame id of one length: one layout group."""
    from friction_joint.bag._cdr import f64_columns, layout_groups
    n = 100_000
    raws = _raw_states([f'frame_{i:06d}' for i in range(n)])
    groups = list(layout_groups(raws, 'sensor_msgs/msg/JointState', 'rec: /joint_states'))
    assert len(groups) == 1
    idx, layout, block = groups[0]
    np.testing.assert_array_equal(idx, np.arange(n))
    off, _ = layout.fields['position']
    np.testing.assert_array_equal(f64_columns(block, off, 1)[:, 0], np.arange(n))


def test_varying_frame_id_lengths_walk_each_message_once(monkeypatch):
    """Frame ids of 300 lengths: one group per length, each message walked at most once."""
    from friction_joint.bag import _cdr
    walks = []
    walk = _cdr.WALKERS['sensor_msgs/msg/JointState']
    monkeypatch.setitem(_cdr.WALKERS, 'sensor_msgs/msg/JointState',
                        lambda raw: walks.append(1) or walk(raw))
    n = 30_000
    frames = ['f' * (i % 300) + str(i) for i in range(n)]
    raws = _raw_states(frames)
    lengths = {len(f) for f in frames}
    seen = np.zeros(n, dtype=int)
    groups = 0
    for idx, layout, block in _cdr.layout_groups(raws, 'sensor_msgs/msg/JointState', 'x'):
        seen[idx] += 1
        groups += 1
        off, _ = layout.fields['position']
        np.testing.assert_array_equal(_cdr.f64_columns(block, off, 1)[:, 0], idx)
    assert (seen == 1).all()
    assert groups <= len(lengths) < n / 10
    assert len(walks) <= n + _cdr.MAX_LAYOUTS
