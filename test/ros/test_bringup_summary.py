# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The closing summary of ``bringup``, read from the processes' logs (no ROS needed)."""
from friction_joint.ros.bringup import run_summary
import numpy as np


def _log(path, node, lines):
    with open(path, 'a', encoding='utf-8') as fh:
        for level, message in lines:
            fh.write(f'[{level}] [1795945050.675176299] [{node}]: {message}\n')


def test_summary_gathers_each_nodes_closing_lines_and_warnings(tmp_path):
    """Each node's own summary once, its warnings counted, a composed log split by node."""
    rng = np.random.default_rng(5)
    n_warn = int(rng.integers(1, 9))
    _log(tmp_path / 'joint_sim.log', 'joint_sim',
         [('INFO', 'realtime simulation of j1')] + [('WARN', 'late')] * n_warn
         + [('INFO', 'realtime run: 4000 states in 4.40 s of wall time'),
            ('INFO', 'rejected 66 input messages')])
    _log(tmp_path / 'composed.log', 'controller', [('INFO', 'answered 1010 states in 4.07 s')])
    _log(tmp_path / 'composed.log', 'estimator', [('WARN', 'slow'), ('INFO', 'answered 4000')])
    (tmp_path / 'notes.txt').write_text('[WARN] [0] [x]: not a log\n')
    lines = run_summary(str(tmp_path))
    assert 'joint_sim: realtime run: 4000 states in 4.40 s of wall time' in lines
    assert 'joint_sim: rejected 66 input messages' in lines
    assert 'controller: answered 1010 states in 4.07 s' in lines
    assert 'estimator: answered 4000' in lines
    assert f'joint_sim: {n_warn} warning(s) in its log' in lines
    assert 'estimator: 1 warning(s) in its log' in lines
    assert not any(line.startswith('x:') for line in lines)
    assert not any('realtime simulation' in line for line in lines)


def test_summary_of_a_missing_log_directory_is_empty(tmp_path):
    """Nothing to read is nothing said (the summary never fails the bring-up)."""
    assert run_summary(str(tmp_path / 'gone')) == []
    assert run_summary(str(tmp_path), str(tmp_path / 'no_recording')) == []
