# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The four classic LuGre experiments of Canudas de Wit et al. (1995).

C. Canudas de Wit, H. Olsson, K. J. Astrom and P. Lischinsky, "A new model
for control of systems with friction", IEEE Trans. Automatic Control 40(3),
1995, demonstrate the LuGre model (seed eq. 10 with linear viscous friction)
on a unit mass with the parameters of their Table I:

    sigma0 = 1e5 N/m, sigma1 = sqrt(1e5) N s/m, sigma2 = F_v = 0.4 N s/m
    (delta_v = 1), F_c = 1 N, F_s = 1.5 N, v_s = 1e-3 m/s, delta_s = 2, m = 1 kg

and reproduce four rate- and memory-dependent friction phenomena with it.
Each experiment here runs this package's own friction core
(:class:`~friction_joint.models.joint.Joint` or :class:`~friction_joint.models.lugre.LuGre`)
with that parameter set written as a gear: the "joint" is the unit mass,
positions are in m and forces in N (``gear_ratio = 1``, ``inertia = 1``).

* :func:`presliding` -- a force below F_s applied to the resting mass
  (Canudas Fig. 2): spring-like displacement with stiffness sigma0.
* :func:`frictional_lag` -- imposed velocity oscillating in the Stribeck
  region (Fig. 3): friction/velocity hysteresis widening with frequency.
* :func:`breakaway` -- force ramps F = r t (Fig. 4): break-away force falls
  as the force rate r rises.
* :func:`stick_slip` -- mass pulled through a spring at constant speed
  (Fig. 6): periodic stick-slip.

Each function returns an :class:`~friction_joint.results.ExperimentResult`:
``summary`` holds the key numbers (plain floats and lists, written to JSON by
the command, see :meth:`~friction_joint.results.ExperimentResult.to_dict`),
``series`` the numpy arrays the figure is drawn from, ``figures`` the one
figure, ``NAME.png``.

Figures and files: :mod:`friction_joint.experiments.classic_report`; the
command ``friction_joint classic EXPERIMENT --out DIR`` runs one experiment
and writes ``DIR/EXPERIMENT.png`` and ``DIR/EXPERIMENT.json``, both atomically.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import math
from typing import Any, TYPE_CHECKING
import warnings

import numpy as np

from ._common import check_steps
from ..exceptions import ArgumentError, GearConfigWarning
from ..gear import gear_from_dict
from ..models.joint import Joint
from ..models.lugre import LuGre
from ..models.static import StaticFriction
from ..results import ExperimentResult

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ['CANUDAS_1995', 'FIGURE_SIZES', 'FIGURE_SIZE', 'canudas_gear', 'presliding',
           'frictional_lag', 'breakaway', 'stick_slip', 'slip_onsets', 'CLASSIC_EXPERIMENTS']

#: Table I of Canudas de Wit et al. (1995) plus the unit mass (SI units).
CANUDAS_1995 = {'sigma0': 1e5, 'sigma1': math.sqrt(1e5), 'sigma2': 0.4,
                'fc': 1.0, 'fs': 1.5, 'vs': 1e-3, 'mass': 1.0}

XI = 25.0   # temperature input; the Canudas set has no temperature dependency


#: the figure's size (inches) of each experiment (default :data:`FIGURE_SIZE`)
FIGURE_SIZES: dict[str, tuple[float, float]] = {'stick-slip': (9, 6.5)}
FIGURE_SIZE: tuple[float, float] = (10, 5)


def _result(name: str, summary: dict[str, Any], series: dict[str, Any]) -> ExperimentResult:
    """Return the run as an :class:`ExperimentResult` with its one figure, ``NAME.png``."""
    def draw(fig: Figure) -> None:
        from .classic_report import draw_classic
        draw_classic(fig, result)
    result = ExperimentResult(name, summary, series)
    result.figures[name + '.png'] = (draw, FIGURE_SIZES.get(name, FIGURE_SIZE))
    return result


