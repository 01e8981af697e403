"""The paper's evaluation experiments on the simulated test bed (seed Section V B-D).

Each experiment runs the simulated hardware (:class:`~friction_joint.testbed.plant.Plant`
with the **truth** gear file) and the identified **model** gear file the way
the paper runs its test bed and its model:

* :func:`chirp` -- dynamic simulation (Section V-B, Fig. 5).  Two chirp
  torque commands with the same rising frequency and a low and a high
  constant amplitude drive the plant open loop against the lever's gravity.
  The LuGre and GMS models are then simulated open loop with the measured
  applied torque (effort) as input and the measured temperature fed in, and
  their velocity and friction torque are compared with the measurement.
* :func:`compensation` -- friction compensation (Section V-C, Fig. 6-7).
  q_d = a sin(1.5 t), a in {0.4, 2.4} rad, the plant started at 27 and at
  35 degC, controller eq. 17 with gains for 0.04 s rise time and 6 %
  overshoot, friction feed-forward none / LuGre / GMS (same gains for all).
* :func:`estimation` -- external torque estimation (Section V-D, Fig. 8).
  Closed-loop motion with variable velocity over most of the lever's
  gravity range; the disturbance observer (eq. 15) leaves the gravity out,
  so the lever load is the unknown external torque it has to estimate,
  with and without the friction model.

Every experiment function takes ``(model, truth, duration_scale=1.0)`` (two
:class:`~friction_joint.gear.GearParams`) and returns an
:class:`ExperimentResult`: ``summary`` (plain numbers for ``summary.json``)
and ``figures`` (file name -> function drawing on a matplotlib Figure).
:data:`EXPERIMENTS` maps the command-line names to them; adding an
experiment is adding an entry.

The command ``friction_joint experiment NAME --model M.yaml --truth T.yaml
--out DIR [--duration-scale X]`` runs one and writes its PNG figures and
``DIR/summary.json``, all atomically (temporary files renamed into place,
the JSON last).  ``--duration-scale`` multiplies every duration (settling,
evaluation window, chirp length) and is meant for quick test runs.

``identification`` (Section V-A) is different: it only needs ``--truth`` and
writes a *recording* (``--out BAG``, a rosbag2 MCAP directory or ``.mcap``
file) of the identification excitation of :mod:`friction_joint.experiments.excitation`
for ``friction_joint identify``.
"""
import collections
import math
import os
import sys
import time

import numpy as np

from ..control.controller import Controller, SineTrajectory, pd_gains
from ..exceptions import FrictionJointError, GearConfigError
from ..gear import load_gear
from ..models.joint import Joint
from ..control.observer import DisturbanceObserver
from ..output import json_bytes, render_png, write_files
from ..testbed.plant import Plant

__all__ = ['ExperimentError', 'ExperimentResult', 'Experiment', 'EXPERIMENTS',
           'SumOfSines', 'chirp', 'compensation', 'estimation', 'identification', 'run_experiment',
           'write_results', 'register']

#: friction feed-forward / observer models compared
MODELS = ('none', 'lugre', 'gms')

#: minimum number of samples in an evaluation window
MIN_SAMPLES = 100


class ExperimentError(FrictionJointError, ValueError):
    """An experiment cannot run with the options given (e.g. a run too short to evaluate)."""


#: ``summary``: dict of plain numbers; ``figures``: {file name: draw(fig)}
ExperimentResult = collections.namedtuple('ExperimentResult', ['summary', 'figures'])

#: ``func(model, truth, duration_scale) -> ExperimentResult``, ``help`` one line;
#: ``output``: ``'results'`` (figures + summary.json in a directory) or ``'recording'``
#: (``func(model, truth, duration_scale, progress=None)`` returns ``(topics, summary)``,
#: written as a rosbag2 recording);
#: ``needs_model``: the experiment uses the ``--model`` gear file
Experiment = collections.namedtuple('Experiment', ['func', 'help', 'output', 'needs_model'],
                                    defaults=('results', True))


# ---------------------------------------------------------------- helpers ---

def _key(x):
    """JSON key of a temperature or amplitude: '27', '0.4'."""
    return f'{float(x):g}'


def _nsteps(duration, dt, what):
    n = int(round(duration / dt))
    if n < MIN_SAMPLES:
        raise ExperimentError(
            f'{what} of {duration:.4g} s has only {n} samples at {1.0 / dt:g} Hz '
            f'(need >= {MIN_SAMPLES}); increase --duration-scale')
    return n


