# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
One recording of a fleet: its static curve, and the friction at a reference point.

:func:`analyse_recording` is the task the fleet runner sends to a worker with
the recording's *path* (the worker reads it): it finds the constant-velocity
plateaus (:func:`~friction_joint.identification.find_plateaus`) and identifies
the static curve (seed eq. 6-7, steps 1-2) **in the model gear file's
structure, around the model's coefficients**:

* F_c and F_v are always fitted (their constant coefficients);
* their temperature coefficients (powers 1..n of the gear file) are fitted
  only when the recording's plateaus can tell them
  (:func:`~friction_joint.identification.check_excitation`: plateaus at
  enough distinct temperatures), their load coefficients likewise (distinct
  loads); otherwise they keep the gear file's values: the gear file's
  temperature and load dependence carries the recording to the reference
  point;
* F_s, v_s and delta_v keep the gear file's values (a daily recording has
  no slow plateaus to tell them).

With F_s, v_s and delta_v fixed the static curve is linear in the F_c and
F_v coefficients, so the fit is a weighted linear least-squares problem
(weights from the plateaus' standard errors, the covariance scaled by the
residual variance): exact, fast, no start values.  A recording that cannot
be analysed (unreadable, corrupt, too little motion) gives ``status:
failed`` and a one-line ``reason``; nothing is raised.  The result is a
:class:`RecordingResult`; its :meth:`~RecordingResult.to_dict` (what
:func:`recording_task` sends back from a Dask worker, and what the cache
holds) and :meth:`~RecordingResult.from_dict` are its plain-JSON form.

:func:`reference_friction` evaluates a fit at the fleet's reference operating
point: F_c at (xi_ref, tau_L = 0) and the friction torque at the reference
speed (the mean of +v_ref and -v_ref), each with its standard error.
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Any, TYPE_CHECKING
import warnings

import numpy as np

from ..bag import read_recording
from ..exceptions import FrictionJointError
from ..gear import parse_gear
from ..identification import check_excitation, find_plateaus, StaticStructure
from ..models.static import pack_static, PackedStatic, StaticFriction

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['FIT_VERSION', 'RecordingResult', 'analyse_recording', 'recording_task',
           'reference_friction', 'fitted_terms', 'result_problem']

#: bumped when the per-recording analysis changes (old cached results are recomputed)
FIT_VERSION = 1
_ROWS = {'fc': 0, 'fs': 1, 'fv': 2}


def _terms_for(gear, temp_orders, load_orders):
    """Free coefficients ``[(name, index)]`` for the given told orders."""
    terms = []
    for p in ('fc', 'fv'):
        terms += [(p, i) for i in range(temp_orders[p] + 1)]
    for p in ('fc', 'fv'):
        terms += [(p + '_load', j) for j in range(load_orders[p])]
    return terms


def fitted_terms(gear, plateaus):
    """
    Return the coefficients a recording's plateaus can tell, ``[(name, index), ...]``.

    Starts from the gear file's structure for F_c and F_v and lowers the
    temperature orders, then drops the load terms, until
    :func:`~friction_joint.identification.check_excitation` accepts; the
    constant terms must be told (else its :class:`ExcitationError` is raised).
    """
    f = gear.friction
    top = {'fc': len(f.fc) - 1, 'fv': len(f.fv) - 1}
    loads = {'fc': len(f.fc_load), 'fv': len(f.fv_load)}

    def ok(temp, load):
        try:
            check_excitation(plateaus, StaticStructure(temp, load, {}, False))
        except FrictionJointError:
            return False
        return True

    base_t, base_l = {'fc': 0, 'fv': 0}, {'fc': 0, 'fv': 0}
    check_excitation(plateaus, StaticStructure(base_t, base_l, {}, False))   # raises
    temp = dict(base_t)
    for k in range(max(top.values()), 0, -1):
        cand = {p: min(k, top[p]) for p in top}
        if ok(cand, base_l):
            temp = cand
            break
    load = dict(base_l)
    for p in ('fc', 'fv'):
        if loads[p] and ok(temp, dict(load, **{p: loads[p]})):
            load[p] = loads[p]
    return _terms_for(gear, temp, load)