def canudas_gear(params=None):
    """
    Return the Canudas 1995 parameter set as a validated gear (unit mass, SI units).

    Parameters
    ----------
    params : dict, optional
        Overrides of :data:`CANUDAS_1995` entries.

    Returns
    -------
    GearParams
        LuGre model, linear viscous term (delta_v = 1), Gaussian Stribeck
        curve (delta_s = 2), ``inertia`` = the mass.

    """
    p = dict(CANUDAS_1995, **(params or {}))
    data = {'joint_name': 'canudas_1995_mass', 'gear_ratio': 1.0, 'inertia': p['mass'],
            'friction': {'model': 'lugre', 'fc': [p['fc']], 'fv': [p['sigma2']],
                         'fs': [p['fs']], 'vs': [p['vs']], 'delta_v': [1.0], 'delta_s': 2.0,
                         'lugre': {'sigma0': p['sigma0'], 'sigma1': p['sigma1']}}}
    # The published set deliberately violates the LuGre passivity bound
    # sigma1 < sigma2 Fc / (Fs - Fc) = 0.8 N s/m (sigma1 = 316 N s/m); the
    # experiments reproduce the paper as published, so the GearConfigWarning
    # that gear_from_dict raises for it is suppressed here, and only here.
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', GearConfigWarning)
        return gear_from_dict(data, source='Canudas de Wit et al. 1995, Table I')


def _midpoints(n, dt):
    """
    Step-end times t_k = k dt and midpoints t_k - dt/2 of n steps.

    Inputs of the core are held over each step, so a continuous input is
    sampled at the step midpoints (second-order accurate).
    """
    t = dt * np.arange(1, n + 1)
    return t, t - 0.5 * dt


def _nsteps(duration, dt):
    n = check_steps(duration, dt, 'a run')
    if n < 2:
        raise ArgumentError(f'duration {duration} s is shorter than two steps of {dt} s')
    return n


# ------------------------------------------------------------ presliding ---

