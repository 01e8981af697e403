# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
One step of the joint integrated together with each friction model: the kernels of :mod:`.joint`.

:func:`_lugre_joint_step`, :func:`_gms_joint_step` and :func:`_static_joint_step`
advance the joint J qdd = f - tau_r with the LuGre, GMS or static friction
torque tau_r over one step; :mod:`.joint` (its module docstring describes the
scheme) runs them over a batch and a sequence of samples.  They keep private names (numba
kernels of 12 to 18 positional scalars, not an interface): ``__all__`` lists them for
:mod:`.joint`, their one caller.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ._expint import affine2_step, implicit_euler_v
from .gms import gms_update_ramp
from .lugre import G_MIN, lugre_torque
from .static import g_abs, s_visc, sign
from .._jit import njit

if TYPE_CHECKING:
    from typing import TypeAlias

    from numpy.typing import NDArray

    #: a float array: the elements' rows (N,)
    _A: TypeAlias = NDArray[np.float64]

__all__ = ['_lugre_joint_step', '_gms_joint_step', '_static_joint_step']


@njit
def _chord(fv: float, dv: float, kap: float, v0: float, v1: float,
           s0: float) -> tuple[float, float]:
    """Slope and offset of the viscous term's chord between v0 and v1."""
    if v1 == v0:
        return 0.0, s0
    c = (s_visc(fv, dv, kap, v1) - s0) / (v1 - v0)
    return max(c, 0.0), s0 - max(c, 0.0) * v0


@njit
def _implicit_visc(m: float, r: float, c: float, dv: float, vguess: float) -> float:
    """
    Root of m v + c sign(v)|v|^dv = r (m > 0, c >= 0); unique, sign(v) = sign(r).

    Newton on the convex increasing function of w = |v|^dv (dv < 1) or
    u = |v| (dv >= 1): after its first step it approaches the root from
    above, so it converges from any start.  Warm start at |vguess|.
    """
    if r == 0.0:
        return 0.0
    ar = abs(r)
    if c == 0.0:
        return r / m
    same = vguess != 0.0 and (vguess > 0.0) == (r > 0.0)
    if dv < 1.0:
        p = 1.0 / dv
        w: float = abs(vguess) ** dv if same else min(ar / c, (ar / m) ** dv)
        for _ in range(50):
            wp1 = w ** (p - 1.0)
            dw = (m * wp1 * w + c * w - ar) / (m * p * wp1 + c)
            w -= dw
            if abs(dw) <= 1e-13 * w:
                break
        u: float = w ** p
    else:
        u = abs(vguess) if same else ar / m
        for _ in range(50):
            up1 = u ** (dv - 1.0)
            du = (m * u + c * up1 * u - ar) / (m + c * dv * up1)
            u -= du
            if abs(du) <= 1e-13 * u:
                break
    return u if r > 0.0 else -u


@njit
def _lugre_joint_step(q: float, v: float, z: float, f: float, jj: float, sg0: float, sg1: float,
                      fc: float, fs: float, fv: float, vs: float, dv: float, ds: float,
                      kap: float, h: float) -> tuple[float, float, float, float]:
    """One coupled step of joint + LuGre; returns (q, v, z, tau_r) at the step's end."""
    s0 = s_visc(fv, dv, kap, v)
    # predictor: implicit Euler, LuGre rate at v; s(vn) implicit where its slope
    # is stiff (h s'(v) > J/2, always near qd = 0), else held at s(v)
    g0 = max(g_abs(fc, fs, vs, ds, kap, v), G_MIN)
    a = sg0 * abs(v) / g0
    if v == 0.0 or h * dv * s0 / v > 0.5 * jj:
        dd = 1.0 + h * a
        vn = _implicit_visc(jj + h * (sg1 + h * sg0) / dd,
                            jj * v + h * (f - (sg0 - sg1 * a) * z / dd),
                            h * fv * kap ** dv, dv, v)
    else:
        vn = implicit_euler_v((-a, 1.0, -(sg0 - sg1 * a) / jj, -sg1 / jj),
                              (0.0, (f - s0) / jj), (z, v), h)
    c, sc = _chord(fv, dv, kap, v, vn, s0)
    if v * vn > 0.0:
        # corrector (no reversal in the step): exponential Rosenbrock-Euler, the
        # system linearised at the step's start with its exact Jacobian, d(a z)/dv
        # included; s by its chord.  Second order also where the bristle
        # relaxation is stiff (a h >> 1): the end state then sits on the
        # linearised quasi-equilibrium, which is exact to O(h^2)
        a = sg0 * abs(v) / g0
        x = abs(kap * v / vs)
        u: float = x * x if ds == 2.0 else x ** ds
        da = sg0 * (g0 + (fs - fc) * math.exp(-u) * ds * u) / (g0 * g0)
        if v < 0.0:
            da = -da
        d1 = 1.0 - da * z
        zn, vn, _, dq = affine2_step((-a, d1, -(sg0 - sg1 * a) / jj, -(sg1 * d1 + c) / jj),
                                     (v * da * z, (f - sg1 * v * da * z - sc) / jj), (z, v), h)
    else:
        # a reversal (or rest) inside the step: rate frozen at the mid-step velocity
        vm = 0.5 * (v + vn)
        a = sg0 * abs(vm) / max(g_abs(fc, fs, vs, ds, kap, vm), G_MIN)
        zn, vn, _, dq = affine2_step((-a, 1.0, -(sg0 - sg1 * a) / jj, -(sg1 + c) / jj),
                                     (0.0, (f - sc) / jj), (z, v), h)
    tau_r = lugre_torque(zn, vn, sg0, sg1, g_abs(fc, fs, vs, ds, kap, vn),
                         s_visc(fv, dv, kap, vn))
    return q + dq, vn, zn, tau_r