def _check_scale(duration_scale):
    try:
        x = float(duration_scale)
    except (TypeError, ValueError):
        raise ExperimentError(f'duration scale must be a number, got {duration_scale!r}') from None
    if not (math.isfinite(x) and x > 0.0):
        raise ExperimentError(f'duration scale must be a finite number > 0, got {duration_scale}')
    return x


def _check_model(model, kinds, where='model gear'):
    """The model gear must carry the parameters of every dynamic model used."""
    for kind in kinds:
        if kind in ('lugre', 'gms') and getattr(model.friction, kind) is None:
            src = f' ({model.source})' if model.source else ''
            raise GearConfigError(f'{where}{src} has no friction.{kind} section, '
                                  f'needed for the {kind} model of this experiment')


def _rmse(e):
    return float(np.sqrt(np.mean(np.square(e))))


def _corr(a, b):
    if np.std(a) == 0.0 or np.std(b) == 0.0:
        return float('nan')
    return float(np.corrcoef(a, b)[0, 1])


def _grid(ax):
    ax.grid(True, alpha=0.3)


COLORS = {'none': 'C3', 'lugre': 'C0', 'gms': 'C2', 'measured': 'k', 'truth': 'k'}
LABELS = {'none': 'no friction model', 'lugre': 'LuGre', 'gms': 'GMS'}


class SumOfSines:
    """q_d(t) = sum_i a_i sin(w_i t + p_i) with its first two derivatives.

    Parameters
    ----------
    components : sequence of (amplitude, omega, phase)
        rad, rad/s, rad.
    """

    def __init__(self, components):
        self.components = [(float(a), float(w), float(p)) for a, w, p in components]

    def __call__(self, t):
        q = qd = qdd = 0.0
        for a, w, p in self.components:
            s, c = math.sin(w * t + p), math.cos(w * t + p)
            q += a * s
            qd += a * w * c
            qdd -= a * w * w * s
        return q, qd, qdd


def _closed_loop(plant, controller, reference, n, observers=None):
    """Run ``n`` control steps; returns dict of arrays at the sample times.

    The command for step k is computed from the sample at its start and the
    reference at that time (eq. 17); ``observers`` (name -> observer) see the
    measurements of each new sample.
    """
    observers = observers or {}
    out = {k: np.empty(n) for k in ('t', 'q_d', 'qd_d', 'q', 'q_true', 'qd', 'qd_true',
                                    'tau_cmd', 'effort', 'xi', 'xi_true', 'tau_ext',
                                    'tau_link', 'tau_r')}
    est = {name: np.empty(n) for name in observers}
    s = plant.last
    ref = reference(s.t)
    for k in range(n):
        tau = controller(s.q, s.qd, s.xi, *ref)
        s = plant.step(tau)
        ref = reference(s.t)
        out['t'][k] = s.t
        out['q_d'][k] = ref[0]
        out['qd_d'][k] = ref[1]
        out['q'][k] = s.q
        out['q_true'][k] = s.q_true
        out['qd'][k] = s.qd
        out['qd_true'][k] = s.qd_true
        out['tau_cmd'][k] = tau
        out['effort'][k] = s.effort
        out['xi'][k] = s.xi
        out['xi_true'][k] = s.xi_true
        out['tau_ext'][k] = s.tau_ext
        out['tau_link'][k] = s.tau_link
        out['tau_r'][k] = s.tau_r
        for name, obs in observers.items():
            est[name][k] = obs(s.effort, s.q, s.qd, s.xi)
    out['estimates'] = est
    return out


# ------------------------------------------------------------------ chirp ---

CHIRP = {
    'amplitudes': (5.5, 6.5),   # Nm: low (stick-slip, long stiction phases), high (~3 rad/s)
    'f0': 0.1,                  # Hz at t = 0
    'f1': 1.0,                  # Hz at the end of the run
    'duration': 20.0,           # s (times duration_scale)
    'xi0': 30.0,                # degC, plant start temperature
    'stiction_velocity': 1e-3,  # rad/s: |true velocity| below this counts as stiction
}


def chirp_signal(amplitude, duration, dt, f0, f1):
    """Linear chirp torque A sin(2 pi (f0 t + (f1 - f0) t^2 / (2 T))) at t = k dt."""
    t = dt * np.arange(int(round(duration / dt)))
    return t, amplitude * np.sin(2.0 * np.pi * (f0 * t + (f1 - f0) * t * t / (2.0 * duration)))


