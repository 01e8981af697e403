# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Pre-sliding data: reversal segments, their checks, and the batched model simulation.

Step 3 of the identification (:mod:`friction_joint.identification.presliding`)
fits only the samples near velocity reversals; :func:`presliding_segments`
finds them, :func:`prepare_batch` turns them into the arrays the batched
LuGre/GMS simulation of :func:`batch_frictions` runs on.
"""
from __future__ import annotations

import builtins
from collections.abc import Iterable, Mapping, Sequence
import dataclasses
import math
from typing import TYPE_CHECKING, TypedDict

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import FloatArray, IntArray
from ..exceptions import ArgumentError, ExcitationError, GearConfigError, PreslidingDataError
from ..models.gms import GMS
from ..models.lugre import LuGre
from ..models.static import StaticFriction

if TYPE_CHECKING:
    from ..gear import FrictionParams, GearParams, GMSParams, LuGreParams, RippleParams

__all__ = ['PRESLIDING_PARAMETERS', 'EXPERIMENT_ADVICE', 'Segment', 'presliding_segments',
           'default_v_max', 'default_settle', 'initial_params', 'batch_frictions', 'gear_with',
           'prepare_batch', 'check_presliding_excitation', 'BatchData', 'PreslidingOptions']


#: free parameters of each model, in the order of the search vector
PRESLIDING_PARAMETERS = {'lugre': ('sigma0', 'sigma1'), 'gms': ('k_total', 'c')}

#: the experiment that determines the pre-sliding parameters (used in error messages)
EXPERIMENT_ADVICE = ('run slow motions with velocity reversals: a slow slide in one direction '
                     'longer than the pre-sliding range (the travel after a reversal over which '
                     'the friction builds up, several times F_s / stiffness), then small '
                     'sinusoidal or triangular motions around standstill with swings from a '
                     'tenth of that range up to it, or a slow position sine within it so that '
                     'each reversal passes through pre-sliding; check that the measured '
                     'position follows them, not only the command')


#: one prepared segment: velocity, friction torque, temperature, load, initial state
_Prepared = tuple[FloatArray, FloatArray, FloatArray, FloatArray, str]


def _check_series(name: str, a: ArrayLike, n: int | None = None) -> FloatArray:
    a = np.asarray(a, dtype=float)
    if a.ndim != 1:
        raise PreslidingDataError(f'{name} must be a 1-D array, got shape {a.shape}')
    if n is not None and a.size != n:
        raise PreslidingDataError(f'{name} has {a.size} samples, expected {n} like t')
    if not np.all(np.isfinite(a)):
        raise PreslidingDataError(f'{name} contains NaN or inf at sample '
                                  f'{int(np.argmin(np.isfinite(a)))}')
    return a


def _series(name: str, a: ArrayLike, n: int) -> FloatArray:
    """Return a per-sample series: scalars are broadcast."""
    if np.ndim(a) == 0:
        v = float(np.asarray(a))
        if not math.isfinite(v):
            raise PreslidingDataError(f'{name} must be finite, got {v}')
        return np.full(n, v)
    return _check_series(name, a, n)


def _sample_time(t: FloatArray) -> float:
    d = np.diff(t)
    if t.size < 3:
        raise PreslidingDataError(f'need at least 3 samples, got {t.size}')
    if not np.all(d > 0):
        raise PreslidingDataError('t must be strictly increasing')
    dt = float(np.median(d))
    if np.max(np.abs(d - dt)) > 0.01 * dt:
        raise PreslidingDataError(
            f'samples must be equally spaced (median step {dt:.6g} s, steps from {d.min():.6g} '
            f'to {d.max():.6g} s); resample the recording first')
    return dt


def _noise_level(qd: FloatArray) -> float:
    """Robust velocity noise: MAD of qd minus its 31-sample moving average."""
    k = min(31, qd.size)
    smooth = np.convolve(np.pad(qd, (k // 2, k - 1 - k // 2), mode='edge'), np.ones(k) / k,
                         'valid')
    r = qd - smooth
    return 1.4826 * float(np.median(np.abs(r - np.median(r))))


def _curve_at(gear: GearParams, xi: float) -> dict[str, float]:
    p = StaticFriction(gear.friction).parameters(float(xi))
    return {k: float(np.ravel(v)[0]) for k, v in p.items()}


def default_v_max(gear: GearParams, xi: float) -> float:
    """Upper velocity of the pre-sliding windows: 2 v_s / kappa at temperature xi."""
    f = gear.friction
    if f.fs is None:
        return 0.05
    return 2.0 * _curve_at(gear, xi)['vs'] / f.velocity_scale


def default_settle(gear: GearParams, model: str, xi: float) -> float:
    """
    Slide (rad) after which every candidate's state is the sliding one.

    LuGre: 10 F_s / sigma0 (the bristle memory decays as exp(-sigma0 dq / g)).
    GMS: 3 x the largest break-away travel alpha_i F_s / k_i (covers an
    element going from one extreme to the other with k up to 1.5 x too stiff).
    """
    f = gear.friction
    fs = _curve_at(gear, xi)['fs']
    if model == 'lugre':
        if f.lugre is None:
            raise GearConfigError('the gear has no friction.lugre section to start from')
        return 10.0 * fs / f.lugre.sigma0
    if f.gms is None:
        raise GearConfigError('the gear has no friction.gms section to start from')
    return 3.0 * max(a * fs / k for a, k in zip(f.gms.alpha, f.gms.k, strict=True))


# ------------------------------------------------------------ segments

@dataclasses.dataclass(frozen=True)
class Segment:
    """
    A stretch of a recording used by the fit.

    Attributes
    ----------
    start, stop : int
        Sample range [start, stop) simulated.
    init : {'sliding', 'rest'}
        Model state at ``start`` (see the module docstring).
    reversals : int
        Velocity reversals inside.

    """

    start: int
    stop: int
    init: str = 'sliding'
    reversals: int = 0

    @property
    def slice(self) -> builtins.slice:  # noqa: A003
        return slice(self.start, self.stop)

    def __len__(self) -> int:
        return self.stop - self.start


def presliding_segments(t: ArrayLike, qd: ArrayLike, *, gear: GearParams | None = None,
                        model: str = 'lugre', xi: ArrayLike | None = None,
                        v_max: float | None = None, v_noise: float | None = None,
                        settle: float | None = None, min_samples: int = 30,
                        from_rest: bool = False, split: bool = True) -> list[Segment]:
    """
    Find windows around slow velocity reversals, each starting in a known state.

    Parameters
    ----------
    t, qd : array_like, (T,)
        Sample times (s, equally spaced) and velocity (rad/s).
    gear : GearParams, optional
        Starting gear; gives the defaults of ``v_max`` and ``settle``.
    model : {'lugre', 'gms'}
        Model whose ``settle`` default is used.
    xi : float or array_like, optional
        Temperature (degC) at which the defaults are evaluated (mean taken);
        default the middle of ``friction.temperature_range``.
    v_max : float, optional
        |qd| below which the motion counts as slow (rad/s); default
        2 v_s / kappa of the gear (0.05 rad/s without a Stribeck term).
    v_noise : float, optional
        Direction hysteresis (rad/s): |qd| must exceed it to count as motion;
        default 5 x a robust estimate of the velocity noise.
    settle : float, optional
        Travel (rad) since the last reversal after which the friction state
        counts as settled; default :func:`default_settle`.
    min_samples : int
        A slow window must hold at least this many samples.
    from_rest : bool
        The recording starts from a relaxed rest: the first window may start
        at sample 0 (``init='rest'``) without a settled slide before it.
    split : bool
        Split windows at every settled slide between reversals.

    Returns
    -------
    list of Segment

    Raises
    ------
    ExcitationError
        The joint never moves, never reverses, reverses only fast, or no slow
        reversal is preceded by a settled slide; the message says which
        experiment is missing.

    """
    t = _check_series('t', t)
    qd = _check_series('qd', qd, t.size)
    dt = _sample_time(t)
    if model not in PRESLIDING_PARAMETERS:
        raise ArgumentError(f"model must be 'lugre' or 'gms', got {model!r}")
    if xi is None:
        xi_m = 0.5 * sum(gear.friction.temperature_range) if gear is not None else 30.0
    else:
        xi_m = float(np.mean(np.asarray(xi, dtype=float)))
    if gear is not None:
        v_max = default_v_max(gear, xi_m) if v_max is None else v_max
        settle = default_settle(gear, model, xi_m) if settle is None else settle
    if v_max is None or settle is None:
        raise ArgumentError('give a gear or both v_max and settle')
    v_max, settle = float(v_max), float(settle)
    if v_noise is None:
        v_noise = max(5.0 * _noise_level(qd), 1e-9)
    v_noise = min(float(v_noise), 0.5 * v_max)

    rev, windows, d = _slow_reversals(qd, v_max, v_noise, min_samples)
    # travel since the start of each direction run -> first settled sample of each run
    run_id = np.zeros(qd.size, dtype=int)
    run_id[rev] = 1
    run_id = np.cumsum(run_id)
    bounds = np.concatenate(([0], rev, [qd.size]))
    pos = np.concatenate(([0.0], np.cumsum(0.5 * (qd[1:] + qd[:-1]) * dt)))
    first_settled: list[int] = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        k = np.flatnonzero(d[b - 1] * (pos[a:b] - pos[a]) >= settle)
        if k.size:
            first_settled.append(a + int(k[0]))
    settled = np.asarray(first_settled, dtype=int)
    segments: list[Segment] = []
    for a, b in windows:
        prev_stop = segments[-1].stop if segments else 0
        first_rev = int(rev[np.argmax(rev > a)])
        before = settled[(settled < first_rev) & (settled >= prev_stop)]
        if before.size:
            p = int(before[-1])
            # the slide into the window settled before it: start at the window
            starts: list[tuple[int, str]] = [
                (a if p <= a and run_id[p] == run_id[a] else p, 'sliding')]
        elif from_rest and not segments:
            starts = [(0, 'rest')]                    # state known from the relaxed start
        else:
            starts = []                               # state at the first reversal unknown
        later = [(int(p), 'sliding') for p in settled if first_rev < p < b]
        starts += later if (split or not starts) else []
        if not split:
            starts = starts[:1]
        pieces: list[Segment] = []
        for i, (s, init) in enumerate(starts):
            e = starts[i + 1][0] if i + 1 < len(starts) else b
            nrev = int(np.count_nonzero((rev > s) & (rev < e)))
            if pieces and (nrev == 0 or e - s < min_samples):
                last = pieces[-1]                     # a slide without reversal: extend
                pieces[-1] = Segment(last.start, e, last.init, last.reversals + nrev)
            elif nrev:
                pieces.append(Segment(s, e, init, nrev))
        segments += pieces
    if not segments:
        raise ExcitationError(
            f'no slow reversal is preceded by a slide of at least {settle:.3g} rad in one '
            'direction, so the friction state at the start of the reversals is unknown; '
            f'{EXPERIMENT_ADVICE} (or, for a recording that starts from a relaxed rest, '
            'pass from_rest=True)')
    return segments


def _slow_reversals(qd: FloatArray, v_max: float, v_noise: float, min_samples: int
                    ) -> tuple[IntArray, list[tuple[int, int]], FloatArray]:
    """
    Reversal indices, the slow windows (|qd| < v_max) that hold one, directions.

    A reversal is the first sample of a new direction run; the direction d
    (+1, -1, 0 before the first motion) is the sign of the last sample with
    |qd| > v_noise (hysteresis).  Raises
    ExcitationError when there is no motion, no reversal or no slow window.
    """
    moving = np.abs(qd) > v_noise
    if not np.any(moving):
        raise ExcitationError(
            f'the joint never moves: |qd| stays below the noise level {v_noise:.3g} rad/s, so '
            f'there is no pre-sliding motion to fit; {EXPERIMENT_ADVICE}')
    idx = np.maximum.accumulate(np.where(moving, np.arange(qd.size), -1))
    d = np.where(idx >= 0, np.sign(qd[np.maximum(idx, 0)]), 0.0)
    rev = np.flatnonzero((d[1:] != d[:-1]) & (d[:-1] != 0)) + 1
    if rev.size == 0:
        raise ExcitationError(
            'no velocity reversal in the data: the motion never changes direction, so the '
            f'pre-sliding transition after a reversal is not observed; {EXPERIMENT_ADVICE}')
    slow = np.abs(qd) < v_max
    edges = np.flatnonzero(np.diff(np.concatenate(([0], slow.astype(np.int8), [0]))))
    windows = [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)
               if b - a >= min_samples and np.any((rev > a) & (rev < b))]
    if not windows:
        raise ExcitationError(
            f'the velocity reversals are too fast: around every reversal |qd| stays below '
            f'{v_max:.3g} rad/s (the pre-sliding/Stribeck range) for fewer than {min_samples} '
            f'samples, so the pre-sliding regime is not resolved; {EXPERIMENT_ADVICE}')
    return rev, windows, d


# ------------------------------------------------------------ model batch

def initial_params(gear: GearParams, model: str) -> dict[str, float]:
    f = gear.friction
    if model == 'lugre':
        if f.lugre is None:
            raise GearConfigError('the gear has no friction.lugre section (sigma0, sigma1) to '
                                  'start the LuGre fit from')
        return {'sigma0': f.lugre.sigma0, 'sigma1': f.lugre.sigma1}
    if f.gms is None:
        raise GearConfigError('the gear has no friction.gms section (k, c) to start the GMS '
                              'fit from')
    return {'k_total': float(sum(f.gms.k)), 'c': f.gms.c}


def _lugre(f: FrictionParams) -> LuGreParams:
    """Return the friction section's LuGre section (GearConfigError without one)."""
    if f.lugre is None:
        raise GearConfigError('the gear has no friction.lugre section')
    return f.lugre


