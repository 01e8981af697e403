# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Plant and run variation for :mod:`~friction_joint.experiments.hidden`.

What :func:`~friction_joint.experiments.hidden.simulate_recording` fixes by
default and a benchmark of the diagnosis should vary:

* run kinds (:data:`RUN_KINDS`, one per temperature segment, glued as separate
  pieces with a gap): ``rich`` (the default plan: plateaus, pre-sliding sinusoids,
  multi-sine sweep), ``plateaus`` (constant-velocity plateau pairs only),
  ``sweep`` (the multi-sine sweep only), ``oneway`` (stretches at constant
  speeds in one direction with stops between them: no velocity reversal) and
  ``sweep_oneway`` (:func:`sweep_oneway`: one sweep in one direction through
  large angles, -a .. +b with a, b in 1.5-3 rad, under a random smooth speed
  profile, like a cobot joint sweeping through gravity; the segment starts at
  rest at the sweep's start angle, the lever repositioned during the gap);
* the plant: controller gains, publish rate of ``/joint_states``, sensor noise,
  current-loop bandwidth (drive-torque lag), temperature-sensor lag, number of
  segments, gap between them and total length (:data:`PLANT_RANGES`,
  :func:`draw_plant`);
* the nuisances of real robot data, each drawn with the odds of
  :data:`PLANT_ODDS`, independently: a coarse output encoder
  (``encoder_bits`` 10-14: 1 024-16 384 counts per turn), a wide speed range
  (an extra plateau speed 300-1000 times below the fastest band's lower edge:
  ``cfg['speed_ratio']``, see :func:`speed_bands`) and a warm-up recording
  (``warmup=True``: the housing temperature only rises, over the whole recording).

:func:`relative_size` expresses a drawn effect size relative to the base
friction level (the Coulomb level F_c).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
import dataclasses
import math
from typing import Any, TYPE_CHECKING

import numpy as np

from ._common import check_steps
from .excitation import BlockPlan
from ..exceptions import ArgumentError

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['RUN_KINDS', 'PLANT_RANGES', 'PLANT_ODDS', 'SWEEP_ONEWAY', 'add_sweep',
           'speed_bands', 'sweep_oneway', 'plan_kind', 'draw_plant', 'relative_size',
           'RecordingOptions']

#: segment run kinds (see the module docstring); ``rich`` is the default plan
RUN_KINDS = ('rich', 'plateaus', 'sweep', 'oneway', 'sweep_oneway')

#: ranges of :func:`draw_plant` (log-uniform unless noted)
PLANT_RANGES = {
    'kp_scale': (0.5, 2.0),
    'kd_scale': (0.5, 2.0),
    'publish_every': (1, 15),           # /joint_states = 3 kHz / every (uniform integer)
    'noise_scale': (0.3, 3.0),
    'current_bandwidth_scale': (0.1, 2.0),   # x 800 Hz
    'temperature_lag_scale': (0.5, 10.0),    # x 4 s
    'n_segments': (2, 5),               # uniform integer
    'gap': (0.5, 60.0),                 # s between segments
    'duration': (30.0, 300.0),          # s of motion in total
    'encoder_bits': (10, 14),           # uniform integer (coarse encoder)
    'speed_ratio': (300.0, 1000.0),     # fastest band's lower edge / extra slow plateau speed
}

#: probability per case of each real-data nuisance of :func:`draw_plant` (independent)
PLANT_ODDS = {'coarse_encoder': 0.4, 'wide_speeds': 0.4, 'warmup': 0.3}

#: one-way sweep (:func:`sweep_oneway`): extent each side of 0 (rad, uniform), fastest
#: mean speed (rad/s; the slowest fills the segment), max/min speed of the profile
#: (uniform), speed-profile harmonics, envelope ramp (s, at most a quarter of the sweep)
SWEEP_ONEWAY = {'extent': (1.5, 3.0), 'mean_speed_max': 2.0, 'spread': (1.5, 4.0),
                'harmonics': 3, 'ramp': 1.0}

ONEWAY_TRAVEL = 2.0 * math.pi           # rad, at most per one-way segment
ONEWAY_STOP = 0.3                       # s at rest between one-way stretches


def _log_uniform(rng, lo, hi):
    return float(np.exp(rng.uniform(math.log(lo), math.log(hi))))


def add_sweep(plan, rng, rest, cfg):
    """Append the smooth multi-sine sweep of ``rest`` seconds (if long enough) to ``plan``."""
    ramp = cfg['sweep_ramp']
    if not rest > 2.0 * ramp + 0.5:
        return
    dt = plan.dt
    check_steps(plan.n * dt + rest, dt, 'an excitation plan')
    m = int(round(rest / dt))
    t = dt * np.arange(1, m + 1)
    T = m * dt
    q = np.zeros(m)
    qd = np.zeros(m)
    qdd = np.zeros(m)
    for a, f_lo, f_hi in cfg['sweep']:
        w = 2.0 * math.pi * rng.uniform(f_lo, f_hi)
        p = rng.uniform(0.0, 2.0 * math.pi)
        q += a * np.sin(w * t + p)
        qd += a * w * np.cos(w * t + p)
        qdd -= a * w * w * np.sin(w * t + p)
    # smooth envelope (C2): raised-cosine rise and fall
    e = np.ones(m)
    ed = np.zeros(m)
    edd = np.zeros(m)
    for sl, sign, t0 in ((t < ramp, 1.0, 0.0), (t > T - ramp, -1.0, T)):
        x = (t[sl] - t0) * sign / ramp          # 0 at the edge .. 1 inside
        wr = math.pi / ramp
        e[sl] = 0.5 - 0.5 * np.cos(math.pi * x)
        ed[sl] = sign * 0.5 * wr * np.sin(math.pi * x)
        edd[sl] = 0.5 * wr * wr * np.cos(math.pi * x)
    # raised cosine has a jump in the 2nd derivative at the edge; square it (C2 at 0)
    e2, ed2, edd2 = e * e, 2 * e * ed, 2 * (ed * ed + e * edd)
    qe = q * e2
    qde = qd * e2 + q * ed2
    qdde = qdd * e2 + 2 * qd * ed2 + q * edd2
    base = plan.q_end
    plan._add(base + qe, qde, qdde)
    plan.hold(0.1)


def speed_bands(cfg):
    """
    Plateau speed bands of ``cfg``: ``speed_bands`` plus the slow band of ``speed_ratio``.

    ``cfg['speed_ratio']`` (optional, None: none) adds one plateau speed at the
    fastest band's lower edge divided by the ratio: a plan with plateaus in every
    band then spans at least that ratio between its slowest and fastest plateau.
    """
    bands = [tuple(b) for b in cfg['speed_bands']]
    ratio = cfg.get('speed_ratio')
    if ratio:
        v = max(b[0] for b in bands) / float(ratio)
        bands.append((v, v))
    return bands


def sweep_oneway(rng, dt, duration, cfg):
    """
    Plan one sweep in one direction through large angles: ``(q, qd, qdd)`` of a segment.

    From rest at -a to +b (or +a to -b; a, b drawn from ``SWEEP_ONEWAY['extent']``)
    after ``cfg['hold']`` s, then 0.1 s at rest.  The mean speed is log-uniform
    between the one that fills ``duration`` and ``mean_speed_max`` (never below the
    former); the speed profile is a smooth random positive function (exp of a few
    random harmonics over the sweep, max/min ratio from ``spread``) under a C2
    envelope, so the velocity never changes sign.
    """
    sw = SWEEP_ONEWAY
    sign = float(rng.choice([-1.0, 1.0]))
    a, b = (float(x) for x in rng.uniform(*sw['extent'], 2))
    travel = a + b
    avail = max(duration - cfg['hold'] - 0.2, 1.0)
    v_fill = travel / avail
    v_mean = _log_uniform(rng, v_fill, max(v_fill * 1.0001, sw['mean_speed_max']))
    m = max(8, int(round(travel / v_mean / dt)))
    T = m * dt
    t = dt * np.arange(1, m + 1)
    g = np.zeros(m)
    for k in range(1, sw['harmonics'] + 1):
        g += rng.standard_normal() / k * np.sin(math.pi * k * t / T + rng.uniform(0, 2 * math.pi))
    g -= 0.5 * (g.max() + g.min())
    g *= 0.5 * math.log(rng.uniform(*sw['spread'])) / max(np.max(np.abs(g)), 1e-12)
    ramp = min(sw['ramp'], 0.25 * T)
    env = np.ones(m)
    for sl, x in ((t < ramp, t / ramp), (t > T - ramp, (T - t) / ramp)):
        env[sl] = (0.5 - 0.5 * np.cos(math.pi * x[sl])) ** 2
    w = np.exp(g) * env
    v = w * (travel / (dt * np.sum(w)))                 # rectangle rule: exact travel
    plan = BlockPlan(dt)
    plan._add(np.array([-sign * a]), np.zeros(1), np.zeros(1))
    plan.hold(cfg['hold'])
    plan._add(-sign * a + sign * dt * np.cumsum(v), sign * v, sign * np.gradient(v, dt))
    plan.hold(0.1)
    q, qd, qdd = plan.arrays()
    return q[1:], qd[1:], qdd[1:]


def _plateau_pair(plan, rng, band, window, cfg, duration):
    """Append one +v/-v plateau pair if it fits in ``duration``; return whether it did."""
    v = float(np.exp(rng.uniform(*np.log(band))))
    c = float(rng.uniform(-cfg['center_range'], cfg['center_range']))
    settle = cfg['settle'] + cfg['settle_travel'] / v
    t_ramp = max(0.05, math.pi * v / (2.0 * cfg['accel']))
    travel = v * (settle + window + t_ramp)
    need = 1.5 + 2.0 * (2.0 * t_ramp + settle + window + 0.05)
    if plan.t_end + need > duration:
        return False
    plan.move(c - 0.5 * travel, cfg['move_accel'], cfg['move_speed'])
    for direction in (1.0, -1.0):
        plan.ramp(0.0, direction * v, cfg['accel'])
        plan.constant(direction * v, settle + window)
        plan.ramp(direction * v, 0.0, cfg['accel'])
        plan.hold(0.05)
    return True


def _oneway(plan, rng, duration, cfg):
    sign = float(rng.choice([-1.0, 1.0]))
    plan.move(-sign * cfg['center_range'], cfg['move_accel'], cfg['move_speed'])
    bands = speed_bands(cfg)
    window = max(cfg['min_window'], 0.05 * duration)
    left = ONEWAY_TRAVEL
    while left > 0.05:
        for i in rng.permutation(len(bands)):
            v = float(np.exp(rng.uniform(*np.log(bands[i]))))
            t_ramp = max(0.05, math.pi * v / (2.0 * cfg['accel']))
            hold = min(window, left / v - t_ramp)
            if hold < 0.2 or plan.t_end + 2 * t_ramp + hold + ONEWAY_STOP > duration:
                return
            plan.ramp(0.0, sign * v, cfg['accel'])
            plan.constant(sign * v, hold)
            plan.ramp(sign * v, 0.0, cfg['accel'])
            plan.hold(ONEWAY_STOP)
            left -= v * (hold + t_ramp)


def plan_kind(plan, rng, kind, duration, cfg):
    """
    Fill ``plan`` (a started :class:`~friction_joint.experiments.excitation.BlockPlan`).

    ``kind`` is one of :data:`RUN_KINDS` except ``rich`` and ``sweep_oneway``
    (planned by :func:`~friction_joint.experiments.hidden.plan_segment` itself and
    :func:`sweep_oneway`: their start is not the plan's); the plan
    ends when its content is done, at most ``duration`` s.
    """
    if kind == 'sweep':
        plan.move(0.0, cfg['move_accel'], cfg['move_speed'])
        add_sweep(plan, rng, duration - plan.t_end, cfg)
    elif kind == 'plateaus':
        bands = speed_bands(cfg)
        window = max(cfg['min_window'], 2.0 * cfg['window'])
        done = False
        while not done:
            for i in rng.permutation(len(bands)):
                if not _plateau_pair(plan, rng, bands[i], window, cfg, duration):
                    done = True
                    break
    elif kind == 'oneway':
        _oneway(plan, rng, duration, cfg)
    else:
        raise ArgumentError(f'unknown run kind {kind!r}; kinds: {", ".join(RUN_KINDS)}')
    plan.hold(0.1)


def draw_plant(rng, duration=None, kinds=RUN_KINDS, odds=None):
    """
    Draw :class:`~friction_joint.experiments.hidden.RecordingOptions` that vary the plant, runs.

    ``duration``: ``(lo, hi)`` s (log-uniform; default :data:`PLANT_RANGES`).  The
    segments' run kinds are drawn from ``kinds`` with at least one ``rich`` run
    (if ``rich`` is among them).  The nuisances of :data:`PLANT_ODDS` (``odds``
    overrides them, e.g. ``{'warmup': 1.0}``) are drawn independently: a coarse
    encoder (``encoder_bits``, else the gear's), a wide speed range (the ``cfg``
    entry ``speed_ratio``, see :func:`speed_bands`) and a warm-up recording
    (``warmup``).  Returns ``(kwargs, cfg)``: ``RecordingOptions`` fields and the ``cfg``
    overrides (publish rate, gap, speed ratio).
    """
    r = PLANT_RANGES
    p = dict(PLANT_ODDS, **(odds or {}))
    lo, hi = r['duration'] if duration is None else duration
    nseg = int(rng.integers(r['n_segments'][0], r['n_segments'][1] + 1))
    seg_kinds = [str(k) for k in rng.choice(list(kinds), nseg)]
    if 'rich' in kinds and 'rich' not in seg_kinds:
        seg_kinds[int(rng.integers(nseg))] = 'rich'
    every = int(rng.integers(r['publish_every'][0], r['publish_every'][1] + 1))
    kwargs = {
        'duration': _log_uniform(rng, lo, hi) if hi > lo else float(lo),
        'n_segments': nseg,
        'kinds': seg_kinds,
        'gain_scale': (_log_uniform(rng, *r['kp_scale']), _log_uniform(rng, *r['kd_scale'])),
        'noise_scale': _log_uniform(rng, *r['noise_scale']),
        'current_bandwidth_scale': _log_uniform(rng, *r['current_bandwidth_scale']),
        'temperature_lag_scale': _log_uniform(rng, *r['temperature_lag_scale']),
    }
    cfg = {'publish_rate': 3000.0 / every, 'gap': _log_uniform(rng, *r['gap'])}
    # the nuisances: one uniform draw each, whatever the odds (same draws for other odds)
    u_enc, u_wide, u_warm = rng.uniform(size=3)
    bits = int(rng.integers(r['encoder_bits'][0], r['encoder_bits'][1] + 1))
    ratio = _log_uniform(rng, *r['speed_ratio'])
    if u_enc < p['coarse_encoder']:
        kwargs['encoder_bits'] = bits
    if u_wide < p['wide_speeds']:
        cfg['speed_ratio'] = ratio
    kwargs['warmup'] = bool(u_warm < p['warmup'])
    return kwargs, cfg


def relative_size(base, effect, size):
    """
    Size of a drawn effect relative to the base friction level F_c (dimensionless).

    ``thermal``: change of Fc plus Fv at 1 rad/s across the span, / Fc; ``load``:
    fc_load m g l / Fc; ``position_ripple``: amplitude / Fc; ``nonlinear_viscous``:
    max over |v| <= 3 rad/s of Fv | |v|^delta_v - |v| | / Fc; ``stribeck``:
    Fs / Fc - 1; ``presliding``: 1 / stiffness scale (pre-sliding length relative
    to the base's ``lugre``/``gms`` section; not a torque); ``inertia``: the
    inertia change times J * 10 rad/s^2 / Fc; ``asymmetry``: offset / Fc; ``gravity``:
    the amplitude over q of the truth's minus the base's lever torque, / Fc.
    """
    fc, fv = base.friction.fc[0], base.friction.fv[0]
    s = size
    if effect == 'thermal':
        return (s['fc_change'] * fc + s['fv_change'] * fv) / fc
    if effect == 'load':
        return s['fc_load'] * base.mgl / fc
    if effect == 'position_ripple':
        return s['amplitude'] / fc
    if effect == 'nonlinear_viscous':
        v = np.linspace(0.0, 3.0, 301)
        return float(np.max(fv * np.abs(v ** s['delta_v'] - v)) / fc)
    if effect == 'stribeck':
        return s['fs_ratio'] - 1.0
    if effect == 'presliding':
        return 1.0 / s['stiffness_scale']
    if effect == 'inertia':
        return s['change'] * base.inertia * 10.0 / fc
    if effect == 'asymmetry':
        return s['offset'] / fc
    if effect == 'gravity':     # |a sin(q - d) - b sin q| peaks at sqrt(a^2 + b^2 - 2ab cos d)
        a, b, d = base.mgl * (1.0 + s['sign'] * s['change']), base.mgl, s['angle']
        return math.sqrt(max(a * a + b * b - 2.0 * a * b * math.cos(d), 0.0)) / fc
    return float('nan')


@dataclasses.dataclass(frozen=True)
class RecordingOptions:
    """
    The options of :func:`~friction_joint.experiments.hidden.simulate_recording`: runs, topics.

    Attributes
    ----------
    duration : float
        Total seconds of motion (split over the temperature segments).
    seed : int
        Excitation and sensor-noise seed.
    base_gear : GearParams, optional
        The model the controller uses for its inertia and gravity feed-forward and
        whose temperature range sets the segment temperatures; default the truth gear.
    n_segments : int, optional
        Temperature segments (default 3).
    link_torque : bool
        Include ``/link_torque``.
    command : bool
        Include ``/joint_command``.
    compress : bool
        Write the rosbag2 directory as the shipped sample is stored: a plain
        ``.mcap`` with zstd-compressed chunks and CRCs, ``ros_distro: jazzy``
        (MCAP tools and Foxglove open it as is).  Only for a directory ``path``.
    cfg : dict, optional
        Overrides of :data:`~friction_joint.experiments.hidden.SEGMENT` (e.g.
        ``publish_rate``: /joint_states and the other 1 kHz topics decimated from the 3 kHz
        plant; ``gap``: s between segments).
    kinds : sequence of str, optional
        Run kind per segment (:data:`RUN_KINDS`,
        cycled); default all ``rich``.
    gain_scale : float or (float, float)
        Factor on the PD gains (kp, kd), or one factor for both.
    noise_scale : float
        Factor on the sensors' noise (applied torque, effort, link torque, temperature).
    current_bandwidth_scale : float
        Factor on the current-loop bandwidth (smaller: more drive-torque lag).
    temperature_lag_scale : float
        Factor on the temperature sensor's time constant.
    encoder_bits : int, optional
        Resolution of the recorded output encoder (bits per turn; e.g. 10-14 for a
        coarse encoder of 1 024-16 384 counts): ``/joint_states`` positions are its
        counts, while the drive's loop runs on its fine (motor-side) encoder, the
        gear's ``sensors.encoder_bits``, and reports its velocity; default that one.
    warmup : bool
        A warm-up recording: the housing starts at the lowest segment temperature and
        one ambient (a heat input) above it warms it, through the segments and the
        gaps, to about the highest at the end: the temperature only rises (no
        segment resets it).  Default: each segment soaked at its own temperature.

    """

    duration: float = 90.0
    seed: int = 0
    base_gear: GearParams | None = None
    n_segments: int | None = None
    link_torque: bool = True
    command: bool = True
    compress: bool = False
    cfg: Mapping[str, Any] | None = None
    kinds: Sequence[str] | None = None
    gain_scale: float | tuple[float, float] = 1.0
    noise_scale: float = 1.0
    current_bandwidth_scale: float = 1.0
    temperature_lag_scale: float = 1.0
    encoder_bits: int | None = None
    warmup: bool = False
