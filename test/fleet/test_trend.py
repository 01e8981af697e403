# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""The wear test on synthetic series: its false-alarm rate, a hinge found, the extra variance."""
from friction_joint.fleet import extra_variance, trend_test
import numpy as np


def _series(rng, n=12, onset=None, slope=0.0, sd=0.01, extra=0.0):
    days = np.arange(n) + rng.uniform(0.25, 0.8, n)
    travel = np.cumsum(rng.uniform(400.0, 4000.0, n))
    se = np.full(n, sd)
    y = 4.8 + rng.normal(0.0, np.sqrt(sd ** 2 + extra ** 2), n)
    if onset is not None:
        y += slope * np.clip(days - onset, 0.0, None)
    return days, travel, y, se


def test_false_alarms_stay_near_alpha_on_flat_series():
    rng = np.random.default_rng(3)
    flags = [trend_test(*_series(rng, extra=0.01), extra_var=0.01 ** 2, n_boot=199,
                        seed=k).wear for k in range(200)]
    assert np.mean(flags) <= 0.03


def test_hinge_found_with_its_onset_and_rate():
    rng = np.random.default_rng(4)
    days, travel, y, se = _series(rng, onset=4.3, slope=0.05)
    res = trend_test(days, travel, y, se, n_boot=199)
    assert res.wear and res.p_value < 0.01
    assert abs(res.onset_day - 4.3) < 1.0
    assert abs(res.rate_per_day - 0.05) < 4 * res.rate_per_day_se
    assert res.to_dict()['onset_range'][0] <= res.onset_day <= res.to_dict()['onset_range'][1]


def test_extra_variance_ignores_a_linear_trend():
    rng = np.random.default_rng(5)
    series = []
    for _ in range(40):
        x = np.cumsum(rng.uniform(0.5, 1.5, 15))
        se = np.full(15, 0.01)
        y = 0.2 * x + rng.normal(0.0, np.hypot(0.01, 0.03), 15)
        series.append((x, y, se))
    assert 0.02 < np.sqrt(extra_variance(series)) < 0.04
