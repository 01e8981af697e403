"""Identification step 3: pre-sliding parameters of LuGre and GMS (seed Section V-A).

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
"""
import dataclasses
import math
import time
import warnings

import numpy as np
from scipy import signal

from ..exceptions import ExcitationError, FrictionJointError, GearConfigWarning
from ..models.gms import GMS
from ..models.lugre import LuGre
from ..models.static import StaticFriction

__all__ = ['PatternSearchResult', 'pattern_search', 'Segment', 'presliding_segments',
           'PreslidingFit', 'fit_presliding', 'presliding_rmse', 'zero_phase_derivatives',
           'PreslidingDataError', 'default_v_max', 'default_settle', 'PARAMETERS',
           'EXPERIMENT_ADVICE']

#: free parameters of each model, in the order of the search vector
PARAMETERS = {'lugre': ('sigma0', 'sigma1'), 'gms': ('k_total', 'c')}

#: the experiment that determines the pre-sliding parameters (used in error messages)
EXPERIMENT_ADVICE = ('run slow motions with velocity reversals: a slow slide of a few mrad in '
                     'one direction, then small sinusoidal or triangular motions around '
                     'standstill (amplitude below and around the pre-sliding range, a fraction '
                     'of a mrad to a few mrad), or a slow position sine of a few mrad so that '
                     'each reversal passes through pre-sliding')

#: relative search bounds around the starting value (factor down, factor up)
DEFAULT_BOUNDS = {'sigma0': (10.0, 10.0), 'sigma1': (1e3, 1e2),
                  'k_total': (10.0, 10.0), 'c': (100.0, 100.0)}
#: starting value used when the gear's value is 0 (sigma1 may be 0; log space needs > 0)
ZERO_START = {'sigma1': 0.1}


class PreslidingDataError(FrictionJointError, ValueError):
    """Arrays given to the pre-sliding fit are malformed (lengths, NaN, time axis)."""


# ------------------------------------------------------------ pattern search

@dataclasses.dataclass
class PatternSearchResult:
    """Result of :func:`pattern_search`.

    Attributes
    ----------
    x : ndarray
        Best point found.
    fun : float
        Objective at ``x``.
    nit : int
        Iterations (polls).
    nfev : int
        Points evaluated.
    ncalls : int
        Calls of the (batched) objective.
    step : float
        Final step (mesh size).
    success : bool
        True when the step fell below ``min_step``; False when an evaluation
        or iteration limit stopped the search.
    message : str
    """

    x: np.ndarray
    fun: float
    nit: int
    nfev: int
    ncalls: int
    step: float
    success: bool
    message: str


