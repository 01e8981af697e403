# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Open-loop velocity of held-out windows: the base and the extended model against the encoder.

The base and the final model are simulated open loop
(:class:`~friction_joint.models.joint.Joint`) from the measured state over
:data:`WINDOW` s windows of held-out blocks, driven by the measured drive
torque, temperature and external torque; each window with the gear of the fit
that did not see its block (:func:`fold_gears`).
"""
from __future__ import annotations

from collections.abc import Sequence
import math
from typing import Any, TYPE_CHECKING

import numpy as np

from . import structures as dm
from .fitted_gear import sim_gear
from .gravity import corrected_lever, lever_section

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .crossval import CVResult
    from .data import DiagnosisData
    from ..gear import GearParams

__all__ = ['WINDOW', 'simulate_windows', 'fold_gears']

#: open-loop simulation window (s)
WINDOW = 0.5


def _windows(data: DiagnosisData) -> tuple[NDArray[np.int64], int]:
    """Start indices and length (samples) of open-loop simulation windows."""
    starts: list[int] = []
    n_len: int | None = None
    for p in np.unique(data.piece):
        idx = np.flatnonzero(data.piece == p)
        dt = data.dt[idx[0]]
        n = int(round(WINDOW / dt))
        if n_len is None:
            n_len = n
        if n != n_len or n < 2:                     # n < 2: refused by load_data (MAX_STEP)
            continue
        for a in range(idx[0], idx[-1] - n, n):
            if data.block_of[a] == data.block_of[a + n]:
                starts.append(a)
    return np.asarray(starts, dtype=np.int64), n_len or 1


def simulate_windows(data: DiagnosisData, gears_by_fold: Sequence[GearParams],
                     offsets_by_fold: Sequence[float],
                     levers_by_fold: Sequence[tuple[float, float]] | None = None
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """
    Open-loop velocity of every window with its held-out fold's gear.

    ``levers_by_fold``: per fold ``(m g l, angle offset)`` of the lever torque the
    simulation adds (default the data's lever model, :func:`fold_gears`).

    Returns
    -------
    (sim, meas, fold) : arrays (W, n-1), (W, n-1), (W,)

    """
    from ..models.joint import Joint
    starts, n = _windows(data)
    if len(starts) == 0:
        return np.zeros((0, 1)), np.zeros((0, 1)), np.zeros(0, int)
    idx = starts[:, None] + np.arange(n - 1)[None, :]
    folds = data.block_of[starts]
    sim = np.empty((len(starts), n - 1))
    meas = data.qd[idx + 1]
    by_model: dict[str, list[int]] = {}
    for w, f in enumerate(folds):
        by_model.setdefault(gears_by_fold[f].friction.model, []).append(w)
    for model, windows in by_model.items():
        ws = np.asarray(windows)
        glist = [gears_by_fold[folds[w]] for w in ws]
        lev = np.array([levers_by_fold[folds[w]] if levers_by_fold else (data.mgl_sim, 0.0)
                        for w in ws])
        j = Joint(glist, model=model, mgl=lev[:, 0], lever_offset=lev[:, 1])
        j.reset(q=data.q[starts[ws]], qd=data.qd[starts[ws]])
        off = np.array([offsets_by_fold[folds[w]] for w in ws])[:, None]
        tau = data.effort[idx[ws]] - off
        te = data.tau_ext[idx[ws]] if data.mgl_sim == 0.0 else 0.0
        dt = float(data.dt[starts[0]])
        tr = j.simulate(tau, dt, xi=data.xi[idx[ws]], tau_ext=te)
        sim[ws] = tr.qd
    return sim, meas, folds


def fold_gears(base: GearParams, cv: CVResult, ctx: dm.Context, data: DiagnosisData
               ) -> tuple[list[GearParams], list[float], list[tuple[float, float]]]:
    """
    Per fold: simulation gear, friction offset and lever ``(m g l, angle offset)``.

    Without ``/link_torque`` the lever is the base's, corrected by a fitted
    ``gravity`` term; with it the lever torque is the fitted term alone (the
    measured external torque is applied as it is).
    """
    gears: list[GearParams] = []
    offsets: list[float] = []
    levers: list[tuple[float, float]] = []
    lever = lever_section(base)
    own = (data.mgl_sim, float(lever.get('angle_offset', 0.0)))
    for f, s in enumerate(cv.structures):
        beta, names = cv.betas[f], cv.names[f]
        coef = dm.coefficients(s, beta, names, ctx)
        gears.append(sim_gear(base, s, coef))
        offsets.append(coef.get('offset', 0.0))
        grav = coef.get('gravity')
        if grav is not None and 'pose' in grav:     # the joint model has a sine: the nearest
            if ctx.pose is None:                    # set whenever a pose term is fitted
                raise AssertionError('a pose term without the frame of its stroke')
            grav = _pose_as_sine(grav['pose'], ctx.pose)
        if grav is None:
            levers.append(own if data.mgl_sim else (0.0, 0.0))
        elif data.mgl_sim:
            info = corrected_lever(base, grav)[1]
            levers.append((info['mgl'], info['angle_offset']))
        else:
            levers.append((math.hypot(grav['sin'], grav['cos']),
                           math.atan2(-grav['cos'], grav['sin'])))
    return gears, offsets, levers


def _pose_as_sine(pose: dict[str, Any], frame: tuple[float, float]) -> dict[str, float]:
    """Return ``{'sin': a, 'cos': b}`` nearest (least squares) a pose term over its stroke."""
    c, h = frame
    q = np.linspace(c - h, c + h, 41)
    tq = np.polynomial.polynomial.polyval(q - pose['center'], pose['coefficients'])
    (a, b), *_ = np.linalg.lstsq(np.column_stack([np.sin(q), np.cos(q)]), tq, rcond=None)
    return {'sin': float(a), 'cos': float(b)}
