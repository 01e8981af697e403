# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
What the data pin, how well, and how far the identified curve can be trusted.

* :func:`identifiability`: per parameter of the static curve, whether the data pin
  it (kept from the structure file and why, from
  :func:`~friction_joint.identification.physical_fit.fit_physical` and
  :func:`~friction_joint.identification.static_structure.carry_structure`), its
  relative standard error at the middle of the recorded temperature range (a
  parameter fitted with more than :data:`WEAK` of its value is *weakly pinned*), and
  plain-language lines for the gear file's header, ``identification.json`` and the
  report.
* :func:`held_out_validation`: the curve refitted without each of ten blocks of
  plateaus (random subsets) predicts them; RMS and worst error per speed band.  A band it
  misses by more than :data:`HELD_OUT_TOLERANCE` is where the curve is not pinned; the
  curve counts as identified (``curve_identified``) when no band is.
"""
from __future__ import annotations

import math
from typing import Any, Protocol, TYPE_CHECKING

import numpy as np

from ._arrays import FloatArray
from .physical_problem import lever_torque, PhysicalProblem, solve_bounded
from ..models.static import PARAMETERS

if TYPE_CHECKING:
    from .physical_fit import PhysicalFit
    from .plateaus import Plateaus

__all__ = ['WEAK', 'SPEED_BANDS', 'HELD_OUT_TOLERANCE', 'curve_uncertainty', 'identifiability',
           'held_out_validation', 'model_adequacy']

#: a fitted parameter whose standard error exceeds this fraction of its value is weakly pinned
WEAK = 0.5
#: speed bands of the held-out validation (log-spaced over the plateau speeds)
SPEED_BANDS = 4
#: a band whose held-out worst error exceeds this fraction of the friction torque is not pinned
HELD_OUT_TOLERANCE = 0.02


_IDX = {p: i for i, p in enumerate(PARAMETERS)}


class _Identified(Protocol):
    """What :func:`identifiability` reads of a fitted ``StaticIdentifier``."""

    @property
    def plateaus(self) -> Plateaus:
        """Return the plateaus fitted."""

    @property
    def info(self) -> dict[str, Any]:
        """Return the fit's information (``temperature_range``)."""


def _value_se(fit: PhysicalFit, name: str, xi: float, load: float) -> tuple[float, float]:
    """Value of a curve parameter at (xi, load) and its standard error (delta method)."""
    layout, theta = fit.layout, fit.theta
    x, lo = np.array([xi]), np.array([load])
    v0 = float(layout.physics(theta[None, :], x, lo)[0, _IDX[name], 0])
    h = 1e-6 * np.maximum(np.abs(theta), 1e-3)
    th = np.repeat(theta[None, :], len(theta), axis=0) + np.diag(h)
    g = (layout.physics(th, x, lo)[:, _IDX[name], 0] - v0) / h
    var = float(g @ fit.cov @ g)
    return v0, math.sqrt(max(var, 0.0))


def _change_se(fit: PhysicalFit, name: str, xa: float, xb: float, load: float
               ) -> tuple[float, float]:
    """Change of a curve parameter from xa to xb at ``load`` and its standard error."""
    layout, theta = fit.layout, fit.theta
    x, lo = np.array([xa, xb]), np.array([load, load])

    def change(th: FloatArray) -> FloatArray:
        v = layout.physics(th, x, lo)[:, _IDX[name]]
        d: FloatArray = v[:, 1] - v[:, 0]
        return d

    c0 = float(change(theta[None, :])[0])
    h = 1e-6 * np.maximum(np.abs(theta), 1e-3)
    g = (change(np.repeat(theta[None, :], len(theta), axis=0) + np.diag(h)) - c0) / h
    return c0, math.sqrt(max(float(g @ fit.cov @ g), 0.0))


