# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``drift``: friction that changes with accumulated travel, not with temperature.

A base recording of the simulated test bed at one temperature gets a run-in
added to its drive torque: the Coulomb level starts higher by a drawn
fraction and decays with the accumulated travel on a drawn length scale
(seeded; override with ``FRICTION_JOINT_TEST_SEED``).  ``diagnose`` must
name ``drift`` and nothing else, and report it as not representable in the
gear file.  A recording with a hidden ``thermal`` effect (temperature rising
along with the travel) must not name ``drift``.
"""
import json
import os
from pathlib import Path

import friction_joint
from friction_joint.bag import write_recording
from friction_joint.diagnosis import diagnose
from friction_joint.experiments.hidden import (apply_effects, draw_effect, RecordingOptions,
                                               simulate_recording)
from friction_joint.jobs import run_diagnose
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
MASTER_SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20260105'))


def _run_in(topics, base, rng):
    """Add a run-in (Coulomb level decaying with accumulated travel) to the drive torque."""
    js = topics['/joint_states']
    size = float(rng.uniform(0.1, 0.3))              # initial excess, fraction of F_c
    length = float(rng.uniform(0.15, 0.5))           # decay length, fraction of the travel
    dt = np.diff(js['t'], prepend=js['t'][0])
    s = np.cumsum(np.abs(js['qd']) * dt)
    s = s / s[-1]
    fc = float(np.polynomial.polynomial.polyval(
        np.mean(topics['/joint_temperature']['xi']), base.friction.fc))
    js['effort'] = js['effort'] + size * fc * np.exp(-s / length) * np.sign(js['qd'])
    return {'size': size, 'length': length}


def test_drift_named_alone(tmp_path):
    """A run-in at one temperature: ``drift`` named, nothing else; not in the gear file."""
    rng = np.random.default_rng([MASTER_SEED, 1])
    seed = int(rng.integers(0, 2**31 - 1))
    base = friction_joint.load_gear(BASE)
    topics, _ = simulate_recording(base, None, options=RecordingOptions(
        duration=30.0, seed=seed, n_segments=1))
    drawn = _run_in(topics, base, rng)
    what = f'[master seed {MASTER_SEED}] run-in {drawn}, recording seed {seed}'
    write_recording(tmp_path / 'rec', topics)
    out = tmp_path / 'out'
    run_diagnose([str(tmp_path / 'rec')], str(BASE), str(out))
    rep = json.loads((out / 'report.json').read_text())
    cand = {c['effect']: c for c in rep['candidates']}
    assert rep['named_causes'] == ['drift'], f'{what}: {rep["candidates"]}'
    assert cand['drift']['testable'] and cand['drift']['representable'] is False, what
    assert 'not representable in the gear file' in cand['drift']['reason'], what
    assert rep['extended_effects'] == [], what
    assert any('drift' in n for n in rep['notes']), rep['notes']
    assert len(rep['diagnosed']['fit']['drift']['fc_drift']) == 2, what
    assert rep['diagnosed']['torque_rmse'] < 0.9 * rep['extended']['torque_rmse'], what
    friction_joint.load_gear(out / 'extended.yaml')
    assert (out / 'cause_drift.png').exists()
    assert 'not representable in the gear file' in (out / 'report.md').read_text()


def test_thermal_is_not_drift(tmp_path):
    """A hidden thermal effect over three rising temperatures: ``drift`` is not named."""
    rng = np.random.default_rng([MASTER_SEED, 2])
    effects = {'thermal': draw_effect(rng, 'thermal')}
    seed = int(rng.integers(0, 2**31 - 1))
    what = f'[master seed {MASTER_SEED}] hidden {effects}, recording seed {seed}'
    base = friction_joint.load_gear(BASE)
    topics, summary = simulate_recording(
        apply_effects(base, effects), None, options=RecordingOptions(
            duration=30.0, seed=seed, base_gear=base))
    assert summary['temperatures'] == sorted(summary['temperatures']), what
    write_recording(tmp_path / 'rec', topics)
    rep = diagnose([str(tmp_path / 'rec')], base).to_dict()
    cand = {c['effect']: c for c in rep['candidates']}
    assert cand['drift']['testable'], what
    first = {c['effect']: c for c in rep['rounds'][0]['candidates']}
    # the temperature rises with the travel: drift alone may explain part of it, but
    # thermal explains it better and drift adds nothing once thermal is in
    assert first['thermal']['gain_raw'] > first['drift']['gain_raw'], what
    assert rep['named_causes'] == ['thermal'], f'{what}: {rep["candidates"]}'