def pattern_search(fun, x0, lower, upper, step=0.5, min_step=1e-3, max_step=None,
                   expand=2.0, contract=0.5, scale=None, max_iter=1000, max_evals=20000):
    """Minimise ``fun`` over a box by generalized (compass) pattern search.

    Parameters
    ----------
    fun : callable
        ``fun(X) -> f``: X of shape (m, n), returns m objective values.  All
        poll points of an iteration are passed in one call (batched).
    x0 : array_like, (n,)
        Start; projected onto the box.
    lower, upper : array_like, (n,)
        Bounds (finite, lower < upper).
    step : float
        Initial step (in units of ``scale``).
    min_step : float
        Stop when the step falls below this.
    max_step : float, optional
        Cap of the step when expanding (default: 4 * ``step``).
    expand, contract : float
        Step factors after a successful and an unsuccessful poll
        (expand >= 1 > contract > 0).
    scale : array_like, (n,), optional
        Per-coordinate step scale: the poll points are x +- step * scale_i e_i.
    max_iter, max_evals : int
        Limits on polls and evaluated points.

    Returns
    -------
    PatternSearchResult

    Notes
    -----
    A complete poll of the 2n coordinate directions is evaluated each
    iteration and the best improving point is taken (the batch costs little
    more than one point).  Poll points outside the box are projected onto it
    and dropped when the projection is the current point, so every point
    evaluated is feasible.
    """
    x = np.asarray(x0, dtype=float).ravel()
    n = x.size
    lo = np.broadcast_to(np.asarray(lower, dtype=float), (n,))
    hi = np.broadcast_to(np.asarray(upper, dtype=float), (n,))
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo < hi)):
        raise ValueError(f'bounds must be finite with lower < upper, got {lo}, {hi}')
    if not (step > 0 and min_step > 0 and expand >= 1.0 and 0.0 < contract < 1.0):
        raise ValueError('need step > 0, min_step > 0, expand >= 1, 0 < contract < 1')
    sc = np.ones(n) if scale is None else np.broadcast_to(np.asarray(scale, float), (n,))
    max_step = 4.0 * step if max_step is None else float(max_step)
    x = np.clip(x, lo, hi)
    directions = np.vstack([np.eye(n), -np.eye(n)])

    def poll_points(center, delta):
        pts = np.clip(center + delta * sc * directions, lo, hi)
        keep = np.any(pts != center, axis=1)
        return pts[keep]

    def evaluate(points):
        vals = np.asarray(fun(points), dtype=float).reshape(-1)
        if vals.shape[0] != points.shape[0]:
            raise ValueError(f'objective returned {vals.shape[0]} values '
                             f'for {points.shape[0]} points')
        return np.where(np.isfinite(vals), vals, np.inf)

    delta = float(step)
    pts = poll_points(x, delta)
    vals = evaluate(np.vstack([x[None, :], pts]))        # start and first poll together
    fx, vals = vals[0], vals[1:]
    nfev, ncalls, nit = 1 + len(pts), 1, 0
    success, message = False, ''
    while True:
        nit += 1
        if len(vals) and vals.min() < fx:
            i = int(np.argmin(vals))
            x, fx = pts[i].copy(), float(vals[i])
            delta = min(delta * expand, max_step)
        else:
            delta *= contract
        if delta < min_step:
            success, message = True, f'step {delta:.3g} below min_step {min_step:g}'
            break
        if nit >= max_iter:
            message = f'iteration limit {max_iter} reached (step {delta:.3g})'
            break
        pts = poll_points(x, delta)
        if nfev + len(pts) > max_evals:
            message = f'evaluation limit {max_evals} reached (step {delta:.3g})'
            break
        vals = evaluate(pts) if len(pts) else np.empty(0)
        nfev += len(pts)
        ncalls += 1 if len(pts) else 0
    return PatternSearchResult(x, float(fx), nit, nfev, ncalls, delta, success, message)


# ------------------------------------------------------------ data helpers

def zero_phase_derivatives(q, dt, cutoff=100.0, order=2):
    """Velocity and acceleration from a sampled position without phase lag.

    Forward-backward Butterworth low-pass (``scipy.signal.filtfilt``) of the
    position, then central differences.  Offline only (non-causal).

    Parameters
    ----------
    q : array_like, (T,)
        Position (rad), e.g. the encoder reading.
    dt : float
        Sample time (s).
    cutoff : float
        Low-pass cut-off (Hz), below the Nyquist frequency.
    order : int
        Butterworth order (applied twice).

    Returns
    -------
    qd, qdd : ndarray, (T,)
    """
    q = np.asarray(q, dtype=float)
    rate = 1.0 / float(dt)
    if not 0.0 < cutoff < 0.5 * rate:
        raise PreslidingDataError(f'cut-off {cutoff} Hz must be between 0 and the Nyquist '
                                  f'frequency {0.5 * rate:g} Hz')
    b, a = signal.butter(order, cutoff, fs=rate)
    if q.size <= 3 * max(len(a), len(b)):
        raise PreslidingDataError(f'position signal of {q.size} samples is too short to filter')
    qf = signal.filtfilt(b, a, q)
    qd = np.gradient(qf, dt)
    return qd, np.gradient(qd, dt)


def _check_series(name, a, n=None):
    a = np.asarray(a, dtype=float)
    if a.ndim != 1:
        raise PreslidingDataError(f'{name} must be a 1-D array, got shape {a.shape}')
    if n is not None and a.size != n:
        raise PreslidingDataError(f'{name} has {a.size} samples, expected {n} like t')
    if not np.all(np.isfinite(a)):
        raise PreslidingDataError(f'{name} contains NaN or inf at sample '
                                  f'{int(np.argmin(np.isfinite(a)))}')
    return a