def _batch(gear, terms):
    """Packed static curves: the gear's, then one per term with that coefficient + 1."""
    base = pack_static(gear.friction)
    nb = 1 + len(terms)
    temp = np.repeat(base.temp, nb, axis=0)
    load = np.repeat(base.load, nb, axis=0)
    mirror = gear.friction.fs is None                # no Stribeck: F_s is F_c
    for b, (name, i) in enumerate(terms, start=1):
        p = name[:-5] if name.endswith('_load') else name
        arr = load if name.endswith('_load') else temp
        arr[b, _ROWS[p], i] += 1.0
        if mirror and p == 'fc':
            arr[b, _ROWS['fs'], i] += 1.0
    rep = (lambda a: np.repeat(a, nb))
    return StaticFriction.from_packed(PackedStatic(
        temp, load, rep(base.delta_s), rep(base.velocity_scale), rep(base.t_lo),
        rep(base.t_hi), offset=rep(base.offset)))


#: the keys of a result (``ok``: all of them, in this order; ``failed``: the first five of
#: ``_KEYS_FAILED``; a failure outside the analysis -- a missing file, a dead worker --: the
#: first three)
_KEYS_FAILED = ('path', 'status', 'reason', 'version', 'time_s')
_KEYS_OK = _KEYS_FAILED + ('terms', 'delta', 'cov', 'rms', 'plateaus', 'speed',
                           'raw_friction', 'raw_friction_se', 'xi_range', 'xi_mean',
                           'load_range', 'travel', 'duration')
_ORDER_OK = ('plateaus', 'speed', 'raw_friction', 'raw_friction_se', 'xi_range', 'xi_mean',
             'load_range', 'travel', 'duration', 'path', 'status', 'reason', 'version',
             'terms', 'delta', 'cov', 'rms', 'time_s')


def _plain(value):
    return [_plain(v) for v in value] if isinstance(value, tuple) else value


def _frozen(value):
    return tuple(_frozen(v) for v in value) if isinstance(value, list) else value


@dataclasses.dataclass(frozen=True)
class RecordingResult:
    """
    One recording's analysis: the fleet's per-recording result.

    Attributes
    ----------
    path : str
        The recording.
    status : str
        ``ok`` or ``failed``.
    reason : str
        Why it failed (one line); empty when ok.
    version : int or None
        :data:`FIT_VERSION` of the analysis; None for a failure outside it (a
        missing recording, a task whose worker died): never cached.
    time_s : float or None
        Seconds the analysis took.
    terms : tuple of (str, int)
        The coefficients fitted (name, index).
    delta : tuple of float
        Change of those coefficients from the gear file's.
    cov : tuple of tuple of float
        Their covariance.
    rms : float or None
        RMS residual of the fit (N m).
    plateaus : int or None
        Constant-velocity plateaus found.
    speed : float or None
        Median plateau speed (rad/s).
    raw_friction, raw_friction_se : float or None
        Mean |tau_r| over the plateaus and its standard error (N m).
    xi_range : tuple of float or None
        Temperatures recorded, (lowest, highest) degC.
    xi_mean : float or None
        Mean plateau temperature (degC).
    load_range : tuple of float or None
        Loads over the plateaus, (lowest, highest) N m.
    travel : float or None
        Rad moved.
    duration : float or None
        Seconds recorded.
    cached : bool
        Taken from the cache, not computed in this run (not part of :meth:`to_dict`).

    """

    path: str
    status: str
    reason: str = ''
    version: int | None = None
    time_s: float | None = None
    terms: tuple[tuple[str, int], ...] = ()
    delta: tuple[float, ...] = ()
    cov: tuple[tuple[float, ...], ...] = ()
    rms: float | None = None
    plateaus: int | None = None
    speed: float | None = None
    raw_friction: float | None = None
    raw_friction_se: float | None = None
    xi_range: tuple[float, float] | None = None
    xi_mean: float | None = None
    load_range: tuple[float, float] | None = None
    travel: float | None = None
    duration: float | None = None
    cached: bool = False

    @property
    def ok(self) -> bool:
        """Whether the recording was analysed."""
        return self.status == 'ok'

    def to_dict(self) -> dict[str, Any]:
        """
        Return the result as plain JSON types: what a Dask task sends back and the cache holds.

        Returns
        -------
        dict
            ``ok``: every field but ``cached``; ``failed``: ``path``, ``status``,
            ``reason``, ``version``, ``time_s`` (the first three when ``version`` is None).

        """
        keys = _ORDER_OK if self.ok else _KEYS_FAILED if self.version is not None \
            else _KEYS_FAILED[:3]
        return {k: _plain(getattr(self, k)) for k in keys}

    @classmethod
    def from_dict(cls, doc: dict[str, Any], **changes: object) -> RecordingResult:
        """
        Return the result from its plain form (:meth:`to_dict`).

        Parameters
        ----------
        doc : dict
            The plain form (a task's result, a cache entry that passed
            :func:`result_problem`, a failure ``{'path', 'status', 'reason'}``).
        **changes
            Fields to set instead (e.g. ``path``, ``cached``).

        Returns
        -------
        RecordingResult

        """
        fields = {k: _frozen(v) for k, v in doc.items()}
        fields.update(changes)
        return cls(**fields)