def presliding(*, amplitude: float | None = None, ramp_time: float = 5.0,
               hold_time: float = 2.0, dt: float = 1e-4,
               params: dict[str, Any] | None = None) -> ExperimentResult:
    """
    Pre-sliding displacement under a force below F_s (Canudas 1995, Fig. 2).

    The resting unit mass is loaded with a piecewise-linear force
    0 -> +A, hold, -> -A, hold, -> +A, hold, -> -A, hold, -> 0, hold
    (each ramp of amplitude A takes ``ramp_time``, so the rate is constant).
    With A < F_s the mass never slides: it moves micrometres, like a
    nonlinear spring with hysteresis.  Quasi-statically (|v| << v_s, so
    g = F_s) eq. 10 gives, with w = sigma0 z / F_s and u = A / F_s,

        dx = F_s / sigma0 * dw / (1 - sign(v) w):
        x(+A) = -F_s/sigma0 ln(1 - u),  x(-A) = -F_s/sigma0 ln(1 + u),

    a closed loop between the two, and x = 0 again after the full cycle
    ending at zero force.  At zero force (z = 0) the tangent stiffness is
    exactly sigma0.

    The ramps must be slow: the break-away force falls with the force rate
    (:func:`breakaway`), to about 1.43 N at 1 N/s, so a fast ramp to
    0.95 F_s makes the mass slide.  The default (0.285 N/s) stays in
    pre-sliding; check ``v_peak`` when changing it.

    Parameters
    ----------
    amplitude : float, optional
        Force amplitude A (N); default 0.95 F_s as in the paper.
    ramp_time, hold_time : float
        Duration of a ramp 0 -> A and of each hold (s).
    dt : float
        Integration step (s).
    params : dict, optional
        Overrides of :data:`CANUDAS_1995`.

    Returns
    -------
    ExperimentResult
        ``summary``: ``sigma0``, ``force_amplitude`` (N), ``stiffness``
        (N/m, mean of the zero-force passages), ``stiffness_passages``
        (least-squares slope of applied force vs displacement over
        |F| <= 0.02 F_s on each ramp from +A to -A or back),
        ``stiffness_virgin`` (the same on the first loading from rest, where
        the tangent sigma0 (1 - F/F_s) makes it about 0.7 % lower),
        ``stiffness_error`` (stiffness / sigma0 - 1), ``x_max``, ``x_min``, ``x_end`` (m, after
        the final hold at zero force), ``v_peak`` (m/s, largest |v|; far
        below v_s unless the mass slid), ``loop_closure`` (m, displacement at
        the second +A hold minus the first), ``x_max_quasistatic``,
        ``x_min_quasistatic`` (m, formulas above).
        ``series``: ``t``, ``force``, ``x``, ``v``, ``friction``.

    """
    p = dict(CANUDAS_1995, **(params or {}))
    a = 0.95 * p['fs'] if amplitude is None else float(amplitude)
    if not 0.0 < a < p['fs']:
        raise ArgumentError(
            f'presliding: amplitude must be in (0, F_s = {p["fs"]}) N, got {a}')
    tr, th = float(ramp_time), float(hold_time)
    knots_f = [0.0, a, a, -a, -a, a, a, -a, -a, 0.0, 0.0]
    durations = [0.0, tr, th, 2 * tr, th, 2 * tr, th, 2 * tr, th, tr, th]
    knots_t = np.cumsum(durations)
    n = _nsteps(knots_t[-1], dt)
    t, tm = _midpoints(n, dt)
    force = np.interp(tm, knots_t, knots_f)
    joint = Joint(canudas_gear(params), model='lugre')
    traj = joint.simulate(force, dt, xi=XI)
    x, v = traj.q, traj.qd

    lim = 0.02 * p['fs']

    def slope(i):
        sel = (tm > knots_t[i - 1]) & (tm < knots_t[i]) & (np.abs(force) <= lim)
        return float(np.polyfit(x[sel], force[sel], 1)[0])
    # ramps from +A to -A or back cross zero force (z = 0) mid-ramp; the
    # first ramp starts from the relaxed state (virgin curve, F >= 0 only)
    passages = [slope(i) for i in range(1, len(knots_f)) if knots_f[i - 1] * knots_f[i] < 0.0]
    stiffness = float(np.mean(passages))

    def x_at(time):
        return float(np.interp(time, t, x))
    loop_closure = x_at(knots_t[6]) - x_at(knots_t[2])
    q_scale = p['fs'] / p['sigma0']
    summary = {
        'sigma0': p['sigma0'],
        'force_amplitude': a,
        'stiffness': stiffness,
        'stiffness_error': stiffness / p['sigma0'] - 1.0,
        'stiffness_passages': passages,
        'stiffness_virgin': slope(1),
        'x_max': float(x.max()),
        'x_min': float(x.min()),
        'x_end': float(x[-1]),
        'v_peak': float(np.abs(v).max()),
        'loop_closure': loop_closure,
        'x_max_quasistatic': -q_scale * math.log(1.0 - a / p['fs']),
        'x_min_quasistatic': -q_scale * math.log(1.0 + a / p['fs']),
    }
    series = {'t': t, 'force': force, 'x': x, 'v': v, 'friction': traj.tau_r}
    return _result('presliding', summary, series)


# --------------------------------------------------------- frictional lag ---

def _loop_width(v, f, margin=0.05, points=201):
    """
    Max friction difference between decelerating and accelerating branch.

    ``v``, ``f`` cover one period starting at the velocity maximum; the
    branches are compared on a common velocity grid that leaves out
    ``margin`` of the velocity range at either end (where they meet).
    Returns ``(width, area)``: the width (N) and the loop area |closed
    integral of f dv| (N m/s).
    """
    k = int(np.argmin(v))
    vd, fd = v[:k + 1][::-1], f[:k + 1][::-1]      # decelerating, now increasing in v
    va, fa = v[k:], f[k:]                           # accelerating
    lo, hi = v.min(), v.max()
    grid = np.linspace(lo + margin * (hi - lo), hi - margin * (hi - lo), points)
    diff = np.interp(grid, vd, fd) - np.interp(grid, va, fa)
    vc = np.append(v, v[0])
    fc = np.append(f, f[0])
    area = abs(float(np.sum(0.5 * (fc[1:] + fc[:-1]) * np.diff(vc))))
    return float(np.max(np.abs(diff))), area


