# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The building blocks of the physical static fit: its layout, its problem, its solver.

:class:`PhysicalLayout` (node values with a free delta_s, F_s tied to F_c, the v_s band,
the lever model's gravity error), :class:`PhysicalProblem` (plateau residuals plus
one-sided physics penalties), :func:`grid_profile` (the linear part solved exactly on a
grid of the nonlinear parameters), :func:`solve_bounded` and the small helpers
:func:`feasible_theta`, :func:`project_theta`; the fit itself is
:func:`friction_joint.identification.physical_fit.fit_physical`.
"""
from __future__ import annotations

from collections.abc import Mapping
import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import lsq_linear

from ._arrays import BoolArray, FloatArray
from .static_problem import CoefficientLayout, Problem
from ..models.static import PackedStatic, PARAMETERS, StaticFriction

if TYPE_CHECKING:
    from scipy.optimize import OptimizeResult

    from .plateaus import Plateaus
    from .static_structure import StaticStructure
    from ..gear import FrictionParams

__all__ = ['PENALTY', 'DELTA_S_BOUNDS', 'VS_BAND', 'FS_RATIO_MAX', 'vs_band', 'PhysicalLayout',
           'PhysicalProblem', 'lever_torque', 'grid_profile', 'profile_interval',
           'parameter_values', 'solve_bounded', 'feasible_theta', 'project_theta']

#: weight of a physics violation (Nm) relative to a plateau residual, times sqrt(n)
PENALTY = 30.0
#: delta_s is fitted within these bounds
DELTA_S_BOUNDS = (0.4, 3.0)
#: v_s band: from VS_BAND[0] x the slowest plateau speed to VS_BAND[1] x the fastest
VS_BAND = (1.0 / 30.0, 1.0)
#: F_s at most this multiple of F_c (break-away torque of gears: 1 to about 2 F_c)
FS_RATIO_MAX = 4.0

_IDX = {p: i for i, p in enumerate(PARAMETERS)}


def vs_band(plateaus: Plateaus, velocity_scale: float = 1.0) -> tuple[float, float]:
    """Return the v_s band (curve units: velocity_scale x rad/s) the data can speak to."""
    speed = velocity_scale * np.abs(plateaus.qd)
    return float(VS_BAND[0] * speed.min()), float(VS_BAND[1] * speed.max())


class PhysicalLayout(CoefficientLayout):
    """
    :class:`CoefficientLayout` with a free delta_s, F_s tied to F_c and a v_s band.

    Parameters
    ----------
    structure : StaticStructure
        The fitted structure.
    t_range : tuple of float
        Recorded temperature range (degC).
    load_ref : float
        Load scale (Nm).
    ties : dict, optional
        ``{'fs': r}``: F_s = r F_c (temperature and load coefficients), not fitted.
    free_delta_s : bool
        Fit delta_s (a ``'scalar'`` block named ``delta_s``).
    band : tuple of float, optional
        Bounds of the v_s node values.
    load_max : float
        Largest load of the data (the physics conditions hold up to it).
    lag_max : float, optional
        Fit ``sensor_lag`` (0..lag_max s): the friction follows the temperature the
        sensor will read that many seconds later (xi + lag x xi_rate).
    lever : bool
        Fit ``lever_error`` e: where tau_ext came from the structure's lever model, the
        measured friction torque is the curve plus e tau_ext (the lever's gravity m g l
        is (1 + e) times the structure's).

    """

    def __init__(self, structure: StaticStructure, t_range: tuple[float, float],
                 load_ref: float, *, ties: Mapping[str, float | str] | None = None,
                 free_delta_s: bool = False, band: tuple[float, float] | None = None,
                 load_max: float = 0.0, lever: bool = False,
                 lag_max: float | None = None) -> None:
        super().__init__(structure, t_range, load_ref)
        self.ties = dict(ties or {})
        self.band = band
        self.load_max = float(load_max)
        self.lag_max = lag_max
        # scalar blocks, in this order: name -> (bounds, present)
        self.scalar_bounds = {
            'delta_s': (DELTA_S_BOUNDS, free_delta_s),
            'sensor_lag': ((0.0, lag_max), bool(lag_max)),   # a lagging temperature sensor
            'lever_error': ((-0.5, 0.5), lever),             # lever model's m g l x (1 + e)
            'fs_ratio': ((1.0, FS_RATIO_MAX), self.ties.get('fs') == 'free'),   # F_s = r F_c
        }
        for name, (_, present) in self.scalar_bounds.items():
            if present:
                self.blocks.append((name, 'scalar', slice(self.size, self.size + 1)))
                self.maps[name] = np.eye(1)
                self.size += 1

    def bounds(self) -> tuple[FloatArray, FloatArray]:
        lo, hi = super().bounds()                     # node values of the temperature blocks
        for name, kind, sl in self.blocks:
            if name == 'vs' and self.band is not None:
                lo[sl], hi[sl] = self.band
            elif kind == 'scalar':
                lo[sl], hi[sl] = self.scalar_bounds[name][0]
        return lo, hi

    def packed(self, thetas: ArrayLike) -> PackedStatic:
        thetas = np.atleast_2d(thetas)
        b = thetas.shape[0]
        temp = np.zeros((b, 5, self.nt))
        load = np.zeros((b, 5, self.nl))
        ds = np.full(b, float(self.s.delta_s))
        ratio = np.full(b, self.ties['fs']) if 'fs' in self.ties and \
            self.ties['fs'] != 'free' else None
        for p, c in self.s.fixed.items():
            temp[:, _IDX[p], :len(c)] = c
        for name, kind, sl in self.blocks:
            coef = thetas[:, sl] @ self.maps[name].T
            if kind == 'temp':
                temp[:, _IDX[name], :coef.shape[1]] = coef
            elif kind == 'load':
                load[:, _IDX[name[:-5]], :coef.shape[1]] = coef
            elif name == 'delta_s':
                ds = coef[:, 0]
            elif name == 'fs_ratio':
                ratio = coef[:, 0]
        if ratio is not None:
            temp[:, _IDX['fs']] = ratio[:, None] * temp[:, _IDX['fc']]
            load[:, _IDX['fs']] = ratio[:, None] * load[:, _IDX['fc']]
        if not self.s.stribeck:
            temp[:, _IDX['fs']] = temp[:, _IDX['fc']]
            load[:, _IDX['fs']] = load[:, _IDX['fc']]
            temp[:, _IDX['vs'], 0] = 1.0
        ones = np.ones(b)
        return PackedStatic(temp, load, ds, self.s.velocity_scale * ones, -1e9 * ones,
                            1e9 * ones)

    def torque(self, thetas: ArrayLike, qd: ArrayLike, xi: ArrayLike, load: ArrayLike,
               tau_ext: ArrayLike | None = None, xi_rate: ArrayLike | None = None
               ) -> FloatArray:
        """(B, N) friction torque as measured: the curve, plus e tau_ext (lever model)."""
        thetas = np.atleast_2d(thetas)
        lag = [s_ for n_, _, s_ in self.blocks if n_ == 'sensor_lag']
        if lag and xi_rate is not None:
            xi = np.asarray(xi, dtype=float)[None, :] + thetas[:, lag[0]] * np.asarray(
                xi_rate, dtype=float)[None, :]
            qd = np.broadcast_to(np.asarray(qd, dtype=float), np.shape(xi))
            load = np.broadcast_to(np.asarray(load, dtype=float), np.shape(xi))
        out = super().torque(thetas, qd, xi, load)
        sl = [s_ for n_, _, s_ in self.blocks if n_ == 'lever_error']
        if sl and tau_ext is not None:
            out = out + np.atleast_2d(thetas)[:, sl[0]] * np.asarray(tau_ext)[None, :]
        return out

    def physics(self, thetas: ArrayLike, xi: FloatArray, load: FloatArray) -> FloatArray:
        """
        Raw parameter values (not clipped) at the (xi, load) points: (B, 5, K).

        Parameters
        ----------
        thetas : ndarray (B, size)
            Parameter vectors.
        xi, load : ndarray (K,)
            Temperatures (degC) and loads (Nm).

        """
        pk = self.packed(thetas)
        xp = np.vstack([xi ** i for i in range(pk.temp.shape[2])])
        lp = np.vstack([load ** (j + 1) for j in range(pk.load.shape[2])])
        return pk.temp @ xp + pk.load @ lp

    def corners(self, n: int = 5) -> tuple[FloatArray, FloatArray]:
        """Temperature and load points where the physics conditions are checked."""
        # the written file's range is the recorded one rounded outwards to 0.1 degC
        xi = np.linspace(self.t_range[0] - 0.1, self.t_range[1] + 0.1, n)
        loads = np.array([0.0, self.load_max]) if self.load_max > 0 else np.zeros(1)
        x, lo = np.meshgrid(xi, loads)
        return x.ravel(), lo.ravel()


class PhysicalProblem(Problem):
    """Plateau residuals plus one-sided physics penalties (:data:`PENALTY`)."""

    layout: PhysicalLayout

    def __init__(self, layout: PhysicalLayout, plateaus: Plateaus, *,
                 penalty: float = PENALTY) -> None:
        super().__init__(layout, plateaus)
        self.lever = lever_torque(plateaus)
        self.rate = plateaus.xi_rate.astype(float)
        self.weight = penalty * math.sqrt(max(len(self.y), 1))
        self.cx, self.cl = layout.corners()
        self.stribeck = layout.s.stribeck and 'fs' not in layout.ties

    def data_residuals(self, thetas: ArrayLike) -> FloatArray:
        """(B, n) model minus measured friction torque."""
        return self.layout.torque(thetas, self.qd, self.xi, self.load, self.lever,
                                  self.rate) - self.y

    def penalties(self, thetas: ArrayLike) -> FloatArray:
        v = self.layout.physics(np.atleast_2d(thetas), self.cx, self.cl)
        parts = [np.maximum(0.0, -v[:, _IDX['fc']]), np.maximum(0.0, -v[:, _IDX['fv']])]
        if self.stribeck:
            parts.append(np.maximum(0.0, v[:, _IDX['fc']] - v[:, _IDX['fs']]))
            parts.append(np.maximum(0.0, v[:, _IDX['fs']] - FS_RATIO_MAX * v[:, _IDX['fc']]))
        return self.weight * np.concatenate(parts, axis=1)

    def residual_batch(self, thetas: ArrayLike) -> FloatArray:
        thetas = np.atleast_2d(thetas)
        self.nfev += len(thetas)
        return np.concatenate([self.data_residuals(thetas), self.penalties(thetas)], axis=1)

    def data_jacobian(self, theta: FloatArray, free: BoolArray) -> FloatArray:
        """Jacobian of the plateau residuals only (covariance)."""
        return self.jacobian(theta, free, residuals=self.data_residuals)


def lever_torque(plateaus: Plateaus) -> FloatArray:
    """Per plateau: its mean tau_ext where it came from the lever model, else 0."""
    model = np.array([src == 'lever_model' for src in plateaus.torque_source] or [False])
    src = np.clip(plateaus.source, 0, len(model) - 1)
    return np.where(model[src], plateaus.tau_ext, 0.0)


def _linear_mask(layout: CoefficientLayout) -> BoolArray:
    """Entries of theta the curve is linear in: F_c, F_s, F_v nodes and their load terms."""
    m = np.zeros(layout.size, dtype=bool)
    for name, kind, sl in layout.blocks:
        base = name[:-5] if kind == 'load' else name
        if base in ('fc', 'fs', 'fv', 'lever_error'):
            m[sl] = True
    return m


def grid_profile(layout: PhysicalLayout, plateaus: Plateaus, *, vs_grid: FloatArray,
                 dv_grid: FloatArray, ds_grid: FloatArray) -> tuple[FloatArray, FloatArray]:
    """
    Residual over a grid of (v_s, delta_v, delta_s), the linear part solved exactly.

    Returns
    -------
    sse : ndarray (len(vs_grid), len(dv_grid), len(ds_grid))
    thetas : ndarray (same + (size,))
        The parameter vector of each grid point.

    """
    lin = _linear_mask(layout)
    idx = np.flatnonzero(lin)
    lo, hi = layout.bounds()
    y = plateaus.tau_r.astype(float)
    # starts within reason: no torque term beyond a few times the largest measured torque
    # (else a dip far below the data trades a huge F_s against a huge negative load term)
    cap = FS_RATIO_MAX * float(np.max(np.abs(y))) if len(y) else np.inf
    for name, kind, sl in layout.blocks:
        param = name[:-5] if kind == 'load' else name
        if param in ('fc', 'fs'):
            lo[sl] = np.maximum(lo[sl], -cap)
            hi[sl] = np.minimum(hi[sl], cap)
        elif kind == 'load':
            lo[sl], hi[sl] = -cap, cap
    lo, hi = lo[idx], hi[idx]
    shape = (len(vs_grid), len(dv_grid), len(ds_grid))
    sse = np.full(shape, np.inf)
    thetas = np.zeros(shape + (layout.size,))
    blocks = {name: sl for name, _, sl in layout.blocks}
    base = np.zeros((int(np.prod(shape)), layout.size))
    for k, (a, b, c) in enumerate(np.ndindex(*shape)):
        if 'vs' in blocks:
            base[k, blocks['vs']] = vs_grid[a]
        if 'delta_v' in blocks:
            base[k, blocks['delta_v']] = dv_grid[b]
        if 'delta_s' in blocks:
            base[k, blocks['delta_s']] = ds_grid[c]
    # columns: the torque at theta = base + e_j minus the torque at base (one batch)
    n_lin = len(idx)
    batch = np.repeat(base, n_lin + 1, axis=0)
    for j, i in enumerate(idx):
        batch[j + 1::n_lin + 1, i] += 1.0
    tq = layout.torque(batch, plateaus.qd, plateaus.xi, plateaus.load, lever_torque(plateaus),
                       plateaus.xi_rate)
    tq = tq.reshape(len(base), n_lin + 1, -1)
    for k, (a, b, c) in enumerate(np.ndindex(*shape)):
        r0 = tq[k, 0]
        cols = (tq[k, 1:] - r0).T
        res = lsq_linear(cols, y - r0, bounds=(lo, hi), method='bvls')
        th = base[k].copy()
        th[idx] = res.x
        thetas[a, b, c] = th
        sse[a, b, c] = float(np.sum((cols @ res.x + r0 - y) ** 2))
    return sse, thetas


def profile_interval(grid: FloatArray, profile: FloatArray, best: float, n: int, p: int
                     ) -> tuple[float, float, bool, bool]:
    """
    Grid values whose profile residual is within the likelihood-ratio bound of ``best``.

    The bound is ``best (1 + 4 / (n - p))``: an F-type interval of about two standard
    errors.  Returns ``(lo, hi, at_low_end, at_high_end)``.
    """
    bound = best * (1.0 + 4.0 / max(n - p, 1))
    ok = np.flatnonzero(profile <= bound)
    if not len(ok):
        k = int(np.argmin(profile))
        ok = np.array([k])
    return (float(grid[ok.min()]), float(grid[ok.max()]), bool(ok.min() == 0),
            bool(ok.max() == len(grid) - 1))


def parameter_values(gear_friction: FrictionParams, xi: float, load: float = 0.0
                     ) -> dict[str, float]:
    """Return (F_c, F_s, F_v, v_s, delta_v) of a friction section at xi (dict of floats)."""
    v = StaticFriction(gear_friction).parameters(np.atleast_1d(float(xi)), float(load))
    return {k: float(np.asarray(x).ravel()[0]) for k, x in v.items()}


# ------------------------------------------------------------------ the fit ---

def solve_bounded(problem: PhysicalProblem, theta0: FloatArray, free: BoolArray | None = None,
                  *, tol: float = 1e-10, max_nfev: int = 200
                  ) -> tuple[FloatArray, float, OptimizeResult]:
    """Minimise a problem over the ``free`` entries; returns (theta, plateau SSE, result)."""
    free = np.ones(problem.layout.size, dtype=bool) if free is None else free
    theta, res = problem.solve(theta0, free, max_nfev=max_nfev, tol=tol)
    sse = float(np.sum(problem.data_residuals(theta)[0] ** 2))
    return theta, sse, res


def feasible_theta(layout: PhysicalLayout, theta: FloatArray) -> FloatArray:
    """
    Lift what the stiff penalties left a hair below physics (F_c, F_v >= 0, F_s >= F_c).

    A constant added to every node value of a temperature polynomial adds it to the
    polynomial; the lift is the largest violation over the checked temperatures and
    loads (nanonewton-metres to micronewton-metres after a converged fit).
    """
    theta = theta.copy()
    blocks = {name: sl for name, kind, sl in layout.blocks if kind == 'temp'}
    x, lo = layout.corners(n=21)
    for name, ref in (('fc', None), ('fv', None), ('fs', 'fc')):
        if name not in blocks:
            continue
        v = layout.physics(theta[None, :], x, lo)[0]
        gap = v[_IDX[name]] - (v[_IDX[ref]] if ref else 0.0)
        low = float(gap.min())
        if low < 0.0:
            theta[blocks[name]] += -low * (1.0 + 1e-9) + 1e-12
    return theta


def project_theta(src: CoefficientLayout, dst: CoefficientLayout, theta: FloatArray
                  ) -> FloatArray:
    """Carry a parameter vector of layout ``src`` over to layout ``dst`` (blocks by name)."""
    out = np.zeros(dst.size)
    have = {name: sl for name, _, sl in src.blocks}
    lo, hi = dst.bounds()
    for name, _, sl in dst.blocks:
        if name in have and (have[name].stop - have[name].start) == (sl.stop - sl.start):
            out[sl] = theta[have[name]]
    return np.clip(out, np.where(np.isfinite(lo), lo, -np.inf),
                   np.where(np.isfinite(hi), hi, np.inf))
