# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Nonlinear parameters between grid points are fitted continuously (variable projection).

The truth's delta_v is drawn from a continuous range, away from the points of
the grid, so the grid alone is off by several per cent; the refined fit must
recover it (in the final fit and in every cross-validation fold, on the
training blocks only), and ``diagnose`` must name exactly the one effect
hidden, without a second candidate absorbing what a grid point leaves.
"""
import os
from pathlib import Path

import friction_joint
from friction_joint.diagnosis import crossval, structures
from friction_joint.diagnosis.data import load_data
from friction_joint.diagnosis.pipeline import diagnose
from friction_joint.experiments.hidden import (apply_effects, EFFECT_RANGES, RecordingOptions,
                                               simulate_recording)
from friction_joint.experiments.hidden_plant import draw_plant
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
MASTER_SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20251127'))
#: relative tolerance of a refined parameter
TOL = 0.02
#: nuisance odds of the plant draw
ODDS = {'coarse_encoder': 0.0, 'warmup': 0.0}


def _off_grid(rng, lo, hi, grid):
    """Draw uniformly from lo..hi, at least a quarter grid step away from every grid point."""
    step = float(np.min(np.diff(grid)))
    while True:
        x = float(rng.uniform(lo, hi))
        if np.min(np.abs(grid - x)) >= 0.25 * step and np.min(np.abs(grid - x)) > 1.5 * TOL * x:
            return x


def _recording(tmp_path, case, *, plant):
    rng = np.random.default_rng([MASTER_SEED, case])
    dv = _off_grid(rng, *EFFECT_RANGES['nonlinear_viscous']['delta_v'], structures.DV_GRID)
    base = friction_joint.load_gear(BASE)
    truth = apply_effects(base, {'nonlinear_viscous': {'delta_v': dv}})
    seed = int(rng.integers(0, 2**31 - 1))
    # plant nuisance drawn; a coarse encoder and a warm-up are other tests' business
    kwargs, cfg = (draw_plant(rng, duration=(30.0, 45.0), odds=ODDS) if plant
                   else ({'duration': 30.0}, None))
    rec = tmp_path / 'rec'
    simulate_recording(truth, rec, options=RecordingOptions(
        seed=seed, base_gear=base, cfg=cfg, **kwargs))
    what = f'[master seed {MASTER_SEED}] delta_v {dv:.4f}, seed {seed}, plant {kwargs} {cfg}'
    return base, rec, dv, what


def test_delta_v_between_grid_points_is_recovered(tmp_path):
    """fit_all and every CV fold recover a delta_v between grid points within 2 %."""
    base, rec, dv, what = _recording(tmp_path, 0, plant=False)
    data = load_data([str(rec)], base)
    ctx = structures.Context(base, data)
    grid = structures.grid_of(structures.CandidateStructure(dv_free=True), 'dv', ctx)
    nearest = min(abs(s.dv - dv) for s in grid)
    assert nearest > TOL * dv, f'{what}: the draw is on the grid'
    s, _, _, _ = crossval.fit_all(grid, ctx, data.y)
    assert abs(s.dv - dv) <= TOL * dv, f'{what}: fitted delta_v {s.dv:.4f}'
    cv = crossval.cross_validate_structures(grid, ctx, data.y, data.block, data.n_blocks)
    folds = [c.dv for c in cv.structures]
    assert all(abs(f - dv) <= TOL * dv for f in folds), f'{what}: per fold {folds}'
    # a fold refines on its training blocks only: spoiling its held-out block changes nothing
    y = data.y.copy()
    held = data.block == 0
    y[held] += np.sign(y[held]) * np.abs(y[held]) ** 0.5
    spoilt = crossval.cross_validate_structures(grid, ctx, y, data.block, data.n_blocks)
    assert spoilt.structures[0] == cv.structures[0], f'{what}: {spoilt.structures[0]}'
    assert spoilt.structures[1] != cv.structures[1], f'{what}: {spoilt.structures[1]}'


@pytest.mark.parametrize('case', [1, 2])
def test_nonlinear_viscous_alone_is_named(case, tmp_path):
    """A delta_v between grid points is named alone, and fitted within 2 %."""
    base, rec, dv, what = _recording(tmp_path, case, plant=True)
    diag = diagnose([str(rec)], base)
    named = diag.report['named_causes']
    assert named == ['nonlinear_viscous'], f'{what}: named {named}; ' \
        f'candidates {diag.report["candidates"]}'
    fitted = float(np.polynomial.polynomial.polyval(np.mean(diag.gear.friction.temperature_range),
                                                    diag.gear.friction.delta_v))
    assert abs(fitted - dv) <= TOL * dv, f'{what}: extended.yaml delta_v {fitted:.4f}'