def model_adequacy(validation: dict[str, Any], n: int, p: int) -> float:
    """
    Return the factor (>= 1) by which the held-out error says the covariance is too small.

    With only noise, the held-out mean square error exceeds the in-sample one by about
    (n + p) / (n - p); what exceeds that is structure the model misses (a lagging or
    biased sensor, an effect outside the model), and the parameters' variances are
    scaled up by it.

    Parameters
    ----------
    validation : dict
        :func:`held_out_validation`.
    n, p : int
        Plateaus and fitted coefficients.

    Returns
    -------
    float

    """
    if not validation.get('blocks') or n <= p or not validation['rms_in_sample'] > 0:
        return 1.0
    ratio = (validation['rms'] / validation['rms_in_sample']) ** 2
    return float(max(1.0, ratio * (n - p) / (n + p)))


def curve_uncertainty(fit: PhysicalFit, plateaus: Plateaus, xi_lo: float, xi_hi: float, *,
                      speeds: int = 12) -> dict[str, float]:
    """
    Return the largest relative +-2 standard-error band of the fitted curve in the ranges.

    Over the plateaus' speeds (log-spaced, both directions), the recorded temperature
    range's ends and the load range's ends; from the covariance by the delta method.

    Parameters
    ----------
    fit : PhysicalFit
        The fit.
    plateaus : Plateaus
        The data (their speed and load ranges).
    xi_lo, xi_hi : float
        Recorded temperature range (degC).
    speeds : int
        Speeds checked.

    Returns
    -------
    dict
        ``worst_rel`` (2 SE / |torque|) and where: ``qd``, ``xi``, ``load``.

    """
    speed = np.abs(plateaus.qd)
    v = np.geomspace(speed.min(), speed.max(), speeds)
    qd, xi, load = (a.ravel() for a in np.meshgrid(
        np.concatenate([v, -v]), [xi_lo, xi_hi],
        [float(plateaus.load.min()), float(plateaus.load.max())], indexing='ij'))
    theta = fit.theta
    h = 1e-6 * np.maximum(np.abs(theta), 1e-3)
    batch = np.vstack([theta[None, :], theta[None, :] + np.diag(h)])
    tq = fit.layout.torque(batch, qd, xi, load)
    g = (tq[1:] - tq[0]) / h[:, None]
    se = np.sqrt(np.clip(np.einsum('ik,ij,jk->k', g, fit.cov, g), 0.0, None))
    rel = 2.0 * se / np.maximum(np.abs(tq[0]), 1e-12)
    k = int(np.argmax(rel))
    return {'worst_rel': float(rel[k]), 'qd': float(abs(qd[k])), 'xi': float(xi[k]),
            'load': float(load[k])}