def _gms(f: FrictionParams) -> GMSParams:
    """Return the friction section's GMS section (GearConfigError without one)."""
    if f.gms is None:
        raise GearConfigError('the gear has no friction.gms section')
    return f.gms


def batch_frictions(gear: GearParams, model: str, params: Iterable[Mapping[str, float]]
                    ) -> list[FrictionParams]:
    """Return FrictionParams for each row of ``params`` (dicts of full parameter values)."""
    f = gear.friction
    out = []
    for p in params:
        if model == 'lugre':
            lug = dataclasses.replace(_lugre(f), sigma0=float(p['sigma0']),
                                      sigma1=float(p['sigma1']))
            out.append(dataclasses.replace(f, lugre=lug))
        else:
            k0 = np.asarray(_gms(f).k, dtype=float)
            k = tuple(float(v) for v in k0 * (p['k_total'] / k0.sum()))
            out.append(dataclasses.replace(f, gms=dataclasses.replace(_gms(f), k=k,
                                                                      c=float(p['c']))))
    return out


def gear_with(gear: GearParams, model: str, p: Mapping[str, float]) -> GearParams:
    if model == 'lugre':
        return gear.replace({'friction': {'lugre': {'sigma0': float(p['sigma0']),
                                                    'sigma1': float(p['sigma1'])}}})
    k0 = np.asarray(_gms(gear.friction).k, dtype=float)
    k = [float(v) for v in k0 * (p['k_total'] / k0.sum())]
    return gear.replace({'friction': {'gms': {'k': k, 'c': float(p['c'])}}})