def frictional_lag(*, omegas: Sequence[float] = (1.0, 10.0, 25.0), v_mean: float = 1.5e-3,
                   v_amplitude: float = 1e-3, periods: int = 2,
                   samples_per_period: int = 100000,
                   params: dict[str, Any] | None = None) -> ExperimentResult:
    """
    Frictional lag: hysteresis in friction vs velocity (Canudas 1995, Fig. 3).

    The velocity imposed on the LuGre model oscillates in the Stribeck
    region, v(t) = v_mean + v_amplitude cos(omega t) (the paper's
    1e-3 (cos(omega t) + 1.5) m/s by default; it never reverses).  The
    bristle state lags behind the velocity, so friction is higher while the
    velocity decreases than while it increases, and the loop widens with
    frequency.

    Loop width: in the last period, the largest difference between the
    friction on the decelerating and on the accelerating branch at equal
    velocity, over the velocity range without 5 % at either end.

    Parameters
    ----------
    omegas : sequence of float
        Angular frequencies (rad/s).
    v_mean, v_amplitude : float
        Velocity offset and amplitude (m/s); v_amplitude < v_mean.
    periods : int
        Periods simulated from relaxed bristles (z = 0); the last is analysed.
    samples_per_period : int
        Steps per period (the step is 2 pi / (omega * samples_per_period)).
    params : dict, optional
        Overrides of :data:`CANUDAS_1995`.

    Returns
    -------
    ExperimentResult
        ``summary``: ``omegas`` (rad/s), ``v_mean``, ``v_amplitude`` (m/s),
        ``loop_width`` (N per frequency), ``loop_area`` (N m/s per frequency).
        ``series``: ``v`` and ``friction`` (lists of arrays, one period per
        frequency), ``v_static``, ``friction_static`` (the steady-state curve).

    """
    if not 0.0 < v_amplitude < v_mean:
        raise ArgumentError('frictional_lag: need 0 < v_amplitude < v_mean (no reversal)')
    if int(periods) < 1:
        raise ArgumentError('frictional_lag: periods must be >= 1')
    gear = canudas_gear(params)
    widths, areas, vs_list, fs_list = [], [], [], []
    m = int(samples_per_period)
    for omega in omegas:
        dt = 2.0 * math.pi / (float(omega) * m)
        n = m * int(periods)
        _, tm = _midpoints(n, dt)
        v = v_mean + v_amplitude * np.cos(omega * tm)
        f = LuGre(gear.friction).simulate(v, XI, 0.0, dt, z0=0.0)
        # last period, starting at the velocity maximum (steps centred on
        # t = j*period): friction after step k belongs to the held velocity v[k]
        v1, f1 = v[n - m:], f[n - m:]
        width, area = _loop_width(v1, f1)
        widths.append(width)
        areas.append(area)
        vs_list.append(v1)
        fs_list.append(f1)
    v_static = np.linspace(v_mean - v_amplitude, v_mean + v_amplitude, 401)
    f_static = StaticFriction(gear.friction).torque(v_static, XI)
    summary = {'omegas': [float(w) for w in omegas], 'v_mean': float(v_mean),
               'v_amplitude': float(v_amplitude), 'loop_width': widths, 'loop_area': areas}
    series = {'v': vs_list, 'friction': fs_list, 'v_static': v_static,
              'friction_static': f_static}
    return _result('lag', summary, series)


# -------------------------------------------------------------- break-away ---