def chirp(model, truth, duration_scale=1.0):
    """Dynamic simulation with chirp torques (paper Section V-B, Fig. 5).

    Two chirp torque commands (:data:`CHIRP`: 0.1 -> 1.0 Hz over 20 s, 5.5 Nm
    and 6.5 Nm) drive the plant open loop from rest at q = 0 (lever hanging)
    at 30 degC.  Both amplitudes exceed the stiction torque (about 4.9 Nm),
    and the lever's gravity (m g l = 11 Nm) pulls the joint back: the low
    amplitude gives stick-slip with long stiction phases, the high one
    reaches about 3 rad/s.  The model gear's LuGre and GMS joints
    (``Joint(model, model=..., mgl=model.mgl)``) are simulated with the
    measured effort and the measured temperature as inputs (their load
    tau_L comes from their own gravity term).

    Parameters
    ----------
    model, truth : GearParams
        Identified model and simulated hardware.
    duration_scale : float
        Multiplies the chirp duration (the frequency range is kept).

    Returns
    -------
    ExperimentResult
        ``summary``: per model and amplitude (keys like ``'5.5'``)
        ``velocity_rmse`` (rad/s, model vs measured velocity),
        ``velocity_rmse_rel`` (relative to the RMS measured velocity),
        ``velocity_corr`` (correlation coefficient), ``friction_rmse`` (Nm,
        model friction vs the true friction torque incl. ripple); per
        amplitude ``peak_velocity``, ``rms_velocity`` (rad/s, measured),
        ``stiction_fraction`` (time share with |true velocity| < 1e-3 rad/s),
        ``effort_rmse`` (Nm, measured effort vs command).
    """
    scale = _check_scale(duration_scale)
    _check_model(model, ('lugre', 'gms'))
    c = CHIRP
    duration = c['duration'] * scale
    models = ('lugre', 'gms')
    summary = {'experiment': 'chirp', 'duration_scale': scale, 'duration_s': duration,
               'f0_hz': c['f0'], 'f1_hz': c['f1'], 'xi0': c['xi0'],
               'amplitudes': list(c['amplitudes']),
               'velocity_rmse': {m: {} for m in models},
               'velocity_rmse_rel': {m: {} for m in models},
               'velocity_corr': {m: {} for m in models},
               'friction_rmse': {m: {} for m in models},
               'peak_velocity': {}, 'rms_velocity': {}, 'stiction_fraction': {},
               'effort_rmse': {}}
    series = []
    for amp in c['amplitudes']:
        plant = Plant(truth, xi0=c['xi0'])
        _nsteps(duration, plant.dt, 'chirp run')
        t, cmd = chirp_signal(amp, duration, plant.dt, c['f0'], c['f1'])
        meas = plant.run(cmd)
        key = _key(amp)
        sims = {}
        for m in models:
            joint = Joint(model, model=m, mgl=model.mgl)
            sim = joint.simulate(meas['effort'], plant.dt, xi=meas['xi'])
            sims[m] = sim
            summary['velocity_rmse'][m][key] = _rmse(sim.qd - meas['qd'])
            summary['velocity_rmse_rel'][m][key] = (_rmse(sim.qd - meas['qd'])
                                                    / max(_rmse(meas['qd']), 1e-12))
            summary['velocity_corr'][m][key] = _corr(sim.qd, meas['qd'])
            summary['friction_rmse'][m][key] = _rmse(sim.tau_r - meas['tau_r'])
        summary['peak_velocity'][key] = float(np.max(np.abs(meas['qd'])))
        summary['rms_velocity'][key] = _rmse(meas['qd'])
        summary['stiction_fraction'][key] = float(
            np.mean(np.abs(meas['qd_true']) < c['stiction_velocity']))
        summary['effort_rmse'][key] = _rmse(meas['effort'] - cmd)
        series.append((amp, meas['t'], cmd, meas, sims))

    def draw(fig):
        axes = fig.subplots(3, len(series), sharex='col', squeeze=False)
        for j, (amp, t, cmd, meas, sims) in enumerate(series):
            tag = 'low' if j == 0 else 'high'
            a0, a1, a2 = axes[:, j]
            a0.plot(t, cmd, color='C1', lw=1.0, label='commanded')
            a0.plot(t, meas['effort'], color='k', lw=0.6, ls='--', label='applied (measured)')
            a0.set_ylabel('torque (Nm)')
            a0.set_title(f'{tag} amplitude: {amp:g} Nm chirp, '
                         f'{c["f0"]:g}-{c["f1"]:g} Hz')
            a1.plot(t, meas['qd'], color='k', lw=1.2, label='measured')
            for m in models:
                a1.plot(t, sims[m].qd, color=COLORS[m], lw=0.8,
                        label=f'{LABELS[m]} (RMSE {summary["velocity_rmse"][m][_key(amp)]:.3f} rad/s)')
            a1.set_ylabel('velocity (rad/s)')
            a2.plot(t, meas['tau_r'], color='k', lw=1.0, label='true friction (incl. ripple)')
            for m in models:
                a2.plot(t, sims[m].tau_r, color=COLORS[m], lw=0.8, label=LABELS[m])
            a2.set_ylabel('friction torque (Nm)')
            a2.set_xlabel('time (s)')
            for ax in (a0, a1, a2):
                ax.legend(fontsize='x-small', loc='upper left')
                _grid(ax)

    return ExperimentResult(summary, {'chirp.png': (draw, (13, 10))})


