# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A candidate's fitted parameters lie where the data are, and the next step it suggests runs.

Issue 33: a friction that dips below the Coulomb level at low speed was named
``stribeck`` with F_s 40-45 % *below* F_c (no Stribeck hump), and the suggested
``identify`` on the same recordings refused.  The truths, their sizes and the
plant's nuisances are drawn at random (seeded); ``diagnose`` sees only the
recording and the base gear.
"""
import json
import os
import re
import subprocess
import sys

from friction_joint.diagnosis import diagnose
from friction_joint.diagnosis.findings import SENTENCES
from friction_joint.diagnosis.physical import constraints, solve_physical
from friction_joint.diagnosis.result import DataRanges
from friction_joint.experiments.hidden import (apply_effects, draw_effect, RecordingOptions,
                                               simulate_recording)
from friction_joint.gear import load_gear
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')


class _Ctx:
    def __init__(self, rng):
        self.u_grid = np.linspace(-1.5, 1.5, 9)
        self.vl_max = float(rng.uniform(0.5, 3.0))


@pytest.mark.parametrize('seed', range(6))
def test_a_low_speed_dip_fits_no_breakaway_below_coulomb(seed):
    """Before: the bounded fit kept F_s >= 0 only, and a dip gave F_s well below F_c."""
    rng = np.random.default_rng([3301, seed])
    v = np.exp(rng.uniform(np.log(0.005), np.log(3.0), int(rng.integers(300, 3000))))
    fc, fv, vs = rng.uniform(0.5, 3.0), rng.uniform(0.1, 1.0), rng.uniform(0.01, 0.1)
    fs = fc * rng.uniform(0.4, 0.8)                             # friction lower at low speed
    e = np.exp(-(v / vs) ** 2)
    y = fc * (1 - e) + fs * e + fv * v + rng.normal(0, 0.01 * fc, v.size)
    x = np.column_stack([1 - e, e, v])
    names = [('fc', 0), ('fs', 0), ('fv', 0)]
    beta = solve_physical(x.T @ x, x.T @ y, constraints(names, _Ctx(rng)))
    assert beta[1] >= beta[0] - 1e-9 * abs(beta[0]), (fc, fs, beta)


@pytest.mark.parametrize('seed', range(2))
def test_a_low_speed_dip_is_not_named_a_stribeck_below_coulomb(tmp_path, seed):
    """Before: named stribeck, 'F_s = 1.32 Nm (40 % below F_c = 2.2 Nm)'."""
    rng = np.random.default_rng([3302, seed])
    base = load_gear(BASE)
    truth = apply_effects(base, {'stribeck': {'fs_ratio': float(rng.uniform(0.5, 0.75)),
                                              'vs': float(rng.uniform(0.03, 0.1))}})
    rec = str(tmp_path / 'rec')
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=float(rng.uniform(30, 40)), seed=int(rng.integers(1e6)), base_gear=base,
        n_segments=2, noise_scale=float(rng.uniform(0.5, 2.0))))
    rep = diagnose([rec], base).report
    fit = rep['extended_fit']
    if fit.get('fs'):
        assert fit['fs'][0] >= fit['fc'][0], (rep['named_causes'], fit)
    for r in rep['rounds']:
        for c in r['candidates']:
            assert not (c['effect'] == 'stribeck' and c.get('significant')
                        and fit.get('fs') and fit['fs'][0] < fit['fc'][0])


def _suggested(md):
    """Return the commands of the report's 'What to do next' section."""
    part = md.split('## What to do next', 1)[1].split('\n## ', 1)[0]
    return re.findall(r'^ {8}(friction_joint \w+ .*)$', part, re.M)


@pytest.mark.parametrize('seed', range(2))
def test_the_suggested_next_steps_run(tmp_path, seed):
    """Before: ``identify`` was suggested on recordings without plateaus in both directions."""
    rng = np.random.default_rng([3303, seed])
    base = load_gear(BASE)
    truth = apply_effects(base, {'stribeck': draw_effect(rng, 'stribeck',
                                                         strength=float(rng.uniform(0.5, 1)))})
    rec = str(tmp_path / 'rec')
    kinds = [str(rng.choice(['sweep', 'oneway']))] if seed == 0 else ['rich']
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=float(rng.uniform(30, 40)), seed=int(rng.integers(1e6)), base_gear=base,
        n_segments=2, kinds=kinds))
    out = tmp_path / 'out'
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get('PYTHONPATH', ''))
    run = subprocess.run([sys.executable, '-m', 'friction_joint', 'diagnose', rec, '--model',
                          BASE, '--out', str(out)], capture_output=True, text=True,
                         cwd=str(tmp_path), env=env, timeout=600)
    assert run.returncode == 0, run.stderr
    with open(out / 'report.md', encoding='utf-8') as fh:
        md = fh.read()
    with open(out / 'report.json', encoding='utf-8') as fh:
        named = json.load(fh)['named_causes']
    assert 'stribeck' in named, (kinds, named)
    steps = _suggested(md)
    assert steps, md
    for cmd in steps:
        step = subprocess.run([sys.executable, '-m'] + cmd.split(), capture_output=True,
                              text=True, cwd=str(tmp_path), env=env, timeout=600)
        assert step.returncode == 0, (kinds, cmd, step.stderr[-800:])


@pytest.mark.parametrize('seed', range(4))
def test_the_stribeck_finding_gives_the_joint_speed(seed):
    """Before: v_s in the curve's units (velocity_scale x rad/s) was printed as rad/s."""
    rng = np.random.default_rng([3304, seed])
    kappa = float(np.exp(rng.uniform(np.log(0.05), np.log(100.0))))
    vs = float(rng.uniform(0.02, 0.2))
    fit = {'fc': [float(rng.uniform(0.5, 3))], 'velocity_scale': kappa, 'vs': [vs * kappa]}
    fit['fs'] = [fit['fc'][0] * float(rng.uniform(1.2, 2))]
    ranges = DataRanges(temperature=None, speed=(0.01, 2.0), load=(0.0, 0.0),
                        position=(0.0, 0.0), travel=0.0, level=1.0, inertia=0.0)
    text = SENTENCES['stribeck'](fit, {}, ranges)
    assert f'within about {vs:.3g} rad/s' in text, (kappa, text)
