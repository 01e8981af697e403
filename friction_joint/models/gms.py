# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Modified Generalized Maxwell-Slip (GMS) friction model (seed eq. 11-13).

N elasto-slide elements in parallel plus the viscous term:

    tau_rd = sum_i k_i z_i + s(qd, xi, tau_L)                                (13)

Dimensionally consistent form
-----------------------------
The paper writes the sticking law in deflection units (dz_i/dt = qd, eq. 11)
but compares z_i with the torque g_i in the slipping law (eq. 12), and its
sum (eq. 13) multiplies z_i by a stiffness again.  We use the form of
Al-Bender, Lampaert & Swevers (2005), which keeps z_i a deflection (rad) and
F_i = k_i z_i the element torque (Nm):

* sticking:  dz_i/dt = qd, until |F_i| reaches alpha_i |g(qd, xi, tau_L)| in
  the direction of motion;                                               (11)
* slipping:  dF_i/dt = sgn(qd) C_i (1 - F_i / (alpha_i g)),  C_i = alpha_i C,
  until the velocity reverses (or stops), when the element sticks again.  (12)

alpha_i > 0 with sum alpha_i = 1 is the paper's g_i = mu g with mu = 1/N by
default, and C_i = mu C likewise; C has units Nm/s (the rate at which a
slipping element's torque approaches its share of g).  In steady sliding
every element slips with F_i = alpha_i g, so tau_rd = g + s: the static
curve, at every temperature and load.  Right after a reversal all elements
stick and the stiffness is sum k_i.  Elements with different break-away
deflections alpha_i |g| / k_i give hysteresis with non-local memory.

Discrete time
-------------
For a velocity held constant over a step both laws are solved exactly: a
sticking element moves linearly until it reaches its threshold (the crossing
time inside the step is computed) and then relaxes exponentially,
F -> alpha_i g + (F - alpha_i g) exp(-C t / |g|), which is its exact
solution.  Nothing here can diverge.  :func:`gms_update_ramp` does the same
for a velocity ramping linearly over the step (the joint integrator's):
there the slip onset is where the element torque meets alpha_i g(qd) at
the velocity of that instant, not at the step's mean velocity.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._sampled import SampledFrictionModel
from .lugre import G_MIN
from .static import curve_params, g_abs, s_visc, sign
from .._jit import njit
from ..exceptions import GearConfigError

if TYPE_CHECKING:
    from typing import TypeAlias

    from .params import FrictionParams, GMSParams

    #: a float array
    _A: TypeAlias = NDArray[np.float64]
    #: the element states ``(z, stick, slipdir)``: deflections (rad), 1/0, +1/-1
    _State: TypeAlias = tuple[NDArray[np.float64], NDArray[np.int8], NDArray[np.float64]]
    #: the elements ``(k, alpha, c)``: stiffnesses, torque shares, attraction parameter
    _Elements: TypeAlias = tuple[NDArray[np.float64], NDArray[np.float64], float]
    #: ``(F_c, F_s, v_s, delta_s, kappa)``
    _Curve: TypeAlias = tuple[float, float, float, float, float]

__all__ = ['GMS', 'gms_update', 'gms_update_ramp', 'pack_gms']


@njit(inline='always')
def _element(f: float, stuck: int, slipdir: float, ki: float, share: float, v: float, h: float,
             ga: float, lam: float) -> tuple[float, int, float]:
    """
    One element over a step of constant velocity v: returns (torque, stick, slip direction).

    ``f`` is its torque k_i z_i at the start, ``share`` alpha_i, ``lam`` C / |g|.
    """
    sv = sign(v)
    if stuck == 0 and sv != slipdir:
        stuck = 1                              # reversal or standstill: sticks again
    if sv == 0.0:
        return f, stuck, slipdir
    target = sv * share * ga                   # alpha_i g(v), signed
    if stuck == 1:
        fnew = f + ki * v * h
        if sv * fnew < sv * target:
            return fnew, stuck, slipdir
        if sv * f >= sv * target:              # reaches its share of g in this step
            t_hit = 0.0
        else:
            t_hit = (target - f) / (ki * v)
            f = target
        return target + (f - target) * math.exp(-lam * (h - t_hit)), 0, sv
    return target + (f - target) * math.exp(-lam * h), stuck, slipdir


@njit(inline='always')
def gms_update(state: _State, elements: _Elements, v: float, h: float, gabs: float,
               commit: bool = True) -> float:
    """
    Advance the N element states in place over a step of constant velocity v.

    ``state`` is ``(z, stick, slipdir)``: deflections (rad), 1/0, +1/-1;
    ``elements`` is ``(k, alpha, c)``: stiffnesses, torque shares, attraction
    parameter; returns sum k_i z_i at the step's end.  ``commit=False`` only
    returns it and leaves the state unchanged (a prediction).
    """
    z, stick, slipdir = state
    k, alpha, c = elements
    ga = max(gabs, G_MIN)
    lam = c / ga
    total = 0.0
    for i in range(z.shape[0]):
        f, st, sd = _element(k[i] * z[i], stick[i], slipdir[i], k[i], alpha[i], v, h, ga, lam)
        if commit:
            z[i] = f / k[i]
            stick[i] = st
            slipdir[i] = sd
        total += f
    return total


@njit(inline='always')
def _onset(f: float, ki: float, share: float, sv: float, v0: float, v1: float, dn: float,
           h: float, curve: _Curve, p0: float, p1: float) -> tuple[float, float]:
    """
    Slip onset of a sticking element over a step with velocity ramping v0 -> v1.

    The element reaches its share of g where
    p(t) = sv (f + ki x(t)) - share |g(v(t))| = 0, x(t) = v0 t + (dn - v0 h) (t/h)^2
    (x(h) = dn) and v linear in t; p0 < 0 <= p1 are its values at the ends.
    Regula falsi; returns the onset and the velocity there.
    """
    fc, fs, vs, ds, kap = curve
    ta, tb, t = 0.0, h, 0.0
    for _ in range(3):
        t = (ta * p1 - tb * p0) / (p1 - p0)
        s = t / h
        p = sv * (f + ki * (v0 * t + (dn - v0 * h) * s * s)) - share * g_abs(
            fc, fs, vs, ds, kap, v0 + (v1 - v0) * s)
        if p < 0.0:
            ta, p0 = t, p
        else:
            tb, p1 = t, p
    return t, v0 + (v1 - v0) * t / h


@njit(inline='always')
def gms_update_ramp(state: _State, elements: _Elements, ramp: tuple[float, float, float],
                    h: float, curve: _Curve, commit: bool = True) -> tuple[float, float]:
    """
    :func:`gms_update` over a step whose velocity ramps linearly.

    ``ramp`` is ``(v0, v1, dn)``: the velocity at the step's start and end
    and the displacement over the step; ``curve`` is
    ``(F_c, F_s, v_s, delta_s, kappa)``.  A sticking element that
    reaches its share of g in the step slips from the located onset, the
    threshold g taken at the velocity there and the rest of the step at the
    velocity in its middle.  (A constant-velocity step at the mean velocity
    dn / h puts both at the mean velocity: an O(h) error in the onset and in
    the element's torque from then on, a first-order global error.)  A step
    in which the velocity changes sign falls back to :func:`gms_update`.

    Returns sum k_i z_i at the step's end and the earliest onset in the step
    (h if none).
    """
    fc, fs, vs, ds, kap = curve
    v0, v1, dn = ramp
    vbar = dn / h
    ga = max(g_abs(fc, fs, vs, ds, kap, vbar), G_MIN)
    sv = sign(vbar)
    if sv == 0.0 or v0 * sv < 0.0 or v1 * sv < 0.0:
        return gms_update(state, elements, vbar, h, ga, commit), h
    z, stick, slipdir = state
    k, alpha, c = elements
    decay = -1.0
    g0 = -1.0
    g1 = -1.0
    first = h
    total = 0.0
    for i in range(z.shape[0]):
        f = k[i] * z[i]
        st = stick[i]
        sd = slipdir[i]
        if st == 0 and sv != sd:
            st = 1
        if st == 1:
            if g1 < 0.0:                   # the curve at the step's end, once
                g1 = g_abs(fc, fs, vs, ds, kap, v1)
            p1 = sv * (f + k[i] * dn) - alpha[i] * g1
            if p1 < 0.0:
                f += k[i] * dn
            else:
                if g0 < 0.0:
                    g0 = g_abs(fc, fs, vs, ds, kap, v0)
                p0 = sv * f - alpha[i] * g0
                t_hit = 0.0
                vh = v0
                if p0 < 0.0:
                    t_hit, vh = _onset(f, k[i], alpha[i], sv, v0, v1, dn, h, curve, p0, p1)
                    f = sv * alpha[i] * g_abs(fc, fs, vs, ds, kap, vh)
                first = min(first, t_hit)
                st, sd = 0, sv
                vm = 0.5 * (vh + v1)
                gm = max(g_abs(fc, fs, vs, ds, kap, vm), G_MIN)
                target = sv * alpha[i] * gm
                f = target + (f - target) * math.exp(-c / gm * (h - t_hit))
        else:
            if decay < 0.0:
                decay = math.exp(-c / ga * h)
            target = sv * alpha[i] * ga
            f = target + (f - target) * decay
        if commit:
            z[i] = f / k[i]
            stick[i] = st
            slipdir[i] = sd
        total += f
    return total, first


@njit
def _gms_run(temp: _A, load: _A, delta_s: _A, kappa: _A, t_lo: _A, t_hi: _A, k: _A, alpha: _A,
             c: _A, qd: _A, xi: _A, tl: _A, h: float, z: _A, stick: NDArray[np.int8],
             slipdir: _A, tau: _A) -> None:
    nb, nt = qd.shape
    for b in range(nb):
        for t in range(nt):
            fc, fs, fv, vs, dv = curve_params(temp, load, (t_lo, t_hi), b, xi[b, t], tl[b, t])
            v = qd[b, t]
            ga = g_abs(fc, fs, vs, delta_s[b], kappa[b], v)
            tot = gms_update((z[b], stick[b], slipdir[b]), (k[b], alpha[b], c[b]), v, h, ga)
            tau[b, t] = tot + s_visc(fv, dv, kappa[b], v)


def pack_gms(flist: list[FrictionParams]) -> tuple[_A, _A, _A]:
    """Element arrays (B, N) padded with inert elements (alpha = 0) and C (B,)."""
    gms: list[GMSParams] = []
    for f in flist:
        if f.gms is None:
            raise GearConfigError('GMS model needs friction.gms (k, alpha, c)')
        gms.append(f.gms)
    n = max(len(g.k) for g in gms)
    k = np.ones((len(flist), n))
    alpha = np.zeros((len(flist), n))
    for b, g in enumerate(gms):
        k[b, :len(g.k)] = g.k
        alpha[b, :len(g.alpha)] = g.alpha
    return k, alpha, np.array([g.c for g in gms], dtype=float)


class GMS(SampledFrictionModel):
    """
    Modified GMS model for one gear or a batch of B gears.

    Parameters
    ----------
    frictions : FrictionParams or list or tuple of FrictionParams
        Each must have a ``gms`` section (k, alpha, c).

    """

    def __init__(self, frictions: FrictionParams | list[FrictionParams]
                 | tuple[FrictionParams, ...]) -> None:
        flist = self._init_batch(frictions)
        self.k, self.alpha, self.c = pack_gms(flist)
        self.reset()

    @property
    def state(self) -> NDArray[np.float64]:
        """Element deflections z (B, N) in rad."""
        return self.z.copy()

    def reset(self, *, z: ArrayLike = 0.0) -> None:
        """
        Put all elements sticking with deflection z.

        Parameters
        ----------
        z : array_like, scalar, (N,) or (B, N)
            Element deflections (rad); default relaxed.

        """
        self.z: NDArray[np.float64] = np.zeros_like(self.k) + np.asarray(z, dtype=float)
        self.stick = np.ones(self.k.shape, dtype=np.int8)
        self.slipdir = np.zeros(self.k.shape, dtype=np.float64)

    def _run(self, qd: _A, xi: _A, tl: _A, dt: float, out: _A) -> None:
        _gms_run(*self.packed.args(), self.k, self.alpha, self.c, qd, xi, tl, dt,
                 self.z, self.stick, self.slipdir, out)

    def simulate(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike, dt: float, *,
                 reset: bool = False) -> NDArray[np.float64]:
        """
        Return the friction torque for a sampled velocity sequence.

        Parameters
        ----------
        qd, xi, tau_l : array_like, (T,) or (B, T) or scalar
            Velocity (rad/s), temperature (degC), load (Nm); held over each step.
        dt : float
            Sample time (s).
        reset : bool
            Start from relaxed, sticking elements (:meth:`reset`) instead of the
            current state.

        Returns
        -------
        tau : ndarray, (T,) or (B, T)
            Friction torque after each step.

        """
        if reset:
            self.reset()
        return self._simulate(qd, xi, tau_l, dt)