class _Item(TypedDict):
    """One segment of :class:`BatchData`."""

    u: FloatArray
    xi: FloatArray
    tl: FloatArray
    y: FloatArray
    k0: int
    init: str
    v0: float
    xi0: float
    tl0: float


class BatchData:
    """Segments prepared for the model: midpoint velocity in, torque one sample later out."""

    def __init__(self, segs: Iterable[_Prepared], dt: float, burn_in: float) -> None:
        self.dt = dt
        self.items: list[_Item] = []
        for qd, tau, xi, tl, init in segs:
            u = 0.5 * (qd[:-1] + qd[1:])
            k0 = min(max(int(round(burn_in / dt)), 0), u.size)
            moving = np.flatnonzero(np.abs(qd) > 0)
            direction = float(np.sign(qd[moving[0]])) if moving.size else 0.0
            self.items.append({'u': u, 'xi': xi[1:], 'tl': np.abs(tl[1:]), 'y': tau[1:],
                               'k0': k0, 'init': init,
                               'v0': qd[0] if qd[0] != 0 else direction * 1e-12,
                               'xi0': xi[0], 'tl0': abs(tl[0])})
        self.n = sum(it['u'].size - it['k0'] for it in self.items)

    def simulate(self, frictions: Iterable[FrictionParams], model: str) -> list[FloatArray]:
        """Model torque of each parameter set on every segment: list of (B, T_i)."""
        out: list[FloatArray] = []
        if model == 'lugre':
            lugre = LuGre(list(frictions))
            for it in self.items:
                if it['init'] == 'sliding':
                    lugre.settle(it['v0'], it['xi0'], it['tl0'])
                else:
                    lugre.reset(z=0.0)
                out.append(lugre.simulate(it['u'], it['xi'], it['tl'], self.dt))
        else:
            gms = GMS(list(frictions))
            for it in self.items:
                gms.reset()
                if it['init'] == 'sliding':
                    _settle_gms(gms, it['v0'], it['xi0'], it['tl0'])
                out.append(gms.simulate(it['u'], it['xi'], it['tl'], self.dt))
        return out

    def residuals(self, frictions: Iterable[FrictionParams], model: str) -> FloatArray:
        """Residuals (B, N) over the samples used."""
        sims = self.simulate(frictions, model)
        return np.concatenate([s[:, it['k0']:] - it['y'][it['k0']:]
                               for s, it in zip(sims, self.items, strict=True)], axis=1)

    def mse(self, frictions: Iterable[FrictionParams], model: str) -> FloatArray:
        r = self.residuals(frictions, model)
        mse: FloatArray = np.mean(r * r, axis=1)
        return mse


