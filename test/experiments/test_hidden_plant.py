# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The plant nuisances of the hidden-effect simulator: what real robot data look like.

One-way sweeps through large angles, coarse encoders, speed ranges of several
hundred to one and warm-up recordings, drawn by
:func:`~friction_joint.experiments.hidden_plant.draw_plant` (seeded draws) and
checked on the planned reference or the simulated recording.
"""
import math
import warnings

import friction_joint
from friction_joint.experiments.hidden import (plan_segment, RecordingOptions, SEGMENT,
                                               simulate_recording)
from friction_joint.experiments.hidden_plant import draw_plant, RUN_KINDS
import numpy as np

BASE = 'config/csd25_base.yaml'
DT = 1.0 / 3000.0
SEED = 20261127


def _base():
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        return friction_joint.load_gear(BASE)


def test_sweep_oneway_never_reverses_and_covers_three_radians():
    rng = np.random.default_rng(SEED)
    assert 'sweep_oneway' in RUN_KINDS
    drawn = [k for _ in range(40) for k in draw_plant(rng)[0]['kinds']]
    assert 'sweep_oneway' in drawn
    for _ in range(12):
        duration = float(np.exp(rng.uniform(math.log(5.0), math.log(150.0))))
        q, qd, qdd = plan_segment(rng, 80.0, DT, duration, float(rng.uniform(-3, 3)), SEGMENT,
                                  kind='sweep_oneway')
        sign = np.sign(qd[np.argmax(np.abs(qd))])
        assert np.all(sign * qd >= 0.0), 'the sweep reverses'
        travel = sign * (q[-1] - q[0])
        assert 3.0 <= travel <= 6.0 + 1e-9
        assert np.ptp(q) == travel, 'the position goes back somewhere'
        assert len(q) * DT <= duration + 1e-9
        # starts and ends at rest, consistent reference (the controller tracks it)
        assert qd[0] == 0.0 and qd[-1] == 0.0
        np.testing.assert_allclose(np.diff(q) / DT, qd[1:], atol=1e-6 * np.max(np.abs(qd)))
        assert np.max(np.abs(np.diff(qd) / DT - qdd[1:])) < 0.05 * np.max(np.abs(qdd)) + 1e-3


def test_coarse_encoder_counts_per_turn():
    rng = np.random.default_rng(SEED + 1)
    bits = [draw_plant(rng, odds={'coarse_encoder': 1.0})[0]['encoder_bits'] for _ in range(30)]
    assert all(1000 <= 2 ** b <= 20000 for b in bits)
    assert len(set(bits)) >= 3
    b = bits[0]
    topics, _ = simulate_recording(_base(), None, options=RecordingOptions(
        duration=3.0, seed=3, n_segments=1, command=False, encoder_bits=b))
    q = np.unique(topics['/joint_states']['q'])
    step = np.min(np.diff(q))
    counts = 2.0 * math.pi / step
    assert abs(counts - 2 ** b) < 1e-6 * 2 ** b, (counts, b)
    # positions are whole counts
    k = q / step
    assert np.max(np.abs(k - np.round(k))) < 1e-6


def test_warmup_temperature_never_falls():
    rng = np.random.default_rng(SEED + 2)
    plant, cfg = draw_plant(rng, (4.0, 8.0), kinds=('plateaus', 'oneway', 'sweep_oneway'),
                            odds={'warmup': 1.0})
    assert plant['warmup'] is True
    base = _base()
    topics, summary = simulate_recording(base, None, options=RecordingOptions(
        seed=int(rng.integers(1000)), cfg=cfg, link_torque=False, command=False, **plant))
    xi = topics['/joint_temperature']['xi']
    assert np.all(np.diff(xi) >= 0.0), 'the warm-up temperature falls'
    seg = summary['segments']
    for a, b in zip(seg, seg[1:], strict=False):
        assert b['xi_start'] > a['xi_end'] > a['xi_start']
    # it spans most of the base's temperature range (a warm-up, not self-heating)
    lo, hi = base.friction.temperature_range
    assert seg[-1]['xi_end'] - seg[0]['xi_start'] > 0.5 * (hi - lo)


def _plateau_ratio(qd):
    """Fastest / slowest plateau speed: constant-velocity stretches run both ways."""
    steady = qd[1:][(np.diff(qd) == 0.0) & (qd[1:] != 0.0)]
    v = np.unique(np.round(steady, 12))
    both = v[np.isin(-v, v) & (v > 0)]
    return both.max() / both.min()


def test_wide_speed_range_plateaus():
    rng = np.random.default_rng(SEED + 3)
    ratios = []
    for _ in range(6):
        _, cfg = draw_plant(rng, odds={'wide_speeds': 1.0})
        _, qd, _ = plan_segment(rng, 80.0, DT, float(rng.uniform(10.0, 40.0)), 0.0,
                                dict(SEGMENT, **cfg), kind='rich')
        ratios.append(_plateau_ratio(qd))
    assert min(ratios) >= 300.0, ratios
    assert max(ratios) <= 2000.0, ratios
    # without the draw the plan keeps the base bands (ratio below 150)
    _, cfg = draw_plant(rng, odds={'wide_speeds': 0.0})
    assert 'speed_ratio' not in cfg
    _, qd, _ = plan_segment(rng, 80.0, DT, 20.0, 0.0, dict(SEGMENT, **cfg), kind='rich')
    assert _plateau_ratio(qd) < 300.0
