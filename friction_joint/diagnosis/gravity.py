# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ``gravity`` candidate: a direction-independent ``m g l sin(q - q0)`` the base lacks.

A joint that carries a lever, a payload or a link whose gravity model is off
(or missing) shows a torque ``a sin q + b cos q`` (q the output angle) that
does not change sign with the velocity, so no friction term absorbs it.  The
candidate adds those two columns (:mod:`~friction_joint.diagnosis.structures`).

When it is testable (:func:`gravity_untestable`)
------------------------------------------------
One cycle per turn must be told from what the base already has and from a
constant and a slope in q: over a short stroke ``sin q`` is a slope and
``cos q`` a constant, and the two columns would fit any offset or trend.  The
columns are projected on the span of the base structure's columns, a constant
and q (bin averages); the candidate is testable when the better-determined
combination of the two keeps at least :data:`MIN_CURVATURE` of its energy
outside that span (a scale-free rule: about 1 rad of stroke swept evenly);
an untestable gravity's reason names the stroke the same motion would need.  A linear
device (imported with a radius: its "angle" is a length over a radius) has no
gravity candidate.

Short strokes: a pose-dependent load (:func:`pose_frame`)
--------------------------------------------------------
When the stroke is too short for the sine (the rule above), ``gravity`` is
still tested, as what it is over that stroke: a direction-independent torque
smooth in position, ``c0 + c1 x + c2 x^2`` with ``x = (q - centre) / (half
stroke)`` (the constant left to ``friction.offset`` when the structure has
one).  The report says (:data:`POSE_CAVEAT`) that it stands for any
pose-dependent load error, and the extended gear file carries it as
``lever.pose_torque`` about ``lever.pose_center`` (:func:`pose_lever`), which
:meth:`~friction_joint.gear.GearParams.lever_torque` adds to the lever's sine.

The corrected lever (:func:`corrected_lever`)
---------------------------------------------
With the external torque from the base's lever ``m g l sin(q - q0)`` (no
``/link_torque``), the fitted ``a sin q + b cos q`` is what the lever model
misses, and the corrected lever is the one of the sum:
``M sin(q - q1) = (m g l cos q0 + a) sin q + (b - m g l sin q0) cos q``:
mass ``M / (g l)`` (length kept; 1 m when the base has none) and
``angle_offset`` q1.  With a ``/link_torque`` the lever is not in the data,
and the term stands for a position-dependent torque of the measured link side;
it is written to the lever section all the same, with that note.
"""
from __future__ import annotations

from collections.abc import Iterable
import math
import os
from typing import Any, TYPE_CHECKING

import numpy as np

from . import criterion as cr
from ..bag.provenance import import_mapping

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .crossval import CVResult
    from .data import DiagnosisData
    from ..gear import GearParams

__all__ = ['MIN_CURVATURE', 'POSE_CAVEAT', 'gravity_untestable', 'linear_device',
           'corrected_lever', 'pose_frame', 'pose_lever', 'pose_beyond_offset', 'lever_section']

#: what a ``gravity`` found over a short stroke stands for
POSE_CAVEAT = ('over this stroke the sine of a lever, m g l sin(q - q0), cannot be told from '
               'any smooth pose-dependent load: the term is a pose-dependent load error '
               '(gravity, a payload, a cable, the gravity model), fitted as an offset, a slope '
               'and a curvature about the centre of the stroke and valid over the recorded '
               'positions only')

#: least share of the energy of a gravity column outside the span of the base, 1 and q
MIN_CURVATURE = 2e-3


def linear_device(paths: Iterable[str | os.PathLike[str]]) -> bool:
    """Return whether any recording was imported as a linear device (with a radius)."""
    return any((import_mapping(path) or {}).get('radius_m') is not None for path in paths)


def gravity_untestable(data: DiagnosisData, base_columns: NDArray[np.float64],
                       linear: bool = False) -> str | None:
    """
    Return why ``gravity`` is untestable on ``data`` (a one-line reason), or None.

    Parameters
    ----------
    data : DiagnosisData
        The diagnosis data.
    base_columns : ndarray (n_bins, p)
        The base structure's design matrix.
    linear : bool
        The recordings come from a linear device.

    """
    if linear:
        return 'a linear device (imported with a radius) has no gravity torque'
    q = data.average(data.q)
    span = np.column_stack([base_columns, np.ones_like(q), q])
    u, sv, _ = np.linalg.svd(span / np.maximum(np.linalg.norm(span, axis=0), 1e-300),
                             full_matrices=False)
    u = u[:, sv > 1e-10 * sv[0]]
    share = _curvature(q, u)
    if share < MIN_CURVATURE:
        stroke = float(np.ptp(q))
        need = _stroke_needed(q, base_columns)
        needed = (f'the same motion over about {need:.3g} rad would be' if math.isfinite(need)
                  else 'even a full turn of the same motion would not be')
        return (f'the joint covers {stroke:.3g} rad: over so short a stroke m g l sin(q - q0) '
                f'is a constant and a slope (its curvature keeps {share:.2g} of its energy, '
                f'at least {MIN_CURVATURE:g} needed; {needed} enough)')
    return None


def _curvature(q: NDArray[np.float64], u: NDArray[np.float64]) -> float:
    """Return the energy share of the better-determined gravity column outside span ``u``."""
    g = np.column_stack([np.sin(q), np.cos(q)])
    rest = g - u @ (u.T @ g)
    # the better-determined combination of sin and cos: the largest singular value of the rest
    return float(np.linalg.svd(rest, compute_uv=False)[0] ** 2 / max(len(q), 1))


def _stroke_needed(q: NDArray[np.float64], base_columns: NDArray[np.float64]) -> float:
    """
    Return the stroke (rad) at which the same motion, scaled about its middle, is testable.

    The motion ``q`` is stretched about the middle of its range (the base's
    columns kept, 1 and q with it) until the curvature share reaches
    :data:`MIN_CURVATURE` (bisection on the log of the stretch); inf when a full
    turn does not reach it.
    """
    mid, stroke = 0.5 * (q.min() + q.max()), float(np.ptp(q))
    if stroke <= 0:
        return float('inf')

    def share(c: float) -> float:
        qs = mid + c * (q - mid)
        span = np.column_stack([base_columns, np.ones_like(qs), qs])
        u, sv, _ = np.linalg.svd(span / np.maximum(np.linalg.norm(span, axis=0), 1e-300),
                                 full_matrices=False)
        return _curvature(qs, u[:, sv > 1e-10 * sv[0]])

    lo, hi = 0.0, math.log(2 * math.pi / stroke)
    if hi <= 0 or share(math.exp(hi)) < MIN_CURVATURE:
        return float('inf')
    for _ in range(30):
        m = 0.5 * (lo + hi)
        lo, hi = (m, hi) if share(math.exp(m)) < MIN_CURVATURE else (lo, m)
    return stroke * math.exp(hi)


def lever_section(base: GearParams) -> dict[str, Any]:
    """
    Return the base gear's ``lever`` section (it has defaults: never absent).

    Parameters
    ----------
    base : GearParams
        The base gear.

    Returns
    -------
    dict
        ``mass``, ``gravity``, ``length``, ``angle_offset``, ...

    """
    lever = base.section('lever')
    if lever is None:
        raise AssertionError('the lever section has defaults')
    return lever


def corrected_lever(base: GearParams, coef: dict[str, float]
                    ) -> tuple[dict[str, float], dict[str, float]]:
    """
    Return the ``lever`` section of the extended gear and its gravity amplitude change.

    ``coef`` is the gravity part of a fit: ``{'sin': a, 'cos': b}`` (Nm).
    """
    lever = lever_section(base)
    q0 = float(lever.get('angle_offset', 0.0))
    mgl = lever['mass'] * lever['gravity'] * lever['length']
    big_a = mgl * math.cos(q0) + coef['sin']
    big_b = coef['cos'] - mgl * math.sin(q0)
    amp = math.hypot(big_a, big_b)
    q1 = math.atan2(-big_b, big_a) if amp > 0 else 0.0
    length = lever['length'] if lever['length'] > 0 else 1.0
    new = {'mass': amp / (lever['gravity'] * length), 'length': length, 'angle_offset': q1}
    return new, {'mgl_base': mgl, 'mgl': amp, 'angle_offset_base': q0, 'angle_offset': q1}


def pose_frame(data: DiagnosisData) -> tuple[float, float]:
    """Return ``(centre, half stroke)`` (rad) of the sliding bins' positions."""
    q = np.asarray(data.average(data.q), float)
    lo, hi = float(q.min()), float(q.max())
    return 0.5 * (lo + hi), max(0.5 * (hi - lo), 1e-9)


