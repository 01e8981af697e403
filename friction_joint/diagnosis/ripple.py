# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Ripple periods a recording can tell: a ripple must repeat within the travel of a piece.

A position ripple is a torque that *repeats* with the position.  A period is
tried only when the longest piece of the data (its position range, the
``stroke``) covers at least :data:`MIN_REPEATS` periods: a slower position
dependence (a lever or payload error, a cable) is ``gravity`` or a finding
of the residual scan, never a ripple.  The periods tried are the gear's
tooth engagement 2 pi / (2 N) and 2 pi / N, and the strongest period of a
periodogram of the friction torque against position (after a Coulomb +
viscous fit), searched between twice the travel of a bin and
``stroke / MIN_REPEATS``.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .data import BIN
from .scan import position_periodogram

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .data import DiagnosisData

__all__ = ['MIN_REPEATS', 'ripple_cycles', 'ripple_untestable', 'longest_period']

#: fewest periods of a ripple within the stroke of a piece
MIN_REPEATS = 3
#: bins per eighth of the period needed to test a ripple
MIN_PHASE_BINS = 5


def _stroke(data: DiagnosisData, q: NDArray[np.float64]) -> float:
    return float(getattr(data, 'stroke', 0.0) or (np.ptp(q) if len(q) else 0.0))


def longest_period(data: DiagnosisData) -> float:
    """Longest ripple period (rad) the data can tell: the stroke of a piece / MIN_REPEATS."""
    return _stroke(data, np.asarray(getattr(data, 'q', ()), float)) / MIN_REPEATS


def ripple_cycles(data: DiagnosisData, gear_ratio: float) -> list[float]:
    """
    Ripple fundamentals (cycles per output turn) tried by the ``position_ripple`` candidate.

    2 N and N (tooth engagement of a gear of ratio N), plus the strongest
    period of a periodogram of the measured friction torque against position
    after a Coulomb + viscous fit, between twice the travel of a bin and
    :func:`longest_period`, when it is not one of those: a ripple at another
    period (motor cogging, a bearing) is found instead of assumed.  Only
    periods of at most :func:`longest_period` are returned (possibly none).
    """
    p_long = longest_period(data)
    cycles = [c for c in (2.0 * gear_ratio, float(gear_ratio))
              if c > 0 and 2.0 * math.pi / c <= p_long]
    y = np.asarray(getattr(data, 'y', ()), float)
    if len(y) < 50:
        return cycles
    q, v = data.average(data.q), data.average(data.qd)
    x = np.column_stack([np.sign(v), v, np.ones_like(v)])
    r = y - x @ np.linalg.lstsq(x, y, rcond=None)[0]
    travel = float(np.sum(np.abs(np.diff(data.qf)))) if len(data.qf) > 1 else 0.0
    p_min = max(2.0 * float(np.median(np.abs(v))) * BIN, 2.0 * getattr(data, 'resolution', 0.0))
    p_max = min(0.5 * travel, float(np.ptp(q)), p_long)
    if not (p_min > 0.0 and p_max > 2.0 * p_min):
        return cycles
    periods, power = position_periodogram(q, [r], p_min, p_max)
    if not len(periods):
        return cycles
    found = 2.0 * math.pi / float(periods[int(np.argmax(power[0]))])
    # a peak further than half the periodogram's resolution (pi / position range) from the
    # periods already tried is another period (a ripple at 2 N + 2 is not 2 N's)
    if all(abs(found - c) > math.pi / float(np.ptp(q)) for c in cycles):
        cycles.append(found)
    return cycles


def ripple_untestable(data: DiagnosisData, gear_ratio: float) -> str | None:
    """
    Return why ``position_ripple`` cannot be tested on ``data`` (None: it can).

    Untestable when the gear's ripple period 2 pi / (2 N) does not repeat
    :data:`MIN_REPEATS` times within the stroke of a piece (the periodogram
    finds a period in noise too: it is tried, never a reason to test), or
    when its phase is not covered (every eighth of the period visited by
    :data:`MIN_PHASE_BINS` bins).
    """
    period = 2.0 * math.pi / (2.0 * gear_ratio)
    stroke = _stroke(data, np.asarray(getattr(data, 'q', ()), float))
    if not MIN_REPEATS * period <= stroke:
        return (f'the longest piece travels {stroke:.4g} rad, less than {MIN_REPEATS} periods '
                f'of the ripple period 2 pi / (2 N) = {period:.4g} rad (a ripple must repeat '
                'within a piece)')
    phase = np.mod(data.average(data.q), period) / period
    hist = np.bincount(np.minimum((phase * 8).astype(int), 7), minlength=8)
    if np.any(hist < MIN_PHASE_BINS):
        return (f'the positions visited do not cover the phase of the ripple period '
                f'2 pi / (2 N) = {period:.4g} rad (every eighth of it needs {MIN_PHASE_BINS} '
                'bins)')
    return None