def _first_peak(f, prominence):
    """Index of the first local maximum of f followed by a drop > prominence, or None."""
    run = np.maximum.accumulate(f)
    below = np.flatnonzero(f < run - prominence)
    if below.size == 0:
        return None
    return int(np.argmax(f[:below[0]]))


def breakaway(*, rates: Sequence[float] = (0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0),
              f_end: float = 2.0, prominence: float = 0.01,
              params: dict[str, Any] | None = None) -> ExperimentResult:
    """
    Varying break-away force under force ramps F = r t (Canudas 1995, Fig. 4).

    A force ramp F(t) = r t is applied to the resting unit mass.  Definition
    used (Canudas et al. 1995, Sec. IV: the friction force when the mass
    starts to slide, found where the velocity rises sharply): the
    *break-away force* is the stiction peak, the first maximum of the
    friction force, after which friction drops as the mass breaks loose
    into gross sliding (a drop of more than ``prominence`` is required, so
    that numerical ripple is not taken for a peak).  The applied force and
    time at that instant are reported too.

    With LuGre the peak falls as r rises: the faster the ramp, the higher
    the velocity already reached when the bristles saturate, and the lower
    the Stribeck curve g(v) that bounds sigma0 z there.  The effect ends
    where the ramp makes the pre-sliding (bristle) velocity r / sigma0
    itself comparable to v_s: from about r = 35 N/s on (Canudas set), the
    friction rises straight to the kinetic level F_c + sigma2 v without a
    stiction peak, and the break-away force is undefined (reported as
    ``None``).

    Parameters
    ----------
    rates : sequence of float
        Force rates r (N/s).
    f_end : float
        Each ramp runs until F = f_end (N); must exceed F_s.
    prominence : float
        Drop (N) after the maximum that marks it as the break-away peak.
    params : dict, optional
        Overrides of :data:`CANUDAS_1995`.

    Returns
    -------
    ExperimentResult
        ``summary``: ``rates`` (N/s), ``breakaway_force`` (N, friction at the
        peak; None where there is none), ``applied_force_at_breakaway`` (N),
        ``time_to_breakaway`` (s), ``fs``, ``fc`` (N).
        ``series``: per rate (lists of arrays) ``t``, ``force`` (applied),
        ``friction``, ``v``.

    """
    p = dict(CANUDAS_1995, **(params or {}))
    if f_end <= p['fs']:
        raise ArgumentError(f'breakaway: f_end must exceed F_s = {p["fs"]} N')
    gear = canudas_gear(params)
    out: dict[str, list[Any]] = {'breakaway_force': [], 'applied_force_at_breakaway': [],
                                 'time_to_breakaway': []}
    series: dict[str, list[Any]] = {'t': [], 'force': [], 'friction': [], 'v': []}
    for r in rates:
        r = float(r)
        if not r > 0.0:
            raise ArgumentError(f'breakaway: force rates must be > 0, got {r}')
        # force increment per step <= 1e-4 N and step <= 1e-4 s
        dt = min(1e-4, 1e-4 / r)
        n = _nsteps(f_end / r, dt)
        t, tm = _midpoints(n, dt)
        force = r * tm
        traj = Joint(gear, model='lugre').simulate(force, dt, xi=XI)
        k = _first_peak(traj.tau_r, prominence)
        if k is None:
            for key in out:
                out[key].append(None)
        else:
            out['breakaway_force'].append(float(traj.tau_r[k]))
            out['applied_force_at_breakaway'].append(float(r * t[k]))
            out['time_to_breakaway'].append(float(t[k]))
        for key, arr in (('t', t), ('force', force), ('friction', traj.tau_r), ('v', traj.qd)):
            series[key].append(arr)
    summary = {'rates': [float(r) for r in rates], **out, 'fs': p['fs'], 'fc': p['fc']}
    return _result('breakaway', summary, series)


# -------------------------------------------------------------- stick-slip ---

