# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Identification of the static friction model from constant-velocity plateaus (seed V-A).

The paper identifies its model in three steps; this module does the first
two (the third, pre-sliding parameters, lives in
:mod:`friction_joint.identification.presliding` and is called by the command when present):

* **Step 1** -- velocity and temperature: the coefficients of the temperature
  polynomials of F_c, F_s, F_v, v_s and delta_v (eq. 6-7) by least squares
  (eq. 16) over the plateau data points, ``scipy.optimize.least_squares``
  with the trust-region reflective method (the paper's Matlab ``trf``), the
  load terms held fixed.
* **Step 2** -- load: with step 1 fixed, the load coefficients (powers
  1..m of tau_L, eq. 7).

Because every plateau carries some load (the lever's gravity; at high speed a
plateau sweeps the whole revolution), step 1 cannot be run on load-free data
alone: steps 1 and 2 are alternated (step 1 starts with the load terms at
zero) until the load coefficients settle (at most four passes), and a final
joint least-squares pass over all coefficients removes what is left of the
coupling.  Parameter
standard errors come from that final pass: Cov = s^2 (J^T J)^-1 with J the
Jacobian and s^2 the residual variance, mapped linearly to the file's
coefficients.

Parametrisation.  Internally each temperature polynomial of order n is
represented by its values at n + 1 Chebyshev-Lobatto nodes spanning the
recorded temperature range (well conditioned, and bounds on node values keep
F_c, F_s, F_v >= 0, v_s > 0, 0.05 <= delta_v <= 3 where there are data);
load coefficients multiply (tau_L / L)^j with L the largest plateau load.
The model is evaluated with the package's own static curve
(:class:`~friction_joint.models.static.StaticFriction`, batched: one call gives all
finite-difference columns of the Jacobian), so the identified file means
exactly what was fitted.  Load powers above 1 are evaluated at the plateau's
mean load (exact for the linear load terms, an approximation otherwise).

The model structure (which coefficients exist, the list lengths) comes from
the STRUCTURE gear file; ``orders='auto'`` instead chooses per-parameter
polynomial orders by held-out error (:func:`select_orders`).  Data that cannot
determine a coefficient raise :class:`~friction_joint.exceptions.ExcitationError`
naming what to record (:func:`check_excitation`).

Object API::

    ident = StaticIdentifier(load_gear('config/csd25.yaml')).fit(plateaus)
    ident.predict(qd, xi, tau_l)        # static friction torque, Nm
    ident.results                       # rows: parameter, power, value, se
    ident.gear                          # GearParams with the identified coefficients
"""
from __future__ import annotations

from collections.abc import Callable, Iterable
import dataclasses
import math
import time
from typing import Any, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import BoolArray, FloatArray, IntArray
from .folds import held_out_sse, random_folds
from .identifiability import held_out_validation, identifiability, model_adequacy
from .physical_fit import fit_physical, PhysicalFit
from .static_problem import (CoefficientLayout, covariance, fit_structure, load_reference,
                             Problem, temperature_range)
from .static_structure import (carry_structure, check_excitation, distinct_levels, group_table,
                               one_direction_note, PARAMETER_UNITS, StaticStructure)
from ..exceptions import ExcitationError, GearConfigError
from ..gear.schema import TEMPERATURE_BOUNDS
from ..models.static import PARAMETERS, StaticFriction

if TYPE_CHECKING:
    from .plateaus import Plateaus
    from ..gear import GearParams

__all__ = ['StaticIdentifier', 'cross_validate_orders', 'select_orders']


def cross_validate_orders(plateaus: Plateaus, structure: StaticStructure, *, folds: int = 5,
                          theta_full: np.ndarray | None = None, seed: int = 0) -> float:
    """
    Return the held-out RMS (Nm) of a structure by k-fold cross-validation over plateaus.

    The plateaus are dealt into ``folds`` random folds (seeded,
    :func:`~friction_joint.identification.folds.random_folds`: random subsets of
    plateaus, not runs of consecutive ones); each fold is left out in turn, the
    structure refitted (all coefficients at once, started from ``theta_full``
    when given) on the rest, and the left-out plateaus predicted
    (:func:`~friction_joint.identification.folds.held_out_sse`).

    Parameters
    ----------
    plateaus : Plateaus
        The data.
    structure : StaticStructure
        The model structure.
    folds : int
        Number of folds (random subsets of the plateaus; at most one per plateau).
    theta_full : ndarray, optional
        The fit on all plateaus, the start of each fold's fit; default fitted here.
    seed : int
        Seed of the fold assignment.

    Returns
    -------
    float

    """
    t_range, load_ref = temperature_range(plateaus), load_reference(plateaus)
    if theta_full is None:
        _, theta_full, _, _ = fit_structure(structure, plateaus, t_range, load_ref, stepwise=False)
    layout = CoefficientLayout(structure, t_range, load_ref)

    def fit_predict(fold: int, train: BoolArray, test: IntArray) -> FloatArray:
        """Refit without the fold's plateaus; the residuals on them."""
        _, th, _, _ = fit_structure(structure, plateaus.select(train), t_range, load_ref,
                                    theta0=theta_full, stepwise=False)
        held = plateaus.select(test)
        return layout.torque(th, held.qd, held.xi, held.load)[0, :] - held.tau_r

    n = len(plateaus)
    sse, count = held_out_sse(random_folds(n, min(folds, n), seed=seed), n, fit_predict)
    sq = 0.0
    for s in sse:                  # in fold order, as the held-out errors come
        sq += float(s)
    return math.sqrt(sq / max(int(count.sum()), 1))


def select_orders(plateaus: Plateaus, structure: StaticStructure, *, max_order: int = 2,
                  max_load_order: int = 2, threshold: float = 0.05, folds: int = 5,
                  progress: Callable[[str], None] | None = None, one_direction: bool = False
                  ) -> tuple[StaticStructure, list[dict[str, Any]]]:
    """
    Choose per-parameter polynomial orders by held-out error (``--orders auto``).

    Greedy forward selection: start with every parameter constant in temperature
    and no load terms; in each round raise, one at a time, the temperature order
    of each parameter (up to ``max_order``) and the load order of fc and fv (up
    to ``max_load_order``), skipping what the data cannot determine
    (:func:`check_excitation`), and keep the raise with the lowest k-fold
    held-out RMS if it lowers the RMS by at least ``threshold`` (5 %).  Then
    a backward pass lowers, one at a time, any order whose removal costs less
    than ``threshold`` of held-out RMS (an order raised early may have become
    unnecessary).  Lower orders are preferred unless clearly better.

    Parameters
    ----------
    plateaus : Plateaus
        The data.
    structure : StaticStructure
        The structure whose parameters are selected (its orders are not used).
    max_order, max_load_order : int
        Highest temperature and load orders tried.
    threshold : float
        Relative held-out RMS a raise must gain (and a removal may cost).
    folds : int
        Folds of the cross-validation.
    progress : callable, optional
        ``progress(message)`` per round.
    one_direction : bool
        Accept one-direction plateaus with tau_ext measured (:func:`check_excitation`).

    Returns
    -------
    structure : StaticStructure
        The chosen orders.
    trace : list of dict
        Every candidate tried: ``orders``, ``load_orders``, ``cv_rms``, ``accepted``.

    """
    cur = structure.with_orders(orders=dict.fromkeys(structure.params, 0),
                                load_orders=dict.fromkeys(PARAMETERS, 0))
    check_excitation(plateaus, cur, one_direction=one_direction)
    t_range, load_ref = temperature_range(plateaus), load_reference(plateaus)
    _, th, _, _ = fit_structure(cur, plateaus, t_range, load_ref, stepwise=False)
    best = cross_validate_orders(plateaus, cur, folds=folds, theta_full=th)
    trace = [{'orders': dict(cur.orders), 'load_orders': dict(cur.load_orders), 'cv_rms': best,
              'accepted': True}]
    if progress:
        progress(f'orders auto: all constant, no load terms: held-out RMS {best:.4f} Nm')

    def score(cands: list[StaticStructure], label: str) -> list[tuple[float, StaticStructure]]:
        """Held-out RMS of each candidate the data can determine; logged in ``trace``."""
        results = []
        for cand in cands:
            try:
                check_excitation(plateaus, cand, one_direction=one_direction)
            except ExcitationError:
                continue
            _, th, _, _ = fit_structure(cand, plateaus, t_range, load_ref, stepwise=False)
            cv = cross_validate_orders(plateaus, cand, folds=folds, theta_full=th)
            results.append((cv, cand))
            trace.append({'orders': dict(cand.orders), 'load_orders': dict(cand.load_orders),
                          'cv_rms': cv, 'accepted': False})
            if progress:
                progress(f'orders auto: {label} {cand.describe()}: held-out RMS {cv:.4f} Nm')
        return results

    while True:
        cands = []
        for p in cur.params:
            if cur.orders[p] < max_order:
                cands.append(cur.with_orders(orders={p: cur.orders[p] + 1}))
        for p in ('fc', 'fv'):
            if p in cur.orders and cur.load_orders.get(p, 0) < max_load_order:
                cands.append(cur.with_orders(load_orders={p: cur.load_orders.get(p, 0) + 1}))
        results = score(cands, 'try')
        if not results:
            break
        cv, cand = min(results, key=lambda r: r[0])
        if cv > (1.0 - threshold) * best:
            break
        best, cur = cv, cand
        for t in trace:
            if t['orders'] == cand.orders and t['load_orders'] == cand.load_orders:
                t['accepted'] = True
        if progress:
            progress(f'orders auto: keep {cur.describe()} ({cv:.4f} Nm)')
    # backward pass: drop an order again where the higher one is not clearly better
    while True:
        cands = [cur.with_orders(orders={p: cur.orders[p] - 1})
                 for p in cur.params if cur.orders[p] > 0]
        cands += [cur.with_orders(load_orders={p: cur.load_orders[p] - 1})
                  for p in cur.load_params]
        results = score(cands, 'try without one order:')
        if not results:
            break
        cv, cand = min(results, key=lambda r: r[0])
        if (1.0 - threshold) * cv > best:
            break
        best, cur = min(best, cv), cand
        trace[-len(results) + [r[1] for r in results].index(cand)]['accepted'] = True
        if progress:
            progress(f'orders auto: drop to {cur.describe()} ({cv:.4f} Nm)')
    return cur, trace


# ---------------------------------------------------------------- identifier ---

class StaticIdentifier:
    """
    Identify the static friction model (steps 1 and 2 of seed Section V-A).

    Parameters
    ----------
    structure : GearParams
        The STRUCTURE gear file: which coefficients exist (list lengths), delta_s,
        velocity_scale, inertia and lever; its coefficient values are not used.
    orders : None, 'auto' or dict
        None: the structure's orders.  'auto': chosen by held-out error
        (:func:`select_orders`).  A dict ``{'fc': 2, 'fc_load': 1, ...}`` overrides
        individual orders.
    fixed : iterable of str
        Parameters kept at the structure's values (e.g. ``('delta_v',)``).
    progress : callable, optional
        ``progress(message)`` for long fits.

    Attributes
    ----------
    gear : GearParams
        The structure with the identified coefficients and
        ``temperature_range`` set to the recorded temperature range.
    coefficients, standard_errors : dict
        Parameter (``fc``, ``fc_load``, ...) -> list in the file's convention.
    results : list of dict
        One row per coefficient: ``parameter``, ``power``, ``value``, ``se``, ``unit``.
    rms : float
        RMS residual over the plateaus (Nm).
    group_fits : list of dict
        Order-0 fits per temperature group (markers of Fig. 3 b).
    info : dict
        Steps, iterations, timings, node values, order selection trace.

    Notes
    -----
    The attributes are set by :meth:`fit`.

    """

    def __init__(self, structure: GearParams, *, orders: str | dict[str, int] | None = None,
                 fixed: Iterable[str] = (),
                 progress: Callable[[str], None] | None = None) -> None:
        self.structure_gear = structure
        self.base = StaticStructure.from_gear(structure, fixed=fixed)
        self.orders = orders
        self.progress = progress
        self.gear: GearParams | None = None

    # -- fitting
    def _structure(self, plateaus: Plateaus) -> StaticStructure:
        if self.orders == 'auto':
            s, trace = select_orders(plateaus, self.base, progress=self.progress,
                                     one_direction=True)
            self.info['order_selection'] = trace
            return s
        if isinstance(self.orders, dict):
            temp = {k: int(v) for k, v in self.orders.items() if not k.endswith('_load')}
            load = {k[:-5]: int(v) for k, v in self.orders.items() if k.endswith('_load')}
            bad = [k for k in temp if k not in self.base.orders] + \
                  [k for k in load if k not in PARAMETERS]
            if bad:
                raise GearConfigError(f'orders: unknown or absent parameter(s) {", ".join(bad)}')
            return self.base.with_orders(orders=temp, load_orders=load)
        if self.orders is not None:
            raise GearConfigError(f"orders must be None, 'auto' or a dict, got {self.orders!r}")
        return self.base

    def fit(self, plateaus: Plateaus) -> StaticIdentifier:
        """
        Fit plateaus; returns self.

        Parameters
        ----------
        plateaus : Plateaus
            The data (:func:`~friction_joint.identification.find_plateaus`).

        Returns
        -------
        StaticIdentifier
            ``self``, fitted.

        Raises
        ------
        ExcitationError
            No plateaus, plateaus in one direction with tau_ext not measured (no
            /link_torque), or fewer plateaus than the coefficients the data determine.
            One direction with tau_ext measured is fitted; the other direction is assumed
            symmetric and said (:func:`one_direction_note`).  What the data cannot pin (a Stribeck
            dip below the slowest plateau, a temperature or load order the ranges cannot
            carry, delta_v over too narrow a speed range) is not an error: it is kept
            and said (:attr:`identifiability`).

        """
        t_start = time.perf_counter()
        self.info: dict[str, Any] = {}
        t0 = time.perf_counter()
        if self.orders == 'auto':
            check_excitation(plateaus, self.base.with_orders(
                orders=dict.fromkeys(self.base.params, 0),
                load_orders=dict.fromkeys(PARAMETERS, 0)), one_direction=True)
        s = self._structure(plateaus)
        self.info['time_order_selection_s'] = time.perf_counter() - t0
        s, notes = carry_structure(plateaus, s, prior=self.structure_gear.friction)
        check_excitation(plateaus, s, stribeck=False, temperature=False, load=False,
                         one_direction=True)
        side = one_direction_note(plateaus)          # one direction: the other is assumed
        if side:
            notes = {f'{side["assumed"]} direction': {k: side[k] for k in ('why', 'kept',
                                                                           'advice')}, **notes}
        self.plateaus = plateaus
        t_range, load_ref = temperature_range(plateaus), load_reference(plateaus)
        if self.progress:
            self.progress(f'fitting {s.describe()} to {len(plateaus)} plateaus '
                          f'(xi {t_range[0]:.1f}..{t_range[1]:.1f} degC)')
        t0 = time.perf_counter()
        fit = fit_physical(s, plateaus, t_range, load_ref, prior=self.structure_gear.friction,
                           progress=self.progress)
        self.info['time_fit_s'] = time.perf_counter() - t0
        self.structure = fit.structure
        self.layout, self.theta = fit.layout, fit.theta
        self.info['steps'] = fit.steps
        self.info['multistart'] = fit.starts
        t0 = time.perf_counter()
        self.validation = held_out_validation(fit, plateaus, t_range, load_ref)
        self.info['time_validation_s'] = time.perf_counter() - t0
        adequacy = model_adequacy(self.validation, len(plateaus), fit.layout.size)
        fit.cov = fit.cov * adequacy
        fit.cov_method['held_out_factor'] = adequacy
        cov, s2 = fit.cov, fit.s2
        a = fit.layout.transform()
        cov_c = a @ cov @ a.T
        se_all = np.sqrt(np.clip(np.diag(cov_c), 0.0, None))
        coefs = fit.layout.coefficients(fit.theta)
        self.coefficients = {k: [float(x) for x in v] for k, v in coefs.items()}
        self.standard_errors = {name: [float(x) for x in se_all[sl]]
                                for name, _, sl in fit.layout.blocks}
        if 'delta_s' in self.coefficients:             # a scalar of the file, not a list
            self.coefficients['delta_s'] = self.coefficients['delta_s'][:1]
        node_se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
        self.info['nodes'] = {name: {'xi': fit.layout.nodes[name].tolist(),
                                     'value': fit.theta[sl].tolist(), 'se': node_se[sl].tolist()}
                              for name, kind, sl in fit.layout.blocks if kind == 'temp'}
        self.info['residual_variance'] = s2
        self.info['covariance_method'] = fit.cov_method
        self.info['temperature_range'] = list(t_range)
        self.info['load_ref'] = load_ref
        self.info['nfev'] = fit.nfev
        self.residuals = fit.residuals
        self.rms = float(np.sqrt(np.mean(fit.residuals ** 2)))
        self.gear = self._gear(coefs, t_range, fit)
        self.identifiability = identifiability(self, fit, notes, validation=self.validation)
        t0 = time.perf_counter()
        self.group_fits = self._group_fits(plateaus, load_ref)
        self.info['time_group_fits_s'] = time.perf_counter() - t0
        self.info['time_identifier_s'] = time.perf_counter() - t_start
        return self

    def _gear(self, coefs: dict[str, FloatArray], t_range: tuple[float, float],
              fit: PhysicalFit | None = None) -> GearParams:
        fr: dict[str, Any] = {p: [float(x) for x in c] for p, c in coefs.items()
                              if p not in ('delta_s', 'fs_ratio', 'lever_error', 'sensor_lag')}
        for p in self.base.load_orders:              # load terms dropped by auto orders
            key = p + '_load'
            if key not in fr and self.base.load_orders.get(p, 0) > 0:
                fr[key] = []
        if fit is not None:
            st = fit.structure
            fr['delta_s'] = float(st.delta_s)
            for p, c in st.fixed.items():            # kept where the data do not pin them
                fr[p] = [float(x) for x in c]
            if fit.fs_ratio is not None:             # F_s as a ratio of F_c
                r = fit.fs_ratio
                fr['fs'] = [r * x for x in fr['fc']]
                fr['fs_load'] = [r * x for x in fr.get('fc_load', [])]
        lo = math.floor(t_range[0] * 10.0) / 10.0
        hi = math.ceil(t_range[1] * 10.0) / 10.0
        fr['temperature_range'] = [lo, hi]
        t_lo, t_hi, why = TEMPERATURE_BOUNDS
        if not t_lo <= lo < hi <= t_hi:               # the recordings' fault, not the model's
            raise ExcitationError(
                f'the recorded temperatures span {lo}..{hi} degC, outside [{t_lo}, {t_hi}] '
                f'degC ({why}): a wrong unit or a corrupt value in the recordings')
        try:
            return self.structure_gear.replace({'friction': fr})
        except GearConfigError as exc:
            msg = str(exc)                             # the coefficients are the data's
            src = self.structure_gear.source
            if src and msg.startswith(f'{src}: '):
                msg = msg[len(src) + 2:]
            raise ExcitationError(
                f'the identified coefficients are not physical over the recorded temperature '
                f'range {lo}..{hi} degC ({msg}); the data do not pin the polynomial down: '
                'lower its order or record at more temperatures') from None

    def _group_fits(self, plateaus: Plateaus, load_ref: float) -> list[dict[str, Any]]:
        """
        Order-0 fits per temperature group with the identified load terms (Fig. 3 b).

        The gear warms while a group's plateaus run (a few tenths of a kelvin,
        often faster at the faster plateaus): each plateau's torque is first
        moved to the group's mean temperature with the identified model, so a
        constant-parameter fit does not take the drift for a velocity dependence.
        """
        labels, _ = group_table(plateaus)
        out = []
        single = self.structure.with_orders(orders=dict.fromkeys(self.structure.params, 0))
        for g in range(labels.max() + 1 if len(labels) else 0):
            m = labels == g
            sub = plateaus.select(m)
            if m.sum() < 8 or distinct_levels(sub.qd) < 4 or (min(np.sum(sub.qd > 0), np.sum(
                    sub.qd < 0)) < 1 and not one_direction_note(plateaus)):
                continue
            drift = (self.predict(sub.qd, sub.xi, sub.load)
                     - self.predict(sub.qd, float(sub.xi.mean()), sub.load))
            sub = dataclasses.replace(sub, tau_r=sub.tau_r - drift)
            lay = CoefficientLayout(single, temperature_range(sub), load_ref)
            th: FloatArray = np.zeros(lay.size)
            main = {name: sl for name, _, sl in self.layout.blocks}
            at = self.predict_parameters(float(sub.xi.mean()))
            for name, kind, sl in lay.blocks:
                th[sl] = float(at[name][0]) if kind == 'temp' else self.theta[main[name]]
            free = lay.mask('temp')
            prob = Problem(lay, sub)
            try:
                th, res = prob.solve(th, free)
                cov, _ = covariance(prob, th)
                se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
            except (ValueError, np.linalg.LinAlgError):
                continue
            entry: dict[str, Any] = {
                'xi': float(sub.xi.mean()), 'xi_min': float(sub.xi.min()),
                'xi_max': float(sub.xi.max()), 'plateaus': int(m.sum()),
                'rms': float(np.sqrt(2 * res.cost / len(sub))), 'values': {}, 'se': {}}
            for name, kind, sl in lay.blocks:
                if kind == 'temp':
                    entry['values'][name] = float(th[sl][0])
                    entry['se'][name] = float(se[sl][0])
            out.append(entry)
        return out

    # -- results
    def _need_fit(self) -> GearParams:
        if self.gear is None:
            raise RuntimeError('call fit() first')
        return self.gear

    def predict(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike = 0.0) -> np.ndarray:
        """
        Return the identified model's static friction torque, Nm (xi clipped to its range).

        Parameters
        ----------
        qd, xi, tau_l : array_like
            Velocity (rad/s), temperature (degC), load (Nm).

        Returns
        -------
        ndarray
            The torque (Nm).

        """
        return StaticFriction(self._need_fit().friction).torque(qd, xi, tau_l)

    def predict_parameters(self, xi: ArrayLike, tau_l: ArrayLike = 0.0) -> dict[str, np.ndarray]:
        """
        Return the evaluated curve parameters (fc, fs, fv, vs, delta_v) at xi, tau_l.

        Parameters
        ----------
        xi, tau_l : array_like
            Temperature (degC), load (Nm).

        Returns
        -------
        dict of str to ndarray

        """
        return StaticFriction(self._need_fit().friction).parameters(np.atleast_1d(xi), tau_l)

    @property
    def results(self) -> list[dict[str, Any]]:
        """One row per identified coefficient: parameter, power, value, se, unit."""
        self._need_fit()
        rows = []
        for name, vals in self.coefficients.items():
            load = name.endswith('_load')
            base = name[:-5] if load else name
            for i, (v, e) in enumerate(zip(vals, self.standard_errors[name], strict=True)):
                power = i + 1 if load else i
                var = 'tau_L' if load else 'xi'
                unit = PARAMETER_UNITS[base] + (f'/Nm^{power}' if load else
                                                (f'/degC^{power}' if power else ''))
                rows.append({'parameter': name, 'power': f'{var}^{power}', 'value': v,
                             'se': e, 'unit': unit})
        for name, vals in self.structure.fixed.items():
            for i, v in enumerate(vals):
                rows.append({'parameter': name, 'power': f'xi^{i}', 'value': float(v),
                             'se': None, 'unit': 'fixed'})
        return rows

    def results_table(self) -> str:
        """Return the :attr:`results` as aligned text."""
        lines = [f'{"parameter":<14}{"power":<9}{"value":>14}{"std. error":>14}  unit']
        for r in self.results:
            se = '(fixed)' if r['se'] is None else f'{r["se"]:.4g}'
            lines.append(f'{r["parameter"]:<14}{r["power"]:<9}{r["value"]:>14.6g}{se:>14}  '
                         f'{r["unit"]}')
        return '\n'.join(lines)

    def report(self) -> dict[str, Any]:
        """Return a JSON-able summary: parameters, standard errors, RMS, plateaus, timings."""
        self._need_fit()
        step_rms: dict[str, float] = {}
        for st in self.info.get('steps', []):
            step_rms[str(st['step'])] = math.sqrt(st['cost'] / len(self.plateaus))
        return {
            'structure': {'orders': self.structure.orders,
                          'load_orders': dict(self.structure.load_orders.items()),
                          'fixed': self.structure.fixed, 'stribeck': self.structure.stribeck,
                          'delta_s': self.structure.delta_s,
                          'velocity_scale': self.structure.velocity_scale},
            'orders_mode': 'auto' if self.orders == 'auto' else
                           ('given' if self.orders else 'structure'),
            'parameters': self.coefficients,
            'standard_errors': self.standard_errors,
            'fixed': self.structure.fixed,
            'results': self.results,
            'rms_residual': self.rms,
            'rms_by_step': step_rms,
            'max_abs_residual': float(np.max(np.abs(self.residuals))),
            'plateau_count': len(self.plateaus),
            'temperature_range': self.info['temperature_range'],
            'load_range': [float(self.plateaus.load.min()), float(self.plateaus.load.max())],
            'speed_range': [float(np.abs(self.plateaus.qd).min()),
                            float(np.abs(self.plateaus.qd).max())],
            'temperature_groups': self.group_fits,
            'nodes': self.info['nodes'],
            'steps': self.info['steps'],
            'order_selection': self.info.get('order_selection'),
            'identifiability': self.identifiability,
            'validation': self.validation,
            'multistart': self.info.get('multistart'),
            'covariance': self.info.get('covariance_method'),
            'timings': {k: v for k, v in self.info.items() if k.startswith('time_')},
        }