# ----------------------------------------------------------- compensation ---

COMPENSATION = {
    'amplitudes': (0.4, 2.4),       # rad
    'omega': 1.5,                   # rad/s
    'temperatures': (27.0, 35.0),   # degC, plant start temperature
    'rise_time': 0.04,              # s
    'overshoot': 0.06,
    'settle': 1.0,                  # s before the evaluation window
    'periods': 2,                   # evaluation window, periods of q_d
    'ff_velocity': ('measured', 'desired'),   # first: main result, others reported too
}


def _compensation_run(model, truth, kp, kd, kind, xi0, amp, n, ff_velocity):
    c = COMPENSATION
    plant = Plant(truth, xi0=xi0)
    ctrl = Controller(model, kp, kd, friction=kind, dt=plant.dt, ff_velocity=ff_velocity)
    return _closed_loop(plant, ctrl, SineTrajectory(amp, c['omega']), n)


def compensation(model, truth, duration_scale=1.0):
    """Friction compensation with eq. 17 (paper Section V-C, Fig. 6-7).

    For each start temperature (27, 35 degC), amplitude (0.4, 2.4 rad) and
    friction feed-forward (none, LuGre, GMS) the plant tracks
    q_d = a sin(1.5 t) from rest at q = 0 with the controller of eq. 17
    (gains from :func:`~friction_joint.control.controller.pd_gains` for the model
    inertia, 0.04 s rise time, 6 % overshoot; the same gains for all cases).
    After a settling interval of 1 s the error q_d - q_true is evaluated
    over two periods of q_d.  The friction feed-forward is driven by the
    measured velocity as in eq. 17; the variant driven by the desired
    velocity is run and reported as well.

    Parameters
    ----------
    model, truth : GearParams
    duration_scale : float
        Multiplies the settling interval and the evaluation window.

    Returns
    -------
    ExperimentResult
        ``summary``: ``max_error_pct[model][temperature][amplitude]`` (max
        |q_d - q_true| in % of a), ``rmse[...]`` (rad), ``max_error[...]``
        (rad), ``temperature_end[...]`` (degC, true, end of run) for
        model in none/lugre/gms, keys like ``'27'`` and ``'0.4'``; ``gains``;
        ``ff_velocity`` (the variant of the main tables) and
        ``ff_velocity_variants[variant]`` with the same tables for the
        others (lugre and gms only).
    """
    scale = _check_scale(duration_scale)
    _check_model(model, ('lugre', 'gms'))
    c = COMPENSATION
    kp, kd = pd_gains(model.inertia, c['rise_time'], c['overshoot'])
    dt = 1.0 / truth.section('simulation')['rate']
    period = 2.0 * math.pi / c['omega']
    settle = c['settle'] * scale
    window = c['periods'] * period * scale
    n_settle = int(round(settle / dt))
    n_eval = _nsteps(window, dt, 'compensation evaluation window')
    n = n_settle + n_eval
    temps = [_key(x) for x in c['temperatures']]
    amps = [_key(a) for a in c['amplitudes']]

    def table(models):
        return {m: {tk: {} for tk in temps} for m in models}

    main, *others = c['ff_velocity']
    summary = {'experiment': 'compensation', 'duration_scale': scale,
               'omega': c['omega'], 'amplitudes': list(c['amplitudes']),
               'temperatures': list(c['temperatures']),
               'gains': {'kp': kp, 'kd': kd, 'rise_time': c['rise_time'],
                         'overshoot': c['overshoot'], 'inertia': model.inertia},
               'settle_s': settle, 'evaluation_s': window, 'ff_velocity': main,
               'max_error_pct': table(MODELS), 'rmse': table(MODELS),
               'max_error': table(MODELS), 'temperature_end': table(MODELS),
               'peak_velocity': {},
               'ff_velocity_variants': {v: {'max_error_pct': table(('lugre', 'gms')),
                                            'rmse': table(('lugre', 'gms'))} for v in others}}
    traces = {}
    for xi0, tk in zip(c['temperatures'], temps):
        for amp, ak in zip(c['amplitudes'], amps):
            for kind in MODELS:
                for variant in c['ff_velocity']:
                    if variant != main and kind == 'none':
                        continue        # nothing to feed forward: identical to the main run
                    r = _compensation_run(model, truth, kp, kd, kind, xi0, amp, n, variant)
                    e = (r['q_d'] - r['q_true'])[n_settle:]
                    pct = 100.0 * float(np.max(np.abs(e))) / amp
                    if variant == main:
                        summary['max_error_pct'][kind][tk][ak] = pct
                        summary['rmse'][kind][tk][ak] = _rmse(e)
                        summary['max_error'][kind][tk][ak] = float(np.max(np.abs(e)))
                        summary['temperature_end'][kind][tk][ak] = float(r['xi_true'][-1])
                        summary['peak_velocity'][ak] = float(np.max(np.abs(r['qd_d'])))
                        traces[(tk, ak, kind)] = (r['t'], r['q_d'] - r['q_true'])
                    else:
                        v = summary['ff_velocity_variants'][variant]
                        v['max_error_pct'][kind][tk][ak] = pct
                        v['rmse'][kind][tk][ak] = _rmse(e)

    def draw_errors(fig):
        axes = fig.subplots(len(amps), len(temps), sharex=True, squeeze=False)
        for i, ak in enumerate(amps):
            for j, tk in enumerate(temps):
                ax = axes[i, j]
                for kind in MODELS:
                    t, e = traces[(tk, ak, kind)]
                    pct = summary['max_error_pct'][kind][tk][ak]
                    ax.plot(t, 1e3 * e, color=COLORS[kind], lw=0.9,
                            label=f'{LABELS[kind]} (max {pct:.2f} %)')
                ax.axvspan(0.0, settle, color='0.85', lw=0, label='settling (not evaluated)')
                ax.set_title(f'$q_d = {ak}\\,\\sin({c["omega"]:g}t)$ rad, '
                             f'start {tk} \u00b0C (peak {summary["peak_velocity"][ak]:.2f} rad/s)')
                ax.set_ylabel('position error $q_d - q$ (mrad)')
                if i == len(amps) - 1:
                    ax.set_xlabel('time (s)')
                ax.legend(fontsize='x-small', loc='upper right')
                _grid(ax)

    def draw_bars(fig):
        ax = fig.subplots()
        cases = [(tk, ak) for ak in amps for tk in temps]
        x = np.arange(len(cases))
        w = 0.26
        for i, kind in enumerate(MODELS):
            mx = [summary['max_error_pct'][kind][tk][ak] for tk, ak in cases]
            rm = [100.0 * summary['rmse'][kind][tk][ak] / float(ak) for tk, ak in cases]
            pos = x + (i - 1) * w
            ax.bar(pos, mx, w * 0.9, color=COLORS[kind], alpha=0.8,
                   label=f'{LABELS[kind]}: max error')
            ax.bar(pos, rm, w * 0.25, color='k',
                   label='RMSE' if i == len(MODELS) - 1 else None)
            for p_, v_ in zip(pos, mx):
                ax.text(p_, v_, f'{v_:.2f}', ha='center', va='bottom', fontsize='x-small')
        ax.set_xticks(x)
        ax.set_xticklabels([f'a = {ak} rad\n{tk} \u00b0C' for tk, ak in cases])
        ax.set_ylabel('position error (% of amplitude a)')
        ax.set_title('maximum tracking error (thick bars) and RMSE (thin bars), '
                     f'ff velocity: {main}')
        ax.legend(fontsize='small')
        _grid(ax)

    return ExperimentResult(summary, {'compensation_error.png': (draw_errors, (13, 8)),
                                      'compensation_bars.png': (draw_bars, (10, 5.5))})