def _failed(path, reason, started):
    return RecordingResult(path, 'failed', ' '.join(str(reason).split()), FIT_VERSION,
                           time.perf_counter() - started)


def analyse_recording(path: str, gear_text: str, *, gear_name: str = 'the model gear file',
                      joint_name: str | None = None) -> RecordingResult:
    """
    Analyse one recording (the fleet's per-recording task; module docstring).

    Parameters
    ----------
    path : str
        The recording (rosbag2 directory or ``.mcap`` file), read here.
    gear_text : str
        The model gear file's text (parsed here, small to ship).
    gear_name : str
        Its name in messages.
    joint_name : str, optional
        Joint to read (default the recording's first).

    Returns
    -------
    RecordingResult
        ``status`` ``ok`` with the fit and the recording's ranges, or ``failed``
        with its ``reason``.

    """
    return _analyse(path, gear_text, gear_name, joint_name)


def recording_task(path: str, gear_text: str, *, gear_name: str = 'the model gear file',
                   joint_name: str | None = None) -> dict[str, Any]:
    """
    Return :func:`analyse_recording`'s result as plain data (a Dask task's result).

    Parameters
    ----------
    path : str
        The recording, read by the worker.
    gear_text : str
        The model gear file's text.
    gear_name : str
        Its name in messages.
    joint_name : str, optional
        Joint to read (default the recording's first).

    Returns
    -------
    dict
        :meth:`RecordingResult.to_dict`.

    """
    return _analyse(path, gear_text, gear_name, joint_name).to_dict()


def _analyse(path, gear_text, gear_name, joint_name):
    started = time.perf_counter()
    path = str(path)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')
            gear = parse_gear(gear_text, gear_name)
            rec = read_recording(path, joint_name=joint_name)
            plat = find_plateaus(rec, gear)
        info = _recording_info(rec, plat)
        terms = fitted_terms(gear, plat)
    except FrictionJointError as exc:
        return _failed(path, exc, started)
    except Exception as exc:                          # noqa: B902 - a broken file, any error
        return _failed(path, f'cannot be analysed: {type(exc).__name__}: {exc}', started)
    model = _batch(gear, terms)
    tq = model.torque(plat.qd, plat.xi, plat.load)
    x = (tq[1:] - tq[0]).T
    y = plat.tau_r - tq[0]
    w = 1.0 / np.maximum(plat.tau_r_se, 1e-4) ** 2
    sw = np.sqrt(w)
    a = x * sw[:, None]
    delta, *_ = np.linalg.lstsq(a, y * sw, rcond=None)
    r = y - x @ delta
    dof = max(len(y) - len(terms), 1)
    s2 = float((w * r * r).sum() / dof)
    try:
        cov = np.linalg.inv(a.T @ a) * max(s2, 1e-12)
    except np.linalg.LinAlgError:
        return _failed(path, 'the plateaus cannot separate F_c from F_v (singular fit): '
                       'record plateaus at more distinct speeds', started)
    return RecordingResult(
        path, 'ok', '', FIT_VERSION, time.perf_counter() - started,
        tuple((n, int(i)) for n, i in terms), tuple(delta.tolist()),
        tuple(tuple(row) for row in cov.tolist()), float(math.sqrt(np.mean(r * r))), **info)


