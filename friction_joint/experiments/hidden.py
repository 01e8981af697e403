# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Measured-style recordings with hidden effects, for testing ``friction_joint diagnose``.

A *truth* gear is a base gear file (e.g. ``config/csd25_base.yaml``) plus one
or more effects the base model lacks (docs/interfaces.md, diagnose outputs, names them).
:func:`apply_effect` builds such a truth, :func:`draw_effect` draws a
realistic size of an effect at random, and :func:`simulate_recording` runs the
truth on the simulated test bed (:class:`~friction_joint.testbed.plant.Plant`, with
its realistic sensors) under a rich closed-loop excitation and writes what a
measurement would give: a rosbag2 MCAP recording with the contract topics.
Nothing in the recording (topics, names, metadata) tells which effect the
truth has.

The excitation (per temperature segment, see :func:`plan_segment`)
-------------------------------------------------------------------
The recording consists of ``n_segments`` (default 3) *temperature segments*,
like runs in a temperature chamber: each segment runs on a fresh plant whose
thermal ambient and initial housing temperature are set to the segment
temperature (spread over the base's ``friction.temperature_range``, 2 degC
inside each end: 22, 30, 38 degC for [20, 40]; a random +-0.5 degC per
segment).  The frictional losses warm the housing a little within a segment
(the housing time constant is ~9 min, so a 90 s run cannot span several degC
by self-heating alone).  Segments follow each other in one recording with
``gap`` seconds (default 1 s) without messages between them (the soak); the
lever angle carries over from one segment to the next.

Each segment, under a PD controller with inertia and gravity feed-forward of
the BASE model (:class:`~friction_joint.control.controller.Controller`, no friction
compensation, gains from :func:`~friction_joint.control.controller.pd_gains`), runs

1. a short hold;
2. constant-velocity plateau pairs (+v then -v) at four speeds, one from
   each band 0.02-0.04, 0.08-0.2, 0.4-1.0 and 1.5-3.0 rad/s, each pair
   centred at a random lever angle in [-1.2, 1.2] rad (load m g l |sin q|
   from 0 to ~10 Nm, independent of the speed);
3. a slow slide and small position sinusoids (0.1-3 mrad at 2 Hz), every
   reversal of which passes through pre-sliding;
4. a smooth multi-sine sweep over the rest of the segment:
   ``q = env(t) (1.1 sin(w1 t) + 0.15 sin(w2 t) + 0.02 sin(w3 t))`` with
   random frequencies near 0.15-0.3, 0.5-0.9 and 2-3 Hz and phases: the
   lever sweeps about +-1.3 rad, velocities up to ~3 rad/s with reversals
   and slow stretches, accelerations up to ~10 rad/s^2.