# ------------------------------------------------------------- estimation ---

ESTIMATION = {
    # q_d: two incommensurate sinusoids, reaching about +-1.5 rad (gravity
    # up to +-11 Nm) with velocities up to about 1.8 rad/s and reversals at
    # varying speed and load
    'reference': ((0.9, 0.6, 0.5), (0.6, 1.7, 0.0)),
    'duration': 20.0,       # s
    'settle': 1.0,          # s, not evaluated
    'xi0': 30.0,            # degC
    'beta': 60.0,           # rad/s, observer cut-off Q(s) = beta / (s + beta)
    'beta_sweep': (30.0, 60.0, 120.0),   # LuGre observer, reported for the choice of beta
    'controller': 'lugre',  # friction feed-forward of the controller running the motion
}


def estimation(model, truth, duration_scale=1.0):
    """External torque estimation with eq. 15 (paper Section V-D, Fig. 8).

    The plant follows the sum-of-sines reference of :data:`ESTIMATION`
    (controller eq. 17 with LuGre feed-forward) so that the lever's gravity
    sweeps most of +-11 Nm at varying speed.  Disturbance observers with
    beta = 60 rad/s (Q(s) time constant 17 ms) leave the gravity out
    (``gravity=False``), so the lever load is the unknown external torque
    they estimate: without a friction model (eq. 4), with LuGre and with GMS
    (eq. 15).  The estimate is compared with the true tau_ext and with the
    (noisy) link torque sensor over the run after a 1 s settling interval.

    beta: the estimate lags tau_ext by about 1/beta, and the friction model
    is driven by the measured (filtered) velocity; at beta = 60 rad/s the lag
    error over the load swings stays near 0.1 Nm while the observer still
    smooths the velocity noise.  A LuGre observer at 30 and 120 rad/s is run
    alongside and reported (``beta_sweep``).

    Returns
    -------
    ExperimentResult
        ``summary``: ``rms_error``, ``max_error`` (Nm) and ``rms_error_pct``,
        ``max_error_pct`` (% of ``load_amplitude`` = max |tau_ext|) per
        observer model (none/lugre/gms) against the true tau_ext,
        ``vs_link_sensor`` (the same against the sensor),
        ``link_sensor_rms_error`` (Nm), ``beta``, ``beta_sweep``, ``q_range``,
        ``peak_velocity``.
    """
    scale = _check_scale(duration_scale)
    _check_model(model, ('lugre', 'gms'))
    c = ESTIMATION
    kp, kd = pd_gains(model.inertia, COMPENSATION['rise_time'], COMPENSATION['overshoot'])
    ref = SumOfSines(c['reference'])
    plant = Plant(truth, xi0=c['xi0'], q0=ref(0.0)[0])
    n = _nsteps(c['duration'] * scale, plant.dt, 'estimation run')
    n_settle = int(round(c['settle'] * scale / plant.dt))
    _nsteps((n - n_settle) * plant.dt, plant.dt, 'estimation evaluation window')
    ctrl = Controller(model, kp, kd, friction=c['controller'], dt=plant.dt)
    observers = {kind: DisturbanceObserver(model, c['beta'], plant.dt, friction=kind, gravity=False)
                 for kind in MODELS}
    sweep = [b for b in c['beta_sweep'] if b != c['beta']]
    for b in sweep:
        observers[f'lugre@{b:g}'] = DisturbanceObserver(model, b, plant.dt, friction='lugre',
                                                        gravity=False)
    r = _closed_loop(plant, ctrl, ref, n, observers)
    w = slice(n_settle, None)
    te = r['tau_ext'][w]
    load = float(np.max(np.abs(te)))

    def errors(est, against):
        e = est[w] - against
        return _rmse(e), float(np.max(np.abs(e)))

    summary = {'experiment': 'estimation', 'duration_scale': scale, 'beta': c['beta'],
               'controller_friction': c['controller'], 'xi0': c['xi0'],
               'duration_s': n * plant.dt, 'settle_s': n_settle * plant.dt,
               'load_amplitude': load,
               'q_range': [float(np.min(r['q'][w])), float(np.max(r['q'][w]))],
               'peak_velocity': float(np.max(np.abs(r['qd'][w]))),
               'tau_ext_range': [float(np.min(te)), float(np.max(te))],
               'rms_error': {}, 'max_error': {}, 'rms_error_pct': {}, 'max_error_pct': {},
               'vs_link_sensor': {'rms_error': {}, 'max_error': {}},
               'link_sensor_rms_error': _rmse(r['tau_link'][w] - te),
               'beta_sweep': {}}
    for kind in MODELS:
        rms, mx = errors(r['estimates'][kind], te)
        summary['rms_error'][kind] = rms
        summary['max_error'][kind] = mx
        summary['rms_error_pct'][kind] = 100.0 * rms / load
        summary['max_error_pct'][kind] = 100.0 * mx / load
        rms_l, mx_l = errors(r['estimates'][kind], r['tau_link'][w])
        summary['vs_link_sensor']['rms_error'][kind] = rms_l
        summary['vs_link_sensor']['max_error'][kind] = mx_l
    for b in c['beta_sweep']:
        name = 'lugre' if b == c['beta'] else f'lugre@{b:g}'
        rms, mx = errors(r['estimates'][name], te)
        summary['beta_sweep'][_key(b)] = {'rms_error': rms, 'max_error': mx,
                                          'rms_error_pct': 100.0 * rms / load,
                                          'max_error_pct': 100.0 * mx / load}

    def draw(fig):
        a0, a1, a2 = fig.subplots(3, 1, sharex=True, gridspec_kw={'height_ratios': [3, 2, 1.3]})
        t = r['t']
        a0.plot(t, r['tau_link'], color='0.6', lw=0.5, label='link torque sensor')
        a0.plot(t, r['tau_ext'], color='k', lw=1.4, label=r'applied $\tau_{ext}$ (true)')
        for kind in MODELS:
            a0.plot(t, r['estimates'][kind], color=COLORS[kind], lw=0.9,
                    label=f'estimate, {LABELS[kind]}')
        a0.set_ylabel('external torque (Nm)')
        a0.set_title(f'external torque estimation, observer eq. 15, '
                     f'$\\beta$ = {c["beta"]:g} rad/s, gravity as unknown load')
        for kind in MODELS:
            a1.plot(t, r['estimates'][kind] - r['tau_ext'], color=COLORS[kind], lw=0.8,
                    label=f'{LABELS[kind]} (RMS {summary["rms_error"][kind]:.2f} Nm, '
                          f'{summary["rms_error_pct"][kind]:.1f} %)')
        a1.axhline(1.0, color='k', ls=':', lw=0.8)
        a1.axhline(-1.0, color='k', ls=':', lw=0.8, label='$\\pm$1 Nm')
        a1.set_ylabel(r'error $\hat\tau_{ext} - \tau_{ext}$ (Nm)')
        a2.plot(t, r['q'], color='C4', lw=0.9, label='position (rad)')
        a2.plot(t, r['qd'], color='C5', lw=0.7, label='velocity (rad/s)')
        a2.set_ylabel('q (rad), $\\dot q$ (rad/s)')
        a2.set_xlabel('time (s)')
        for ax in (a0, a1, a2):
            ax.axvspan(0.0, summary['settle_s'], color='0.85', lw=0)
            ax.legend(fontsize='x-small', loc='upper right', ncol=2)
            _grid(ax)

    return ExperimentResult(summary, {'estimation.png': (draw, (12, 10))})


