# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The open residual scan points at an effect outside the candidate list.

A base recording of the simulated test bed gets a torque periodic in position
added to its drive torque, at a period drawn at random (seeded; override with
``FRICTION_JOINT_TEST_SEED``) well away from the gear's ripple periods
2 pi / (k N), so no candidate covers it: the scan's strongest position period
must be within 5 % of the drawn one, significant and flagged.  On a clean
recording no variable is flagged.
"""
import math
import os
from pathlib import Path

import friction_joint
from friction_joint.bag import write_recording
from friction_joint.diagnosis import diagnose, EFFECTS
from friction_joint.diagnosis.scan import SCAN_ALPHA
from friction_joint.experiments.hidden import RecordingOptions, simulate_recording
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
MASTER_SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20260106'))


def _scan(tmp_path, case, periodic, effects=None):
    rng = np.random.default_rng([MASTER_SEED, case])
    seed = int(rng.integers(0, 2**31 - 1))
    base = friction_joint.load_gear(BASE)
    topics, _ = simulate_recording(base, None, options=RecordingOptions(duration=30.0, seed=seed))
    drawn = {}
    if periodic:
        longest_ripple = 2 * math.pi / base.gear_ratio        # 2 pi / (k N), k >= 1
        period = float(rng.uniform(1.3 * longest_ripple, 0.4))
        amp = float(rng.uniform(0.03, 0.08)) * base.friction.fc[0]
        js = topics['/joint_states']
        js['effort'] = js['effort'] + amp * np.sin(2 * np.pi * js['q'] / period
                                                   + rng.uniform(0, 2 * np.pi))
        drawn = {'period': period, 'amplitude': amp}
    write_recording(tmp_path / 'rec', topics)
    rep = diagnose([str(tmp_path / 'rec')], base,
                   **({} if effects is None else {'effects': effects})).to_dict()
    what = f'[master seed {MASTER_SEED}] hidden {drawn or "nothing"}, recording seed {seed}'
    return {e['variable']: e for e in rep['residual_scan']}, drawn, what, rep


def test_ripple_candidate_finds_a_foreign_period(tmp_path):
    """A torque periodic in position at a drawn period (not a gear harmonic): named, its period."""
    scan, drawn, what, rep = _scan(tmp_path, 1, True)
    assert rep['named_causes'] == ['position_ripple'], what
    cycles = rep['extended_fit']['position_ripple']['cycles_per_rev']
    assert abs(cycles * drawn['period'] / (2 * math.pi) - 1) < 0.05, f'{what}: {cycles}'


def test_scan_finds_a_period_in_position(tmp_path):
    """Without the ripple candidate, the scan finds the drawn period within 5 %, flagged."""
    effects = [e for e in EFFECTS if e != 'position_ripple']
    scan, drawn, what, rep = _scan(tmp_path, 1, True, effects=effects)
    pos = scan['position']
    assert abs(pos['period'] / drawn['period'] - 1) < 0.05, f'{what}: {pos}'
    assert pos['p_value'] < SCAN_ALPHA and pos['flagged'], f'{what}: {pos}'


def test_scan_clean_recording(tmp_path):
    """No hidden effect: no variable flagged; variables the data lack get a note."""
    scan, _, what, rep = _scan(tmp_path, 2, False)
    members = {v for name, e in scan.items() for v in e.get('group', [name])}
    assert members == {'time', 'position', 'velocity', 'acceleration', 'temperature_rate',
                       'dwell'}, what
    assert not [e for e in scan.values() if e['flagged']], f'{what}: {scan}'
    for e in scan.values():
        assert e['note'] or e['p_value'] is not None, e
