# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``diagnose`` on corrupt recordings: an error naming the recording, never a wrong answer.

Reversed or overlapping time stamps, a flipped bit (with and without checksums) and a
gear whose joint the recording does not have.  One short simulated recording (made once
per module) is damaged in each test.
"""
from pathlib import Path
import subprocess
import sys

import friction_joint
from friction_joint.bag import write_recording
from friction_joint.diagnosis.data import load_data
from friction_joint.exceptions import RecordingError
from friction_joint.experiments.hidden import RecordingOptions, simulate_recording
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'


@pytest.fixture(scope='module')
def base():
    return friction_joint.load_gear(BASE)


@pytest.fixture(scope='module')
def topics(base):
    """Topics of a short valid recording of the base gear."""
    out, _ = simulate_recording(base, None, options=RecordingOptions(
        duration=20.0, seed=7, n_segments=2))
    return out


def _copy(topics):
    return {t: {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in spec.items()}
            for t, spec in topics.items()}


def _diagnose(rec, out):
    cmd = [sys.executable, '-m', 'friction_joint', 'diagnose', str(rec), '--model', str(BASE),
           '--out', str(out), '--quiet']
    return subprocess.run(cmd, capture_output=True, text=True, timeout=600, cwd=str(ROOT))


def _rejected(res, rec, out, *words):
    assert res.returncode == 2, f'exit {res.returncode}:\n{res.stdout}\n{res.stderr}'
    err = res.stderr.strip()
    assert len(err.splitlines()) == 1 and 'Traceback' not in err, err
    assert str(rec) in err, f'the error does not name the recording: {err}'
    assert 'csd25_base.yaml' not in err, f'the gear file is blamed: {err}'
    for w in words:
        assert w in err, f'{w!r} not in: {err}'
    assert not (out / 'report.json').exists()


def test_reversed_stamps_are_rejected_not_diagnosed(topics, tmp_path):
    """Header stamps reversed over 2 s (bag order forward): exit 2, not 'named causes'."""
    t = _copy(topics)
    for spec in t.values():
        spec['t_recv'] = spec['t'].copy()
        w = (spec['t'] >= 6.0) & (spec['t'] < 8.0)
        spec['t'][w] = spec['t'][w][::-1]
    write_recording(tmp_path / 'rec', t)
    res = _diagnose(tmp_path / 'rec', tmp_path / 'out')
    _rejected(res, tmp_path / 'rec', tmp_path / 'out', '/joint_states', 'backwards')


def _unsealed_copy(src, dst):
    """Copy a recording as other tools write it (rosbags' MCAP writer: no CRCs, no compression)."""
    from rosbags.rosbag2 import Reader, StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    with Reader(src) as reader, Writer(dst, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        conns = {c.id: w.add_connection(c.topic, c.msgtype, typestore=ts)
                 for c in reader.connections}
        for con, stamp, raw in reader.messages():
            w.write(conns[con.id], stamp, raw)


def _flip(path, value, bit):
    data = bytearray(path.read_bytes())
    raw = np.float64(value).tobytes()
    at = data.find(raw)
    assert at > 0 and data.find(raw, at + 1) < 0
    data[at + bit // 8] ^= 1 << (bit % 8)
    path.write_bytes(bytes(data))


def test_flipped_bit_blames_the_recording_not_the_gear(topics, tmp_path):
    """One flipped exponent bit in one effort value of a CRC-less recording."""
    write_recording(tmp_path / 'plain', topics)
    _unsealed_copy(tmp_path / 'plain', tmp_path / 'rec')
    effort = topics['/joint_states']['effort']
    i = 9000
    assert np.count_nonzero(effort == effort[i]) == 1
    _flip(next((tmp_path / 'rec').glob('*.mcap')), effort[i], 60)
    res = _diagnose(tmp_path / 'rec', tmp_path / 'out')
    _rejected(res, tmp_path / 'rec', tmp_path / 'out', '/joint_states', 'effort',
              f't = {topics["/joint_states"]["t"][i]:.3f}')


def test_flipped_bit_in_a_checksummed_recording(topics, tmp_path, base):
    write_recording(tmp_path / 'rec', topics)
    path = next((tmp_path / 'rec').glob('*.mcap'))
    data = bytearray(path.read_bytes())
    data[len(data) // 3] ^= 0x04
    path.write_bytes(bytes(data))
    with pytest.raises(RecordingError, match='checksum') as info:
        load_data([tmp_path / 'rec'], base)
    assert str(tmp_path / 'rec') in str(info.value)


def test_overlapping_runs_are_rejected(topics, tmp_path, base):
    """The same run appended again (glued with overlapping time bases)."""
    t = _copy(topics)
    for spec in t.values():
        n = len(spec['t'])
        for k, v in list(spec.items()):
            if isinstance(v, np.ndarray) and v.shape[:1] == (n,):
                spec[k] = np.concatenate([v, v])
        spec['t_recv'] = np.arange(2 * n) * (spec['t'][1] - spec['t'][0])
    write_recording(tmp_path / 'rec', t)
    with pytest.raises(RecordingError, match='overlap') as info:
        load_data([tmp_path / 'rec'], base)
    assert str(tmp_path / 'rec') in str(info.value) and '/joint_states' in str(info.value)


def test_gear_joint_missing_from_the_recording(topics, tmp_path, base):
    t = _copy(topics)
    for topic in ('/joint_states', '/joint_command'):
        t[topic]['name'] = 'wrist'
    write_recording(tmp_path / 'rec', t)
    with pytest.raises(RecordingError) as info:
        load_data([tmp_path / 'rec'], base)
    msg = str(info.value)
    for word in (str(tmp_path / 'rec'), repr(base.joint_name), 'wrist'):
        assert word in msg, msg
    data = load_data([tmp_path / 'rec'], base, joint_name='wrist')        # --joint wrist
    assert data.recordings[0].joint_name == 'wrist'


def test_gaps_split_the_recording_into_pieces(topics, tmp_path, base):
    """A pause (two runs glued with a gap) is fine: no derivative bridges it."""
    t = _copy(topics)
    for spec in t.values():
        spec['t'] = np.where(spec['t'] >= 5.0, spec['t'] + 3.0, spec['t'])
    write_recording(tmp_path / 'rec', t)
    data = load_data([tmp_path / 'rec'], base)
    ref = load_data([_write(tmp_path / 'ref', topics)], base)
    assert data.piece.max() == ref.piece.max() + 1
    gap = np.flatnonzero(np.diff(data.t) > 2.5)
    assert len(gap) == 1 and data.piece[gap[0]] != data.piece[gap[0] + 1]


def _thin(spec, keep):
    n = len(spec['t'])
    return {k: (v[keep] if isinstance(v, np.ndarray) and v.shape[:1] == (n,) else v)
            for k, v in spec.items()}


@pytest.mark.parametrize('kind', ['jitter', 'dropped'])
def test_irregular_sampling_is_accepted(topics, tmp_path, base, kind):
    """Measured data: stamps jitter by 30 % of dt, or one sample in 200 is missing."""
    rng = np.random.default_rng(11)
    t = _copy(topics)
    n = len(t['/joint_states']['t'])
    if kind == 'jitter':                       # sampled at irregular times (and so stamped)
        t0 = t['/joint_states']['t']
        stamps = t0 + rng.uniform(-3e-4, 3e-4, n)
        stamps[[0, -1]] = t0[[0, -1]]
        for topic in ('/joint_states', '/joint_command', '/link_torque'):
            for k, v in t[topic].items():
                if k != 't' and isinstance(v, np.ndarray) and v.shape == (n,):
                    t[topic][k] = np.interp(stamps, t0, v)
            t[topic]['t'] = stamps
    else:
        keep = np.ones(n, dtype=bool)
        keep[rng.choice(np.arange(1, n - 1), n // 200, replace=False)] = False
        for topic in ('/joint_states', '/joint_command', '/link_torque'):
            t[topic] = _thin(t[topic], keep)
    data = load_data([_write(tmp_path / 'rec', t)], base)
    ref = load_data([_write(tmp_path / 'ref', topics)], base)
    assert data.piece.max() == ref.piece.max()                 # the same runs, no more
    assert data.n_bins > 0.95 * ref.n_bins
    for sign in (1, -1):
        y, y_ref = (np.median(d.y[np.sign(d.average(d.qd)) == sign]) for d in (data, ref))
        assert y == pytest.approx(y_ref, rel=0.02)


def _write(path, topics):
    write_recording(path, topics)
    return path