# --------------------------------------------------------- identification ---

def identification(model, truth, duration_scale=1.0, progress=None):
    """Identification excitation (paper Section V-A): a recording for ``friction_joint identify``.

    Constant-velocity plateaus 0.01..3.5 rad/s in both directions at four
    temperatures across the truth's range, the lever at different angles,
    and slow pre-sliding sinusoids; see :mod:`friction_joint.experiments.excitation`.
    ``model`` is not used; ``progress(message)`` is called once per
    temperature block.

    Returns
    -------
    topics : dict
        Contract topics, the input of :func:`friction_joint.bag.reader.write_recording`.
    summary : dict
        Plan and run facts (block temperatures, planned plateaus, duration).
    """
    from .excitation import simulate_identification
    return simulate_identification(truth, _check_scale(duration_scale), progress=progress)


#: command-line name -> experiment
EXPERIMENTS = {
    'chirp': Experiment(chirp, 'open-loop chirp torques, measured vs LuGre/GMS simulation (Fig. 5)'),
    'compensation': Experiment(compensation, 'sine tracking with friction feed-forward '
                                             'none/LuGre/GMS at 27 and 35 degC (Fig. 6-7)'),
    'estimation': Experiment(estimation, 'external torque estimation with the disturbance '
                                         'observer, with and without friction model (Fig. 8)'),
    'identification': Experiment(identification, 'constant-velocity plateaus at several '
                                                 'temperatures and loads plus pre-sliding '
                                                 'sinusoids, written as a recording (--out BAG) '
                                                 'for "friction_joint identify" (Section V-A)',
                                 'recording', False),
}