@njit
def _gms_joint_step(q: float, v: float, z: _A, stick: NDArray[np.int8], slipdir: _A, k: _A,
                    alpha: _A, cc: float, f: float, jj: float, fc: float, fs: float, fv: float,
                    vs: float, dv: float, ds: float, kap: float,
                    h: float) -> tuple[float, float, float]:
    """
    One coupled step of joint + GMS (element arrays updated in place).

    A velocity reversal or an element's slip onset predicted inside the step
    splits it there, so the elements stick again at the reversal and not a
    step late (which would leave an O(h) error in every element's
    deflection), and the element torques are smooth inside each substep (a
    kink inside leaves an O(h^2) velocity error, large with stiff elements).
    At most three splits per step.  Returns (q, qd, tau_r) at the step's end.
    """
    tau_r = 0.0
    for n in range(4):
        q, v, tau_r, h = _gms_substep(q, v, z, stick, slipdir, k, alpha, cc, f, jj,
                                      fc, fs, fv, vs, dv, ds, kap, h, n < 3)
        if h <= 0.0:
            break
    return q, v, tau_r


@njit(inline='always')
def _gms_sticking(z: _A, stick: NDArray[np.int8], slipdir: _A, k: _A,
                  sv: float) -> tuple[float, float]:
    """Stiffness of the elements that stick for velocity sign sv, and the total torque."""
    kst = 0.0
    ftot = 0.0
    for i in range(z.shape[0]):
        ftot += k[i] * z[i]
        if stick[i] == 1 or sv != slipdir[i]:
            kst += k[i]
    return kst, ftot


@njit
def _gms_substep(q: float, v: float, z: _A, stick: NDArray[np.int8], slipdir: _A, k: _A,
                 alpha: _A, cc: float, f: float, jj: float, fc: float, fs: float, fv: float,
                 vs: float, dv: float, ds: float, kap: float, h: float,
                 split: bool) -> tuple[float, float, float, float]:
    """
    Joint + GMS over h; returns (q, qd, tau_r, rest).

    With ``split``, a velocity reversal or an element's slip onset predicted
    inside the step ends the substep there and ``rest`` is the time left of
    the step (0 otherwise).

    The sticking elements are springs inside the exactly solved 2x2 system;
    the torque of the others (slipping, or changing state in the step) is a
    load whose change over the step is taken linear in time: a first pass with
    it held at its start value predicts its end value, the second pass uses
    the mean of both (trapezoidal, second order).
    """
    kst, ftot = _gms_sticking(z, stick, slipdir, k, sign(v))
    s0 = s_visc(fv, dv, kap, v)
    a = (0.0, 1.0, -kst / jj, 0.0)
    vn = implicit_euler_v(a, (0.0, (f - ftot - s0) / jj), (0.0, v), h)
    full = h
    if split and vn * v < 0.0:
        h1 = h * v / (v - vn)
        if 1e-3 * h < h1 < (1.0 - 1e-3) * h:
            h = h1
            vn = implicit_euler_v(a, (0.0, (f - ftot - s0) / jj), (0.0, v), h)
    curve = (fc, fs, vs, ds, kap)
    elements = (k, alpha, cc)
    for n in range(2):
        c, sc = _chord(fv, dv, kap, v, vn, s0)
        dn, vn, _, _ = affine2_step((0.0, 1.0, -kst / jj, -c / jj),
                                    (0.0, (f - ftot - sc) / jj), (0.0, v), h)
        # what the elements' torque does beyond the sticking springs, predicted
        pred, onset = gms_update_ramp((z, stick, slipdir), elements, (v, vn, dn), h, curve,
                                      False)
        if n == 1 or not (split and 1e-3 * h < onset < (1.0 - 1e-3) * h):
            break
        h = onset                        # a slip onset inside: end the substep there
        vn = implicit_euler_v(a, (0.0, (f - ftot - s0) / jj), (0.0, v), h)
    extra = pred - ftot - kst * dn
    c, sc = _chord(fv, dv, kap, v, vn, s0)
    dn, vn, _, _ = affine2_step((0.0, 1.0, -kst / jj, -c / jj),
                                (0.0, (f - ftot - 0.5 * extra - sc) / jj), (0.0, v), h)
    tot, _ = gms_update_ramp((z, stick, slipdir), elements, (v, vn, dn), h, curve)
    return q + dn, vn, tot + s_visc(fv, dv, kap, vn), full - h


@njit
def _static_joint_step(q: float, v: float, f: float, jj: float, fc: float, fs: float, fv: float,
                       vs: float, dv: float, ds: float, kap: float,
                       h: float) -> tuple[float, float, float]:
    """
    One step of joint + static friction with a Karnopp stick zone.

    When the velocity would reach zero inside the step the joint sticks if the
    net torque is within the break-away torque F_s, and otherwise moves on in
    the direction of the net torque for the rest of the step.
    """
    if v == 0.0:
        if abs(f) <= fs:
            return q, 0.0, f
        vn = h * (f - sign(f) * fs) / jj
        return q + 0.5 * h * vn, vn, sign(f) * fs
    fr = sign(v) * g_abs(fc, fs, vs, ds, kap, v) + s_visc(fv, dv, kap, v)
    vn = v + h * (f - fr) / jj
    if sign(vn) != sign(v):
        t0 = h * v / (v - vn)
        if abs(f) <= fs:
            return q + 0.5 * t0 * v, 0.0, f - jj * (0.0 - v) / h
        vn = (h - t0) * (f - sign(f) * fs) / jj
        return q + 0.5 * t0 * v + 0.5 * (h - t0) * vn, vn, f - jj * (vn - v) / h
    return q + 0.5 * h * (v + vn), vn, fr
