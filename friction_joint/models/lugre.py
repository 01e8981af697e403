# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Modified LuGre friction model with thermal and load dependency (seed eq. 10).

    tau_rd = sigma0 z + sigma1 dz/dt + s(qd, xi, tau_L)
    dz/dt  = qd - sigma0 |qd| / |g(qd, xi, tau_L)| * z                      (10)

g and s are the temperature- and load-dependent Stribeck and viscous terms of
:mod:`friction_joint.models.static` (eq. 1, 5-7); the paper divides by g, we divide
by |g| so the sign of z follows the motion.  At constant velocity z tends to
sign(qd)|g|/sigma0, dz/dt to 0, and tau_rd to the static curve g + s.

Discrete time
-------------
For a velocity held constant over a step of length h (a sampled velocity
signal, as in a 3 kHz control loop) eq. 10 is linear in z with the constant
rate a = sigma0 |qd| / |g|, so it is integrated *exactly*:

    z+ = exp(-a h) z + (1 - exp(-a h)) / a * qd

This update cannot diverge for any sigma0 or h (it is a convex combination of
z and the steady state).  The output uses dz/dt evaluated at the end of the
step.  For a joint whose velocity itself responds to the friction torque
see :mod:`friction_joint.models.joint`, which integrates the coupled system.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._sampled import SampledFrictionModel
from .static import curve_params, g_abs, s_visc, StaticFriction
from .._jit import njit
from ..exceptions import GearConfigError

if TYPE_CHECKING:
    from .params import FrictionParams, LuGreParams

__all__ = ['LuGre', 'lugre_update', 'lugre_torque', 'G_MIN']

G_MIN = 1e-12


@njit
def lugre_update(z: float, v: float, h: float, sigma0: float, gabs: float) -> float:
    """Exact bristle update over a step of constant velocity v (eq. 10)."""
    a = sigma0 * abs(v) / max(gabs, G_MIN)
    ah = a * h
    if ah < 1e-12:
        return z + v * h
    e = math.exp(-ah)
    return e * z - math.expm1(-ah) / a * v


@njit
def lugre_torque(z: float, v: float, sigma0: float, sigma1: float, gabs: float,
                 s: float) -> float:
    """Friction torque sigma0 z + sigma1 dz/dt + s at state z, velocity v (eq. 10)."""
    zdot = v - sigma0 * abs(v) / max(gabs, G_MIN) * z
    return sigma0 * z + sigma1 * zdot + s


@njit
def _lugre_run(temp: NDArray[np.float64], load: NDArray[np.float64],
               delta_s: NDArray[np.float64], kappa: NDArray[np.float64],
               t_lo: NDArray[np.float64], t_hi: NDArray[np.float64],
               sigma0: NDArray[np.float64], sigma1: NDArray[np.float64],
               qd: NDArray[np.float64], xi: NDArray[np.float64], tl: NDArray[np.float64],
               h: float, z: NDArray[np.float64], tau: NDArray[np.float64]) -> None:
    nb, nt = qd.shape
    for b in range(nb):
        zb = z[b]
        for k in range(nt):
            fc, fs, fv, vs, dv = curve_params(temp, load, (t_lo, t_hi), b, xi[b, k], tl[b, k])
            v = qd[b, k]
            ga = g_abs(fc, fs, vs, delta_s[b], kappa[b], v)
            zb = lugre_update(zb, v, h, sigma0[b], ga)
            tau[b, k] = lugre_torque(zb, v, sigma0[b], sigma1[b], ga,
                                     s_visc(fv, dv, kappa[b], v))
        z[b] = zb


class LuGre(SampledFrictionModel):
    """
    Modified LuGre model for one gear or a batch of B gears.

    Parameters
    ----------
    frictions : FrictionParams or list or tuple of FrictionParams
        Each must have a ``lugre`` section (sigma0, sigma1).

    Notes
    -----
    :meth:`simulate` runs a whole velocity sequence (fast, numba);
    :meth:`step` advances the internal state by one sample for real-time
    loops.  Both use the exact update of the module docstring.

    """

    def __init__(self, frictions: FrictionParams | list[FrictionParams]
                 | tuple[FrictionParams, ...]) -> None:
        flist = self._init_batch(frictions)
        lugres: list[LuGreParams] = []
        for f in flist:
            if f.lugre is None:
                raise GearConfigError('LuGre model needs friction.lugre (sigma0, sigma1)')
            lugres.append(f.lugre)
        self.sigma0 = np.array([p.sigma0 for p in lugres])
        self.sigma1 = np.array([p.sigma1 for p in lugres])
        self.z = np.zeros(len(flist))

    @property
    def state(self) -> NDArray[np.float64]:
        return self.z.copy()

    def reset(self, *, z: ArrayLike = 0.0) -> None:
        """
        Set the bristle deflection.

        Parameters
        ----------
        z : array_like, scalar or (B,)
            Bristle deflection (rad); default relaxed.

        """
        self.z = np.broadcast_to(np.asarray(z, dtype=float), (self.batch,)).copy()

    def settle(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike = 0.0) -> None:
        """
        Put the state at the steady state of velocity qd (sliding).

        Parameters
        ----------
        qd, xi, tau_l : array_like, scalar, (T,) or (B, T)
            Velocity (rad/s), temperature (degC), load (Nm); the last sample counts.

        """
        g, _ = StaticFriction.from_packed(self.packed).components(qd, xi, tau_l)
        self.z = np.asarray(g, dtype=float)[:, -1] / self.sigma0

    def _run(self, qd: NDArray[np.float64], xi: NDArray[np.float64], tl: NDArray[np.float64],
             dt: float, out: NDArray[np.float64]) -> None:
        _lugre_run(*self.packed.args(), self.sigma0, self.sigma1, qd, xi, tl, dt, self.z, out)

    def simulate(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike, dt: float, *,
                 z0: ArrayLike | None = None) -> NDArray[np.float64]:
        """
        Return the friction torque for a sampled velocity sequence.

        Parameters
        ----------
        qd, xi, tau_l : array_like, (T,) or (B, T) or scalar
            Velocity (rad/s), temperature (degC), load (Nm); held over each step.
        dt : float
            Sample time (s).
        z0 : array_like, optional
            Initial state; default the current state (see :meth:`reset`).

        Returns
        -------
        tau : ndarray, (T,) or (B, T)
            Friction torque after each step.

        """
        if z0 is not None:
            self.reset(z=z0)
        return self._simulate(qd, xi, tau_l, dt)
