# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Identification step 3: pre-sliding parameters of LuGre and GMS (seed Section V-A).

With the static curve g + s of steps 1-2 fixed, the dynamic parameters are
fitted to low-velocity experiments with velocity reversals ("mainly
pre-sliding phases") by a pattern search that minimises the torque error of
the model driven by the measured velocity:

* LuGre (eq. 10): ``sigma0`` (bristle stiffness, Nm/rad) and ``sigma1``
  (micro-damping, Nm s/rad).
* GMS (eq. 11-13): ``k_total`` = sum of the element stiffnesses k_i (Nm/rad;
  the ratios k_i / k_total of the starting gear's structure are kept, so
  ``k_total`` scales all k_i alike) and ``c`` (attraction C, Nm/s).  The
  torque fractions alpha_i stay as they are.  Two free parameters: the
  stiffness right after a reversal is k_total, and the spread of the
  break-away deflections alpha_i |g| / k_i keeps the structure's shape.

Objective
---------
For a candidate parameter vector the model is driven by the measured
velocity of each segment and its friction torque compared with the measured
one (e.g. ``effort - tau_ext - J qdd``); the objective is the RMS torque error
over all samples used (Nm).  A position ripple of the gear (identified like
the static curve, ``friction.position_ripple``) is removed from the measured
torque when the position is given: the models do not contain it, and on the
simulated test bed its 0.06 Nm left in biased C by about 50 % and sigma0 by
2 %.

The models take the velocity as held over a sample step and return the
torque at the step's end, so the input is the midpoint velocity
``(qd[k] + qd[k+1]) / 2`` and the output is compared with ``tau_r[k+1]``.
Feeding ``qd[k]`` and comparing with ``tau_r[k]`` would put the model half a
sample ahead, which biases sigma1 by about -sigma0 dt / 2 (-3 Nm s/rad for
2e4 Nm/rad at 3 kHz; on the test bed it drove sigma1 to its lower bound).

Likewise any *lag* of the velocity signal: the drive's causally filtered
velocity (the test bed's encoder difference through a 250 Hz Butterworth
filter, about 1.1 ms delay) shifts the fitted sigma1 by about
+sigma0 * delay (+13 and +30 Nm s/rad for sigma0 = 1.1e4 and 2.7e4 in the
tests, against true values near 1) with a small standard error, while
sigma0 is unaffected.  Differentiate the encoder position without phase
lag instead (:func:`zero_phase_derivatives`, offline, forward-backward
filter).

State at a segment's start
--------------------------
Friction in pre-sliding has memory, so every simulated segment must start
in a known state.  ``init='sliding'`` (the default): the segment starts
while the joint slides in one direction after having travelled at least
``settle`` rad since the last reversal; the model then starts in the steady
sliding state of the measured velocity there (LuGre z = g / sigma0, all GMS
elements slipping with F_i = alpha_i g), which is what any parameter set
reaches after a slide that long.  ``init='rest'``: the recording starts from
a relaxed joint at rest (z = 0, all elements sticking unloaded), as the
simulated test bed does at power-on.  ``burn_in`` additionally leaves the
first seconds of each segment out of the objective.

:func:`presliding_segments` finds such segments in a recording: windows
around velocity zero crossings where |qd| stays below ``v_max`` (a few
Stribeck velocities), each starting at a settled slide, split at every
settled slide in between so that a segment holds the reversal(s) between
two slides.

Pattern search
--------------
:func:`pattern_search` is a generalized pattern search (compass search,
Torczon 1997; Kolda, Lewis & Torczon 2003) written here: scipy has no
pattern search, and the packages that have one (pymoo, nevergrad, NOMAD's
PyNomadBBO) are large frameworks for a 2-4 parameter problem and evaluate
poll points one by one.  Each iteration polls all 2n points x +- step e_i
(projected onto the bounds) in ONE call of the objective, which simulates
them as one batch of parameter sets (the LuGre and GMS kernels take a
batch), moves to the best poll point if it improves, and then expands the
step; otherwise it contracts the step.  It stops when the step falls below
``min_step``.  The fit searches in log-parameter space, so steps are
relative changes and the parameters stay positive.

Standard errors
---------------
From the curvature of the mean squared error M at the optimum (central
finite differences in log space, all points in one batched simulation):
Cov(log theta) = 2 M tau / N * H^-1, the Gauss-Newton covariance with the
residual variance M, and N samples counted as N / tau independent ones,
tau being the integrated autocorrelation time of the residual (residuals of
filtered, sampled data are correlated).  The relative standard error of a
parameter is its log-space standard error.  They are approximate: model
error (sensor lag, ripple, temperature lag) is treated as noise.  A
parameter the data do not determine has a flat objective and a large (or
infinite) standard error; sigma1 usually is one (see the tests).

Because model error is treated as noise, a parameter whose whole effect is
below the noise can still get a small standard error: it absorbs a
systematic mismatch and the curvature of that is sharp.  The fit therefore
also measures each parameter's **effect**: the relative rise of the RMS
error when the parameter is moved an e-fold (x e and / e) from the optimum.
An effect below ``EFFECT_FLOOR`` (1 % of the residual) marks the parameter
undetermined whatever its standard error says (the data's own residual is
the scale, so the rule holds for any gear and noise level).

What the data lack
------------------
When a fit fails or is rejected, :func:`presliding_excitation` says why in
plain words from the recordings themselves: the *pre-sliding range* is the
travel after a reversal within which the friction state still remembers the
reversal (:func:`~friction_joint.identification.presliding_data.default_settle`
of the gear: 10 F_s / sigma0 for LuGre, 3 x the largest alpha_i F_s / k_i for
GMS, F_s from the fitted static curve), and the recordings are searched for
reversals whose swing (travel between two turning points of the measured
position) is shorter than that.  A commanded position (``/joint_command``)
with such swings that the measured one does not show means the joint did not
follow them (it stuck).  The advice gives swings in that range.
"""
from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
import dataclasses
import math
import time
from typing import Any, cast
import warnings

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._arrays import FloatArray, IntArray
from .pattern_search import pattern_search
from .presliding_data import (batch_frictions, BatchData, check_presliding_excitation,
                              default_settle, EXPERIMENT_ADVICE, gear_with, initial_params,
                              prepare_batch, PRESLIDING_PARAMETERS, PreslidingOptions,
                              Segment)
from .presliding_stats import (autocorr_time, covariance_from_hessian, fd_hessian,
                               log_interval)
from ..exceptions import ArgumentError, ExcitationError, GearConfigWarning
from ..gear import GearParams
from ..models.static import StaticFriction
from ..results import json_clean

#: relative rise of the RMS error over an e-fold change below which a parameter
#: counts as undetermined (its effect hides in the residual)
EFFECT_FLOOR = 0.01

__all__ = ['PreslidingFit', 'fit_presliding', 'presliding_rmse', 'reversal_swings',
           'presliding_excitation', 'DEFAULT_BOUNDS', 'ZERO_START']

#: relative search bounds around the starting value (factor down, factor up)
DEFAULT_BOUNDS = {'sigma0': (10.0, 10.0), 'sigma1': (1e3, 1e2),
                  'k_total': (10.0, 10.0), 'c': (100.0, 100.0)}
#: starting value used when the gear's value is 0 (sigma1 may be 0; log space needs > 0)
ZERO_START = {'sigma1': 0.1}


# ------------------------------------------------------------ the fit

@dataclasses.dataclass
class PreslidingFit:
    """
    Result of :func:`fit_presliding`.

    Attributes
    ----------
    model : str
    params : dict
        Fitted values (``sigma0``, ``sigma1`` or ``k_total``, ``c``); free
        parameters fitted, the others as in the starting gear.
    initial : dict
        Starting values.
    stderr : dict
        Approximate standard errors of the free parameters (same units,
        delta method value * rel_stderr; meaningful when rel_stderr << 1,
        ``inf`` when the objective is flat along the parameter).
    rel_stderr : dict
        Standard errors of the log-parameters (= relative standard errors).
    interval : dict
        ``(value * exp(-rel_stderr), value * exp(rel_stderr))``, the
        approximate 68 % range; (0, inf) for an undetermined parameter.
    correlation : ndarray
        Correlation matrix of the free log-parameters.
    gear : GearParams
        The starting gear with the fitted parameters (GMS: the k_i scaled).
    segments : list of Segment
    report : dict
        ``objective_initial``, ``objective_final`` (RMS torque error, Nm),
        ``n_samples``, ``n_segments``, ``evaluations``, ``batched_calls``,
        ``iterations``, ``wall_time`` (s), ``success``, ``message``,
        ``at_bound`` (parameters that ended on a search bound),
        ``effect`` (per parameter, the relative rise of the RMS error over an
        e-fold change from the optimum), ``undetermined`` (free parameters
        with rel_stderr > 1, on a bound, or with an effect below
        ``EFFECT_FLOOR``: the data do not fix them; their value is only the
        search's end),
        ``bounds``, ``autocorrelation_time`` (samples), ``warnings``
        (e.g. a fitted sigma1 above the passivity bound; also emitted).

    """

    model: str
    params: dict[str, float]
    initial: dict[str, float]
    stderr: dict[str, float]
    rel_stderr: dict[str, float]
    interval: dict[str, tuple[float, float]]
    correlation: np.ndarray
    gear: GearParams
    segments: list[Segment]
    report: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        """Return the fit's numbers as plain JSON types (not the gear and segments)."""
        out = json_clean({'model': self.model, 'params': self.params, 'initial': self.initial,
                          'stderr': self.stderr, 'rel_stderr': self.rel_stderr,
                          'interval': self.interval, 'correlation': self.correlation,
                          'n_segments': len(self.segments), 'report': self.report})
        return cast('dict[str, Any]', out)


#: a batched objective: log-parameter rows (m, n) to m values
_Batched = Callable[[FloatArray], FloatArray]


def _bounds(names: Sequence[str], start: Mapping[str, float],
            bounds: Mapping[str, tuple[float, float]] | None
            ) -> tuple[FloatArray, FloatArray]:
    lo, hi = [], []
    for nm in names:
        if bounds and nm in bounds:
            a, b = (float(v) for v in bounds[nm])
            if not 0.0 < a < b:
                raise ArgumentError(f'bounds[{nm!r}] must be 0 < lower < upper, '
                                    f'got {bounds[nm]}')
        else:
            down, up = DEFAULT_BOUNDS[nm]
            a, b = start[nm] / down, start[nm] * up
        lo.append(a)
        hi.append(b)
    return np.array(lo), np.array(hi)


def _effects(rmse: _Batched, x: FloatArray, names: Sequence[str],
             lo: FloatArray, hi: FloatArray, base: float) -> dict[str, float]:
    """Relative rise of ``rmse`` when each log-parameter moves by +-1 (within the bounds)."""
    rows = []
    for i in range(len(names)):
        for d in (-1.0, 1.0):
            row = np.array(x, dtype=float)
            row[i] = np.clip(row[i] + d, lo[i], hi[i])
            rows.append(row)
    values = np.asarray(rmse(np.array(rows)), dtype=float).reshape(len(names), 2)
    return {nm: float(max(np.max(v) - base, 0.0) / base) if base > 0 else math.inf
            for nm, v in zip(names, values, strict=True)}


def fit_presliding(t: ArrayLike, qd: ArrayLike, tau_r: ArrayLike, xi: ArrayLike, tau_l: ArrayLike,
                   gear: GearParams, *, segments: Sequence[Segment | slice] | None = None,
                   q: ArrayLike | None = None,
                   options: PreslidingOptions | None = None) -> PreslidingFit:
    """
    Fit the pre-sliding parameters of LuGre or GMS with the static curve fixed.

    Parameters
    ----------
    t, qd, tau_r : array_like (T,) or list of arrays
        Sample times (s, equally spaced), measured velocity (rad/s, without
        phase lag against tau_r, see :func:`zero_phase_derivatives`) and
        measured friction torque (Nm, e.g. ``effort - tau_ext - J qdd``).
        Lists are segments, each starting in the state ``init``.
    xi, tau_l : float, array_like (T,) or list
        Temperature (degC) and load tau_L (Nm) per sample (or per segment).
    gear : GearParams
        Starting gear: its static curve is kept; its LuGre/GMS section gives
        the starting values and (GMS) the stiffness structure.
    segments : list of Segment or slice, optional
        With whole-recording arrays: the parts to fit (e.g. from
        :func:`presliding_segments`).  Default: the whole arrays as one
        segment in state ``init``.
    q : array_like (T,) or list, optional
        Measured position (rad).  When given and the gear has a
        ``position_ripple`` section, that ripple (fixed, like the static
        curve) is subtracted from tau_r: LuGre and GMS do not contain it,
        and an unremoved ripple of a few hundredths of a Nm biases the fit.
    options : PreslidingOptions, optional
        The model to fit (default ``lugre``), the free parameters, bounds, initial state,
        burn-in and the search's steps; default ``PreslidingOptions()``.

    Returns
    -------
    PreslidingFit

    Raises
    ------
    ExcitationError
        The data hold no velocity reversal, or none slow enough to show the
        pre-sliding regime; the message names the experiment to run.
    PreslidingDataError
        Malformed arrays.

    """
    o = PreslidingOptions() if options is None else options
    model, free, bounds, init, burn_in = o.model, o.free, o.bounds, o.init, o.burn_in
    v_max, step, min_step, max_evals, fd_step = o.v_max, o.step, o.min_step, o.max_evals, o.fd_step
    t0 = time.perf_counter()
    if model not in PRESLIDING_PARAMETERS:
        raise ArgumentError(f"model must be 'lugre' or 'gms', got {model!r}")
    if init not in ('sliding', 'rest'):
        raise ArgumentError(f"init must be 'sliding' or 'rest', got {init!r}")
    start = initial_params(gear, model)
    names = tuple(PRESLIDING_PARAMETERS[model] if free is None else free)
    unknown = [nm for nm in names if nm not in PRESLIDING_PARAMETERS[model]]
    if unknown or not names:
        raise ArgumentError(f'free parameters of {model} are {PRESLIDING_PARAMETERS[model]}, '
                            f'got {names}')
    prepared, dt, segs = prepare_batch(t, qd, tau_r, xi, tau_l, segments, init=init, gear=gear,
                                       q=q)
    check_presliding_excitation(prepared, gear, v_max)
    data = BatchData(prepared, dt, burn_in)
    if data.n < 10 * len(names):
        raise ExcitationError(f'only {data.n} samples to fit (burn-in {burn_in} s); '
                              f'{EXPERIMENT_ADVICE}')
    x_start = {nm: (start[nm] if start[nm] > 0 else ZERO_START[nm]) for nm in start}
    lo, hi = _bounds(names, x_start, bounds)

    def params_of(x_log: FloatArray) -> list[dict[str, float]]:
        out = []
        for row in np.atleast_2d(x_log):
            p = dict(start)
            p.update({nm: float(np.exp(v)) for nm, v in zip(names, row, strict=True)})
            out.append(p)
        return out

    def mse(x_log: FloatArray) -> FloatArray:
        return data.mse(batch_frictions(gear, model, params_of(x_log)), model)

    def rmse(x_log: FloatArray) -> FloatArray:
        return np.sqrt(mse(x_log))

    x0 = np.clip(np.log([x_start[nm] for nm in names]), np.log(lo), np.log(hi))
    f_initial = float(np.sqrt(data.mse(batch_frictions(gear, model, [start]), model)[0]))
    res = pattern_search(rmse, x0, np.log(lo), np.log(hi), step=step, min_step=min_step,
                         max_evals=max_evals)
    hess, n_h = fd_hessian(mse, res.x, fd_step)
    best = params_of(res.x)[0]
    resid = data.residuals(batch_frictions(gear, model, [best]), model)[0]
    tau_ac = autocorr_time(resid)
    m_best = float(np.mean(resid * resid))
    effect = _effects(rmse, res.x, names, np.log(lo), np.log(hi), math.sqrt(m_best))
    cov, var = covariance_from_hessian(hess, 2.0 * m_best * tau_ac / data.n)
    se_log = np.sqrt(var)
    sd = np.sqrt(np.where(np.isfinite(var) & (var > 0), var, np.nan))
    corr = cov / np.outer(sd, sd)
    at_bound = [nm for nm, v, a, b in zip(names, res.x, np.log(lo), np.log(hi), strict=True)
                if v <= a + 1e-9 or v >= b - 1e-9]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always', GearConfigWarning)
        fitted_gear = gear_with(gear, model, best)
    for w in caught:
        warnings.warn(w.message, w.category, stacklevel=2)
    report: dict[str, Any] = {
        'model': model, 'free': list(names),
        'warnings': [str(w.message) for w in caught],
        'objective_initial': f_initial, 'objective_final': float(np.sqrt(m_best)),
        'n_samples': int(data.n), 'n_segments': len(segs),
        'evaluations': res.nfev + n_h + 2, 'batched_calls': res.ncalls + 3,
        'iterations': res.nit, 'success': res.success, 'message': res.message,
        'at_bound': at_bound, 'autocorrelation_time': tau_ac,
        'effect': effect,
        'undetermined': [nm for nm, se in zip(names, se_log, strict=True)
                         if not se <= 1.0 or nm in at_bound or effect[nm] < EFFECT_FLOOR],
        'bounds': {nm: (float(a), float(b)) for nm, a, b in zip(names, lo, hi, strict=True)},
        'wall_time': time.perf_counter() - t0,
    }
    return PreslidingFit(
        model=model, params=best, initial=dict(start),
        stderr={nm: float(best[nm] * s) for nm, s in zip(names, se_log, strict=True)},
        rel_stderr={nm: float(s) for nm, s in zip(names, se_log, strict=True)},
        interval={nm: log_interval(best[nm], s) for nm, s in zip(names, se_log, strict=True)},
        correlation=corr, gear=fitted_gear, segments=segs, report=report)


def presliding_rmse(gear: GearParams, t: ArrayLike, qd: ArrayLike, tau_r: ArrayLike,
                    xi: ArrayLike, tau_l: ArrayLike, *, model: str = 'lugre',
                    segments: Sequence[Segment | slice] | None = None,
                    q: ArrayLike | None = None,
                    init: str = 'sliding', burn_in: float = 0.0) -> float:
    """
    Return the RMS torque error (Nm) of a gear's LuGre or GMS model on (held-out) data.

    Parameters
    ----------
    gear : GearParams
        The gear evaluated.
    t, qd, tau_r, xi, tau_l, model, segments, q, init, burn_in
        As in :func:`fit_presliding` (``q`` removes the position ripple); no excitation check.

    """
    if model not in PRESLIDING_PARAMETERS:
        raise ArgumentError(f"model must be 'lugre' or 'gms', got {model!r}")
    prepared, dt, _ = prepare_batch(t, qd, tau_r, xi, tau_l, segments, init=init, gear=gear, q=q)
    data = BatchData(prepared, dt, burn_in)
    return float(np.sqrt(data.mse([gear.friction], model)[0]))


# ------------------------------------------------------------ what the data lack

def reversal_swings(q: ArrayLike, hysteresis: float
                    ) -> tuple[FloatArray, IntArray]:
    """
    Return the swings of ``q``: the travel between successive turning points (rad).

    A turning point counts once ``q`` has come back from it by more than
    ``hysteresis`` (rad), so noise and encoder counts below it make no swings.
    Returns ``(swings, turns)``: the swings and the indices of the turning points.
    """
    q = np.asarray(q, dtype=float)
    found: list[int] = []
    direction = 0
    hi = lo = q[0] if q.size else 0.0
    i_hi = i_lo = 0
    for i, x in enumerate(q):
        if x > hi:
            hi, i_hi = x, i
        if x < lo:
            lo, i_lo = x, i
        if direction >= 0 and x < hi - hysteresis:
            found.append(i_hi)
            direction, lo, i_lo = -1, x, i
        elif direction <= 0 and x > lo + hysteresis:
            found.append(i_lo)
            direction, hi, i_hi = 1, x, i
    turns = np.asarray(found[1:], dtype=int)       # the first is where the motion starts
    return np.abs(np.diff(q[turns])), turns


#: per recording: commanded time and position, measured time and position
_Command = tuple[FloatArray, FloatArray, FloatArray,
                 FloatArray]


def _travel(x: float) -> str:
    return f'{1e3 * x:.3g} mrad' if x < 0.1 else f'{x:.3g} rad'


def _commanded_small(commands: Iterable[_Command], length: float, hysteresis: float
                     ) -> tuple[list[float], list[float]]:
    """Commanded swings shorter than ``length`` and how far the measured position went."""
    swings: list[float] = []
    moved: list[float] = []
    for t_cmd, q_cmd, t_js, q_js in commands:
        q_cmd = np.asarray(q_cmd, dtype=float)
        if q_cmd.size < 3 or not np.all(np.isfinite(q_cmd)):
            continue
        sw, turns = reversal_swings(q_cmd, hysteresis)
        for k in np.flatnonzero(sw < length):
            a, b = t_cmd[turns[k]], t_cmd[turns[k + 1]]
            sel = (t_js >= a) & (t_js <= b)
            swings.append(float(sw[k]))
            moved.append(float(np.ptp(q_js[sel])) if np.any(sel) else 0.0)
    return swings, moved


def presliding_excitation(pieces: Sequence[Mapping[str, NDArray[Any]]], gear: GearParams,
                          models: Sequence[str], *, commands: Iterable[_Command] = ()
                          ) -> dict[str, Any]:
    """
    Say in plain words whether the recordings can show the pre-sliding parameters.

    Parameters
    ----------
    pieces : list of dict
        Contiguous pieces of the recordings with ``q`` (measured position, rad) and
        ``xi`` (degC).
    gear : GearParams
        The gear of steps 1-2 (its static curve gives F_s) with the structure's
        pre-sliding sections (their stiffness gives the range).
    models : sequence of str
        ``'lugre'``, ``'gms'``.
    commands : sequence of (t_cmd, q_cmd, t, q)
        Commanded position (``/joint_command`` q_d) with the measured one, per recording.

    Returns
    -------
    dict
        ``range_rad`` (per model: the pre-sliding range, see the module docstring),
        ``reversals``, ``smallest_swing_rad``, ``small_reversals`` (swings shorter
        than the largest range), ``commanded_small`` (commanded such swings),
        ``commanded_followed_rad`` (largest measured travel during them), ``why``
        (a sentence, or None when small reversals are there) and ``advice``.

    """
    xi = [float(np.mean(p['xi'])) for p in pieces if len(p['xi'])]
    xi_mid = 0.5 * (min(xi) + max(xi)) if xi else 0.5 * sum(gear.friction.temperature_range)
    ranges = {m: float(default_settle(gear, m, xi_mid)) for m in models}
    length, shortest = max(ranges.values()), min(ranges.values())
    hysteresis = 0.1 * shortest
    per_piece = [reversal_swings(p['q'], hysteresis)[0] for p in pieces]
    swings = np.concatenate(per_piece) if per_piece else np.zeros(0)
    small = int(np.count_nonzero(swings < length))
    cmd, moved = _commanded_small(commands, length, hysteresis)
    out: dict[str, Any]
    out = {'range_rad': ranges, 'reversals': int(swings.size),
           'smallest_swing_rad': float(swings.min()) if swings.size else None,
           'small_reversals': small, 'commanded_small': len(cmd),
           'commanded_followed_rad': max(moved) if moved else None}
    how = {'lugre': '10 F_s / sigma0', 'gms': '3 x the largest alpha_i F_s / k_i'}
    span = ' to '.join(f'{_travel(v)} ({m}: {how[m]})' for m, v in sorted(
        ranges.items(), key=lambda kv: kv[1]))
    if small:
        out['why'] = None
    else:
        seen = (f'the smallest swing between two reversals is {_travel(swings.min())}'
                if swings.size else 'the joint never reverses')
        out['why'] = (f'the recordings hold no velocity reversal within the pre-sliding range: '
                      f'{seen}, but the friction remembers a reversal only over the first '
                      f'{span} of travel after it (F_s = {_curve_at_fs(gear, xi_mid):.3g} Nm '
                      'from steps 1-2, stiffness from the structure); every reversal is '
                      'followed by a full slide, and the small back-and-forth motions that '
                      'determine the pre-sliding parameters are missing')
        if cmd:
            went = (f'moved less than {_travel(hysteresis)}' if max(moved) < hysteresis
                    else f'moved at most {_travel(max(moved))}')
            out['why'] += (f'; /joint_command asked for {len(cmd)} such small reversals (swings '
                           f'{_travel(min(cmd))} to {_travel(max(cmd))}), but the joint did not '
                           f'follow them: the measured position {went} during them (it stuck: '
                           'the controller did not push hard enough to overcome the friction '
                           'at these amplitudes)')
    out['advice'] = (f'record, after a slide of at least {_travel(length)} in one direction, '
                     f'small sinusoids or triangles about standstill with swings from '
                     f'{_travel(0.1 * shortest)} to {_travel(length)}, and check that the '
                     'measured position follows them (not only the command): a stiffer '
                     'position loop, integral action or a torque excitation makes the joint '
                     'move against the friction')
    return out


def _curve_at_fs(gear: GearParams, xi: float) -> float:
    return float(np.ravel(StaticFriction(gear.friction).parameters(float(xi))['fs'])[0])
