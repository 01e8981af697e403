# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The physical-range check of the temperature polynomials is exact on the interval."""
from friction_joint import gear_from_dict, GearConfigError
from friction_joint.gear.polynomial import interval_minimum
import numpy as np
import pytest


def gear(**friction):
    fr = {'fc': [2.0], 'fv': [0.4]}
    fr.update(friction)
    return {'gear_ratio': 80.0, 'inertia': 0.12, 'friction': fr}


def dip(center, depth, width=1.0):
    """Coefficients of (xi - center)^2 / width^2 - depth: below zero near ``center`` only."""
    return [center ** 2 / width ** 2 - depth, -2.0 * center / width ** 2, 1.0 / width ** 2]


@pytest.mark.parametrize('key, center', [('fc', 51.3), ('fv', 13.7), ('delta_v', 88.8)])
def test_dip_between_the_old_check_points_is_found(key, center):
    """Negative only within +-0.7 degC of ``center``, between the 41 points checked before."""
    coef = dip(center, 0.5)
    grid = np.polynomial.polynomial.polyval(np.linspace(0.0, 100.0, 41), coef)
    assert np.all(grid > 0)                                 # the old check passed it
    with pytest.raises(GearConfigError,
                       match=rf'friction.{key}: evaluates to -0.5 \(must be [>=]+ 0\) at '
                             rf'xi = {center:.1f} degC inside friction.temperature_range'):
        gear_from_dict(gear(**{key: coef}))


def test_stribeck_pair_dip_is_found():
    with pytest.raises(GearConfigError, match=r'friction.vs: evaluates to .* at xi = 70.1 degC'):
        gear_from_dict(gear(fs=[3.0], vs=dip(70.1, 1e-3, width=0.01)))


def test_the_range_decides_and_endpoints_count():
    ok = gear(fc=dip(51.3, 0.5), temperature_range=[20.0, 50.0])
    assert gear_from_dict(ok).friction.fc == tuple(dip(51.3, 0.5))
    # negative from the low end on: reported at the low end
    with pytest.raises(GearConfigError, match=r'friction.fc: evaluates to -3 .* xi = 20.0 degC'):
        gear_from_dict(gear(fc=[-5.0, 0.1], temperature_range=[20.0, 50.0]))
    # zero is allowed for F_c (>= 0) but not for v_s (> 0)
    gear_from_dict(gear(fc=[0.0, 0.1], temperature_range=[0.0, 50.0]))
    with pytest.raises(GearConfigError, match=r'friction.vs: evaluates to 0 \(must be > 0\)'):
        gear_from_dict(gear(fs=[3.0], vs=[0.0, 0.01], temperature_range=[0.0, 50.0]))


def test_interval_minimum_matches_a_dense_grid():
    rng = np.random.default_rng(7)
    for order in range(9):
        for _ in range(20):
            coef = rng.normal(size=order + 1) / 10.0 ** np.arange(order + 1)
            lo, hi = sorted(rng.uniform(-20, 120, size=2))
            value, where = interval_minimum(coef, lo, hi)
            xi = np.linspace(lo, hi, 200_001)
            dense = np.polynomial.polynomial.polyval(xi, coef)
            scale = np.max(np.abs(dense)) + 1e-300
            assert lo <= where <= hi
            assert value <= dense.min() + 1e-12 * scale
            assert value >= dense.min() - 1e-6 * scale
            assert value == pytest.approx(np.polynomial.polynomial.polyval(where, coef),
                                          rel=1e-12, abs=1e-12 * scale)
