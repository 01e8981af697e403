# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Where the paper's regime lies: the tracking error against the controller's design inertia.

The paper reports 29-35 % maximum tracking error without friction
compensation (a = 0.4 rad, omega = 1.5 rad/s, Fig. 7) but not the inertia its
gains were designed for.  :func:`gain_sweep` runs the uncompensated and the
LuGre-compensated tracking of :mod:`~friction_joint.experiments.compensation`
for design inertias from 1/40 of the model's joint inertia up to all of it,
at the lowest and highest temperature of the compensation experiment
(imposed as start temperatures here: a design study, not a reproduction),
and reports which design inertias put the uncompensated error in the band.
"""
import math

import numpy as np

from ._common import check_model, check_scale, check_steps, experiment_result, json_key, n_steps
from .compensation import COMPENSATION, tracking_run
from ..control.gains import GAIN_PRESETS, GainDesign, loop_metrics
from ..paper import PAPER
from ..testbed.plant import Plant

__all__ = ['GAIN_SWEEP', 'gain_sweep']

GAIN_SWEEP = {
    'ratios': (1 / 40, 1 / 28, 1 / 20, 1 / 14, 1 / 10, 1 / 7, 1 / 5, 1 / 3, 1 / 2, 1.0),
    'amplitude': 0.4,               # rad, the paper's low-velocity case
    'band': PAPER['uncompensated_band'].value,   # %, the paper's uncompensated maximum error
    'models': ('none', 'lugre'),
}


def _band_edges(x, y, band):
    """Design inertias (log-interpolated) where y crosses the band's edges, None if it does not."""
    lx = np.log(np.asarray(x))
    y = np.asarray(y)
    out = []
    for level in band:
        cross = None
        for i in range(len(y) - 1):
            if (y[i] - level) * (y[i + 1] - level) <= 0 and y[i] != y[i + 1]:
                f = (level - y[i]) / (y[i + 1] - y[i])
                cross = float(math.exp(lx[i] + f * (lx[i + 1] - lx[i])))
                break
        out.append(cross)
    return out


def gain_sweep(model, truth, duration_scale=1.0):
    """
    Maximum tracking error at a = 0.4 rad against the design inertia of the gains.

    Parameters
    ----------
    model, truth : GearParams
        Identified model and simulated hardware.
    duration_scale : float
        Multiplies the settling interval and the evaluation window.

    Returns
    -------
    ExperimentResult
        ``summary``: ``design_inertia`` (kg m^2, the grid), ``ratio`` (to the
        model's joint inertia), ``max_error_pct[model][temperature]`` (lists
        over the grid), ``loop`` (omega_n, zeta on the truth per grid point),
        ``band`` (the paper's 29-35 %), ``band_inertia[temperature]`` (design
        inertias at the band's edges, None where the sweep does not cross
        one), ``presets`` (design inertia of each named preset).

    """
    scale = check_scale(duration_scale)
    check_model(model, ('lugre',))
    c, cc = GAIN_SWEEP, COMPENSATION
    dt = 1.0 / truth.section('simulation')['rate']
    period = 2.0 * math.pi / cc['omega']
    check_steps(cc['settle'] * scale + cc['periods'] * period * scale, dt, 'gain sweep run')
    n_settle = int(round(cc['settle'] * scale / dt))
    n = n_settle + n_steps(cc['periods'] * period * scale, dt, 'gain sweep evaluation window')
    temps = (min(cc['temperatures']), max(cc['temperatures']))
    grid = [r * model.inertia for r in c['ratios']]
    amp = c['amplitude']
    table = {m: {json_key(x): [] for x in temps} for m in c['models']}
    loops = []
    for j in grid:
        kp, kd = GainDesign(design_inertia=j).gains(model.inertia)
        loops.append(loop_metrics(kp, kd, truth.inertia))
        for xi in temps:
            warm = Plant(truth, xi0=xi)
            for kind in c['models']:
                r = tracking_run(model, warm, kp=kp, kd=kd, kind=kind, amp=amp, n=n)
                e = (r['q_d'] - r['q_true'])[n_settle:]
                table[kind][json_key(xi)].append(100.0 * float(np.max(np.abs(e))) / amp)
    summary = {'experiment': 'gain_sweep', 'duration_scale': scale, 'amplitude': amp,
               'omega': cc['omega'], 'temperatures': list(temps), 'design_inertia': grid,
               'ratio': list(c['ratios']), 'model_inertia': model.inertia,
               'truth_inertia': truth.inertia, 'max_error_pct': table, 'loop': loops,
               'band': list(c['band']), 'truth_model': truth.friction.model,
               'band_inertia': {k: _band_edges(grid, v, c['band'])
                                for k, v in table['none'].items()},
               'presets': {k: (p.design_inertia or model.inertia)
                           for k, p in GAIN_PRESETS.items()}}
    return experiment_result('gain_sweep', summary, {}, truth.friction.model)