def slip_onsets(t, v, threshold=0.05):
    """
    Return the times v first rises through ``threshold`` in each slip (linear interpolation).

    After an onset the detector re-arms only once v has fallen below half
    the threshold again (the mass is back to sticking), so ripple around the
    threshold inside one slip is not counted twice.
    """
    t = np.asarray(t, dtype=float)
    v = np.asarray(v, dtype=float)
    up = np.flatnonzero((v[:-1] < threshold) & (v[1:] >= threshold))
    out = []
    armed_from = 0
    for k in up:
        if k < armed_from:
            continue
        out.append(float(t[k] + (threshold - v[k]) / (v[k + 1] - v[k]) * (t[k + 1] - t[k])))
        rearm = np.flatnonzero(v[k + 1:] < 0.5 * threshold)
        if rearm.size == 0:
            break
        armed_from = k + 1 + int(rearm[0])
    return out


def stick_slip(*, k: float = 2.0, vp: float = 0.1, duration: float = 30.0, dt: float = 5e-5,
               threshold: float = 0.05, params: dict[str, Any] | None = None) -> ExperimentResult:
    """
    Stick-slip of the unit mass pulled through a spring (Canudas 1995, Fig. 6).

    The spring end moves at constant speed y = vp t; from rest the mass
    obeys m x'' = k (vp t - x) - F_friction.  In the joint's terms the spring
    is ``k_ext = k`` and the external torque input is -k vp t (sampled at the
    step midpoints).

    Step: the joint integrator is second order in every term; against a
    converged Radau solution the slip onsets are within 0.1 us at the
    default dt = 5e-5 s (0.3 us at 1/3000 s).  test/experiments/test_classic.py
    checks them to 5 us (the reference is converged to about 1 us).

    Parameters
    ----------
    k : float
        Spring stiffness (N/m).
    vp : float
        Pulling speed (m/s).
    duration : float
        Simulated time from rest (s).
    dt : float
        Integration step (s).
    threshold : float
        Velocity (m/s) whose upward crossing marks a slip onset.
    params : dict, optional
        Overrides of :data:`CANUDAS_1995`.

    Returns
    -------
    ExperimentResult
        ``summary`` exactly: ``slip_onsets`` (s), ``period`` (s, mean
        difference of the onsets; None with fewer than two), ``v_max`` (m/s),
        ``x_end`` (m), ``spring_stiffness`` (N/m, ``k``), ``pull_velocity``
        (m/s, ``vp``), ``spring_force_at_slip`` (N, the spring force k (y - x)
        at each slip onset: the force at which the stuck mass broke loose).
        ``series``: ``t``, ``x``, ``v``, ``friction``,
        ``y`` (spring end).

    """
    gear = canudas_gear(params)
    n = _nsteps(duration, dt)
    t, tm = _midpoints(n, dt)
    traj = Joint(gear, model='lugre', k_ext=k).simulate(np.zeros(n), dt, xi=XI,
                                                        tau_ext=-k * vp * tm)
    t0 = np.concatenate(([0.0], t))
    v0 = np.concatenate(([0.0], traj.qd))
    onsets = slip_onsets(t0, v0, threshold)
    period = float(np.mean(np.diff(onsets))) if len(onsets) >= 2 else None
    x0 = np.concatenate(([0.0], traj.q))
    spring = [float(k * (vp * t_on - np.interp(t_on, t0, x0))) for t_on in onsets]
    summary = {'slip_onsets': onsets, 'period': period, 'v_max': float(traj.qd.max()),
               'x_end': float(traj.q[-1]), 'spring_stiffness': float(k),
               'pull_velocity': float(vp), 'spring_force_at_slip': spring}
    series = {'t': t, 'x': traj.q, 'v': traj.qd, 'friction': traj.tau_r, 'y': vp * t}
    return _result('stick-slip', summary, series)


#: command-line name -> experiment function (no arguments: the Canudas 1995 set-up)
CLASSIC_EXPERIMENTS: dict[str, Callable[[], ExperimentResult]] = {
    'presliding': presliding,
    'lag': frictional_lag,
    'breakaway': breakaway,
    'stick-slip': stick_slip,
}
