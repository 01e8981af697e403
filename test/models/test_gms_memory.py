# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
GMS pre-sliding memory: reversal stiffness, Masing rule, non-local memory (seed eq. 11-13).

The displacement path is imposed through the velocity input of
:meth:`GMS.simulate`: every step moves by exactly +-V0*DT, so all paths sit
on one grid of positions (counted in integer steps) and can be compared
point by point.  The speed magnitude is constant, so the Stribeck curve
g(V0) and hence every element's break-away torque alpha_i g is constant:
a slipping element then sits exactly at its share of g and the model is the
rate-independent Maxwell-slip (Iwan) model, whose memory rules hold
exactly.  Tolerances are therefore round-off level; the only difference
between two paths to the same state is the order of floating-point
additions (~1e-15 N here), so 1e-9 relative is a wide margin.
"""
from friction_joint import gear_from_dict, GMS, StaticFriction
import numpy as np
import pytest

K = np.array([3e4, 2e4, 1e4, 5e3])      # element stiffnesses (N/m)
ALPHA = np.full(4, 0.25)                 # the paper's mu = 1/N (default)
FC, FS, VS, FV = 1.0, 1.5, 1e-3, 0.4
V0 = 1e-4                                # imposed speed magnitude (m/s)
DT = 1e-3                                # one step = 1e-7 m
H = V0 * DT
XI = 30.0


@pytest.fixture(scope='module')
def friction():
    gear = gear_from_dict({'gear_ratio': 1.0, 'inertia': 1.0, 'friction': {
        'model': 'gms', 'fc': [FC], 'fs': [FS], 'vs': [VS], 'fv': [FV],
        'gms': {'k': K.tolist(), 'c': 20.0}}})
    return gear.friction


@pytest.fixture(scope='module')
def limits(friction):
    """Break-away deflections d_i = alpha_i g(V0) / k_i, in steps."""
    g = StaticFriction(friction).components(V0, XI)[0][0]
    assert g == pytest.approx(FC + (FS - FC) * np.exp(-(V0 / VS) ** 2))
    return ALPHA * g / K / H


def path(*targets):
    """Velocities (T,) moving through the given positions (integer steps) at +-V0."""
    legs, pos = [], 0
    for target in targets:
        legs.append(np.full(abs(target - pos), np.sign(target - pos) * V0))
        pos = target
    return np.concatenate(legs)


def run(friction, qd):
    """Elastic torque sum k_i z_i after each step, and the position in steps."""
    tau = GMS(friction).simulate(qd, XI, 0.0, DT, reset=True)
    elastic = tau - FV * qd                       # s(v) = Fv v (delta_v = 1)
    pos = np.cumsum(np.sign(qd)).astype(int)
    return elastic, pos


def test_stiffness_after_reversal_is_sum_of_element_stiffnesses(friction, limits):
    a = 1000                                      # 1e-4 m: all elements slip (d < 750 steps)
    assert limits.max() < a
    elastic, pos = run(friction, path(a, -a))
    k = a - 1                                     # last step before the reversal
    # all elements slip at alpha_i g before the reversal ...
    assert elastic[k] == pytest.approx(FC + (FS - FC) * np.exp(-(V0 / VS) ** 2), rel=1e-12)
    # ... and all stick right after it: stiffness sum k_i on the first step
    assert (elastic[k + 1] - elastic[k]) / -H == pytest.approx(K.sum(), rel=1e-6)
    # further on the tangent stiffness is the sum over elements still
    # sticking: element i slips again after a travel of 2 d_i
    slope = (elastic[k + 1:k + 2 * a] - elastic[k:k + 2 * a - 1]) / -H
    travel = np.arange(1, 2 * a)                  # steps since the reversal
    bounds = np.r_[0, np.sort(2 * limits), 2 * a]
    for lo, hi in zip(bounds[:-1], bounds[1:], strict=True):
        inside = (travel > lo + 1) & (travel < hi - 1)   # away from the break points
        expected = K[2 * limits > lo + 1].sum()
        np.testing.assert_allclose(slope[inside], expected, rtol=1e-9, atol=1e-6)


def test_reversal_curve_follows_masing_rule(friction, limits):
    """F_rev(delta) = F_A - 2 F_virgin(delta / 2) (Masing), for the elastic torque."""
    a = 1000
    elastic, pos = run(friction, path(a, -a))
    virgin = elastic[:a]                          # F after 1 .. a steps from rest
    f_a = elastic[a - 1]
    delta = np.arange(2, 2 * a + 1, 2)            # even travels since the reversal
    rev = elastic[a - 1 + delta]
    np.testing.assert_allclose(rev, f_a - 2.0 * virgin[delta // 2 - 1], rtol=1e-9, atol=1e-12)


def test_inner_loop_closes_and_outer_branch_is_resumed(friction, limits):
    a, b, c = 1000, 200, -100                     # -A < C < B < A, in steps of 1e-7 m
    # design checks: at B (travel A + B from -A) the softest element still
    # sticks, so the state at B is not simply "all saturated"; the inner
    # loop B -> C makes the stiffest element slip but not the next one
    assert 2 * limits[3] > a + b and 2 * limits[2] < a + b
    assert 2 * limits[0] < b - c < 2 * limits[1]
    f1, x1 = run(friction, path(a, -a, b, c, b, a))    # with the inner loop
    f2, x2 = run(friction, path(a, -a, a))              # straight back to +A

    # indices: first arrival at B, turn at C, return to B
    n_b1 = a + 2 * a + (a + b) - 1
    n_c = n_b1 + (b - c)
    n_b2 = n_c + (b - c)
    assert (x1[n_b1], x1[n_c], x1[n_b2]) == (b, c, b)
    assert x2[n_b1] == b
    # it is a real loop: the torque on the way back up lies above the way down
    mid = (b + c) // 2
    down = f1[n_b1 + (b - mid)]
    up = f1[n_c + (mid - c)]
    assert up - down > 1e-3
    # the inner loop closes: same torque at B on both passes
    assert f1[n_b2] == pytest.approx(f1[n_b1], rel=1e-9, abs=1e-12)
    # ... and the path without the loop is at the same torque at B
    assert f2[n_b1] == pytest.approx(f1[n_b1], rel=1e-9, abs=1e-12)
    # beyond B the outer branch resumes: identical torque at identical positions
    tail1 = f1[n_b2:]
    tail2 = f2[n_b1:]
    np.testing.assert_array_equal(x1[n_b2:], x2[n_b1:])
    assert len(tail1) == a - b + 1
    np.testing.assert_allclose(tail1, tail2, rtol=1e-9, atol=1e-12)
    # and that branch differs from the inner one (memory is not trivial):
    # between C and B the loop branch lies below the outer branch
    outer_at_mid = f2[n_b1 - (b - mid)]
    assert outer_at_mid - up > 1e-3
