# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Friction compensation (seed Section V-C, Fig. 6-7): sine tracking with feed-forward."""
import copy
import math
import time

import numpy as np

from ._common import (check_model, check_scale, check_steps, closed_loop, experiment_result,
                      json_key, MODEL_LABELS, MODELS, n_steps, reversal_peak_window, rmse)
from .warmup import warm_up
from ..control.controller import Controller, SineTrajectory
from ..control.gains import gain_design, loop_metrics
from ..testbed.plant import Plant

__all__ = ['COMPENSATION', 'compensation', 'tracking_run', 'warmed_plants']


COMPENSATION = {
    'amplitudes': (0.4, 2.4),       # rad
    'omega': 1.5,                   # rad/s
    'temperatures': (27.0, 31.0, 35.0),   # degC, reached by self-heating (warm-up)
    'gains': 'paper',               # gain design preset (control.gains)
    'warm_up_friction': 'lugre',    # feed-forward of the controller during the warm-up
    'settle': 1.0,                  # s before the evaluation window
    'periods': 2,                   # evaluation window, periods of q_d
    'ff_velocity': ('measured', 'desired'),   # first: main result, others reported too
}


def tracking_run(model, warm, *, kp, kd, kind, amp, n, ff_velocity='measured'):
    """Track a sin(omega t) from the warmed-up plant ``warm`` (copied, at rest at q = 0)."""
    plant = copy.deepcopy(warm)
    ctrl = Controller(model, kp, kd, friction=kind, dt=plant.dt, ff_velocity=ff_velocity)
    sine = SineTrajectory(amp, omega=COMPENSATION['omega'])
    t0 = plant.t
    r = closed_loop(plant, ctrl, lambda t: sine(t - t0), n)
    r['t'] = r['t'] - t0
    return r


def warmed_plants(model, truth, kp, kd, temperatures, *, progress=None):
    """
    Plants at rest at q = 0 whose gear self-heated to each temperature, in rising order.

    One plant starts at the truth's ambient temperature and is warmed up
    (:func:`~friction_joint.experiments.warmup.warm_up`) to the first
    temperature, copied, warmed on to the next, and so on.  Returns
    ``[(plant, warm_up_info), ...]`` in the order of ``temperatures``;
    ``progress(message)`` is called after each warm-up.
    """
    plant = Plant(truth)
    ctrl = Controller(model, kp, kd, friction=COMPENSATION['warm_up_friction'], dt=plant.dt)
    out = {}
    for xi in sorted(temperatures):
        t0, wall = plant.t, time.perf_counter()
        info = warm_up(plant, ctrl, xi)
        info['elapsed_s'] = float(plant.t)
        out[xi] = (copy.deepcopy(plant), info)
        if progress is not None:
            progress(f'warm-up to {xi:g} degC by self-heating: {info["reached"]:.1f} degC '
                     f'after {plant.t - t0:.0f} s simulated ({time.perf_counter() - wall:.1f} s)')
    return [out[xi] for xi in temperatures]