def identifiability(ident: _Identified, fit: PhysicalFit, notes: dict[str, dict[str, str]],
                    *, validation: dict[str, Any] | None = None) -> dict[str, Any]:
    """
    Say per parameter whether and how well the data pin it.

    Parameters
    ----------
    ident : StaticIdentifier
        The fitted identifier (its plateaus and structure).
    fit : PhysicalFit
        The fit (kept parameters, profile intervals, covariance).
    notes : dict
        What :func:`~friction_joint.identification.static_structure.carry_structure`
        lowered.
    validation : dict, optional
        :func:`held_out_validation`: a speed band whose plateaus a fit without them
        misses by more than :data:`HELD_OUT_TOLERANCE` of the friction torque (and three
        of their standard errors) is where the curve is not pinned.

    Returns
    -------
    dict
        ``curve_identified`` (bool), ``not_identified`` (name -> ``why``, ``kept``,
        ``advice``), ``weak`` (name -> ``value``, ``se``, ``rel_se``), ``parameters``
        (name -> ``value``, ``se``, ``rel_se``, ``pinned``), ``intervals``,
        ``covariance``, ``lines`` (plain words).

    """
    p = ident.plateaus
    xm = 0.5 * sum(ident.info['temperature_range'])
    load = float(np.mean(p.load)) if len(p) else 0.0
    kappa = fit.structure.velocity_scale
    missing: dict[str, dict[str, str]] = {}
    for name, k in fit.kept.items():
        missing[name] = {'why': k['why'], 'kept': f'{k["value"]} ({k["source"]})'
                         if not isinstance(k['value'], float) else
                         f'{k["value"]:.4g} ({k["source"]})', 'advice': k['advice']}
    missing.update(notes)
    params: dict[str, dict[str, Any]] = {}
    weak: dict[str, dict[str, Any]] = {}
    fitted = {n for n, k, _ in fit.layout.blocks if k == 'temp'}
    for name in PARAMETERS:
        if name not in fitted:
            continue
        v, se = _value_se(fit, name, xm, load)
        scale = 1.0 / kappa if name == 'vs' else 1.0
        rel = se / abs(v) if v else math.inf
        params[name] = {'value': v * scale, 'se': se * scale, 'rel_se': rel,
                        'pinned': bool(rel <= WEAK)}
        if rel > WEAK:
            weak[name] = params[name]
    lo_t, hi_t = ident.info['temperature_range']
    for name, kind, sl in fit.layout.blocks:
        if kind != 'temp' or sl.stop - sl.start < 2:
            continue
        change, se = _change_se(fit, name, lo_t, hi_t, load)
        scale = 1.0 / kappa if name == 'vs' else 1.0
        entry = {'change': change * scale, 'se': se * scale, 'from_xi': lo_t, 'to_xi': hi_t,
                 'resolved': bool(abs(change) > 2.0 * se)}
        params.setdefault(name, {})['temperature_change'] = entry
        if not entry['resolved']:
            weak[f'{name} temperature dependence'] = entry
    if any(name == 'delta_s' for name, _, _ in fit.layout.blocks):
        sl = [s for name, _, s in fit.layout.blocks if name == 'delta_s'][0]
        v = float(fit.theta[sl][0])
        se = float(math.sqrt(max(fit.cov[sl, sl][0, 0], 0.0)))
        params['delta_s'] = {'value': v, 'se': se, 'rel_se': se / v, 'pinned': se / v <= WEAK}
        if se / v > WEAK:
            weak['delta_s'] = params['delta_s']
    lines = []
    for name, m in missing.items():
        lines.append(f'{name} not identified: {m["why"]}; kept: {m["kept"]}; {m["advice"]}')
    for name, w in weak.items():
        if w.get('bound') or w.get('held_out'):
            continue
        if 'change' in w:
            lines.append(f'{name} not resolved: the change from {w["from_xi"]:.1f} to '
                         f'{w["to_xi"]:.1f} degC is {w["change"]:.3g} +- {w["se"]:.2g} (within '
                         'two standard errors of none): the recorded temperature range is too '
                         'narrow for it')
            continue
        lines.append(f'{name} weakly pinned: {w["value"]:.4g} +- {w["se"]:.2g} '
                     f'({100 * w["rel_se"]:.0f} % at {xm:.1f} degC)')
    if any(name == 'lever_error' for name, _, _ in fit.layout.blocks):
        sl = [s_ for name, _, s_ in fit.layout.blocks if name == 'lever_error'][0]
        e = float(fit.theta[sl][0])
        se = float(math.sqrt(max(fit.cov[sl, sl][0, 0], 0.0)))
        params['lever_error'] = {'value': e, 'se': se, 'resolved': bool(abs(e) > 2.0 * se)}
        if abs(e) > 2.0 * se:
            lines.append(f"lever gravity: tau_ext came from the structure file's lever (no "
                         f'/link_torque); the friction torque says its m g l is {100 * e:+.2g} % '
                         f'(+- {100 * se:.2g} %) off, fitted along (the friction curve is '
                         'corrected for it; the lever section is written as given)')
    if any(name == 'sensor_lag' for name, _, _ in fit.layout.blocks):
        sl = [s_ for name, _, s_ in fit.layout.blocks if name == 'sensor_lag'][0]
        lag = float(fit.theta[sl][0])
        se = float(math.sqrt(max(fit.cov[sl, sl][0, 0], 0.0)))
        params['sensor_lag'] = {'value': lag, 'se': se, 'resolved': bool(lag > 2.0 * se)}
        if lag > 2.0 * se:
            lines.append(f'temperature sensor lag: while the temperature changes, the friction '
                         f'follows the housing temperature the sensor reads {lag:.3g} s (+- '
                         f'{se:.2g} s) later; the coefficients refer to the housing temperature '
                         'as the sensor reads it when steady')
    for name in getattr(fit, 'at_bound', []):
        if name in ('fc', 'fv', 'fs', 'lever_error', 'sensor_lag'):
            continue                      # F >= 0 and F_s >= F_c: physics, not a search bound
        entry = dict(params.get(name, {}), bound=True)
        weak[name] = entry
        lines.append(f'{name} ended on the bound of its search range (v_s: '
                     f'{fit.layout.band[0] / kappa if fit.layout.band else 0:.3g}..'
                     f'{fit.layout.band[1] / kappa if fit.layout.band else 0:.3g} rad/s, from a '
                     'thirtieth of the slowest plateau to the fastest; delta_s 0.4..3; delta_v '
                     '0.05..3): the data do not pin it')
    # the curve's own uncertainty over the recorded ranges (delta method): where +-2
    # standard errors exceed the tolerance, the data do not pin the curve there
    unc = curve_uncertainty(fit, p, lo_t, hi_t)
    if unc['worst_rel'] > HELD_OUT_TOLERANCE:
        key = f'curve at {unc["qd"]:.3g} rad/s, {unc["xi"]:.1f} degC'
        weak[key] = dict(unc, held_out=True)
        lines.append(f'{key} not pinned: its +-2 standard errors reach '
                     f'{100 * unc["worst_rel"]:.2g} % of the friction torque there (tau_L '
                     f'{unc["load"]:.2f} Nm); record plateaus near that speed and temperature')
    iv = fit.intervals.get('vs', {})
    kv = fit.kept.get('vs')
    if kv and not iv.get('at_slow_end') and 'shallow' not in kv['why']:
        key = f'curve at {np.abs(p.qd).min():.3g}..{iv["high"]:.3g} rad/s'
        weak[key] = {'held_out': True, 'v_low': float(np.abs(p.qd).min()),
                     'v_high': iv['high']}
        lines.append(f'{key} not pinned: the Stribeck dip lies there but the data do not '
                     'tell its width (v_s kept, see above)')
    for b in (validation or {}).get('bands', []):
        if b['worst_rel'] > HELD_OUT_TOLERANCE and b['worst'] > 3.0 * b.get('se', 0.0):
            key = f'curve at {b["v_low"]:.3g}..{b["v_high"]:.3g} rad/s'
            weak[key] = dict(b, held_out=True)
            lines.append(f'{key} not pinned: a fit without those plateaus misses them by up to '
                         f'{100 * b["worst_rel"]:.2g} % of the friction torque '
                         f'({b["worst"]:.3g} Nm; held-out RMS {100 * b["rel_rms"]:.2g} %): '
                         'record more plateaus in that speed range')
    speed = np.abs(p.qd)
    where = (f'|qd| {speed.min():.3g}..{speed.max():.3g} rad/s, xi {lo_t:.1f}..{hi_t:.1f} degC, '
             f'tau_L {p.load.min():.2f}..{p.load.max():.2f} Nm')
    side = [k.split()[0] for k in missing if k in ('positive direction', 'negative direction')]
    if side:                                      # one direction measured, the other assumed
        have = 'negative' if side[0] == 'positive' else 'positive'
        where = f'{have} velocities only (the {side[0]} direction assumed symmetric), ' + where
    if any(w.get('held_out') for w in weak.values()):
        lines.insert(0, f'the static curve is NOT pinned everywhere in the recorded ranges '
                        f'({where}): see the speed bands below')
    else:
        lines.insert(0, f'the static curve is pinned in the recorded ranges ({where})'
                        + ('' if not missing else '; the recordings cannot tell what is kept '
                           'below'))
    if not missing and not weak:
        lines.append('every parameter of the structure is pinned by the data (relative '
                     f'standard errors at most {100 * WEAK:.0f} %)')
    loose = [k for k, w in weak.items() if w.get('held_out')]
    unchecked = validation is not None and not validation.get('blocks')
    if unchecked and validation is not None:
        lines.insert(0, f'the static curve is NOT checked: {validation["note"]}; record more '
                        'plateaus')
    return {'curve_identified': not loose and not unchecked, 'not_identified': missing,
            'weak': weak,
            'parameters': params, 'intervals': fit.intervals, 'covariance': fit.cov_method,
            'lines': lines}


