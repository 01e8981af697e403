# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Coarse encoders: noise scales measured as they are, pre-sliding seen after reversals.

The simulated test bed runs the CSD-25 base with a coarse encoder (10-14 bits,
drawn; 11-14 with pre-sliding: at 1 024 counts per turn the derivative filter
that keeps this heavy joint's acceleration clean leaves the pre-sliding gain
near the 3 % threshold) and, in most cases, a pre-sliding truth (LuGre or GMS, drawn by
:func:`~friction_joint.experiments.hidden.draw_effect`) whose pre-sliding
length spans a drawn 4-16 encoder counts, as on a small servo with 10 000
counts per turn and a 0.01 rad pre-sliding length (the CSD-25's own
0.1 mrad would hide within one count of such an encoder, and no data could
show it).  ``diagnose`` sees the recording and the static base only.  The
measured velocity noise must be the quantisation noise the encoder gives
through the derivative filter (computed here from the truth's encoder), the
sliding threshold a few of its standard deviations, the pre-sliding
candidate named; without a hidden effect, nothing.  Draws are seeded
(override with ``FRICTION_JOINT_TEST_SEED``).
"""
import math
import os
from pathlib import Path
import warnings

import friction_joint
from friction_joint._filters import zero_phase_derivatives
from friction_joint.diagnosis import diagnose, load_data
from friction_joint.exceptions import GearConfigWarning
from friction_joint.experiments.hidden import (apply_effects, draw_effect, RecordingOptions,
                                               simulate_recording)
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
MASTER_SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20251127'))
DURATION = 30.0


def _truth(case, hidden):
    """Seeded truth: coarse encoder, pre-sliding spanning some counts (or nothing)."""
    rng = np.random.default_rng([MASTER_SEED, case])
    base = friction_joint.load_gear(BASE)
    bits = int(rng.integers(11 if hidden else 10, 15))
    res = 2.0 * math.pi / 2 ** bits
    effects, what = {}, {'encoder_bits': bits}
    if hidden:
        size = draw_effect(rng, 'presliding')
        counts = float(rng.uniform(4.0, 16.0))
        f = base.friction
        stiffness = f.lugre.sigma0 if size['model'] == 'lugre' else float(sum(f.gms.k))
        size['stiffness_scale'] = float(f.fc[0]) / (stiffness * counts * res)
        effects = {'presliding': size}
        what.update(size, counts=round(counts, 2))
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', GearConfigWarning)
        truth = apply_effects(base, effects).replace({'sensors': {'encoder_bits': bits}})
    return base, truth, res, int(rng.integers(0, 2**31 - 1)), what


def _quantisation_noise(res, dt, cutoff):
    """Return the std of the velocity of a white position error uniform over one count."""
    rng = np.random.default_rng(0)
    qd, _ = zero_phase_derivatives(res * (rng.random(200_000) - 0.5), dt, cutoff=cutoff)
    return float(np.std(qd[1000:-1000]))


@pytest.mark.parametrize('case,hidden', [(0, True), (1, True), (2, False)])
def test_coarse_encoder_scales_and_presliding(case, hidden, tmp_path):
    base, truth, res, seed, what = _truth(case, hidden)
    what = f'[master seed {MASTER_SEED}] case {case}: {what}, recording seed {seed}'
    rec = tmp_path / 'rec'
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=DURATION, seed=seed, base_gear=base))
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        data = load_data([str(rec)], base)
        report = diagnose([str(rec)], base).report

    named = report['named_causes']
    cands = [(c['effect'], round(c['gain'], 3), c.get('p_holm')) for c in report['candidates']]
    assert named == (['presliding'] if hidden else []), f'{what}: named {named} {cands}'

    dt = float(np.median(data.dt))
    sigma = _quantisation_noise(res, dt, data.cutoff)
    scales = (f'resolution {data.resolution:.3g} (truth {res:.3g}), cutoff {data.cutoff:.3g} Hz, '
              f'velocity noise {data.velocity_noise:.3g} (truth {sigma:.3g}), '
              f'v_stick {data.v_stick:.3g} rad/s')
    assert data.resolution == pytest.approx(res, rel=0.25), f'{what}: {scales}'
    assert 1.0 / 3.0 <= data.velocity_noise / sigma <= 3.0, f'{what}: {scales}'
    assert sigma <= data.v_stick <= 5.0 * sigma, f'{what}: {scales}'