def _settle_gms(sim: GMS, v: float, xi: float, tau_l: float) -> None:
    """All GMS elements slipping in the direction of v with F_i = alpha_i g(v)."""
    g, _ = StaticFriction.from_packed(sim.packed).components(v, xi, tau_l)
    g = np.asarray(g, dtype=float)[:, -1:]                       # signed, (B, 1)
    sim.z = sim.alpha * g / sim.k
    sim.stick = np.zeros(sim.k.shape, dtype=np.int8)
    sim.slipdir = np.full(sim.k.shape, float(np.sign(v)))


def _ripple(rp: RippleParams, q: FloatArray) -> FloatArray:
    """Position ripple torque sum_n a_n sin(n cycles_per_rev q + phase_n) (as in the joint)."""
    out = np.zeros_like(q)
    for n, (a, ph) in enumerate(zip(rp.amplitude, rp.phase, strict=True)):
        out += a * np.sin((n + 1) * rp.cycles_per_rev * q + ph)
    return out


def _as_list(x: ArrayLike) -> list[ArrayLike] | None:
    """Return the segments of a list of arrays; None for a single array (or a list of numbers)."""
    if isinstance(x, (list, tuple)) and len(x) and np.ndim(x[0]) >= 1:
        return list(x)
    return [] if isinstance(x, (list, tuple)) and not len(x) else None