def compensation(model, truth, duration_scale=1.0, *, gains=None, progress=None):
    """
    Friction compensation with eq. 17 (paper Section V-C, Fig. 6-7).

    The gear is first heated by its own friction losses to each operating
    temperature (27, 31, 35 degC; :func:`warmed_plants`).  From each warm
    state, at rest at q = 0, and for each amplitude (0.4, 2.4 rad) and
    friction feed-forward (none, LuGre, GMS) the plant tracks
    q_d = a sin(1.5 t) with the controller of eq. 17 (gains of the design
    ``gains``, default the ``paper`` preset of
    :mod:`~friction_joint.control.gains`: 0.04 s rise time and 6 % overshoot
    designed for 0.016 kg m^2; the same gains for all cases).  After a
    settling interval of 1 s the error q_d - q_true is evaluated over two
    periods of q_d.  The friction feed-forward is driven by the measured
    velocity as in eq. 17; the variant driven by the desired velocity is run
    and reported as well.

    Parameters
    ----------
    model, truth : GearParams
        Identified model and simulated hardware.
    duration_scale : float
        Multiplies the settling interval and the evaluation window (not the
        warm-up, which lasts until the temperature is reached).
    gains : GainDesign or str, optional
        Gain design (a preset name, ``J=...`` or ``kp=...,kd=...``, see
        :func:`~friction_joint.control.gains.gain_design`); default ``paper``.
    progress : callable, optional
        ``progress(message)`` after each warm-up and after the tracking runs
        at each temperature.

    Returns
    -------
    ExperimentResult
        ``summary``: ``max_error_pct[model][temperature][amplitude]`` (max
        |q_d - q_true| in % of a), ``rmse[...]`` (rad), ``max_error[...]``
        (rad), ``max_error_time[...]`` (s since the start of tracking, where
        the maximum is), ``temperature_end[...]`` (degC, true, end of run) for
        model in none/lugre/gms, keys like ``'27'`` and ``'0.4'``; ``gains``
        (the design and kp, kd), ``loop`` (omega_n, zeta, overshoot and rise
        time of the PD loop on the truth's inertia), ``warm_up[temperature]``
        (temperature reached, warm-up time), ``truth_model`` (the hardware's
        friction model); ``zoom[temperature][amplitude]``: the zoom window
        of Fig. 6 (``window_s``), holding the larger of the LuGre and GMS
        maxima (its ``model`` and ``time_s``);
        ``ff_velocity`` (the variant of the main tables) and
        ``ff_velocity_variants[variant]`` with the same tables for the
        others (lugre and gms only).  ``series['error']``:
        ``(temperature, amplitude, model) -> (t, q_d - q_true)`` of the main
        variant.

    """
    scale = check_scale(duration_scale)
    check_model(model, ('lugre', 'gms'))
    c = COMPENSATION
    design = gain_design(c['gains'] if gains is None else gains)
    kp, kd = design.gains(model.inertia)
    dt = 1.0 / truth.section('simulation')['rate']
    period = 2.0 * math.pi / c['omega']
    settle = c['settle'] * scale
    window = c['periods'] * period * scale
    check_steps(settle + window, dt, 'compensation run')
    n_settle = int(round(settle / dt))
    n_eval = n_steps(window, dt, 'compensation evaluation window')
    n = n_settle + n_eval
    temps = [json_key(x) for x in c['temperatures']]
    amps = [json_key(a) for a in c['amplitudes']]

    def table(models):
        return {m: {tk: {} for tk in temps} for m in models}

    main, *others = c['ff_velocity']
    summary = {'experiment': 'compensation', 'duration_scale': scale,
               'omega': c['omega'], 'amplitudes': list(c['amplitudes']),
               'temperatures': list(c['temperatures']),
               'gains': design.to_dict(model.inertia),
               'loop': loop_metrics(kp, kd, truth.inertia), 'truth_model': truth.friction.model,
               'warm_up': {},
               'settle_s': settle, 'evaluation_s': window, 'ff_velocity': main,
               'max_error_pct': table(MODELS), 'rmse': table(MODELS),
               'max_error': table(MODELS), 'max_error_time': table(MODELS),
               'temperature_end': table(MODELS), 'zoom': {tk: {} for tk in temps},
               'peak_velocity': {},
               'ff_velocity_variants': {v: {'max_error_pct': table(('lugre', 'gms')),
                                            'rmse': table(('lugre', 'gms'))} for v in others}}
    traces = {}
    warm = warmed_plants(model, truth, kp, kd, c['temperatures'], progress=progress)
    for (plant0, info), tk in zip(warm, temps, strict=True):
        summary['warm_up'][tk] = info
        wall, runs = time.perf_counter(), 0
        for amp, ak in zip(c['amplitudes'], amps, strict=True):
            for kind in MODELS:
                for variant in c['ff_velocity']:
                    if variant != main and kind == 'none':
                        continue        # nothing to feed forward: identical to the main run
                    r = tracking_run(model, plant0, kp=kp, kd=kd, kind=kind, amp=amp, n=n,
                                     ff_velocity=variant)
                    runs += 1
                    e = (r['q_d'] - r['q_true'])[n_settle:]
                    pct = 100.0 * float(np.max(np.abs(e))) / amp
                    if variant == main:
                        summary['max_error_pct'][kind][tk][ak] = pct
                        summary['rmse'][kind][tk][ak] = rmse(e)
                        summary['max_error'][kind][tk][ak] = float(np.max(np.abs(e)))
                        summary['max_error_time'][kind][tk][ak] = \
                            float(r['t'][n_settle + int(np.argmax(np.abs(e)))])
                        summary['temperature_end'][kind][tk][ak] = float(r['xi_true'][-1])
                        summary['peak_velocity'][ak] = float(np.max(np.abs(r['qd_d'])))
                        traces[(tk, ak, kind)] = (r['t'], r['q_d'] - r['q_true'])
                    else:
                        v = summary['ff_velocity_variants'][variant]
                        v['max_error_pct'][kind][tk][ak] = pct
                        v['rmse'][kind][tk][ak] = rmse(e)
        if progress is not None:
            progress(f'{tk} degC: {runs} tracking runs of {n * dt:.1f} s (a = '
                     + ', '.join(amps) + ' rad; feed-forward none, LuGre, GMS) in '
                     f'{time.perf_counter() - wall:.1f} s; max error at a = {amps[0]} rad: '
                     + ', '.join(f'{MODEL_LABELS[m]} '
                                 f'{summary["max_error_pct"][m][tk][amps[0]]:.1f} %'
                                 for m in MODELS))

    for (tk, ak, kind), (t, _e) in traces.items():
        if kind != 'none':
            continue
        # the zoom of Fig. 6: the largest LuGre/GMS error of the table, at its reversal of q_d
        reversals = (0.5 + np.arange(int(t[-1] * c['omega'] / math.pi) + 1)) \
            * math.pi / c['omega']     # of q_d = a sin(omega t)
        window = reversal_peak_window(t, [traces[(tk, ak, m)][1] for m in ('lugre', 'gms')],
                                      reversals, float(t[n_settle]), 0.15, 0.5)
        worst = max(('lugre', 'gms'), key=lambda m: summary['max_error'][m][tk][ak])
        summary['zoom'][tk][ak] = {'window_s': list(window), 'model': worst,
                                   'time_s': summary['max_error_time'][worst][tk][ak]}
    return experiment_result('compensation', summary, {'error': traces}, truth.friction.model)