def _recording_info(rec, plat):
    js = rec.joint_states
    tau = np.abs(plat.tau_r)
    n = len(plat)
    xi = rec.temperature.xi if rec.temperature is not None else plat.xi
    return {
        'plateaus': n, 'speed': float(np.median(np.abs(plat.qd))) if n else None,
        'raw_friction': float(tau.mean()) if n else None,
        'raw_friction_se': float(tau.std(ddof=1) / math.sqrt(n)) if n > 1 else None,
        'xi_range': (float(np.min(xi)), float(np.max(xi))) if len(xi) else None,
        'xi_mean': float(np.mean(plat.xi)) if n else None,
        'load_range': (float(plat.load.min()), float(plat.load.max())) if n else None,
        'travel': float(np.abs(np.diff(js.q)).sum()) if len(js.q) > 1 else 0.0,
        'duration': float(rec.duration)}


def reference_friction(fit: RecordingResult, gear: GearParams, xi_ref: float,
                       v_ref: float) -> dict[str, float]:
    """
    Return the fitted friction at the reference point with standard errors.

    Parameters
    ----------
    fit : RecordingResult
        An ``ok`` result of :func:`analyse_recording`.
    gear : GearParams
        The model gear file the fit was made around.
    xi_ref, v_ref : float
        Reference temperature (degC) and speed (rad/s); tau_L = 0.

    Returns
    -------
    dict
        ``fc``, ``fc_se`` (F_c at xi_ref, N m), ``torque``, ``torque_se`` (friction
        torque at +-v_ref, mean of both directions, N m).

    """
    terms = [(n, int(i)) for n, i in fit.terms]
    model = _batch(gear, terms)
    delta = np.asarray(fit.delta, dtype=float)
    cov = np.asarray(fit.cov, dtype=float)
    fc = model.parameters(xi_ref, 0.0)['fc'][:, 0]
    g_fc = fc[1:] - fc[0]
    tq = model.torque(np.array([v_ref, -v_ref]), xi_ref, 0.0)
    both = 0.5 * (tq[:, 0] - tq[:, 1])
    g_tq = both[1:] - both[0]
    return {'fc': float(fc[0] + g_fc @ delta),
            'fc_se': float(math.sqrt(max(g_fc @ cov @ g_fc, 0.0))),
            'torque': float(both[0] + g_tq @ delta),
            'torque_se': float(math.sqrt(max(g_tq @ cov @ g_tq, 0.0)))}


#: bounds of a result's numbers (physical, generous): key -> (low, high)
_BOUNDS = {'time_s': (0.0, 1e9), 'rms': (0.0, 1e9), 'speed': (1e-12, 1e4),
           'raw_friction': (0.0, 1e9), 'raw_friction_se': (0.0, 1e9),
           'xi_mean': (-273.15, 1e4), 'travel': (0.0, 1e15), 'duration': (0.0, 1e9)}
#: longest reason kept (a reason is one line of text)
_REASON_CHARS = 2000


