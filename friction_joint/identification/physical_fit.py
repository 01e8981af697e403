# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A static-curve fit that stays physical, starts from many points and says what it cannot pin.

Steps 1-2 of the identification (:class:`~friction_joint.identification.static_fit.
StaticIdentifier`) run here:

* **Physical by construction.**  Temperature polynomials are node values over the
  recorded temperature range (:class:`~friction_joint.identification.static_problem.
  CoefficientLayout`) with bounds F_c, F_s, F_v >= 0, 0.05 <= delta_v <= 3 and v_s in a
  band set by the data (:func:`vs_band`: from a thirtieth of the slowest plateau
  speed to the fastest); the coupled conditions F_s >= F_c >= 0 and F_v >= 0 over the
  whole recorded temperature *and* load range are one-sided penalty residuals so
  stiff (:data:`PENALTY` per plateau) that a violation costs more than the noise.
  delta_s is fitted within :data:`DELTA_S_BOUNDS` when the data pin it.
* **Many starts.**  The curve is linear in F_c, F_s, F_v and their load terms once
  v_s, delta_v and delta_s are given: for every point of a grid over those three
  (:func:`grid_profile`) the linear part is solved exactly (bounded linear least
  squares), which gives the profile of the residual over v_s and delta_s and the
  starts of the nonlinear fit: the best grid point and the best one of each other
  local minimum of the v_s profile.  Every start is refined; among the minima whose
  residual the data cannot tell apart, the one with the best held-out error wins.