# ----------------------------------------------------------------- output ---

def write_results(result, out_dir, json_name='summary.json'):
    """Write the figures and ``summary.json`` of ``result`` into ``out_dir`` atomically.

    ``json_name`` names the JSON file (default ``summary.json``).

    Everything is rendered in memory, written to temporary files in
    ``out_dir`` (created if missing), then renamed into place with
    :func:`os.replace`, ``summary.json`` last: a ``summary.json`` present
    means the figures next to it belong to it.

    Returns
    -------
    list of str
        The paths written.
    """
    targets = [(name, render_png(draw, size)) for name, (draw, size) in result.figures.items()]
    targets.append((json_name, json_bytes(result.summary)))
    return write_files(out_dir, targets, ExperimentError)


def run_experiment(name, model_path, truth_path, out_dir, duration_scale=1.0, progress=None):
    """Load the gear files, run experiment ``name`` and write its results.

    ``model_path`` may be None for experiments that do not use a model
    (``identification``).  Experiments with ``output == 'recording'`` write a
    rosbag2 recording at ``out_dir`` (which must not exist); the others write
    their figures and ``summary.json`` into the directory ``out_dir``.

    Returns
    -------
    list of str
        The paths written (figures, then ``summary.json``; or the recording).
    """
    if name not in EXPERIMENTS:
        raise ExperimentError(f'unknown experiment {name!r}; choose from {", ".join(EXPERIMENTS)}')
    exp = EXPERIMENTS[name]
    scale = _check_scale(duration_scale)
    if exp.needs_model and model_path is None:
        raise ExperimentError(f'experiment {name} needs --model (the identified model gear file)')
    if exp.output == 'recording' and os.path.lexists(out_dir):
        raise ExperimentError(f'{out_dir} exists already: the {name} experiment writes a new '
                              'recording there; choose another --out')
    model = load_gear(model_path) if model_path is not None else None
    truth = load_gear(truth_path)
    start = time.perf_counter()
    if exp.output == 'recording':
        from ..bag.reader import write_recording
        topics, summary = exp.func(model, truth, scale, progress=progress)
        path = write_recording(out_dir, topics, joint_name=truth.joint_name)
        summary['wall_time_s'] = time.perf_counter() - start
        if progress is not None:
            progress(f'{len(summary.get("plateaus", []))} plateaus planned, '
                     f'{summary.get("duration_s", 0.0):.1f} s simulated in '
                     f'{summary["wall_time_s"]:.1f} s')
        return [path]
    result = exp.func(model, truth, scale)
    result.summary['model_file'] = os.path.abspath(model_path)
    result.summary['truth_file'] = os.path.abspath(truth_path)
    result.summary['wall_time_s'] = time.perf_counter() - start
    return write_results(result, out_dir)


