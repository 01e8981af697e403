# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Shared pieces of the test-bed experiments: their results, checks, the closed loop."""
from __future__ import annotations

import collections
from collections.abc import Mapping
import math
from typing import Any

import numpy as np

from ._basics import clip_window as _clip_window, json_key, MODEL_LABELS, MODELS, reversal_window
from .plots import experiment_figures
from ..exceptions import ExperimentError, GearConfigError
from ..inputs import MEMORY_BUDGET
from ..results import ExperimentResult

__all__ = ['MODELS', 'MIN_SAMPLES', 'STEP_BYTES', 'MAX_STEPS', 'experiment_result', 'Experiment',
           'json_key', 'n_steps', 'check_steps', 'check_scale', 'check_model', 'rmse', 'corr',
           'MODEL_LABELS', 'peak_window', 'reversal_peak_window', 'sign_changes',
           'reversal_window', 'SumOfSines', 'closed_loop']

#: minimum number of samples in an evaluation window
MIN_SAMPLES = 100
#: bytes one simulated step of a run holds (the plant's measured and true signals, each
#: model's simulation and the references: about 32 float64 arrays)
STEP_BYTES = 32 * 8
#: most steps one run may simulate: its arrays fit the memory budget of the inputs
MAX_STEPS = MEMORY_BUDGET // STEP_BYTES


def experiment_result(name: str, summary: dict[str, Any],
                      series: Mapping[str, Any] | None = None,
                      truth_model: str = '') -> ExperimentResult:
    """
    Return the result of one test-bed experiment run, its figures bound to it.

    The figures are drawn from the result by
    :mod:`~friction_joint.experiments.plots` (:func:`experiment_figures`); the
    numbers are written as ``summary.json`` and read by the report.

    Parameters
    ----------
    name : str
        The experiment (``chirp``, ``compensation``, ``estimation``,
        ``gain_sweep``); selects its figures.
    summary : dict
        Plain numbers, as documented by the experiment function.
    series : dict, optional
        The signals the figures are drawn from (numpy arrays), per experiment.
    truth_model : str
        Friction model of the simulated hardware (``lugre``, ``gms``).

    Returns
    -------
    ExperimentResult

    """
    result = ExperimentResult(name, summary, dict(series or {}), truth_model)
    result.figures.update(experiment_figures(result))
    return result


#: ``func(model, truth, duration_scale) -> ExperimentResult``, ``help`` one line;
#: ``output``: ``'results'`` (figures + summary.json in a directory) or ``'recording'``
#: (``func(model, truth, duration_scale, progress=None)`` returns ``(topics, summary)``,
#: written as a rosbag2 recording);
#: ``needs_model``: the experiment uses the ``--model`` gear file
Experiment = collections.namedtuple('Experiment', ['func', 'help', 'output', 'needs_model'],
                                    defaults=('results', True))


# ---------------------------------------------------------------- helpers ---

def check_steps(duration, dt, what):
    """
    Return the number of steps of ``duration`` s at step ``dt``, checked before any allocation.

    Raises
    ------
    ExperimentError
        More than :data:`MAX_STEPS` steps (or an overflow): the arrays of the
        run would not fit the memory budget.

    """
    x = duration / dt
    if not math.isfinite(x) or x > MAX_STEPS:
        raise ExperimentError(
            f'{what} of {duration:.4g} s at {1.0 / dt:g} Hz is {x:.3g} steps, more than the '
            f'{MAX_STEPS} that fit the memory budget ({MEMORY_BUDGET >> 20} MiB at '
            f'{STEP_BYTES} bytes per step); reduce --duration-scale')
    return int(round(x))


def n_steps(duration, dt, what):
    """Return the steps of an evaluated ``duration`` (>= MIN_SAMPLES, <= MAX_STEPS)."""
    n = check_steps(duration, dt, what)
    if n < MIN_SAMPLES:
        raise ExperimentError(
            f'{what} of {duration:.4g} s has only {n} samples at {1.0 / dt:g} Hz '
            f'(need >= {MIN_SAMPLES}); increase --duration-scale')
    return n


