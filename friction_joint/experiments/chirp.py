# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Dynamic simulation (seed Section V-B, Fig. 5).

Open-loop chirp torques, measured vs LuGre/GMS.
"""

import numpy as np

from ._common import check_model, check_scale, corr, experiment_result, json_key, n_steps, rmse
from ..models.joint import Joint
from ..testbed.plant import Plant

__all__ = ['CHIRP', 'chirp_signal', 'chirp']


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
    """
    Dynamic simulation with chirp torques (paper Section V-B, Fig. 5).

    Two chirp torque commands (:data:`CHIRP`: 0.1 -> 1.0 Hz over 20 s, 5.5 Nm
    and 6.5 Nm) drive the plant open loop from rest at q = 0 (lever hanging)
    at 30 degC.  Both amplitudes exceed the stiction torque (about 4.9 Nm),
    and the lever's gravity (m g l = 11 Nm) pulls the joint back: the low
    amplitude gives stick-slip with long stiction phases, the high one
    reaches about 3 rad/s.  The model gear's LuGre and GMS joints
    (``Joint(model, model=..., mgl=model.mgl, lever_offset=...)``) are simulated with the
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
        ``effort_rmse`` (Nm, measured effort vs command).  ``series`` per
        amplitude key: ``t``, ``command`` (Nm), ``measured`` (the plant's
        signals), ``models`` (model -> simulated trajectory).

    """
    scale = check_scale(duration_scale)
    check_model(model, ('lugre', 'gms'))
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
    series = {}
    for amp in c['amplitudes']:
        plant = Plant(truth, xi0=c['xi0'])
        n_steps(duration, plant.dt, 'chirp run')
        t, cmd = chirp_signal(amp, duration, plant.dt, c['f0'], c['f1'])
        meas = plant.run(cmd)
        key = json_key(amp)
        sims = {}
        for m in models:
            joint = Joint(model, model=m, mgl=model.mgl, lever_offset=model.lever_offset)
            sim = joint.simulate(meas['effort'], plant.dt, xi=meas['xi'])
            sims[m] = sim
            summary['velocity_rmse'][m][key] = rmse(sim.qd - meas['qd'])
            summary['velocity_rmse_rel'][m][key] = (rmse(sim.qd - meas['qd'])
                                                    / max(rmse(meas['qd']), 1e-12))
            summary['velocity_corr'][m][key] = corr(sim.qd, meas['qd'])
            summary['friction_rmse'][m][key] = rmse(sim.tau_r - meas['tau_r'])
        summary['peak_velocity'][key] = float(np.max(np.abs(meas['qd'])))
        summary['rms_velocity'][key] = rmse(meas['qd'])
        summary['stiction_fraction'][key] = float(
            np.mean(np.abs(meas['qd_true']) < c['stiction_velocity']))
        summary['effort_rmse'][key] = rmse(meas['effort'] - cmd)
        series[key] = {'t': meas['t'], 'command': cmd, 'measured': meas, 'models': sims}
    return experiment_result('chirp', summary, series, truth.friction.model)