* **Identifiability.**  The v_s and delta_s profiles give likelihood-ratio
  intervals (the residual at most ``1 + 4 / (n - p)`` times the best: about two
  standard errors).  An interval that reaches the slow end of the band means the
  data do not see the Stribeck dip (no plateau near or below v_s): v_s and F_s are
  reported as not identified and kept (v_s from the structure file, moved into the
  interval; F_s as the structure's F_s / F_c ratio times the fitted F_c), never
  fitted to an absurdity.  An interval over the whole delta_s range keeps delta_s
  from the structure.
"""
from __future__ import annotations

from collections.abc import Callable
import dataclasses
import math
from typing import Any, TYPE_CHECKING

import numpy as np

from ._arrays import BoolArray, FloatArray, IntArray
from .physical_problem import (DELTA_S_BOUNDS, feasible_theta, FS_RATIO_MAX, grid_profile,
                               lever_torque, PhysicalLayout, PhysicalProblem, profile_interval,
                               project_theta, solve_bounded, vs_band)
from ..models.static import PARAMETERS

if TYPE_CHECKING:
    from .plateaus import Plateaus
    from .static_structure import StaticStructure
    from ..gear import FrictionParams

__all__ = ['PROFILE_SPAN', 'CONDITION_LIMIT', 'BOOTSTRAP_RESAMPLES', 'PhysicalFit',
           'fit_physical', 'sensor_lag_bound']

#: v_s is not pinned when its profile interval spans more than this factor
PROFILE_SPAN = 3.0

_IDX = {p: i for i, p in enumerate(PARAMETERS)}


@dataclasses.dataclass
class PhysicalFit:
    """
    The result of :func:`fit_physical`.

    Attributes
    ----------
    structure : StaticStructure
        The structure finally fitted: parameters the data do not pin are in its
        ``fixed`` (kept values), delta_s is the fitted or kept value.
    layout : PhysicalLayout
        Its layout (the fitted parameter vector's blocks).
    theta : ndarray
        Fitted parameter vector.
    problem : PhysicalProblem
        The problem fitted.
    cov : ndarray
        Covariance of ``theta``; ``cov_method`` says how it was obtained.
    s2 : float
        Residual variance.
    residuals : ndarray
        Model minus measured friction torque per plateau.
    kept : dict
        Parameter -> what was kept and why (the data do not pin it).
    intervals : dict
        ``vs`` and ``delta_s`` likelihood-ratio intervals of the profiles.
    starts : list of dict
        The starts of the nonlinear fit and where each ended.
    steps : list of dict
        Fit passes (cost, evaluations, time).
    nfev : int
        Residual evaluations.
    cov_method : dict
        How ``cov`` was obtained (``method``, ``condition``, factors applied).
    fs_ratio : float or None
        F_s / F_c where F_s is tied to F_c, else None.
    at_bound : list of str
        Parameters that ended on a bound of their search range.
    time_s : float
        Wall time of the fit (s).

    """

    structure: StaticStructure
    layout: PhysicalLayout
    theta: FloatArray
    problem: PhysicalProblem
    cov: FloatArray
    s2: float
    residuals: FloatArray
    kept: dict[str, dict[str, Any]]
    intervals: dict[str, dict[str, Any]]
    starts: list[dict[str, Any]]
    steps: list[dict[str, Any]]
    nfev: int
    cov_method: dict[str, Any]
    fs_ratio: float | None
    at_bound: list[str]
    time_s: float


def _prior_value(prior: FrictionParams, name: str, xi: float) -> float | None:
    coef = getattr(prior, name)
    if coef is None or not len(coef):
        return None
    return float(np.polynomial.polynomial.polyval(xi, coef))


def sensor_lag_bound(plateaus: Plateaus) -> float | None:
    """
    Return the longest temperature-sensor lag worth fitting (s), or None.

    Half the time the fastest temperature change takes to cross the recorded range;
    None when the temperature does not change at different rates (the lag is then a
    constant offset of the temperature, inseparable from the polynomials).
    """
    rate = np.abs(plateaus.xi_rate)
    span = float(np.ptp(plateaus.xi)) if len(plateaus) else 0.0
    if not len(plateaus) or rate.max() <= 0.0 or np.ptp(plateaus.xi_rate) <= 0.0 or span <= 0:
        return None
    return 0.5 * span / float(rate.max())


def _best_at(sse: FloatArray, thetas: FloatArray, index: int) -> FloatArray:
    """Return the grid point of least residual with the first axis at ``index``."""
    sub = sse[index]
    j = np.unravel_index(int(np.argmin(sub)), sub.shape)
    theta: FloatArray = thetas[index][j]
    return theta


def _profile(problem: PhysicalProblem, sse: FloatArray, thetas: FloatArray, block: slice,
             grid: FloatArray) -> tuple[FloatArray, list[FloatArray]]:
    """
    Residual with one nonlinear parameter held at each grid value, the rest refitted.

    Each point starts from its best grid point and from its neighbour's solution
    (a sweep down the grid, then one up), so one stuck local fit does not dent it.
    """
    p = problem.layout.size
    free = np.ones(p, dtype=bool)
    free[block] = False
    prof = np.full(len(grid), np.inf)
    sols: list[FloatArray | None] = [None] * len(grid)

    def attempt(i: int, start: FloatArray | None) -> None:
        if start is None:                   # no fit at that grid value to start from
            return
        th0 = start.copy()
        th0[block] = grid[i]
        th, e, _ = solve_bounded(problem, th0, free, tol=1e-8, max_nfev=60)
        if e < prof[i]:
            prof[i], sols[i] = e, th

    for i in range(len(grid) - 1, -1, -1):
        attempt(i, _best_at(sse, thetas, i))
        if i + 1 < len(grid):
            attempt(i, sols[i + 1])
    for i in range(1, len(grid)):
        if prof[i - 1] < prof[i]:
            attempt(i, sols[i - 1])
    return prof, [th if th is not None else _best_at(sse, thetas, i)
                  for i, th in enumerate(sols)]


def _local_minima(profile: FloatArray, limit: int = 4) -> list[int]:
    """Return the indices of the local minima of a profile, best first."""
    out = []
    for i in range(len(profile)):
        left = profile[i - 1] if i > 0 else np.inf
        right = profile[i + 1] if i + 1 < len(profile) else np.inf
        if profile[i] <= left and profile[i] <= right:
            out.append(i)
    return sorted(out, key=lambda i: profile[i])[:limit]


def fit_physical(structure: StaticStructure, plateaus: Plateaus, t_range: tuple[float, float],
                 load_ref: float, *, prior: FrictionParams,
                 progress: Callable[[str], None] | None = None, cv_folds: int = 5
                 ) -> PhysicalFit:
    """
    Fit a static structure physically, from many starts, keeping what the data cannot pin.

    Parameters
    ----------
    structure : StaticStructure
        What to fit (after :func:`~friction_joint.identification.static_structure.
        carry_structure`).
    plateaus : Plateaus
        The data.
    t_range : tuple of float
        Recorded temperature range (degC).
    load_ref : float
        Load scale (Nm).
    prior : FrictionParams
        The structure file's friction section: the values kept for what is not pinned.
    progress : callable, optional
        ``progress(message)``.
    cv_folds : int
        Folds of the held-out choice between minima the residual cannot tell apart.

    Returns
    -------
    PhysicalFit

    """
    import time
    t_start = time.perf_counter()
    n = len(plateaus)
    kappa = structure.velocity_scale
    band = vs_band(plateaus, kappa)
    xm = 0.5 * (t_range[0] + t_range[1])
    load_max = float(np.max(plateaus.load)) if n else 0.0
    stribeck = structure.stribeck and 'vs' in structure.orders and 'fs' in structure.orders
    lever = bool(np.ptp(lever_torque(plateaus)) > 0) if n else False
    lag_max = sensor_lag_bound(plateaus)
    layout = PhysicalLayout(structure, t_range, load_ref, free_delta_s=stribeck, band=band,
                            load_max=load_max, lever=lever, lag_max=lag_max)
    vs_grid = np.geomspace(band[0], band[1], 16) if stribeck else np.array([1.0])
    dv_grid = (np.linspace(0.3, 1.5, 7) if 'delta_v' in structure.orders
               else np.array([1.0]))
    ds_grid = np.array([0.5, 1.0, 1.5, 2.0, 2.5, 3.0]) if stribeck else \
        np.array([structure.delta_s])
    sse, thetas = grid_profile(layout, plateaus, vs_grid=vs_grid, dv_grid=dv_grid,
                               ds_grid=ds_grid)
    problem = PhysicalProblem(layout, plateaus)
    p = layout.size
    factor = 1.0 + 4.0 / max(n - p, 1)
    kept: dict[str, dict[str, Any]] = {}
    intervals: dict[str, dict[str, Any]] = {}
    starts: list[dict[str, Any]] = []
    steps: list[dict[str, Any]] = []
    results: list[tuple[float, FloatArray]]
    blocks = {name: sl for name, _, sl in layout.blocks}
    if stribeck:
        # profiles: v_s (resp. delta_s) held at each grid value, everything else refitted
        prof_vs, th_vs = _profile(problem, sse, thetas, blocks['vs'], vs_grid)
        prof_ds, _ = _profile(problem, np.moveaxis(sse, 2, 0), np.moveaxis(thetas, 2, 0),
                              blocks['delta_s'], ds_grid)
        cand = [th_vs[i] for i in _local_minima(prof_vs)]
        results = []
        for th0 in cand:
            t0 = time.perf_counter()
            th, e, res = solve_bounded(problem, th0)
            steps.append({'step': 'joint', 'cost': e, 'nfev': int(res.nfev),
                          'time_s': time.perf_counter() - t0})
            results.append((e, th))
            starts.append({'vs_start': float(th0[blocks['vs']][0] / kappa), 'final_sse': e})
        best = min(min(r[0] for r in results), float(prof_vs.min()), float(prof_ds.min()))
        vlo, vhi, at_lo, _ = profile_interval(vs_grid, prof_vs, best, n, p)
        dlo, dhi, d_lo, d_hi = profile_interval(ds_grid, prof_ds, best, n, p)
        intervals['vs'] = {'low': vlo / kappa, 'high': vhi / kappa,
                           'band': [band[0] / kappa, band[1] / kappa], 'at_slow_end': at_lo,
                           'profile': [[float(v / kappa), float(e)]
                                       for v, e in zip(vs_grid, prof_vs, strict=True)]}
        intervals['delta_s'] = {'low': dlo, 'high': dhi,
                                'band': [float(ds_grid[0]), float(ds_grid[-1])]}
        vmin = float(np.min(np.abs(plateaus.qd)))
        wide = vhi > PROFILE_SPAN * vlo
        if at_lo or wide:
            # the data do not see the Stribeck dip (or not its width): keep v_s (moved into
            # the interval the data allow) and F_s / F_c from the structure file
            v_prior = _prior_value(prior, 'vs', xm)
            v_keep = float(np.clip(v_prior if v_prior and v_prior > 0 else vlo, vlo, vhi))
            fc_p, fs_p = _prior_value(prior, 'fc', xm), _prior_value(prior, 'fs', xm)
            ratio = float(max(1.0, fs_p / fc_p)) if fc_p and fs_p and fc_p > 0 else 1.0
            ds_keep = float(np.clip(prior.delta_s, DELTA_S_BOUNDS[0], DELTA_S_BOUNDS[1]))
            orders = {k: v for k, v in structure.orders.items() if k not in ('vs', 'fs')}
            lo_ord = {k: (0 if k in ('vs', 'fs') else v)
                      for k, v in structure.load_orders.items()}
            s2 = dataclasses.replace(structure, orders=orders, load_orders=lo_ord,
                                     delta_s=ds_keep)
            start = th_vs[int(np.argmin(np.abs(np.log(vs_grid / v_keep))))]
            # the kept values must still agree with the data: the structure's ratio, else a
            # fitted ratio, at the kept v_s; else slide v_s down until they do
            tries: list[tuple[float, float | str]] = [(v_keep, ratio), (v_keep, 'free')]
            tries += [(float(v), ratio) for v in vs_grid[::-1] if v < v_keep]
            done = []
            for v_try, tie in tries:
                s3 = dataclasses.replace(s2, fixed=dict(structure.fixed, vs=[v_try]))
                lay2 = PhysicalLayout(s3, t_range, load_ref, ties={'fs': tie}, band=band,
                                      load_max=load_max, lever=lever, lag_max=lag_max)
                th2 = project_theta(layout, lay2, start)
                if tie == 'free':
                    th2[[s_ for n_, _, s_ in lay2.blocks if n_ == 'fs_ratio'][0]] = ratio
                prob2 = PhysicalProblem(lay2, plateaus)
                th2, e2, _ = solve_bounded(prob2, th2)
                done.append((e2, v_try, tie, s3, lay2, prob2, th2))
                if e2 <= best * factor:
                    break
            else:                                   # none agrees: the closest of them
                done.sort(key=lambda d: d[0])
            e2, v_try, tie, s2, lay2, prob2, th2 = done[-1] if done[-1][0] <= best * factor \
                else done[0]
            if at_lo:
                why = (f'the slowest plateau is {vmin:.3g} rad/s and the data fit as well with '
                       f'v_s anywhere below {vhi / kappa:.3g} rad/s: no plateau near or below '
                       'v_s')
            else:
                why = (f'the data fit as well with v_s anywhere in {vlo / kappa:.3g}..'
                       f'{vhi / kappa:.3g} rad/s (the slowest plateau is {vmin:.3g} rad/s): the '
                       "dip's width trades against its depth F_s - F_c and its shape delta_s")
            if at_lo:
                advice = (f'record plateaus down to {vlo / kappa:.2g} rad/s or slower, several '
                          'around the dip, to identify it')
            else:
                advice = (f'record more plateaus within {vlo / kappa:.2g}..{vhi / kappa:.2g} '
                          'rad/s, where the dip lies, to identify it')
            r_now = ratio if tie != 'free' else float(
                th2[[s_ for n_, _, s_ in lay2.blocks if n_ == 'fs_ratio'][0]][0])
            if r_now < 1.02:
                why += (f'; the dip is shallow (F_s = {r_now:.3g} F_c), so v_s hardly changes '
                        'the curve')
            if v_prior and abs(v_try - v_prior) <= 1e-9 * v_try:
                source = 'structure file'
            elif vlo <= v_try <= vhi:
                source = 'structure file, moved into the range the data allow'
            else:
                source = ("below the range the data allow: the structure file's F_s / F_c "
                          'does not fit the data with a wider dip')
            kept['vs'] = {'value': v_try / kappa, 'source': source, 'why': why,
                          'advice': advice}
            if tie == 'free':
                r = float(th2[[s_ for n_, _, s_ in lay2.blocks if n_ == 'fs_ratio'][0]][0])
                kept['fs'] = {'value': f'{r:.4g} x fc', 'source': 'fitted as a ratio of F_c '
                              "at the kept v_s (the structure file's ratio disagrees with the "
                              'data)', 'why': why, 'advice': advice}
            else:
                kept['fs'] = {'value': f'{ratio:.3g} x fc', 'source': "the structure file's "
                              'F_s / F_c ratio', 'why': why, 'advice': advice}
            kept['delta_s'] = {'value': ds_keep, 'source': 'structure file', 'why': why,
                               'advice': advice}
            structure, layout, problem = s2, lay2, prob2
            results = [(e2, th2)]
        elif d_lo and d_hi:
            ds_keep = float(np.clip(prior.delta_s, dlo, dhi))
            structure = dataclasses.replace(structure, delta_s=ds_keep)
            lay2 = PhysicalLayout(structure, t_range, load_ref, band=band, load_max=load_max,
                                  lever=lever, lag_max=lag_max)
            prob2 = PhysicalProblem(lay2, plateaus)
            results = [solve_bounded(prob2, project_theta(layout, lay2, th))[:2][::-1]
                       for _, th in results]
            kept['delta_s'] = {'value': ds_keep, 'source': 'structure file',
                               'why': f'the data fit as well with any delta_s in '
                                      f'{ds_grid[0]:g}..{ds_grid[-1]:g}: the plateaus do not '
                                      'resolve the shape of the Stribeck dip',
                               'advice': 'record more plateaus between v_s / 3 and 3 v_s'}
            layout, problem = lay2, prob2
    else:
        th0 = thetas.reshape(-1, p)[int(np.argmin(sse))]
        t0 = time.perf_counter()
        th, e, res = solve_bounded(problem, th0)
        steps.append({'step': 'joint', 'cost': e, 'nfev': int(res.nfev),
                      'time_s': time.perf_counter() - t0})
        results = [(e, th)]
    # the fits by residual (stable); several close ones come from the starts, in their order
    ranked = sorted(range(len(results)), key=lambda i: results[i][0])
    e_best = results[ranked[0]][0]
    close = [i for i in ranked if results[i][0] <= e_best * factor]
    chosen = results[close[0]]
    if len(close) > 1 and n >= 2 * cv_folds:
        scores = [_held_out(layout, plateaus, results[i][1], cv_folds) for i in close]
        chosen = results[close[int(np.argmin(scores))]]
        for i, sc in zip(close, scores, strict=True):
            starts[i]['held_out_mse'] = sc
    e, theta = chosen
    theta = feasible_theta(layout, theta)
    fs_terms = structure.orders.get('fs', -1) + 1 + structure.load_orders.get('fs', 0)
    if 'fs' in structure.orders and 'fs' not in layout.ties and fs_terms > 1 and n > p + 2:
        # does the data carry F_s's own temperature and load dependence, or only a ratio?
        e, theta, layout, problem, structure = _try_ratio(
            e, theta, layout, problem, structure, plateaus, t_range, load_ref, band, load_max,
            kept, fs_terms, xm)
    if progress:
        progress(f'  {len(results)} start(s) from a grid of {sse.size} (v_s, delta_v, delta_s) '
                 f'points; RMS {math.sqrt(e / max(n, 1)):.4f} Nm')
    if any(name == 'delta_s' for name, _, _ in layout.blocks):
        sl = [s for name, _, s in layout.blocks if name == 'delta_s'][0]
        structure = dataclasses.replace(structure, delta_s=float(theta[sl][0]))
    fs_ratio: float | None = None
    if 'fs' in layout.ties:                       # the tie, as the values it gives
        tie = layout.ties['fs']
        fs_ratio = float(theta[[s_ for n_, _, s_ in layout.blocks if n_ == 'fs_ratio'][0]][0]) \
            if tie == 'free' else float(tie)
        fc = layout.coefficients(theta)['fc']
        structure = dataclasses.replace(structure, fixed=dict(
            structure.fixed, fs=[float(fs_ratio * c) for c in fc]))
    r = problem.data_residuals(theta)[0]
    dof = max(n - layout.size, 1)
    resid_var = float(r @ r) / dof
    jac = problem.data_jacobian(theta, np.ones(layout.size, dtype=bool))
    cov, method = _covariance(jac, resid_var, problem, layout, plateaus, theta)
    # few plateaus per coefficient: +-2 standard errors should still cover 95 %, so the
    # covariance carries the Student-t factor of the residual degrees of freedom
    from scipy.stats import t as t_dist
    factor_t = float(t_dist.ppf(0.975, dof) / 1.959964)
    cov = cov * factor_t ** 2
    method['student_t_factor'] = factor_t
    lo_b, hi_b = layout.bounds()
    with np.errstate(invalid='ignore'):
        on = ((theta - lo_b <= 1e-6 * np.maximum(np.abs(lo_b), 1e-9))
              | (hi_b - theta <= 1e-6 * np.maximum(np.abs(hi_b), 1e-9)))
    at_bound = [name for name, kind, sl in layout.blocks if kind != 'load' and on[sl].any()]
    return PhysicalFit(structure=structure, layout=layout, theta=theta, problem=problem,
                       cov=cov, s2=resid_var, cov_method=method, residuals=r, kept=kept,
                       intervals=intervals, starts=starts, steps=steps, nfev=problem.nfev,
                       fs_ratio=fs_ratio, at_bound=at_bound,
                       time_s=time.perf_counter() - t_start)


def _try_ratio(e: float, theta: FloatArray, layout: PhysicalLayout, problem: PhysicalProblem,
               structure: StaticStructure, plateaus: Plateaus, t_range: tuple[float, float],
               load_ref: float, band: tuple[float, float], load_max: float,
               kept: dict[str, dict[str, Any]], fs_terms: int, xm: float
               ) -> tuple[float, FloatArray, PhysicalLayout, PhysicalProblem, StaticStructure]:
    """
    F_s as a fitted ratio of F_c when the data do not carry F_s's own dependencies.

    The nested model F_s = r F_c (one coefficient instead of ``fs_terms``) is kept when
    an F-test at 95 % finds the full model no better.
    """
    from scipy.stats import f as f_dist
    n = len(plateaus)
    orders = {k: v for k, v in structure.orders.items() if k != 'fs'}
    lo_ord = {k: (0 if k == 'fs' else v) for k, v in structure.load_orders.items()}
    s_t = dataclasses.replace(structure, orders=orders, load_orders=lo_ord)
    free_ds = any(name == 'delta_s' for name, _, _ in layout.blocks)
    lay_t = PhysicalLayout(s_t, t_range, load_ref, ties={'fs': 'free'}, free_delta_s=free_ds,
                           band=band, load_max=load_max,
                           lever=any(n_ == 'lever_error' for n_, _, _ in layout.blocks),
                           lag_max=layout.lag_max)
    th0 = project_theta(layout, lay_t, theta)
    par = layout.physics(theta[None, :], np.array([xm]), np.array([float(np.mean(plateaus.load))]))
    fc, fs = float(par[0, _IDX['fc'], 0]), float(par[0, _IDX['fs'], 0])
    th0[[s_ for n_, _, s_ in lay_t.blocks if n_ == 'fs_ratio'][0]] = np.clip(
        fs / fc if fc > 0 else 1.0, 1.0 + 1e-6, FS_RATIO_MAX - 1e-6)
    prob_t = PhysicalProblem(lay_t, plateaus)
    th_t, e_t, _ = solve_bounded(prob_t, th0)
    q = fs_terms - 1
    dof = max(n - layout.size, 1)
    stat = max(e_t - e, 0.0) / q / max(e / dof, 1e-300)
    if stat >= f_dist.ppf(0.95, q, dof):
        return e, theta, layout, problem, structure
    r = float(th_t[[s_ for n_, _, s_ in lay_t.blocks if n_ == 'fs_ratio'][0]][0])
    kept['fs'] = {'value': f'{r:.4g} x fc', 'source': 'fitted as a ratio of F_c',
                  'why': f"the data do not carry F_s's own temperature and load dependence "
                         f'({fs_terms} coefficients fit no better than one ratio to F_c: F = '
                         f'{stat:.2g}, 95 % level {f_dist.ppf(0.95, q, dof):.2g})',
                  'advice': 'record the slowest plateaus at several temperatures and loads to '
                            "identify F_s's own dependence"}
    return e_t, th_t, lay_t, prob_t, s_t


def _held_out(layout: PhysicalLayout, plateaus: Plateaus, theta: FloatArray, folds: int
              ) -> float:
    """Held-out mean squared error of a layout started from ``theta`` (random folds)."""
    from .folds import held_out_sse, random_folds
    n = len(plateaus)

    def fit_predict(fold: int, train: BoolArray, test: IntArray) -> FloatArray:
        sub = PhysicalProblem(layout, plateaus.select(train))
        tt, _, _ = solve_bounded(sub, theta, tol=1e-8, max_nfev=100)
        held = plateaus.select(test)
        r: FloatArray = (layout.torque(tt, held.qd, held.xi, held.load, lever_torque(held),
                                       held.xi_rate)[0] - held.tau_r)
        return r

    sse, count = held_out_sse(random_folds(n, folds, seed=0), n, fit_predict)
    return float(np.sum(sse)) / max(int(count.sum()), 1)


#: covariance from s^2 (J^T J)^-1 only while the column-scaled J^T J is conditioned better
CONDITION_LIMIT = 1e8
#: bootstrap resamples where it is not
BOOTSTRAP_RESAMPLES = 30


def _covariance(jac: FloatArray, s2: float, problem: PhysicalProblem, layout: PhysicalLayout,
                plateaus: Plateaus, theta: FloatArray) -> tuple[FloatArray, dict[str, Any]]:
    """Covariance of theta: analytic when well conditioned, else a bootstrap over plateaus."""
    norms = np.linalg.norm(jac, axis=0)
    norms[norms == 0] = 1.0
    js = jac / norms
    sv = np.linalg.svd(js, compute_uv=False)
    cond = float(sv[0] / sv[-1]) ** 2 if sv[-1] > 0 else np.inf
    if cond < CONDITION_LIMIT:
        cov = s2 * np.linalg.pinv(js.T @ js) / np.outer(norms, norms)
        return cov, {'method': 'analytic', 'condition': cond}
    rng = np.random.default_rng(0)
    n = len(plateaus)
    samples = []
    for _ in range(BOOTSTRAP_RESAMPLES):
        idx = rng.integers(0, n, n)
        sub = PhysicalProblem(layout, plateaus.select(idx))
        th, _, _ = solve_bounded(sub, theta, tol=1e-8, max_nfev=100)
        samples.append(th)
    cov = np.cov(np.array(samples).T)
    return np.atleast_2d(cov), {'method': 'bootstrap', 'condition': cond,
                                'resamples': BOOTSTRAP_RESAMPLES}