def pose_lever(base: GearParams, pose: dict[str, Any]
               ) -> tuple[dict[str, Any], dict[str, Any]]:
    """
    Return the ``lever`` changes of the extended gear for a fitted pose term, and its summary.

    ``pose`` is ``{'center': c, 'coefficients': [c0, c1, c2]}`` (Nm per power of
    rad about c); a pose torque of the base is re-expanded about c and added.
    """
    lever = lever_section(base)
    c = float(pose['center'])
    new = np.zeros(3)
    new[:len(pose['coefficients'])] = pose['coefficients']
    old = list(lever.get('pose_torque') or [])
    if old:
        shifted = np.asarray(np.polynomial.Polynomial(old)(
            np.polynomial.Polynomial([c - float(lever['pose_center']), 1.0])).coef, float)
        total = np.zeros(max(len(shifted), 3))
        total[:len(shifted)] += shifted
        total[:3] += new
    else:
        total = new
    coefs = [float(v) for v in total]
    return ({'pose_center': c, 'pose_torque': coefs},
            {'center': c, 'coefficients': [float(v) for v in new], 'pose_torque': coefs})


def pose_beyond_offset(entry: dict[str, Any], offset_cv: CVResult | None, pose_cv: CVResult,
                       level: float, *, alpha: float, min_gain: float,
                       min_explained: float) -> None:
    """
    Keep a significant short-stroke ``gravity`` only if it beats a constant offset too.

    Over a short stroke the pose term holds a constant, which ``asymmetry`` (a
    direction-independent offset) also fits: the term's slope and curvature must
    predict held-out blocks better than the offset alone (``offset_cv``, the
    asymmetry candidate of the round; None when the structure has the offset
    already, so the pose term is a slope and a curvature only), by the
    criterion's test and relevance (``alpha``, ``min_gain``, ``min_explained``).
    ``entry`` (the candidate's table entry) gets ``gain_over_offset``, and a note
    when it is no longer significant.
    """
    if offset_cv is None:
        return
    vs = cr.compare(offset_cv, pose_cv)
    entry['gain_over_offset'] = vs['gain_raw']
    if not (vs['p_value'] < alpha and cr.relevant(vs['gain_raw'], vs['explained_torque'],
                                                  level, min_gain, min_explained)):
        entry['significant'] = False
        entry['note'] = (f'a constant offset explains it as well: over the stroke its slope and '
                         f'curvature gain {100 * vs["gain_raw"]:.1f} % held out against the '
                         f'offset alone (p {vs["p_value"]:.2g})')