def prepare_batch(t: ArrayLike, qd: ArrayLike, tau_r: ArrayLike, xi: ArrayLike, tau_l: ArrayLike,
                  segments: Sequence[Segment | slice] | None, *, init: str,
                  gear: GearParams | None = None, q: ArrayLike | None = None
                  ) -> tuple[list[_Prepared], float, list[Segment]]:
    """
    Per-segment arrays (qd, tau_r, xi, tau_l, init) and the sample time.

    With ``q`` and a gear with ``position_ripple`` the ripple torque is
    removed from tau_r.
    """
    ripple = gear.friction.position_ripple if (gear is not None and q is not None) else None
    maybe_lists = [_as_list(a) for a in (t, qd, tau_r)]
    if any(v is not None for v in maybe_lists):
        lists = [v for v in maybe_lists if v is not None]
        if len(lists) != len(maybe_lists):
            raise PreslidingDataError('t, qd and tau_r must all be lists of segments or all '
                                      'arrays')
        if segments is not None:
            raise PreslidingDataError('give either lists of segment arrays or segments, not both')
        nseg = len(lists[0])
        if nseg == 0 or any(len(v) != nseg for v in lists):
            raise PreslidingDataError('t, qd and tau_r must be lists of the same, non-zero length')
        xis = _as_list(xi) or [xi] * nseg
        tls = _as_list(tau_l) or [tau_l] * nseg
        qs: list[ArrayLike] = []
        if q is not None:
            qs = _as_list(q) or [q] * nseg
        if len(xis) != nseg or len(tls) != nseg or (q is not None and len(qs) != nseg):
            raise PreslidingDataError(f'xi, tau_l and q must be scalars/arrays or lists of '
                                      f'{nseg} segments')
        out, dts = [], []
        for i in range(nseg):
            ti = _check_series(f't[{i}]', lists[0][i])
            dts.append(_sample_time(ti))
            tau_i = _check_series(f'tau_r[{i}]', lists[2][i], ti.size)
            if ripple is not None:
                tau_i = tau_i - _ripple(ripple, _check_series(f'q[{i}]', qs[i], ti.size))
            out.append((_check_series(f'qd[{i}]', lists[1][i], ti.size), tau_i,
                        _series(f'xi[{i}]', xis[i], ti.size),
                        _series(f'tau_l[{i}]', tls[i], ti.size), init))
        if max(dts) - min(dts) > 0.01 * min(dts):
            raise PreslidingDataError(f'segments have different sample times '
                                      f'{min(dts):g}..{max(dts):g} s')
        return out, dts[0], [Segment(0, len(o[0]), init) for o in out]
    t = _check_series('t', t)
    dt = _sample_time(t)
    qd = _check_series('qd', qd, t.size)
    tau_r = _check_series('tau_r', tau_r, t.size)
    if ripple is not None and q is not None:
        tau_r = tau_r - _ripple(ripple, _check_series('q', q, t.size))
    xi = _series('xi', xi, t.size)
    tau_l = _series('tau_l', tau_l, t.size)
    if segments is None:
        segments = [Segment(0, t.size, init)]
    segs = []
    for s in segments:
        s = s if isinstance(s, Segment) else Segment(s.start or 0, s.stop if s.stop is not None
                                                     else t.size, init)
        if not 0 <= s.start < s.stop - 1 < t.size:
            raise PreslidingDataError(f'segment [{s.start}, {s.stop}) is not a range of at '
                                      f'least 2 of the {t.size} samples')
        segs.append(s)
    return ([(qd[s.slice], tau_r[s.slice], xi[s.slice], tau_l[s.slice], s.init) for s in segs],
            dt, segs)