def held_out_validation(fit: PhysicalFit, plateaus: Plateaus, t_range: tuple[float, float],
                        load_ref: float, *, blocks: int = 10) -> dict[str, Any]:
    """
    Predict each block of plateaus (a random subset, seeded) from a fit without it.

    Each refit starts 20 % away from the full fit (every coefficient, seeded signs), so a
    coefficient that only the held-out plateaus pin shows as an error on them.

    Parameters
    ----------
    fit : PhysicalFit
        The fit on all plateaus (its layout and parameters start each refit).
    plateaus : Plateaus
        The data.
    t_range : tuple of float
        Recorded temperature range (degC).
    load_ref : float
        Load scale (Nm).
    blocks : int
        Blocks of plateaus (at most one per plateau); with too few plateaus to refit
        without a block (fewer than the coefficients + 2 left) there is no check.

    Returns
    -------
    dict
        ``blocks``, ``rms`` and ``rms_in_sample`` (Nm), ``bands``: per speed band
        ``v_low``, ``v_high`` (rad/s), ``plateaus``, ``rms`` (Nm), ``worst`` (Nm),
        ``rel_rms`` and ``worst_rel`` (of the measured friction torque).

    """
    n = len(plateaus)
    p = fit.layout.size
    k = int(min(blocks, n))
    if k < 2 or n - math.ceil(n / k) < p + 2:
        return {'blocks': 0, 'note': f'{n} plateaus for {p} coefficients: too few to refit the '
                                     'curve without some of them and check it on those'}
    # random blocks (seeded), not runs in time: a run in time is a run in temperature
    # when the temperature only rises, and the check would measure extrapolation in it
    from .folds import random_folds
    folds = random_folds(n, k, seed=0)
    err = np.full(n, np.nan)
    # each refit starts 20 % away from the full fit (seeded signs): a coefficient only the
    # held-out plateaus pin then stays off, instead of keeping what they told the full fit
    rng = np.random.default_rng(1)
    lo, hi = fit.layout.bounds()
    for part in folds:
        train = np.setdiff1d(np.arange(n), part)
        sub = PhysicalProblem(fit.layout, plateaus.select(train))
        start = fit.theta * (1.0 + 0.2 * rng.choice([-1.0, 1.0], size=len(fit.theta)))
        start = np.clip(start, np.where(np.isfinite(lo), lo, -np.inf),
                        np.where(np.isfinite(hi), hi, np.inf))
        th, _, _ = solve_bounded(sub, start)
        held = plateaus.select(part)
        err[part] = (fit.layout.torque(th, held.qd, held.xi, held.load, lever_torque(held),
                                       held.xi_rate)[0] - held.tau_r)
    speed = np.abs(plateaus.qd)
    edges = np.geomspace(speed.min(), speed.max() * (1 + 1e-9), SPEED_BANDS + 1)
    bands = []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        m = (speed >= a) & (speed < b)
        if not m.any():
            continue
        level = np.abs(plateaus.tau_r[m])
        rel = np.abs(err[m]) / np.maximum(level, 1e-12)
        bands.append({'v_low': float(a), 'v_high': float(b), 'plateaus': int(m.sum()),
                      'se': float(np.median(plateaus.tau_r_se[m])),
                      'rms': float(np.sqrt(np.mean(err[m] ** 2))),
                      'worst': float(np.max(np.abs(err[m]))),
                      'rel_rms': float(np.sqrt(np.mean(rel ** 2))),
                      'worst_rel': float(np.max(rel))})
    return {'blocks': k, 'rms': float(np.sqrt(np.mean(err ** 2))),
            'rms_in_sample': float(np.sqrt(np.mean(fit.residuals ** 2))), 'bands': bands}
