# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Signals the diagnosis's design derives from the measured position: pre-sliding state, travel.

The pre-sliding friction state h of a LuGre or GMS structure is driven by the
increments dq of the zero-phase filtered position (not across the gaps
between pieces, where it restarts relaxed at 0) and normalised by g, the mean
Coulomb level, so that h = +-1 in steady sliding.  It comes from the models'
own updates, in normalised units:

* LuGre: :func:`~friction_joint.models.lugre.lugre_update` (eq. 10, exact for
  each sample) over a unit step with velocity ``a dq``, a = sigma0 / g the
  inverse pre-sliding length, and sigma0 = |g| = 1: its state is h itself,
  h+ = exp(-a |dq|) h + (1 - exp(-a |dq|)) sign(dq);
* GMS: :func:`~friction_joint.models.gms.gms_update` (eq. 11-12) over unit
  steps with velocity ``dq`` and |g| = 1: element i has the stiffness
  k_i / g and the torque share alpha_i, so its torque alpha_i h_i sticks
  (h_i moves by k_i dq / (alpha_i g)) until |h_i| = 1 and then slips there:
  h = sum alpha_i clip(h_i + k_i dq / (alpha_i g), -1, 1), slip being
  instantaneous (attraction :data:`GMS_SLIP`).
"""
from __future__ import annotations

from typing import Protocol, TYPE_CHECKING

import numpy as np

from .._jit import njit
from ..models.gms import gms_update
from ..models.lugre import lugre_update

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .data import DiagnosisData

__all__ = ['presliding_state', 'accumulated_travel', 'GMS_SLIP']


class _StateContext(Protocol):
    """What :func:`presliding_state` reads of a design context (``structures.Context``)."""

    data: DiagnosisData
    g_nom: float
    gms_ratios: NDArray[np.float64]
    gms_alpha: NDArray[np.float64]


#: attraction parameter C of the GMS elements of :func:`presliding_state` (unit steps, |g| = 1):
#: a slipping element's torque is its share of g to the last bit (exp(-C) < 1e-43), while a
#: slip onset that rounding puts past the step's end (by < 1 step) keeps exp(C) finite
#: (C = inf would give inf * 0 = nan there)
GMS_SLIP = 100.0


@njit
def _lugre_state(dq: NDArray[np.float64], piece: NDArray[np.int64], a: float,
                 out: NDArray[np.float64]) -> None:
    """
    Write the LuGre state h = sigma0 z / g over position increments ``dq`` (eq. 10) to out.

    :func:`~friction_joint.models.lugre.lugre_update` in units of the
    pre-sliding length 1 / ``a``: the increment over a unit step is the
    velocity ``a dq``, sigma0 = |g| = 1, so the state is h itself, +-1 in
    steady sliding, h+ = exp(-a |dq|) h + (1 - exp(-a |dq|)) sign(dq).
    """
    h = 0.0
    for k in range(dq.shape[0]):
        if k == 0 or piece[k] != piece[k - 1]:
            h = 0.0
        h = lugre_update(h, a * dq[k], 1.0, 1.0, 1.0)
        out[k] = h


@njit
def _gms_state(dq: NDArray[np.float64], piece: NDArray[np.int64], k: NDArray[np.float64],
               alpha: NDArray[np.float64], out: NDArray[np.float64]) -> None:
    """
    Write the GMS state h = sum alpha_i h_i over position increments ``dq`` to out.

    :func:`~friction_joint.models.gms.gms_update` with |g| = 1 and unit steps
    of velocity ``dq``: element i (stiffness ``k[i]`` per unit Coulomb level)
    sticks until its torque k_i z_i = alpha_i h_i reaches +-alpha_i and then
    slips at it (attraction :data:`GMS_SLIP`), i.e. h_i = clip(h_i + k_i dq /
    alpha_i, -1, 1).
    """
    n = k.shape[0]
    z = np.zeros(n)
    stick = np.ones(n, dtype=np.int8)
    slipdir = np.zeros(n)
    for j in range(dq.shape[0]):
        if j == 0 or piece[j] != piece[j - 1]:
            for i in range(n):
                z[i] = 0.0
                stick[i] = 1
                slipdir[i] = 0.0
        out[j] = gms_update((z, stick, slipdir), (k, alpha, GMS_SLIP), dq[j], 1.0, 1.0)


def presliding_state(ctx: _StateContext, ps: tuple[str, float]) -> NDArray[np.float64]:
    """Normalised pre-sliding friction state h (full rate) for ``ps = (model, stiffness)``."""
    d = ctx.data
    dq = np.diff(d.qf, prepend=d.qf[0])
    dq[np.r_[True, d.piece[1:] != d.piece[:-1]]] = 0.0
    out = np.empty_like(dq)
    model, stiff = ps
    if model == 'lugre':
        _lugre_state(dq, d.piece, stiff / ctx.g_nom, out)
    else:
        _gms_state(dq, d.piece, stiff * ctx.gms_ratios / ctx.g_nom, ctx.gms_alpha, out)
    return out


def accumulated_travel(data: DiagnosisData) -> NDArray[np.float64]:
    """
    Accumulated travel s / s_total (full rate, 0..1) of the data, in recording order.

    ``s = sum |dq|`` of the zero-phase filtered position, not counted across
    the gaps between pieces.
    """
    dq = np.abs(np.diff(data.qf, prepend=data.qf[0]))
    dq[np.r_[True, data.piece[1:] != data.piece[:-1]]] = 0.0
    s: NDArray[np.float64] = np.cumsum(dq)
    total = float(s[-1])
    return s / total if total > 0 else s