def check_scale(duration_scale):
    try:
        x = float(duration_scale)
    except (TypeError, ValueError):
        raise ExperimentError(f'duration scale must be a number, got {duration_scale!r}') from None
    if not (math.isfinite(x) and x > 0.0):
        raise ExperimentError(f'duration scale must be a finite number > 0, got {duration_scale}')
    return x


def check_model(model, kinds, where='model gear'):
    """Check that the model gear carries the parameters of every dynamic model used."""
    for kind in kinds:
        if kind in ('lugre', 'gms') and getattr(model.friction, kind) is None:
            src = f' ({model.source})' if model.source else ''
            raise GearConfigError(f'{where}{src} has no friction.{kind} section, '
                                  f'needed for the {kind} model of this experiment')


def rmse(e):
    return float(np.sqrt(np.mean(np.square(e))))


def corr(a, b):
    if np.std(a) == 0.0 or np.std(b) == 0.0:
        return float('nan')
    return float(np.corrcoef(a, b)[0, 1])


def peak_window(t, errors, start, half_width):
    """
    Zoom window ``(t0, t1)``: ``half_width`` either side of the largest |error|.

    ``errors`` is a sequence of arrays on ``t``; only samples at ``t >= start``
    (after a settling interval) count and the window is shifted to lie among
    them (all samples if there are none).
    """
    t = np.asarray(t)
    mag = np.max(np.abs(np.vstack([np.asarray(e) for e in errors])), axis=0)
    idx = np.flatnonzero(t >= start)
    if idx.size == 0:
        idx = np.arange(t.size)
    k = idx[np.argmax(mag[idx])]
    return _clip_window(t[idx], t[k] - half_width, t[k] + half_width)


def reversal_peak_window(t, errors, reversals, start, before, after):
    """
    Zoom window on the largest |error| after ``start``, framed by its velocity reversal.

    The sample k of the largest |error| of ``errors`` (arrays on ``t``) at
    ``t >= start`` -- the maximum a summary reports -- is found first; the
    window is ``(t_r - before, t_r + after)`` around the reversal t_r (of
    ``reversals``) nearest to it, widened to hold t_k with a margin of a
    tenth of the window's width and cut to the run.  Without a reversal
    within ``before + after`` of t_k: :func:`peak_window` (centred on t_k)
    with half width ``(before + after) / 2``.
    Either way the window contains t_k.
    """
    t = np.asarray(t)
    mag = np.max(np.abs(np.vstack([np.asarray(e) for e in errors])), axis=0)
    idx = np.flatnonzero(t >= start)
    if idx.size == 0:
        idx = np.arange(t.size)
    k = idx[np.argmax(mag[idx])]
    tk = float(t[k])
    reversals = np.asarray(reversals, dtype=float)
    if reversals.size == 0:
        return peak_window(t, errors, start, 0.5 * (before + after))
    tr = float(reversals[np.argmin(np.abs(reversals - tk))])
    margin = 0.1 * (before + after)
    if abs(tr - tk) > before + after:          # no reversal near it: centred on t_k
        return peak_window(t, errors, start, 0.5 * (before + after))
    t0 = min(tr - before, tk - margin)
    t1 = max(tr + after, tk + margin)
    t0, t1 = max(t0, float(t[0])), min(t1, float(t[-1]))
    return float(t0), float(t1)


def sign_changes(t, v):
    """Return the times where ``v`` changes sign (the later sample of each pair)."""
    t, v = np.asarray(t), np.asarray(v)
    return t[1:][np.sign(v[1:]) * np.sign(v[:-1]) < 0]


class SumOfSines:
    """
    q_d(t) = sum_i a_i sin(w_i t + p_i) with its first two derivatives.

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


def closed_loop(plant, controller, reference, n, observers=None):
    """
    Run ``n`` control steps; returns dict of arrays at the sample times.

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