Topics: ``/joint_states`` (the plant's 3 kHz samples decimated to 1 kHz),
``/joint_temperature`` (the plant's 4 Hz housing sensor), ``/link_torque``
(output torque sensor), ``/joint_command`` (commanded effort, q_d, qd_d); measured data
may lack the optional ones: ``RecordingOptions(link_torque=False, command=False)``.

Plant variation (:class:`RecordingOptions`; the defaults are the plant above)
-----------------------------------------------------------------------------
``kinds`` (run kind per segment: ``rich`` as above, ``plateaus``, ``sweep``,
``oneway``, ``sweep_oneway``; :mod:`~friction_joint.experiments.hidden_plant`),
``encoder_bits`` (coarse encoder), ``warmup`` (temperature only rising), ``gain_scale``
(PD gains), ``noise_scale`` (sensor noise), ``current_bandwidth_scale``
(drive-torque lag), ``temperature_lag_scale`` (temperature sensor lag), and
through ``cfg`` the ``publish_rate``, the ``gap`` between segments and ``speed_ratio``;
:func:`~friction_joint.experiments.hidden_plant.draw_plant` draws them all.
``draw_effect(rng, effect, strength=u)`` sets the size from weak (u = 0) to strong (u = 1).

Effect sizes (:data:`EFFECT_RANGES`)
------------------------------------
``thermal``
    Fc rises and Fv falls linearly with the housing temperature: fc, fv
    become ``[c0, c1]`` with the base value at the middle of the recorded
    temperature span and a change of 15-40 % (Fc) and 15-40 % (Fv) across it.
``load``
    ``fc_load = [0.01 .. 0.04]`` N m per N m of tau_L (up to 11 N m here).
``position_ripple``
    ``friction.position_ripple``: (1.5 .. 2.5) x gear_ratio cycles per output
    revolution (continuous: 2 N is the tooth engagement of the ideal gear, a
    real ripple may sit elsewhere; mid range 2 N), amplitude 0.05-0.2 N m,
    random phase.
``nonlinear_viscous``
    ``delta_v = [0.4 .. 0.75]``; fv unchanged, so the viscous torque at
    1 rad/s is the base's.
``stribeck``
    ``fs = fc x (1.3 .. 1.8)``, ``vs = 0.02 .. 0.1`` rad/s.
``presliding``
    the truth runs the LuGre or the GMS model with the base's
    ``friction.lugre`` / ``friction.gms`` sections, stiffnesses scaled by
    0.7-1.4.
``inertia``
    the truth inertia is the base's times 1 +- (0.15 .. 0.35).
``asymmetry``
    ``friction.offset``: a constant torque of 0.1-0.4 N m, either sign.
``gravity``
    the truth's lever differs from the base's: ``lever.mass`` times 1 +- (0.05 .. 0.4)
    and ``lever.angle_offset`` +- (0.03 .. 0.3) rad.  ``diagnose`` sees it only without
    ``/link_torque`` (tau_ext then comes from the base's lever; the sensor measures it).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
import math
import os
import time
from typing import Any, TYPE_CHECKING
import warnings

import numpy as np

from .excitation import record_segment, segment_topics
from .hidden_plant import (add_sweep, plan_kind, RecordingOptions, RUN_KINDS, speed_bands,
                           sweep_oneway)
from ..bag import write_recording
from ..control.controller import Controller, pd_gains
from ..effects import HIDEABLE
from ..exceptions import ArgumentError, GearConfigWarning
from ..testbed.plant import Plant

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['HIDEABLE', 'EFFECT_RANGES', 'MAGNITUDE', 'apply_effect', 'apply_effects',
           'draw_effect', 'segment_temperatures', 'plan_segment', 'RecordingOptions',
           'simulate_recording']

#: realistic size ranges drawn by :func:`draw_effect` (uniform; see the module docstring)
EFFECT_RANGES: dict[str, dict[str, tuple[Any, Any]]] = {
    'thermal': {'fc_change': (0.15, 0.40), 'fv_change': (0.15, 0.40)},
    'load': {'fc_load': (0.01, 0.04)},
    'position_ripple': {'amplitude': (0.05, 0.2), 'phase': (0.0, 2.0 * math.pi),
                        'cycles_ratio': (1.5, 2.5)},
    'nonlinear_viscous': {'delta_v': (0.4, 0.75)},
    'stribeck': {'fs_ratio': (1.3, 1.8), 'vs': (0.02, 0.1)},
    'presliding': {'model': ('lugre', 'gms'), 'stiffness_scale': (0.7, 1.4)},
    'inertia': {'change': (0.15, 0.35), 'sign': (-1.0, 1.0)},
    'asymmetry': {'offset': (0.1, 0.4), 'sign': (-1.0, 1.0)},
    'gravity': {'change': (0.05, 0.4), 'sign': (-1.0, 1.0), 'angle': (0.03, 0.3),
                'angle_sign': (-1.0, 1.0)},
}

#: excitation defaults of :func:`simulate_recording` / :func:`plan_segment`
SEGMENT: dict[str, Any] = {
    'n_segments': 3,
    'temperature_margin': 2.0,      # degC inside the base's temperature_range
    'temperature_jitter': 0.5,      # degC, random offset per segment
    'gap': 1.0,                     # s without messages between segments
    'hold': 0.2,                    # s at rest at the start of a segment
    'speed_bands': ((0.02, 0.04), (0.08, 0.2), (0.4, 1.0), (1.5, 3.0)),   # rad/s
    'speed_ratio': None,            # extra slow plateau: fastest band's lower edge / ratio
    'center_range': 1.2,            # rad, plateau centres drawn in +-this
    'window': 0.6,                  # s per plateau at nominal (30 s) segment length
    'min_window': 0.25,             # s
    'settle': 0.1,                  # s, plus settle_travel / v
    'settle_travel': 2e-3,          # rad
    'accel': 30.0,                  # rad/s^2, plateau ramps
    'move_accel': 40.0,             # rad/s^2
    'move_speed': 3.0,              # rad/s
    'presliding_slide': 3e-3,       # rad at presliding_speed before the sinusoids
    'presliding_speed': 5e-3,       # rad/s
    'presliding_amplitudes': (1e-4, 3e-4, 1e-3, 3e-3),   # rad
    'presliding_frequency': 2.0,    # Hz, one period each
    'sweep': ((1.1, 0.15, 0.3), (0.15, 0.5, 0.9), (0.02, 2.0, 3.0)),   # (rad, f_lo, f_hi Hz)
    'sweep_ramp': 1.0,              # s, envelope rise and fall of the sweep
    'rise_time': 0.04,              # s, PD design (pd_gains)
    'overshoot': 0.06,
    'publish_rate': 1000.0,         # Hz, /joint_states, /link_torque, /joint_command
}


# --------------------------------------------------------------------------- effects

def _span(base, temperatures=None):
    temps = segment_temperatures(base) if temperatures is None else np.asarray(temperatures)
    lo, hi = float(np.min(temps)), float(np.max(temps))
    return lo, hi


#: magnitude (grows from weak to strong) of the size parameters and its inverse
MAGNITUDE = {
    'fc_change': (lambda x: x, lambda m: m), 'fv_change': (lambda x: x, lambda m: m),
    'fc_load': (lambda x: x, lambda m: m), 'amplitude': (lambda x: x, lambda m: m),
    'delta_v': (lambda x: 1.0 - x, lambda m: 1.0 - m),
    'fs_ratio': (lambda x: x - 1.0, lambda m: 1.0 + m),
    'stiffness_scale': (lambda x: 1.0 / x, lambda m: 1.0 / m),
    'change': (lambda x: x, lambda m: m), 'offset': (lambda x: x, lambda m: m),
    'angle': (lambda x: x, lambda m: m),
}


def draw_effect(rng: np.random.Generator, effect: str, *,
                strength: float | None = None) -> dict[str, Any]:
    """
    Draw a random realistic size of ``effect``.

    The size is a dict of the parameters of :data:`EFFECT_RANGES`.  ``strength``
    (optional, <= 1) sets the magnitude parameters (:data:`MAGNITUDE`) instead of
    drawing them: 0 is the weakest end of the range, 1 the strongest, geometric in
    the magnitude between; below 0 extrapolates to weaker sizes.  The other
    parameters (sign, phase, model, vs) are drawn as usual.

    Parameters
    ----------
    rng : numpy.random.Generator
        The random source.
    effect : str
        One of :data:`EFFECT_RANGES`.
    strength : float, optional
        Magnitude from weak (0) to strong (1); default drawn.

    Returns
    -------
    dict
        Parameter -> value.

    """
    if effect not in EFFECT_RANGES:
        raise ArgumentError(f'unknown effect {effect!r}; effects: {", ".join(HIDEABLE)}')
    if strength is not None and not strength <= 1.0:
        raise ArgumentError(f'strength must be <= 1, got {strength}')
    out: dict[str, Any] = {}
    for key, rng_ in EFFECT_RANGES[effect].items():
        if strength is not None and key in MAGNITUDE:
            mag, inv = MAGNITUDE[key]
            lo, hi = sorted((mag(rng_[0]), mag(rng_[1])))
            out[key] = float(inv(lo * (hi / lo) ** strength))
        elif key.endswith('sign'):
            out[key] = float(rng.choice([-1.0, 1.0]))
        elif key == 'model':
            out[key] = str(rng.choice(list(rng_)))
        else:
            out[key] = float(rng.uniform(*rng_))
    return out


def _size(effect, size):
    """Full size dict: a scalar is the first parameter, the others at mid range."""
    ranges = EFFECT_RANGES[effect]
    full = {}
    for key, r in ranges.items():
        if key.endswith('sign'):
            full[key] = 1.0
        elif key == 'model':
            full[key] = r[0]
        else:
            full[key] = 0.5 * (r[0] + r[1])
    if size is None:
        return full
    if not isinstance(size, dict):
        size = {next(iter(ranges)): size}
    unknown = set(size) - set(ranges)
    if unknown:
        raise ArgumentError(f'{effect}: unknown size parameter(s) '
                            f'{", ".join(sorted(unknown))} (known: {", ".join(ranges)})')
    full.update(size)
    return full


def apply_effect(base_gear: GearParams, effect: str, *,
                 size: Mapping[str, Any] | float | None = None,
                 temperatures: Sequence[float] | None = None) -> GearParams:
    """
    Return the truth gear: ``base_gear`` plus ``effect`` of ``size``.

    Parameters
    ----------
    base_gear : GearParams
        The base gear the effect is added to.
    effect : str
        One of :data:`HIDEABLE` (:mod:`friction_joint.effects`).
    size : dict or float, optional
        Parameters as drawn by :func:`draw_effect`; a number sets the first parameter
        of :data:`EFFECT_RANGES` (the others at mid range); default mid range.
    temperatures : sequence of float, optional
        Segment temperatures of the recording (for ``thermal``: the change is over
        their span); default :func:`segment_temperatures` of the base.

    Returns
    -------
    GearParams

    """
    if effect not in HIDEABLE:
        raise ArgumentError(f'unknown effect {effect!r}; effects: {", ".join(HIDEABLE)}')
    with warnings.catch_warnings():
        # a truth with a Stribeck hump may break the LuGre passivity bound of the base's
        # friction.lugre section; the simulated hardware does not care
        warnings.simplefilter('ignore', GearConfigWarning)
        return _apply(base_gear, effect, _size(effect, size), temperatures)


def _apply(base_gear, effect, s, temperatures):
    fr = base_gear.friction
    fc0, fv0 = fr.fc[0], fr.fv[0]
    if effect == 'thermal':
        lo, hi = _span(base_gear, temperatures)
        mid, width = 0.5 * (lo + hi), max(hi - lo, 1e-6)
        c1 = s['fc_change'] * fc0 / width           # Fc rises with temperature
        v1 = -s['fv_change'] * fv0 / width          # Fv falls with temperature
        return base_gear.replace({'friction': {'fc': [fc0 - c1 * mid, c1],
                                               'fv': [fv0 - v1 * mid, v1]}})
    if effect == 'load':
        return base_gear.replace({'friction': {'fc_load': [s['fc_load']]}})
    if effect == 'position_ripple':
        return base_gear.replace({'friction': {'position_ripple': {
            'cycles_per_rev': s['cycles_ratio'] * base_gear.gear_ratio,
            'amplitude': [s['amplitude']],
            'phase': [s['phase']]}}})
    if effect == 'nonlinear_viscous':
        # fv * |v|^delta_v equals the base's fv |v| at |v| = 1 rad/s: fv unchanged
        return base_gear.replace({'friction': {'delta_v': [s['delta_v']]}})
    if effect == 'stribeck':
        return base_gear.replace({'friction': {'fs': [fc0 * s['fs_ratio']], 'vs': [s['vs']]}})
    if effect == 'presliding':
        model, k = s['model'], s['stiffness_scale']
        if model == 'lugre':
            lg = fr.lugre
            if lg is None:
                raise ArgumentError('presliding: the base has no friction.lugre section')
            return base_gear.replace({'friction': {'model': 'lugre', 'lugre': {
                'sigma0': lg.sigma0 * k, 'sigma1': lg.sigma1}}})
        gm = fr.gms
        if gm is None:
            raise ArgumentError('presliding: the base has no friction.gms section')
        return base_gear.replace({'friction': {'model': 'gms', 'gms': {
            'k': [x * k for x in gm.k], 'alpha': list(gm.alpha), 'c': gm.c}}})
    if effect == 'inertia':
        return base_gear.replace({'inertia': base_gear.inertia * (1.0 + s['sign'] * s['change'])})
    if effect == 'gravity':
        if not base_gear.mgl > 0.0:
            raise ArgumentError('gravity: the base has no lever (lever.mass or length 0)')
        lever = base_gear.section('lever')
        return base_gear.replace({'lever': {
            'mass': lever['mass'] * (1.0 + s['sign'] * s['change']),
            'angle_offset': lever['angle_offset'] + s['angle_sign'] * s['angle']}})
    # asymmetry
    return base_gear.replace({'friction': {'offset': s['sign'] * s['offset']}})


def apply_effects(base_gear: GearParams, effects: Mapping[str, Any], *,
                  temperatures: Sequence[float] | None = None) -> GearParams:
    """
    Apply several ``{effect: size}`` one after the other.

    Parameters
    ----------
    base_gear : GearParams
        The base gear the effects are added to.
    effects : dict
        Effect -> size, as :func:`apply_effect` takes them.
    temperatures : sequence of float, optional
        Segment temperatures of the recording (see :func:`apply_effect`).

    Returns
    -------
    GearParams

    """
    gear = base_gear
    for effect, size in effects.items():
        gear = apply_effect(gear, effect, size=size, temperatures=temperatures)
    return gear


# --------------------------------------------------------------------------- excitation

def segment_temperatures(base, n_segments=None, cfg=SEGMENT):
    """Nominal segment temperatures: spread over ``friction.temperature_range`` within margins."""
    n = int(cfg['n_segments'] if n_segments is None else n_segments)
    lo, hi = base.friction.temperature_range
    m = cfg['temperature_margin']
    a, b = lo + m, hi - m
    if not a < b:
        a = b = 0.5 * (lo + hi)
    return np.linspace(a, b, n) if n > 1 else np.array([0.5 * (a + b)])


def plan_segment(rng, gear_ratio, dt, duration, q0=0.0, cfg=SEGMENT, *, kind='rich'):
    """
    Plan the reference ``(q, qd, qdd)`` of one temperature segment of about ``duration`` s.

    ``kind='rich'``: plateau pairs, pre-sliding sinusoids and a multi-sine sweep
    (module docstring); the sweep fills whatever time the other parts leave.  Other
    kinds of :data:`~friction_joint.experiments.hidden_plant.RUN_KINDS`: see
    :func:`~friction_joint.experiments.hidden_plant.plan_kind` and
    :func:`~friction_joint.experiments.hidden_plant.sweep_oneway` (which starts at its
    own angle, not at ``q0``).
    """
    from .excitation import BlockPlan
    if kind == 'sweep_oneway':
        return sweep_oneway(rng, dt, duration, cfg)
    scale = duration / 30.0
    plan = BlockPlan(dt)
    plan._add(np.array([q0]), np.zeros(1), np.zeros(1))
    plan.hold(cfg['hold'])
    if kind != 'rich':
        plan_kind(plan, rng, kind, duration, cfg)
        q, qd, qdd = plan.arrays()
        return q[1:], qd[1:], qdd[1:]
    bands = speed_bands(cfg)
    order = rng.permutation(len(bands))
    for i in order:
        v = float(np.exp(rng.uniform(*np.log(bands[i]))))
        c = float(rng.uniform(-cfg['center_range'], cfg['center_range']))
        window = max(cfg['min_window'], cfg['window'] * scale)
        settle = cfg['settle'] + cfg['settle_travel'] / v
        t_ramp = max(0.05, math.pi * v / (2.0 * cfg['accel']))
        travel = v * (settle + window + t_ramp)
        plan.move(c - 0.5 * travel, cfg['move_accel'], cfg['move_speed'])
        for direction in (1.0, -1.0):
            plan.ramp(0.0, direction * v, cfg['accel'])
            plan.constant(direction * v, settle + window)
            plan.ramp(direction * v, 0.0, cfg['accel'])
            plan.hold(0.05)
    # pre-sliding: slow slide, then small sinusoids (one period each)
    slide, vp = cfg['presliding_slide'], cfg['presliding_speed']
    plan.ramp(0.0, vp, cfg['accel'])
    plan.constant(vp, slide / vp * min(1.0, max(0.3, scale)))
    plan.ramp(vp, 0.0, cfg['accel'])
    plan.hold(0.1)
    for amp in cfg['presliding_amplitudes']:
        plan.sine(amp, cfg['presliding_frequency'], 1)
    plan.hold(0.1)
    plan.move(0.0, cfg['move_accel'], cfg['move_speed'])
    # multi-sine sweep over the remaining time
    add_sweep(plan, rng, duration - plan.t_end, cfg)
    q, qd, qdd = plan.arrays()
    return q[1:], qd[1:], qdd[1:]


# --------------------------------------------------------------------------- simulation

def simulate_recording(truth_gear: GearParams, path: str | os.PathLike[str] | None, *,
                       options: RecordingOptions | None = None,
                       ) -> tuple[dict[str, dict[str, Any]], dict[str, Any]]:
    """
    Run ``truth_gear`` on the simulated test bed under the rich excitation; write a recording.

    Parameters
    ----------
    truth_gear : GearParams
        The simulated hardware (base + hidden effects).
    path : str or os.PathLike or None
        Recording to write (rosbag2 directory, or ``.mcap`` file); must not exist.
        ``None`` writes nothing (the topics are returned).
    options : RecordingOptions, optional
        Duration, seed, base gear, segments, topics and plant variation; default
        ``RecordingOptions()``.

    Returns
    -------
    topics : dict
        Topic -> dict of arrays, as written.
    summary : dict
        ``temperatures`` (segment set-points; warm-up: start temperatures), ``segments``
        (temperature, t0, t1, xi_start, xi_end, kind), ``warmup`` (the ambient or None),
        ``duration_s``, ``samples``, ``gains``, ``seed``, ``wall_time_s``, ``kinds``.

    """
    o = RecordingOptions() if options is None else options
    duration, seed, base_gear, n_segments = o.duration, o.seed, o.base_gear, o.n_segments
    cfg, gain_scale, encoder_bits, warmup = o.cfg, o.gain_scale, o.encoder_bits, o.warmup
    wall = time.perf_counter()
    conf = dict(SEGMENT)
    if cfg:
        unknown = sorted(set(cfg) - set(SEGMENT))
        if unknown:
            raise ArgumentError(f'unknown excitation option(s) {", ".join(unknown)}')
        conf.update(cfg)
    if not (math.isfinite(duration) and duration > 0):
        raise ArgumentError(f'duration must be > 0 s, got {duration}')
    base = truth_gear if base_gear is None else base_gear
    truth_gear = _vary_sensors(truth_gear, o.noise_scale, o.current_bandwidth_scale,
                               o.temperature_lag_scale)
    kinds = ['rich'] if o.kinds is None else [str(k) for k in o.kinds]
    bad = [k for k in kinds if k not in RUN_KINDS]
    if bad or not kinds:
        raise ArgumentError(f'unknown run kind(s) {bad}; kinds: {", ".join(RUN_KINDS)}')
    rng = np.random.default_rng(seed)
    nseg = int(conf['n_segments'] if n_segments is None else n_segments)
    temps = segment_temperatures(base, nseg, conf)
    temps = temps + rng.uniform(-1, 1, len(temps)) * conf['temperature_jitter']
    sim = truth_gear.section('simulation')
    assert sim is not None  # a section with defaults
    rate = sim['rate']
    dt = 1.0 / rate
    every = max(1, int(round(rate / conf['publish_rate'])))
    kp, kd = pd_gains(base.inertia, rise_time=conf['rise_time'], overshoot=conf['overshoot'])
    if gain_scale != 1.0:
        gk = np.broadcast_to(np.asarray(gain_scale, dtype=float), (2,))
        kp, kd = kp * float(gk[0]), kd * float(gk[1])
    seg_len = duration / nseg
    ambient = None
    if warmup:      # lowest to highest temperature over the motion and the gaps
        ends = temps if nseg > 1 else segment_temperatures(base, 2, conf)
        th = truth_gear.section('thermal')
        assert th is not None  # a section with defaults
        total = duration + (nseg - 1) * conf['gap']
        xi_warm = float(np.min(ends))
        ambient = xi_warm + (float(np.max(ends)) - xi_warm) / -math.expm1(
            -total / (th['capacity'] * th['resistance']))

    keys = ('t', 'q', 'qd', 'effort', 'tau', 'cmd', 'q_d', 'qd_d')
    out: dict[str, list[np.ndarray]] = {k: [] for k in keys}
    temp_t: list[np.ndarray] = []
    temp_xi: list[np.ndarray] = []
    segments: list[dict[str, Any]] = []
    t_off, q_start = 0.0, 0.0
    for b, xi_set in enumerate(temps):
        xi0 = float(xi_set if ambient is None else xi_warm)
        q_ref, qd_ref, qdd_ref = plan_segment(rng, truth_gear.gear_ratio, dt, seg_len,
                                              q_start, conf, kind=kinds[b % len(kinds)])
        with warnings.catch_warnings():
            warnings.simplefilter('ignore', GearConfigWarning)
            gear = truth_gear.replace({'thermal': {
                'ambient': xi0 if ambient is None else ambient, 'initial': xi0}})
        plant = Plant(gear, xi0=xi0, seed=int(seed) * 101 + b, q0=float(q_ref[0]))
        ctrl = Controller(base, kp, kd, friction='none', dt=dt)
        n = len(q_ref)
        record_segment(plant, lambda s, k, ctrl=ctrl, q_ref=q_ref, qd_ref=qd_ref, qdd_ref=qdd_ref:
                       ctrl(s.q, s.qd, s.xi, q_ref[k], qd_ref[k], qdd_ref[k]),
                       q_ref, qd_ref, every, t_off, out=out, temp_t=temp_t, temp_xi=temp_xi)
        segments.append({'temperature': xi0, 't0': t_off, 't1': t_off + n * dt, 'xi_start': xi0,
                         'xi_end': float(plant.thermal.xi), 'kind': kinds[b % len(kinds)]})
        q_start = float(plant.last.q_true)
        t_off += n * dt + conf['gap']
        if ambient is not None:     # the warm-up goes on during the gap
            xi_warm = plant.thermal.step(0.0, conf['gap'])

    cat = {k: np.concatenate(v) for k, v in out.items()}
    if encoder_bits:
        # the drive's loop runs on its fine motor-side encoder; the recorded output encoder
        # is the coarse one
        _vary_sensors(truth_gear, 1.0, 1.0, 1.0, encoder_bits)          # checks the value
        count = 2.0 * math.pi / 2.0 ** int(encoder_bits)
        cat['q'] = np.round(cat['q'] / count) * count
    name = truth_gear.joint_name
    topics = segment_topics(cat, temp_t, temp_xi, truth_gear)
    if o.link_torque:
        topics['/link_torque'] = {'t': cat['t'], 'tau': cat['tau']}
    if o.command:
        topics['/joint_command'] = {'t': cat['t'], 'effort': cat['cmd'], 'q_d': cat['q_d'],
                                    'qd_d': cat['qd_d'], 'name': name}
    if path is not None:
        if o.compress:
            _write_compressed(path, topics, name)
        else:
            write_recording(path, topics, joint_name=name)
    summary = {'temperatures': [s['temperature'] for s in segments], 'segments': segments,
               'duration_s': float(cat['t'][-1] - cat['t'][0]), 'samples': int(len(cat['t'])),
               'gains': {'kp': kp, 'kd': kd}, 'seed': int(seed),
               'wall_time_s': time.perf_counter() - wall, 'warmup': ambient,
               'kinds': [kinds[b % len(kinds)] for b in range(nseg)]}
    return topics, summary


def _vary_sensors(gear, noise_scale, bandwidth_scale, lag_scale, encoder_bits=None):
    """``gear`` with its sensor noise, bandwidth, temperature lag scaled, encoder bits set."""
    if noise_scale == 1.0 and bandwidth_scale == 1.0 and lag_scale == 1.0 and not encoder_bits:
        return gear
    for name, x in (('noise_scale', noise_scale), ('current_bandwidth_scale', bandwidth_scale),
                    ('temperature_lag_scale', lag_scale)):
        if not (math.isfinite(x) and x > 0):
            raise ArgumentError(f'{name} must be > 0, got {x}')
    sens = gear.section('sensors')
    new = {k: sens[k] * noise_scale for k in ('torque_noise', 'effort_noise',
                                              'link_torque_noise', 'temperature_noise')}
    new['current_bandwidth'] = sens['current_bandwidth'] * bandwidth_scale
    new['temperature_time_constant'] = sens['temperature_time_constant'] * lag_scale
    if encoder_bits:
        if int(encoder_bits) != encoder_bits or not 1 <= encoder_bits <= 52:
            raise ArgumentError(f'encoder_bits must be an integer 1..52, got {encoder_bits}')
        new['encoder_bits'] = int(encoder_bits)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', GearConfigWarning)
        return gear.replace({'sensors': new})


def _write_compressed(path, topics, joint_name):
    """
    Write ``topics`` as a rosbag2 directory the way the shipped sample is stored.

    One plain ``.mcap`` file with zstd-compressed chunks and CRCs (what
    ``ros2 bag record --storage-preset-profile zstd_small`` and Foxglove read as
    is; no whole-file compression, which MCAP tools cannot open without unpacking),
    ``ros_distro: jazzy`` in ``metadata.yaml``.
    """
    from ..bag.checksums import seal_rosbag2

    path = os.fspath(path)
    if path.endswith('.mcap'):
        raise ArgumentError('compress=True needs a rosbag2 directory path, not .mcap')
    write_recording(path, topics, joint_name=joint_name)     # sealed: zstd chunks, CRCs
    seal_rosbag2(path, ros_distro='jazzy')
    return path