def _number(v):
    """Return ``v`` as a float if it is a finite JSON number (not a bool), else None."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def _bounded(key, v, lo, hi):
    x = _number(v)
    if x is None:
        return f'{key} is {_shown(v)}, not a finite number'
    if not lo <= x <= hi:
        return f'{key} {x:g} is outside {lo:g}..{hi:g}'
    return None


def _shown(v):
    text = repr(v)
    return text if len(text) <= 40 else text[:37] + '...'


def _range_problem(key, v, lo, hi):
    if not isinstance(v, list) or len(v) != 2:
        return f'{key} is {_shown(v)}, not a pair of numbers'
    for x in v:
        problem = _bounded(key, x, lo, hi)
        if problem:
            return problem
    if v[0] > v[1]:
        return f'{key} {_shown(v)} is not increasing'
    return None


def _matrix_problem(terms, delta, cov):
    n = len(terms)
    if not isinstance(delta, list) or len(delta) != n:
        return f'delta is {_shown(delta)}, not {n} numbers (one per term)'
    if any(_number(x) is None or abs(x) > 1e9 for x in delta):
        return 'delta holds a value that is not a finite number'
    if not isinstance(cov, list) or len(cov) != n or \
            any(not isinstance(row, list) or len(row) != n for row in cov):
        return f'cov is not a {n}x{n} matrix (one row and column per term)'
    if any(_number(x) is None or abs(x) > 1e18 for row in cov for x in row):
        return 'cov holds a value that is not a finite number'
    c = np.array(cov, dtype=float)
    if np.any(np.diag(c) < 0) or not np.allclose(c, c.T, rtol=1e-6, atol=1e-300):
        return 'cov is not a covariance (symmetric, variances >= 0)'
    return None


def _terms_problem(terms, gear):
    if not isinstance(terms, list) or not terms:
        return f'terms is {_shown(terms)}, not a list of [name, index] pairs'
    f = gear.friction
    known = set(_terms_for(gear, {'fc': len(f.fc) - 1, 'fv': len(f.fv) - 1},
                           {'fc': len(f.fc_load), 'fv': len(f.fv_load)}))
    seen = set()
    for t in terms:
        if not (isinstance(t, list) and len(t) == 2 and isinstance(t[0], str)
                and isinstance(t[1], int) and not isinstance(t[1], bool)):
            return f'term {_shown(t)} is not a [name, index] pair'
        if (t[0], t[1]) not in known:
            return f'term {_shown(t)} is not a coefficient of the model gear file'
        if (t[0], t[1]) in seen:
            return f'term {_shown(t)} appears twice'
        seen.add((t[0], t[1]))
    if not {('fc', 0), ('fv', 0)} <= seen:
        return 'terms lack the constant F_c or F_v coefficient'
    return None


def result_problem(result, gear):
    """
    Return what is wrong with a per-recording result read from outside, None if it is sound.

    The fleet's cache is data, not trust: before a cached result is used it is
    checked against the schema of :meth:`RecordingResult.to_dict` -- the
    keys of its status (no more, no fewer), their types, finite numbers within
    physical bounds, ranges in order, ``terms`` coefficients of ``gear``
    (each once, the constant F_c and F_v among them), ``delta`` one number per
    term, ``cov`` a symmetric matrix of their size with variances >= 0, a
    ``reason`` of one line.

    Parameters
    ----------
    result : object
        The result as parsed from JSON.
    gear : GearParams
        The model gear file the result must have been fitted around.

    Returns
    -------
    str or None
        The first problem found (a short phrase), or None.

    """
    if not isinstance(result, dict):
        return f'is {_shown(result)}, not an object'
    status = result.get('status')
    if status not in ('ok', 'failed'):
        return f'status is {_shown(status)}, not "ok" or "failed"'
    keys = _KEYS_OK if status == 'ok' else _KEYS_FAILED
    missing = [k for k in keys if k not in result]
    unknown = sorted(str(k) for k in result if k not in keys)
    if missing:
        return f'lacks {", ".join(missing)}'
    if unknown:
        return f'has unknown key {_shown(unknown[0])}'
    if result['version'] != FIT_VERSION or isinstance(result['version'], bool):
        return f'version is {_shown(result["version"])}, not {FIT_VERSION}'
    for key in ('path', 'reason'):
        if not isinstance(result[key], str):
            return f'{key} is {_shown(result[key])}, not text'
    reason = result['reason']
    if len(reason) > _REASON_CHARS or '\n' in reason or '\r' in reason:
        return f'reason is not one line of at most {_REASON_CHARS} characters'
    if status == 'failed':
        return _bounded('time_s', result['time_s'], *_BOUNDS['time_s']) or \
            (None if reason else 'reason is empty')
    for key, (lo, hi) in _BOUNDS.items():
        problem = _bounded(key, result[key], lo, hi)
        if problem:
            return problem
    n = result['plateaus']
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 10 ** 9:
        return f'plateaus is {_shown(n)}, not a count >= 1'
    for key, lo, hi in (('xi_range', -273.15, 1e4), ('load_range', 0.0, 1e9)):
        problem = _range_problem(key, result[key], lo, hi)
        if problem:
            return problem
    return _terms_problem(result['terms'], gear) or \
        _matrix_problem(result['terms'], result['delta'], result['cov'])
