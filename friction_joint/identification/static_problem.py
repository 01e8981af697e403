# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The least-squares problem of identification steps 1-2 and its solution.

Temperature polynomials are parametrised by their values at Chebyshev-Lobatto
nodes over the recorded temperature range (:class:`CoefficientLayout`); :class:`Problem`
evaluates the residuals with the package's own static curve, batched over
the finite-difference columns of the Jacobian; :func:`fit_structure`
alternates steps 1 and 2 and finishes with a joint pass (see
:mod:`friction_joint.identification.static_fit`).
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
import math
import time
from typing import Any, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import least_squares, nnls

from ._arrays import BoolArray, FloatArray
from .static_structure import LOWER, UPPER
from ..models.static import PackedStatic, PARAMETERS, StaticFriction

if TYPE_CHECKING:
    from scipy.optimize import OptimizeResult

    from .plateaus import Plateaus
    from .static_structure import StaticStructure

__all__ = ['CoefficientLayout', 'Problem', 'single_init', 'theta_from_values', 'fit_structure',
           'covariance', 'temperature_range', 'load_reference']


class CoefficientLayout:
    """Parameter vector <-> coefficient arrays of the static curve."""

    def __init__(self, structure: StaticStructure, t_range: tuple[float, float],
                 load_ref: float) -> None:
        self.s = structure
        lo, hi = t_range
        self.t_range = (float(lo), float(hi))
        self.load_ref = float(load_ref)
        self.blocks: list[tuple[str, str, slice]] = []      # (name, kind, slice)
        # name -> matrix theta_block -> coefficients
        self.maps: dict[str, FloatArray] = {}
        self.nodes: dict[str, FloatArray] = {}
        i = 0
        for p in structure.params:
            n = structure.orders[p]
            nodes = self._nodes(n)
            self.nodes[p] = nodes
            self.maps[p] = np.linalg.inv(np.vander(nodes, n + 1, increasing=True))
            self.blocks.append((p, 'temp', slice(i, i + n + 1)))
            i += n + 1
        for p in structure.load_params:
            m = structure.load_orders[p]
            self.maps[p + '_load'] = np.diag(self.load_ref ** -np.arange(1.0, m + 1))
            self.blocks.append((p + '_load', 'load', slice(i, i + m)))
            i += m
        self.size = i
        self.nt = max([structure.orders[p] + 1 for p in structure.params]
                      + [len(c) for c in structure.fixed.values()] + [1])
        self.nl = max([structure.load_orders.get(p, 0) for p in PARAMETERS] + [1])

    def _nodes(self, n: int) -> FloatArray:
        lo, hi = self.t_range
        if n == 0:
            return np.array([0.5 * (lo + hi)])
        k = np.arange(n + 1)
        return 0.5 * (lo + hi) - 0.5 * (hi - lo) * np.cos(np.pi * k / n)

    def mask(self, kind: str) -> BoolArray:
        m = np.zeros(self.size, dtype=bool)
        for _, k, sl in self.blocks:
            if k == kind:
                m[sl] = True
        return m

    def bounds(self) -> tuple[FloatArray, FloatArray]:
        lo = np.full(self.size, -np.inf)
        hi = np.full(self.size, np.inf)
        for name, kind, sl in self.blocks:
            if kind == 'temp':
                lo[sl], hi[sl] = LOWER[name], UPPER[name]
        return lo, hi

    def coefficients(self, theta: FloatArray) -> dict[str, FloatArray]:
        """Name -> coefficient array (file convention: powers of xi, powers of tau_L)."""
        return {name: self.maps[name] @ theta[sl] for name, _, sl in self.blocks}

    def transform(self) -> FloatArray:
        """Matrix A with coefficients = A theta (blocks in layout order)."""
        a = np.zeros((self.size, self.size))
        for name, _, sl in self.blocks:
            a[sl, sl] = self.maps[name]
        return a

    def packed(self, thetas: ArrayLike) -> PackedStatic:
        """Return the PackedStatic of a batch of parameter vectors (B, size)."""
        thetas = np.atleast_2d(thetas)
        b = thetas.shape[0]
        temp = np.zeros((b, 5, self.nt))
        load = np.zeros((b, 5, self.nl))
        idx = {p: i for i, p in enumerate(PARAMETERS)}
        for p, c in self.s.fixed.items():
            temp[:, idx[p], :len(c)] = c
        for name, kind, sl in self.blocks:
            coef = thetas[:, sl] @ self.maps[name].T
            if kind == 'temp':
                temp[:, idx[name], :coef.shape[1]] = coef
            else:
                load[:, idx[name[:-5]], :coef.shape[1]] = coef
        if not self.s.stribeck:                 # no Stribeck: Fs = Fc, vs irrelevant
            temp[:, idx['fs']] = temp[:, idx['fc']]
            load[:, idx['fs']] = load[:, idx['fc']]
            temp[:, idx['vs'], 0] = 1.0
        ones = np.ones(b)
        return PackedStatic(temp, load, self.s.delta_s * ones, self.s.velocity_scale * ones,
                            -1e9 * ones, 1e9 * ones)

    def torque(self, thetas: ArrayLike, qd: ArrayLike, xi: ArrayLike, load: ArrayLike
               ) -> FloatArray:
        """(B, N) static friction torque of a batch of parameter vectors."""
        return StaticFriction.from_packed(self.packed(thetas)).torque(qd, xi, load)


