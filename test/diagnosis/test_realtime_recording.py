# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The project's own realtime recording, made on a loaded machine, is diagnosed.

``friction_joint bringup --mode realtime --duration 12 --record DIR`` runs next
to two busy processes (a loaded machine: the simulator runs late), then
``friction_joint diagnose DIR --model config/csd25_base.yaml`` must succeed
(exit 0) with a sensible report: the gaps of the stamps reported, several
seconds of sliding data, a base fit, held-out RMSEs below the friction level.
"""
import json
import math
import os
from pathlib import Path
import subprocess
import sys

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / 'test' / 'ros'))

import roshelpers  # noqa: E402

BASE = ROOT / 'config' / 'csd25_base.yaml'
MODEL = ROOT / 'config' / 'csd25.yaml'
TRUTH = ROOT / 'config' / 'csd25_truth.yaml'


@pytest.fixture
def ros_env(monkeypatch):
    """Environment of a fresh ROS domain (as the ``ros_env`` fixture of test/ros/conftest.py)."""
    env = roshelpers.ros_environ()
    for key in ('ROS_DOMAIN_ID', 'ROS_AUTOMATIC_DISCOVERY_RANGE'):
        monkeypatch.setenv(key, env[key])
    monkeypatch.delenv('ROS_LOCALHOST_ONLY', raising=False)
    return env


@pytest.mark.ros
@pytest.mark.slow
def test_realtime_recording_on_loaded_machine_is_diagnosed(ros_env, tmp_path):
    rec, out = tmp_path / 'rec', tmp_path / 'diag'
    busy = []
    try:
        for _ in range(2):
            busy.append(subprocess.Popen([sys.executable, '-c', 'while True: pass']))
        res = subprocess.run(
            [sys.executable, '-m', 'friction_joint', 'bringup', '--model', str(MODEL),
             '--truth', str(TRUTH), '--mode', 'realtime', '--duration', '12',
             '--record', str(rec)],
            env=ros_env, capture_output=True, text=True, timeout=180, cwd=str(ROOT))
    finally:
        for p in busy:
            p.kill()
            p.wait(timeout=10)
    assert res.returncode == 0, f'bringup: {res.stdout}\n{res.stderr}'
    assert rec.is_dir(), res.stdout
    res = subprocess.run(
        [sys.executable, '-m', 'friction_joint', 'diagnose', str(rec), '--model', str(BASE),
         '--out', str(out)],
        env=dict(os.environ), capture_output=True, text=True, timeout=600, cwd=str(ROOT))
    assert res.returncode == 0, f'diagnose: {res.stdout}\n{res.stderr}'
    rep = json.loads((out / 'report.json').read_text())
    print(f'\n{res.stderr}\ngaps {rep["data"]["gaps"]}, named {rep["named_causes"]}, RMSE '
          f'{rep["baseline"]["torque_rmse"]:.4f} -> {rep["extended"]["torque_rmse"]:.4f} Nm')
    gaps = rep['data']['gaps']
    assert gaps['bridged'] >= 0 and gaps['split'] >= 0 and gaps['bridge_limit_s'] > 0
    assert rep['data']['sliding_s'] >= 3.0                 # of 12 s
    level = rep['data']['scales']['friction_level']
    assert rep['base_fit']['fc'][0] > 0
    for which in ('baseline', 'extended'):
        rmse = rep[which]['torque_rmse']
        assert math.isfinite(rmse) and rmse < level, (which, rmse, level)
    assert rep['extended']['torque_rmse'] <= rep['baseline']['torque_rmse'] + 1e-12
    assert all(c['effect'] for c in rep['candidates'])
    assert (out / 'report.md').is_file() and (out / 'extended.yaml').is_file()