def _series(name, a, n):
    """A per-sample series: scalars are broadcast."""
    if np.ndim(a) == 0:
        v = float(a)
        if not math.isfinite(v):
            raise PreslidingDataError(f'{name} must be finite, got {v}')
        return np.full(n, v)
    return _check_series(name, a, n)


def _sample_time(t):
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


def _noise_level(qd):
    """Robust velocity noise: MAD of qd minus its 31-sample moving average."""
    k = min(31, qd.size)
    smooth = np.convolve(np.pad(qd, (k // 2, k - 1 - k // 2), mode='edge'), np.ones(k) / k, 'valid')
    r = qd - smooth
    return 1.4826 * float(np.median(np.abs(r - np.median(r))))


def _curve_at(gear, xi):
    p = StaticFriction(gear.friction).parameters(float(xi))
    return {k: float(np.ravel(v)[0]) for k, v in p.items()}


def default_v_max(gear, xi):
    """Upper velocity of the pre-sliding windows: 2 v_s / kappa at temperature xi."""
    f = gear.friction
    if f.fs is None:
        return 0.05
    return 2.0 * _curve_at(gear, xi)['vs'] / f.velocity_scale


def default_settle(gear, model, xi):
    """Slide (rad) after which every candidate's state is the sliding one.

    LuGre: 10 F_s / sigma0 (the bristle memory decays as exp(-sigma0 dq / g)).
    GMS: 3 x the largest break-away travel alpha_i F_s / k_i (covers an
    element going from one extreme to the other with k up to 1.5 x too stiff).
    """
    f = gear.friction
    fs = _curve_at(gear, xi)['fs']
    if model == 'lugre':
        if f.lugre is None:
            raise FrictionJointError('the gear has no friction.lugre section to start from')
        return 10.0 * fs / f.lugre.sigma0
    if f.gms is None:
        raise FrictionJointError('the gear has no friction.gms section to start from')
    return 3.0 * max(a * fs / k for a, k in zip(f.gms.alpha, f.gms.k))


# ------------------------------------------------------------ segments

@dataclasses.dataclass(frozen=True)
class Segment:
    """A stretch of a recording used by the fit.

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
    def slice(self):
        return slice(self.start, self.stop)

    def __len__(self):
        return self.stop - self.start


def presliding_segments(t, qd, gear=None, model='lugre', xi=None, v_max=None, v_noise=None,
                        settle=None, min_samples=30, from_rest=False, split=True):
    """Windows around slow velocity reversals, each starting in a known state.

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
    if model not in PARAMETERS:
        raise FrictionJointError(f"model must be 'lugre' or 'gms', got {model!r}")
    if gear is None and (v_max is None or settle is None):
        raise FrictionJointError('give a gear or both v_max and settle')
    if xi is None:
        xi_m = 0.5 * sum(gear.friction.temperature_range) if gear is not None else 30.0
    else:
        xi_m = float(np.mean(xi))
    v_max = default_v_max(gear, xi_m) if v_max is None else float(v_max)
    settle = default_settle(gear, model, xi_m) if settle is None else float(settle)
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
    settled = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        k = np.flatnonzero(d[b - 1] * (pos[a:b] - pos[a]) >= settle)
        if k.size:
            settled.append(a + int(k[0]))
    settled = np.asarray(settled, dtype=int)
    segments = []
    for a, b in windows:
        prev_stop = segments[-1].stop if segments else 0
        first_rev = int(rev[np.argmax(rev > a)])
        before = settled[(settled < first_rev) & (settled >= prev_stop)]
        if before.size:
            p = int(before[-1])
            # the slide into the window settled before it: start at the window
            starts = [(a if p <= a and run_id[p] == run_id[a] else p, 'sliding')]
        elif from_rest and not segments:
            starts = [(0, 'rest')]                    # state known from the relaxed start
        else:
            starts = []                               # state at the first reversal unknown
        later = [(int(p), 'sliding') for p in settled if first_rev < p < b]
        starts += later if (split or not starts) else []
        if not split:
            starts = starts[:1]
        pieces = []
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


def _slow_reversals(qd, v_max, v_noise, min_samples):
    """Reversal indices, the slow windows (|qd| < v_max) that hold one, directions.

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
    windows = [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])
               if b - a >= min_samples and np.any((rev > a) & (rev < b))]
    if not windows:
        raise ExcitationError(
            f'the velocity reversals are too fast: around every reversal |qd| stays below '
            f'{v_max:.3g} rad/s (the pre-sliding/Stribeck range) for fewer than {min_samples} '
            f'samples, so the pre-sliding regime is not resolved; {EXPERIMENT_ADVICE}')
    return rev, windows, d


# ------------------------------------------------------------ model batch

def _initial(gear, model):
    f = gear.friction
    if model == 'lugre':
        if f.lugre is None:
            raise FrictionJointError('the gear has no friction.lugre section (sigma0, sigma1) to '
                                     'start the LuGre fit from')
        return {'sigma0': f.lugre.sigma0, 'sigma1': f.lugre.sigma1}
    if f.gms is None:
        raise FrictionJointError('the gear has no friction.gms section (k, c) to start the GMS '
                                 'fit from')
    return {'k_total': float(sum(f.gms.k)), 'c': f.gms.c}


def _frictions(gear, model, params):
    """FrictionParams for each row of ``params`` (dicts of full parameter values)."""
    f = gear.friction
    out = []
    for p in params:
        if model == 'lugre':
            lug = dataclasses.replace(f.lugre, sigma0=float(p['sigma0']), sigma1=float(p['sigma1']))
            out.append(dataclasses.replace(f, lugre=lug))
        else:
            k0 = np.asarray(f.gms.k, dtype=float)
            k = tuple(float(v) for v in k0 * (p['k_total'] / k0.sum()))
            out.append(dataclasses.replace(f, gms=dataclasses.replace(f.gms, k=k, c=float(p['c']))))
    return out


def _gear_with(gear, model, p):
    if model == 'lugre':
        return gear.replace({'friction': {'lugre': {'sigma0': float(p['sigma0']),
                                                    'sigma1': float(p['sigma1'])}}})
    k0 = np.asarray(gear.friction.gms.k, dtype=float)
    k = [float(v) for v in k0 * (p['k_total'] / k0.sum())]
    return gear.replace({'friction': {'gms': {'k': k, 'c': float(p['c'])}}})


class _Data:
    """Segments prepared for the model: midpoint velocity in, torque one sample later out."""

    def __init__(self, segs, dt, burn_in):
        self.dt = dt
        self.items = []
        for qd, tau, xi, tl, init in segs:
            u = 0.5 * (qd[:-1] + qd[1:])
            k0 = min(max(int(round(burn_in / dt)), 0), u.size)
            moving = np.flatnonzero(np.abs(qd) > 0)
            direction = float(np.sign(qd[moving[0]])) if moving.size else 0.0
            self.items.append(dict(u=u, xi=xi[1:], tl=np.abs(tl[1:]), y=tau[1:], k0=k0, init=init,
                                   v0=qd[0] if qd[0] != 0 else direction * 1e-12,
                                   xi0=xi[0], tl0=abs(tl[0])))
        self.n = sum(it['u'].size - it['k0'] for it in self.items)

    def simulate(self, frictions, model):
        """Model torque of each parameter set on every segment: list of (B, T_i)."""
        out = []
        if model == 'lugre':
            sim = LuGre(list(frictions))
            for it in self.items:
                if it['init'] == 'sliding':
                    sim.settle(it['v0'], it['xi0'], it['tl0'])
                else:
                    sim.reset(0.0)
                out.append(sim.simulate(it['u'], it['xi'], it['tl'], self.dt))
        else:
            sim = GMS(list(frictions))
            for it in self.items:
                sim.reset()
                if it['init'] == 'sliding':
                    _settle_gms(sim, it['v0'], it['xi0'], it['tl0'])
                out.append(sim.simulate(it['u'], it['xi'], it['tl'], self.dt))
        return out

    def residuals(self, frictions, model):
        """Residuals (B, N) over the samples used."""
        sims = self.simulate(frictions, model)
        return np.concatenate([s[:, it['k0']:] - it['y'][it['k0']:]
                               for s, it in zip(sims, self.items)], axis=1)

    def mse(self, frictions, model):
        r = self.residuals(frictions, model)
        return np.mean(r * r, axis=1)


def _settle_gms(sim, v, xi, tau_l):
    """All GMS elements slipping in the direction of v with F_i = alpha_i g(v)."""
    g, _ = StaticFriction.from_packed(sim.packed).components(v, xi, tau_l)
    g = np.asarray(g, dtype=float)[:, -1:]                       # signed, (B, 1)
    sim.z = sim.alpha * g / sim.k
    sim.stick = np.zeros(sim.k.shape, dtype=np.int8)
    sim.slipdir = np.full(sim.k.shape, float(np.sign(v)))


def _ripple(rp, q):
    """Position ripple torque sum_n a_n sin(n cycles_per_rev q + phase_n) (as in the joint)."""
    out = np.zeros_like(q)
    for n, (a, ph) in enumerate(zip(rp.amplitude, rp.phase)):
        out += a * np.sin((n + 1) * rp.cycles_per_rev * q + ph)
    return out


def _as_list(x):
    """The segments of a list of arrays; None for a single array (or a list of numbers)."""
    if isinstance(x, (list, tuple)) and len(x) and np.ndim(x[0]) >= 1:
        return list(x)
    return [] if isinstance(x, (list, tuple)) and not len(x) else None


def _prepare(t, qd, tau_r, xi, tau_l, segments, init, gear=None, q=None):
    """Per-segment arrays (qd, tau_r, xi, tau_l, init) and the sample time.

    With ``q`` and a gear with ``position_ripple`` the ripple torque is
    removed from tau_r.
    """
    ripple = gear.friction.position_ripple if (gear is not None and q is not None) else None
    lists = [_as_list(a) for a in (t, qd, tau_r)]
    if any(v is not None for v in lists):
        if not all(v is not None for v in lists):
            raise PreslidingDataError('t, qd and tau_r must all be lists of segments or all arrays')
        if segments is not None:
            raise PreslidingDataError('give either lists of segment arrays or segments, not both')
        nseg = len(lists[0])
        if nseg == 0 or any(len(v) != nseg for v in lists):
            raise PreslidingDataError('t, qd and tau_r must be lists of the same, non-zero length')
        xis = _as_list(xi) or [xi] * nseg
        tls = _as_list(tau_l) or [tau_l] * nseg
        qs = _as_list(q) or [q] * nseg
        if len(xis) != nseg or len(tls) != nseg or len(qs) != nseg:
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
    if ripple is not None:
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
            raise PreslidingDataError(f'segment [{s.start}, {s.stop}) is not a range of at least 2 '
                                      f'of the {t.size} samples')
        segs.append(s)
    return ([(qd[s.slice], tau_r[s.slice], xi[s.slice], tau_l[s.slice], s.init) for s in segs],
            dt, segs)


def _check_excitation(prepared, gear, v_max, min_samples=30):
    """At least one slow reversal in one of the segments, else ExcitationError."""
    if not prepared:
        raise ExcitationError(f'no segments to fit; {EXPERIMENT_ADVICE}')
    first = None
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
    raise first[1]


# ------------------------------------------------------------ the fit

@dataclasses.dataclass
class PreslidingFit:
    """Result of :func:`fit_presliding`.

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
        ``undetermined`` (free parameters with rel_stderr > 1 or on a bound:
        the data do not fix them; their value is only the search's end),
        ``bounds``, ``autocorrelation_time`` (samples), ``warnings``
        (e.g. a fitted sigma1 above the passivity bound; also emitted).
    """

    model: str
    params: dict
    initial: dict
    stderr: dict
    rel_stderr: dict
    interval: dict
    correlation: np.ndarray
    gear: object
    segments: list
    report: dict


def _bounds(names, start, bounds):
    lo, hi = [], []
    for nm in names:
        if bounds and nm in bounds:
            a, b = (float(v) for v in bounds[nm])
            if not 0.0 < a < b:
                raise FrictionJointError(f'bounds[{nm!r}] must be 0 < lower < upper, '
                                         f'got {bounds[nm]}')
        else:
            down, up = DEFAULT_BOUNDS[nm]
            a, b = start[nm] / down, start[nm] * up
        lo.append(a)
        hi.append(b)
    return np.array(lo), np.array(hi)


def _autocorr_time(r, max_lag=2000):
    """Integrated autocorrelation time (samples) of residual r: 1 + 2 sum rho_k up to rho <= 0."""
    r = r - r.mean()
    n = r.size
    if n < 10 or not np.any(r):
        return 1.0
    m = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(r, m)
    acf = np.fft.irfft(f * np.conj(f), m)[:min(n, max_lag)]
    acf /= acf[0]
    neg = np.flatnonzero(acf[1:] <= 0.0)
    k = neg[0] + 1 if neg.size else acf.size
    return float(max(1.0, min(1.0 + 2.0 * acf[1:k].sum(), n / 10.0)))


def _hessian(f, x, h):
    """Central-difference Hessian of f (batched) at x with step h: one call."""
    n = x.size
    pts = [x]
    for i in range(n):
        for s in (1.0, -1.0):
            p = x.copy()
            p[i] += s * h
            pts.append(p)
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    for i, j in pairs:
        for si, sj in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
            p = x.copy()
            p[i] += si * h
            p[j] += sj * h
            pts.append(p)
    v = f(np.array(pts))
    f0 = v[0]
    hess = np.empty((n, n))
    for i in range(n):
        hess[i, i] = (v[1 + 2 * i] - 2.0 * f0 + v[2 + 2 * i]) / (h * h)
    base = 1 + 2 * n
    for m, (i, j) in enumerate(pairs):
        pp, pm, mp, mm = v[base + 4 * m: base + 4 * m + 4]
        hess[i, j] = hess[j, i] = (pp - pm - mp + mm) / (4.0 * h * h)
    return hess, len(pts)


def _covariance(hess, scale):
    """scale * inverse of hess, with infinite variance along non-positive curvature."""
    w, v = np.linalg.eigh(hess)
    tol = 1e-12 * max(float(np.max(np.abs(w))), 1e-300)
    good = w > tol
    inv_w = np.where(good, 1.0 / np.where(good, w, 1.0), 0.0)
    cov = scale * (v * inv_w) @ v.T
    var = np.diag(cov).copy()
    bad = np.any((v ** 2 > 1e-6) & ~good[None, :], axis=1)
    var[bad] = np.inf
    return cov, var


def _interval(value, se_log):
    if not np.isfinite(se_log) or se_log > 700.0:
        return (0.0, math.inf)
    return (float(value * math.exp(-se_log)), float(value * math.exp(se_log)))


def fit_presliding(t, qd, tau_r, xi, tau_l, gear, model='lugre', segments=None, q=None,
                   free=None, bounds=None, init='sliding', burn_in=0.0, v_max=None, step=0.5,
                   min_step=2e-3, max_evals=4000, fd_step=0.05):
    """Fit the pre-sliding parameters of LuGre or GMS with the static curve fixed.

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
    model : {'lugre', 'gms'}
    segments : list of Segment or slice, optional
        With whole-recording arrays: the parts to fit (e.g. from
        :func:`presliding_segments`).  Default: the whole arrays as one
        segment in state ``init``.
    q : array_like (T,) or list, optional
        Measured position (rad).  When given and the gear has a
        ``position_ripple`` section, that ripple (fixed, like the static
        curve) is subtracted from tau_r: LuGre and GMS do not contain it,
        and an unremoved ripple of a few hundredths of a Nm biases the fit.
    free : sequence of str, optional
        Parameters to fit (default all of :data:`PARAMETERS` [model]); the
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
    step, min_step : float
        Initial and final pattern-search step in log space (0.5 = x1.65;
        2e-3 = 0.2 %).
    max_evals : int
        Limit on evaluated parameter sets.
    fd_step : float
        Log-space step of the finite-difference Hessian.

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
    t0 = time.perf_counter()
    if model not in PARAMETERS:
        raise FrictionJointError(f"model must be 'lugre' or 'gms', got {model!r}")
    if init not in ('sliding', 'rest'):
        raise FrictionJointError(f"init must be 'sliding' or 'rest', got {init!r}")
    start = _initial(gear, model)
    names = tuple(PARAMETERS[model] if free is None else free)
    unknown = [nm for nm in names if nm not in PARAMETERS[model]]
    if unknown or not names:
        raise FrictionJointError(f'free parameters of {model} are {PARAMETERS[model]}, got {names}')
    prepared, dt, segs = _prepare(t, qd, tau_r, xi, tau_l, segments, init, gear, q)
    _check_excitation(prepared, gear, v_max)
    data = _Data(prepared, dt, burn_in)
    if data.n < 10 * len(names):
        raise ExcitationError(f'only {data.n} samples to fit (burn-in {burn_in} s); '
                              f'{EXPERIMENT_ADVICE}')
    x_start = {nm: (start[nm] if start[nm] > 0 else ZERO_START[nm]) for nm in start}
    lo, hi = _bounds(names, x_start, bounds)

    def params_of(x_log):
        out = []
        for row in np.atleast_2d(x_log):
            p = dict(start)
            p.update({nm: float(np.exp(v)) for nm, v in zip(names, row)})
            out.append(p)
        return out

    def mse(x_log):
        return data.mse(_frictions(gear, model, params_of(x_log)), model)

    def rmse(x_log):
        return np.sqrt(mse(x_log))

    x0 = np.clip(np.log([x_start[nm] for nm in names]), np.log(lo), np.log(hi))
    f_initial = float(np.sqrt(data.mse(_frictions(gear, model, [start]), model)[0]))
    res = pattern_search(rmse, x0, np.log(lo), np.log(hi), step=step, min_step=min_step,
                         max_evals=max_evals)
    hess, n_h = _hessian(mse, res.x, fd_step)
    best = params_of(res.x)[0]
    resid = data.residuals(_frictions(gear, model, [best]), model)[0]
    tau_ac = _autocorr_time(resid)
    m_best = float(np.mean(resid * resid))
    cov, var = _covariance(hess, 2.0 * m_best * tau_ac / data.n)
    se_log = np.sqrt(var)
    sd = np.sqrt(np.where(np.isfinite(var) & (var > 0), var, np.nan))
    corr = cov / np.outer(sd, sd)
    at_bound = [nm for nm, v, a, b in zip(names, res.x, np.log(lo), np.log(hi))
                if v <= a + 1e-9 or v >= b - 1e-9]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always', GearConfigWarning)
        fitted_gear = _gear_with(gear, model, best)
    for w in caught:
        warnings.warn(w.message, w.category, stacklevel=2)
    report = {
        'model': model, 'free': list(names),
        'warnings': [str(w.message) for w in caught],
        'objective_initial': f_initial, 'objective_final': float(np.sqrt(m_best)),
        'n_samples': int(data.n), 'n_segments': len(segs),
        'evaluations': res.nfev + n_h + 2, 'batched_calls': res.ncalls + 3,
        'iterations': res.nit, 'success': res.success, 'message': res.message,
        'at_bound': at_bound, 'autocorrelation_time': tau_ac,
        'undetermined': [nm for nm, se in zip(names, se_log) if not se <= 1.0 or nm in at_bound],
        'bounds': {nm: (float(a), float(b)) for nm, a, b in zip(names, lo, hi)},
        'wall_time': time.perf_counter() - t0,
    }
    return PreslidingFit(
        model=model, params=best, initial=dict(start),
        stderr={nm: float(best[nm] * s) for nm, s in zip(names, se_log)},
        rel_stderr={nm: float(s) for nm, s in zip(names, se_log)},
        interval={nm: _interval(best[nm], s) for nm, s in zip(names, se_log)},
        correlation=corr, gear=fitted_gear, segments=segs, report=report)


def presliding_rmse(gear, model, t, qd, tau_r, xi, tau_l, segments=None, q=None,
                    init='sliding', burn_in=0.0):
    """RMS torque error (Nm) of a gear's LuGre or GMS model on (held-out) data.

    Same data conventions as :func:`fit_presliding` (``q`` removes the
    gear's position ripple); no excitation check.
    """
    if model not in PARAMETERS:
        raise FrictionJointError(f"model must be 'lugre' or 'gms', got {model!r}")
    prepared, dt, _ = _prepare(t, qd, tau_r, xi, tau_l, segments, init, gear, q)
    data = _Data(prepared, dt, burn_in)
    return float(np.sqrt(data.mse([gear.friction], model)[0]))