def check_presliding_excitation(prepared: Sequence[_Prepared], gear: GearParams,
                                v_max: float | None, min_samples: int = 30) -> None:
    """At least one slow reversal in one of the segments, else ExcitationError."""
    if not prepared:
        raise ExcitationError(f'no segments to fit; {EXPERIMENT_ADVICE}')
    first: tuple[int, ExcitationError] | None = None
    for qd, _, xi, _, _ in prepared:
        vm = default_v_max(gear, float(np.mean(xi))) if v_max is None else float(v_max)
        v_noise = min(max(5.0 * _noise_level(qd), 1e-9), 0.5 * vm)
        try:
            _slow_reversals(qd, vm, v_noise, min_samples)
            return
        except ExcitationError as exc:
            # report the most advanced failure: too fast > no reversal > no motion
            rank = 2 if 'too fast' in str(exc) else 1 if 'no velocity reversal' in str(exc) else 0
            if first is None or rank > first[0]:
                first = (rank, exc)
    raise first[1] if first is not None else ExcitationError(f'no segments to fit; '
                                                             f'{EXPERIMENT_ADVICE}')


@dataclasses.dataclass(frozen=True)
class PreslidingOptions:
    """
    The options of the pre-sliding fit (:func:`~friction_joint.identification.fit_presliding`).

    Attributes
    ----------
    model : {'lugre', 'gms'}
        The pre-sliding model to fit.
    free : sequence of str, optional
        Parameters to fit (default all of :data:`PRESLIDING_PARAMETERS` [model]); the
        others keep the gear's values.
    bounds : dict, optional
        ``{name: (lower, upper)}`` search bounds; default a factor 10 around
        the start (sigma1: 1e-3..1e2 x, c: 1e-2..1e2 x).
    init : {'sliding', 'rest'}
        State at the start of segments given as arrays or slices.
    burn_in : float
        Seconds at the start of each segment simulated but not fitted.
    v_max : float, optional
        Slow-velocity limit of the excitation check (default 2 v_s / kappa).
    step : float
        Initial pattern-search step in log space (0.5 = x1.65).
    min_step : float
        Final pattern-search step in log space (2e-3 = 0.2 %).
    max_evals : int
        Limit on evaluated parameter sets.
    fd_step : float
        Log-space step of the finite-difference Hessian.

    """

    model: str = 'lugre'
    free: Sequence[str] | None = None
    bounds: Mapping[str, tuple[float, float]] | None = None
    init: str = 'sliding'
    burn_in: float = 0.0
    v_max: float | None = None
    step: float = 0.5
    min_step: float = 2e-3
    max_evals: int = 4000
    fd_step: float = 0.05
