# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The diagnosis's pre-sliding states come from the models' updates and equal the closed forms.

:mod:`friction_joint.diagnosis.states` drives the LuGre and GMS states with
:func:`~friction_joint.models.lugre.lugre_update` and
:func:`~friction_joint.models.gms.gms_update` in normalised units.  On seeded
random position increments (both directions, reversals, standstill, pieces)
they must equal the closed forms to 1e-12: LuGre h+ = +-1 + (h -+ 1)
exp(-a |dq|), GMS h = sum alpha_i clip(h_i + k_i dq / alpha_i, -1, 1), both
restarting at 0 with every piece.
"""
import math
import os
from types import SimpleNamespace

from friction_joint.diagnosis import states
import numpy as np
import pytest

SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20251127'))
TOL = 1e-12
#: LuGre steps below this a |dq| are taken to first order by lugre_update (error <= a |dq| |h|)
SMALL = 1e-12


def _lugre_reference(dq, piece, a):
    out, h = np.empty_like(dq), 0.0
    for k, d in enumerate(dq):
        if k == 0 or piece[k] != piece[k - 1]:
            h = 0.0
        if d != 0.0:
            s = math.copysign(1.0, d)
            h = s + (h - s) * math.exp(-a * abs(d))
        out[k] = h
    return out


def _gms_reference(dq, piece, k, alpha):
    out, h = np.empty_like(dq), np.zeros(len(k))
    for j, d in enumerate(dq):
        if j == 0 or piece[j] != piece[j - 1]:
            h[:] = 0.0
        h = np.clip(h + k / alpha * d, -1.0, 1.0)
        out[j] = alpha @ h
    return out


def _increments(rng, n=4000, scale=1e-4):
    """Position increments: runs of both signs, standstill (zeros), jitter, steps to 1e-9."""
    run = np.repeat(rng.choice([-1.0, 1.0], n // 50), 50)
    dq = run * scale * 10.0 ** rng.uniform(-5.0, 1.0, n)
    dq[rng.random(n) < 0.15] = 0.0                       # standstill
    jitter = rng.random(n) < 0.05                        # isolated reversals
    dq[jitter] *= -1.0
    piece = np.cumsum(rng.random(n) < 0.004)             # piece starts
    return dq, piece


@pytest.mark.parametrize('trial', range(4))
def test_lugre_state_is_the_exact_update(trial):
    rng = np.random.default_rng([SEED, trial])
    dq, piece = _increments(rng)
    a = 10.0 ** rng.uniform(2.0, 6.0)                    # pre-sliding lengths 1e-6 .. 1e-2 rad
    out = np.empty_like(dq)
    states._lugre_state(dq, piece, a, out)
    ref = _lugre_reference(dq, piece, a)
    assert np.max(np.abs(out - ref)) < TOL
    assert np.all(np.abs(out) <= 1.0 + TOL)
    first = np.r_[True, piece[1:] != piece[:-1]]
    assert np.all(out[first & (dq == 0.0)] == 0.0)       # a piece starts relaxed
    big = np.abs(a * dq) > 10.0
    assert np.allclose(out[big], np.sign(dq[big]), atol=1e-4)   # sliding: +-1


def test_lugre_state_tiny_steps_stay_within_their_first_order_error():
    rng = np.random.default_rng([SEED, 99])
    dq, piece = _increments(rng, n=2000)
    a = 1e4
    dq[::7] = rng.normal(0.0, 1e-18, len(dq[::7]))       # standstill noise, a |dq| < 1e-12
    out = np.empty_like(dq)
    states._lugre_state(dq, piece, a, out)
    small = (np.abs(a * dq) < SMALL) & (dq != 0.0)
    bound = TOL + np.sum(np.abs(a * dq[small]))
    assert np.max(np.abs(out - _lugre_reference(dq, piece, a))) < bound


@pytest.mark.parametrize('trial', range(4))
def test_gms_state_is_maxwell_slip(trial):
    rng = np.random.default_rng([SEED, 10 + trial])
    dq, piece = _increments(rng)
    alpha = rng.dirichlet(np.ones(4))
    k = 10.0 ** rng.uniform(2.0, 6.0) * np.array([0.6, 0.25, 0.1, 0.05])
    out = np.empty_like(dq)
    states._gms_state(dq, piece, k, alpha, out)
    assert np.all(np.isfinite(out))
    assert np.max(np.abs(out - _gms_reference(dq, piece, k, alpha))) < TOL


def test_gms_state_exactly_at_the_threshold_is_finite():
    """Increments that put elements exactly on (or a rounding past) their threshold: no nan."""
    alpha = np.array([0.5, 0.3, 0.2])
    k = np.array([3.0, 1.0, 0.7])
    dq = np.r_[[1.0 / 6.0] * 3, [-1.0 / 3.0] * 6, [1e-17, -1e-17] * 4, [0.1] * 30]
    piece = np.zeros(len(dq), dtype=int)
    out = np.empty_like(dq)
    states._gms_state(dq, piece, k, alpha, out)
    assert np.all(np.isfinite(out))
    assert np.max(np.abs(out - _gms_reference(dq, piece, k, alpha))) < TOL
    assert out[-1] == pytest.approx(1.0, abs=1e-15)
    # f + k dq rounds up to the threshold though (threshold - f) / (k dq) = 2: the slip onset
    # lies a step past the step's end, where an infinite attraction gives inf * 0 = nan
    dq = np.array([1.0 - 2.0 ** -53, 2.0 ** -54, 0.0, 2.0 ** -54])
    out = np.empty_like(dq)
    states._gms_state(dq, np.zeros(4, dtype=int), np.ones(1), np.ones(1), out)
    assert list(out) == [1.0 - 2.0 ** -53, 1.0, 1.0, 1.0]


def test_presliding_state_of_a_context():
    """:func:`presliding_state` scales by the Coulomb level and restarts with each piece."""
    rng = np.random.default_rng([SEED, 20])
    dq, piece = _increments(rng, n=1500)
    qf = np.cumsum(dq)
    ratios = np.array([0.6, 0.25, 0.1, 0.05])
    ctx = SimpleNamespace(data=SimpleNamespace(qf=qf, piece=piece), g_nom=2.5,
                          gms_ratios=ratios, gms_alpha=np.full(4, 0.25))
    inc = np.diff(qf, prepend=qf[0])
    inc[np.r_[True, piece[1:] != piece[:-1]]] = 0.0
    stiff = 5e4
    lugre = states.presliding_state(ctx, ('lugre', stiff))
    assert np.max(np.abs(lugre - _lugre_reference(inc, piece, stiff / 2.5))) < TOL
    gms = states.presliding_state(ctx, ('gms', stiff))
    ref = _gms_reference(inc, piece, stiff * ratios / 2.5, ctx.gms_alpha)
    assert np.max(np.abs(gms - ref)) < TOL