class Problem:
    """Least-squares residuals of the plateau data for a layout."""

    def __init__(self, layout: CoefficientLayout, plateaus: Plateaus) -> None:
        self.layout = layout
        self.qd: FloatArray = plateaus.qd.astype(float)
        self.xi: FloatArray = plateaus.xi.astype(float)
        self.load: FloatArray = plateaus.load.astype(float)
        self.y: FloatArray = plateaus.tau_r.astype(float)
        self.nfev = 0

    def residual_batch(self, thetas: ArrayLike) -> FloatArray:
        self.nfev += len(np.atleast_2d(thetas))
        return self.layout.torque(thetas, self.qd, self.xi, self.load) - self.y

    def solve(self, theta0: ArrayLike, free: BoolArray, max_nfev: int = 200,
              tol: float = 1e-12) -> tuple[FloatArray, OptimizeResult]:
        """
        Minimise over the entries of theta marked ``free`` (ftol = xtol = gtol = ``tol``).

        Returns ``(theta, result of scipy.optimize.least_squares)``.
        """
        theta0 = np.asarray(theta0, dtype=float).copy()
        idx = np.flatnonzero(free)
        lo, hi = self.layout.bounds()
        lo, hi = lo[idx], hi[idx]
        with np.errstate(invalid='ignore'):
            pad_lo = np.where(np.isfinite(lo), lo + 1e-9 * (1 + np.abs(lo)), -np.inf)
            pad_hi = np.where(np.isfinite(hi), hi - 1e-9 * (1 + np.abs(hi)), np.inf)
        x0 = np.clip(theta0[idx], pad_lo, pad_hi)

        def full(x: ArrayLike) -> FloatArray:
            rows = np.atleast_2d(x).shape[0]
            th: FloatArray = np.broadcast_to(theta0, (rows, theta0.size)).copy()
            th[:, idx] = np.atleast_2d(x)
            return th

        def fun(x: FloatArray) -> FloatArray:
            r: FloatArray = self.residual_batch(full(x))[0]
            return r

        def jac(x: FloatArray) -> FloatArray:
            h: FloatArray = 1e-6 * np.maximum(np.abs(x), 0.1)
            xs = np.concatenate([x + np.diag(h), x - np.diag(h)])
            r = self.residual_batch(full(xs))
            k = len(x)
            return ((r[:k] - r[k:]) / (2.0 * h[:, None])).T

        res = least_squares(fun, x0, jac=jac, bounds=(lo, hi), method='trf', x_scale='jac',
                            max_nfev=max_nfev, ftol=tol, xtol=tol, gtol=tol)
        theta = theta0.copy()
        theta[idx] = res.x
        return theta, res

    def jacobian(self, theta: FloatArray, free: BoolArray | None = None,
                 residuals: Callable[[FloatArray], FloatArray] | None = None
                 ) -> FloatArray:
        """Central-difference Jacobian of ``residuals`` (default the residuals) at theta."""
        free = np.ones(theta.size, dtype=bool) if free is None else free
        residuals = self.residual_batch if residuals is None else residuals
        idx = np.flatnonzero(free)
        h = 1e-6 * np.maximum(np.abs(theta[idx]), 0.1)
        th = np.repeat(theta[None, :], 2 * len(idx), axis=0)
        for j, i in enumerate(idx):
            th[j, i] += h[j]
            th[len(idx) + j, i] -= h[j]
        r = residuals(th)
        k = len(idx)
        return ((r[:k] - r[k:]) / (2.0 * h[:, None])).T


# ---------------------------------------------------- initial single-temperature fit ---

def single_init(structure: StaticStructure, plateaus: Plateaus,
                load_part: FloatArray | None = None) -> dict[str, float]:
    """
    Order-0 curve (fc, fs, fv, vs, delta_v) of pooled plateaus by variable projection.

    For each (vs, delta_v) on a grid the curve is linear in (fc, fs, fv): those come
    from non-negative least squares; the best grid point is returned.
    """
    kappa = structure.velocity_scale
    x = kappa * np.abs(plateaus.qd)
    y = np.sign(plateaus.qd) * plateaus.tau_r
    if load_part is not None:
        y = y - load_part
    dv_fixed = structure.fixed.get('delta_v')
    dvs = [float(dv_fixed[0])] if dv_fixed is not None else np.linspace(0.1, 1.6, 31)
    vss = (np.geomspace(max(x.min(), 1e-6) * 0.3, x.max(), 30) if structure.stribeck
           else [1.0])
    ds = structure.delta_s
    fits = []
    for vs in vss:
        e = np.exp(-(x / vs) ** ds) if structure.stribeck else np.zeros_like(x)
        for dv in dvs:
            cols = [1.0 - e, e, x ** dv] if structure.stribeck else [np.ones_like(x), x ** dv]
            a = np.column_stack(cols)
            coef, rn = nnls(a, y)
            fits.append((rn, vs, dv, coef))
    _, vs, dv, coef = min(fits, key=lambda f: f[0])      # the first of the least
    if structure.stribeck:
        fc, fs, fv = coef
    else:
        (fc, fv), fs = coef, coef[0]
    return {'fc': fc, 'fs': fs, 'fv': fv, 'vs': vs, 'delta_v': dv}


