# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A signal scaled as a whole into absurd magnitudes is refused by the reader and by ``import``.

The scale-free check measures a sample against its own signal's spread, so a
torque of 1e300 N m in every sample passed: ``import`` wrote it and ``identify``
ended in a ``ValueError`` traceback from the least-squares solver (its squares
overflow).  Now a sample beyond ``MAX_MAGNITUDE`` (1e12 in SI units) is one line,
exit 2, in ``import`` and in every reader of the recording.
"""
import os
from pathlib import Path
import subprocess
import sys

from friction_joint.bag import read_recording, write_recording
from friction_joint.bag.plausible import MAX_MAGNITUDE
from friction_joint.exceptions import RecordingError
import numpy as np
import pytest
from test_import import _fails

ROOT = Path(__file__).resolve().parents[2]
FIELDS = [('/joint_states', 'q'), ('/joint_states', 'qd'), ('/joint_states', 'effort'),
          ('/link_torque', 'tau')]


def _topics(n=4000, seed=0):
    """Return a plausible 1 kHz joint: a sine motion, Coulomb and viscous friction, load torque."""
    rng = np.random.default_rng(seed)
    t = 1.0 + np.arange(n) * 1e-3
    q = 0.5 * np.sin(0.5 * t)
    qd = 0.25 * np.cos(0.5 * t)
    effort = 2.0 * np.tanh(qd / 0.01) + 0.5 * qd + 0.01 * rng.normal(size=n)
    return {'/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
            '/joint_temperature': {'t': t[::250], 'xi': np.full(len(t[::250]), 30.0)},
            '/link_torque': {'t': t, 'tau': 3.0 * np.sin(q)}}


def _scaled(seed):
    """Return the topics with one field drawn at random scaled as a whole beyond the bound."""
    rng = np.random.default_rng(seed)
    topics = _topics(seed=seed)
    topic, field = FIELDS[rng.integers(len(FIELDS))]
    scale = 10.0 ** rng.uniform(13, 300)
    if field in ('q', 'qd'):                    # a consistent pair: the position check passes
        for f in ('q', 'qd'):
            topics['/joint_states'][f] = topics['/joint_states'][f] * scale
    else:
        topics[topic][field] = topics[topic][field] * scale
    return topics, topic, field


@pytest.mark.parametrize('seed', range(4))
def test_a_signal_scaled_beyond_the_bound_is_refused_by_the_reader(tmp_path, seed):
    """read_recording: one line naming the file, topic, field and the bound."""
    topics, topic, _ = _scaled(seed)
    write_recording(tmp_path / 'rec', topics)
    with pytest.raises(RecordingError) as err:
        read_recording(tmp_path / 'rec')
    msg = str(err.value)
    assert str(tmp_path / 'rec') in msg and topic in msg and 'beyond 1e+12' in msg, msg
    assert '\n' not in msg


def test_values_up_to_the_bound_are_read():
    """A torque just inside the bound is a unit question for identify, not a corrupt value."""
    from friction_joint.bag import check_samples
    t = np.arange(100) * 1e-3
    check_samples('x', t, {'effort': np.full(100, 0.99 * MAX_MAGNITUDE)})
    with pytest.raises(RecordingError, match=r'x: implausible effort .*100 such samples'):
        check_samples('x', t, {'effort': np.full(100, 1.01 * MAX_MAGNITUDE)})


def test_import_refuses_a_torque_of_1e300(tmp_path, capsys):
    """The log ``import`` wrote and ``identify`` then died on: refused at import."""
    topics = _topics()
    js = topics['/joint_states']
    log = tmp_path / 'log.csv'
    rows = np.column_stack([js['t'], js['q'], js['qd'], js['effort'] * 1e300])
    with open(log, 'w') as fh:
        fh.write('t,q,v,tau\n')
        np.savetxt(fh, rows, delimiter=',', fmt='%.12g')
    _fails(capsys, tmp_path / 'rec', log, '--time', 't', '--position', 'q', '--velocity', 'v',
           '--torque', 'tau', expect=(str(log), 'implausible effort', 'beyond 1e+12'))


def test_identify_on_such_a_recording_is_one_line(tmp_path):
    """Run identify (the traceback before): exit 2, one line, nothing written."""
    topics = _topics()
    topics['/joint_states']['effort'] = topics['/joint_states']['effort'] * 1e300
    write_recording(tmp_path / 'rec', topics)
    proc = subprocess.run(
        [sys.executable, '-m', 'friction_joint', 'identify', '--model',
         str(ROOT / 'config' / 'csd25.yaml'), '--out', str(tmp_path / 'g.yaml'),
         '--presliding', 'skip', '--quiet', str(tmp_path / 'rec')],
        capture_output=True, text=True, timeout=300, env=dict(os.environ, PYTHONPATH=str(ROOT)))
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1, proc.stderr
    assert 'implausible effort' in lines[0] and 'beyond 1e+12' in lines[0], lines[0]
    assert sorted(os.listdir(tmp_path)) == ['rec']
