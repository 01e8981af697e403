# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Regular stamps at any rate stay as they are; only irregular ones are resampled."""
from friction_joint.bag.stamps import piece_on_grid, uniform_grid
import numpy as np
import pytest


@pytest.mark.parametrize('seed', range(6))
def test_regular_stamps_rounded_to_nanoseconds_are_not_resampled(seed):
    """Before: 3 kHz / 14 (a step of 4666666.67 ns) was 'irregular' and interpolated."""
    rng = np.random.default_rng(seed)
    rate = 3000.0 / int(rng.integers(1, 16)) * rng.uniform(0.5, 2.0)
    n = int(rng.integers(1000, 50000))
    t = np.round((rng.uniform(0, 100) + np.arange(n) / rate) * 1e9) * 1e-9   # a bag's stamps
    count = 2 * np.pi / 2 ** int(rng.integers(10, 15))                   # a coarse encoder
    q = np.round(np.cumsum(rng.normal(0, 3 * count, n)) / count) * count
    dt, grid = uniform_grid(t)
    assert grid is None and dt == pytest.approx(1.0 / rate, rel=1e-9)
    t2, (q2,), ok = piece_on_grid(t, (q,), [])
    # the samples as they are, on the exact grid the stamps were rounded from
    assert np.array_equal(q2, q) and ok.all() and len(t2) == len(t)
    assert np.max(np.abs(t2 - t)) <= 1e-6 * dt
    assert np.allclose(np.diff(t2), dt, rtol=1e-9, atol=0)
    steps = np.abs(np.diff(q2))
    assert steps[steps > 0].min() == pytest.approx(count, rel=1e-9)      # whole counts


def test_irregular_stamps_are_resampled():
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, 5000))
    dt, grid = uniform_grid(t)
    assert grid is not None and dt == pytest.approx(np.median(np.diff(t)))