def theta_from_values(layout: CoefficientLayout,
                      values: Mapping[str, float | Callable[[FloatArray], ArrayLike]],
                      load: Mapping[str, ArrayLike] | None = None) -> FloatArray:
    """Return theta with each temperature node of parameter p at values[p] (scalar or callable)."""
    theta = np.zeros(layout.size)
    for name, kind, sl in layout.blocks:
        if kind == 'temp':
            v = values[name]
            nodes = layout.nodes[name]
            theta[sl] = v(nodes) if callable(v) else v
            theta[sl] = np.clip(theta[sl], LOWER[name] + 1e-6, UPPER[name] - 1e-6)
        elif load is not None and name in load:
            theta[sl] = load[name]
    return theta


# ------------------------------------------------------------------ fitting ---

def fit_structure(structure: StaticStructure, plateaus: Plateaus, t_range: tuple[float, float],
                  load_ref: float, *, theta0: FloatArray | None = None,
                  stepwise: bool = True, progress: Callable[[str], None] | None = None,
                  max_iterations: int = 4, tol: float = 1e-3
                  ) -> tuple[CoefficientLayout, FloatArray, Problem, dict[str, Any]]:
    """Fit one structure; returns (layout, theta, problem, info)."""
    layout = CoefficientLayout(structure, t_range, load_ref)
    prob = Problem(layout, plateaus)
    info: dict[str, Any] = {'steps': []}
    tmask, lmask = layout.mask('temp'), layout.mask('load')
    if theta0 is None:
        init = single_init(structure, plateaus)
        theta = theta_from_values(layout, init)
        info['init'] = init
    else:
        theta = theta0.copy()
    if not stepwise or not lmask.any():
        t = time.perf_counter()
        theta, res = prob.solve(theta, np.ones(layout.size, dtype=bool))
        info['steps'].append({'step': 'joint' if lmask.any() else 1, 'cost': 2 * res.cost,
                              'nfev': int(res.nfev), 'time_s': time.perf_counter() - t})
        return layout, theta, prob, info
    prev = theta[lmask].copy()
    for it in range(max_iterations):
        for step, mask, label in ((1, tmask, 'step 1 (velocity, temperature)'),
                                  (2, lmask, 'step 2 (load)')):
            t = time.perf_counter()
            theta, res = prob.solve(theta, mask)
            info['steps'].append({'step': step, 'iteration': it, 'cost': 2 * res.cost,
                                  'nfev': int(res.nfev), 'time_s': time.perf_counter() - t})
            if progress:
                progress(f'  {label}, pass {it + 1}: RMS '
                         f'{math.sqrt(2 * res.cost / len(prob.y)):.4f} Nm')
        change = np.max(np.abs(theta[lmask] - prev) / np.maximum(np.abs(theta[lmask]), 1e-3))
        prev = theta[lmask].copy()
        if change < tol:
            break
    t = time.perf_counter()
    theta, res = prob.solve(theta, np.ones(layout.size, dtype=bool))
    info['steps'].append({'step': 'joint', 'cost': 2 * res.cost, 'nfev': int(res.nfev),
                          'time_s': time.perf_counter() - t})
    if progress:
        rms = math.sqrt(2 * res.cost / len(prob.y))
        progress(f'  joint refinement of steps 1+2: RMS {rms:.4f} Nm')
    return layout, theta, prob, info


def covariance(prob: Problem, theta: FloatArray) -> tuple[FloatArray, float]:
    """Covariance of theta: s^2 (J^T J)^-1 (pseudo-inverse if singular), and s^2."""
    jac = prob.jacobian(theta)
    r = prob.residual_batch(theta)[0]
    dof = max(len(r) - theta.size, 1)
    s2 = float(r @ r) / dof
    cov = s2 * np.linalg.pinv(jac.T @ jac)
    return cov, s2


def temperature_range(plateaus: Plateaus) -> tuple[float, float]:
    lo, hi = float(plateaus.xi.min()), float(plateaus.xi.max())
    if hi - lo < 0.2:
        c = 0.5 * (lo + hi)
        lo, hi = c - 0.1, c + 0.1
    return lo, hi


def load_reference(plateaus: Plateaus) -> float:
    return max(float(np.max(plateaus.load)) if len(plateaus) else 0.0, 1.0)