def _run(args):
    paths = run_experiment(args.name, args.model, args.truth, args.out, args.duration_scale,
                           progress=lambda m: print(m, file=sys.stderr, flush=True))
    print('wrote ' + ', '.join(paths))
    return 0


def register(subparsers):
    """Add the ``experiment`` subcommand to an argparse subparsers object."""
    parser = subparsers.add_parser(
        'experiment', help="the paper's evaluation experiments on the simulated test bed",
        description="Run one of the seed paper's evaluation experiments (Section V B-D) on "
                    'the simulated test bed (TRUTH gear file) with the identified MODEL gear '
                    'file, and write its PNG figures and DIR/summary.json.')
    parser.add_argument('name', choices=tuple(EXPERIMENTS), metavar='NAME',
                        help='; '.join(f'{k}: {v.help}' for k, v in EXPERIMENTS.items()))
    parser.add_argument('--model', metavar='M.yaml',
                        help='gear file of the identified model (controller, observer, '
                             'simulation); required by every experiment but identification')
    parser.add_argument('--truth', required=True, metavar='T.yaml',
                        help='gear file of the simulated hardware (plant)')
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output directory (created if missing); for identification the '
                             'recording to write (a rosbag2 directory, or a .mcap file)')
    parser.add_argument('--duration-scale', type=float, default=1.0, metavar='X',
                        help='multiply all run durations by X (default 1; small values for '
                             'quick tests)')
    parser.set_defaults(func=_run)
    return parser
