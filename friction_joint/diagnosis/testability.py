# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Which candidate effects the data can tell: untestable ones get a one-line reason.

A candidate the data cannot tell is reported as untestable (``"testable":
false`` with its ``reason``) and the diagnosis goes on with the others; it is
never named.  Every rule is relative to the data's own scales
(:class:`~friction_joint.diagnosis.data.DiagnosisData`: friction level,
sliding threshold, position resolution), none in rad/s, Nm or Nm/rad:

* ``thermal``: a temperature signal (``/joint_temperature``) whose 2.5-97.5 %
  span while sliding is at least :data:`MIN_XI_SPAN` degC;
* ``load``: a 2.5-97.5 % span of |tau_ext| of at least :data:`LOAD_SPAN`
  times the friction level;
* ``position_ripple``: the ripple period 2 pi / (2 N) repeats at least
  :data:`~friction_joint.diagnosis.ripple.MIN_REPEATS` times within the
  stroke of a piece, every eighth of it visited by five bins (the periods
  tried, :func:`~friction_joint.diagnosis.ripple.ripple_cycles`, all repeat
  that often);
* ``nonlinear_viscous``, ``stribeck``: sliding speeds spanning a ratio of at
  least :data:`SPEED_RATIO` (5-95 %);
* ``presliding``: at least :data:`MIN_REVERSALS` velocity reversals (sign
  changes of qd among samples with ``|qd| >= v_stick``, within a piece: across
  a gap the direction changes unseen);
* ``inertia``: std(J qdd) at least :data:`INERTIA_SPAN` times the friction
  level (a base inertia of 0 cannot be scaled), and (checked after the base
  fit, :func:`inertia_noise_gain`) the encoder's quantisation in the
  acceleration would not by itself let a refitted J gain half the minimum gain
  (errors in variables: the noise is in the measured torque and the regressor);
  in every greedy round the inertia candidate is judged on its gain beyond
  what that noise alone gives against the current model
  (:func:`inertia_noise_mse`);
* ``asymmetry``: both directions each at least :data:`MIN_DIRECTION` of the
  sliding time;
* ``drift``: an accumulated travel of at least :data:`DRIFT_STROKES` strokes
  (so the travel is not confounded with the position).
"""
from __future__ import annotations

from collections.abc import Sequence
import math
from typing import TYPE_CHECKING

import numpy as np

from .ripple import ripple_untestable

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .data import DiagnosisData

__all__ = ['MIN_XI_SPAN', 'LOAD_SPAN', 'SPEED_RATIO', 'MIN_REVERSALS', 'INERTIA_SPAN',
           'MIN_DIRECTION', 'DRIFT_STROKES', 'untestable', 'acceleration_noise',
           'inertia_noise_mse', 'inertia_noise_gain']

#: smallest temperature span (degC, 2.5-97.5 %) to test ``thermal``
MIN_XI_SPAN = 0.5
#: smallest load span (2.5-97.5 %) to test ``load``, as a fraction of the friction level
LOAD_SPAN = 0.2
#: smallest ratio of the 95th to the 5th percentile of the sliding speed
SPEED_RATIO = 5.0
#: fewest velocity reversals to test ``presliding``
MIN_REVERSALS = 4
#: smallest std(J qdd) to test ``inertia``, as a fraction of the friction level
INERTIA_SPAN = 0.01
#: smallest share of the sliding time in each direction to test ``asymmetry``
MIN_DIRECTION = 0.05
#: least accumulated travel to test ``drift``, in strokes (largest position range of a piece)
DRIFT_STROKES = 5.0


def _span(x: NDArray[np.float64]) -> float:
    return float(np.percentile(x, 97.5) - np.percentile(x, 2.5))


def untestable(data: DiagnosisData, gear_ratio: float, effects: Sequence[str]) -> dict[str, str]:
    """
    Return ``{effect: reason}`` for the effects of ``effects`` the data cannot tell.

    Parameters
    ----------
    data : DiagnosisData
        The diagnosis data.
    gear_ratio : float
        The base gear's ratio (the ripple period is 2 pi / (2 gear_ratio)).
    effects : sequence of str
        Candidate effects.

    Returns
    -------
    dict
        Effect -> one-line reason, only for untestable effects.

    """
    why: dict[str, str] = {}
    level = data.friction_level
    qd = data.average(data.qd)
    if 'thermal' in effects:
        if not getattr(data, 'has_temperature', True):
            why['thermal'] = 'no temperature signal in the recordings'
        else:
            span = _span(data.average(data.xi))
            if span < MIN_XI_SPAN:
                why['thermal'] = (f'temperature spans {span:.2f} degC while the joint slides '
                                  f'(at least {MIN_XI_SPAN:g} degC needed)')
    if 'load' in effects:
        span = _span(data.average(data.tl))
        if span < LOAD_SPAN * level:
            why['load'] = (f'the load |tau_ext| spans {span:.3g} Nm while the joint slides, '
                           f'less than {LOAD_SPAN:g} x the friction level {level:.3g} Nm')
    if 'position_ripple' in effects:
        reason = ripple_untestable(data, gear_ratio)
        if reason:
            why['position_ripple'] = reason
    aq = np.abs(qd)
    lo, hi = np.percentile(aq, 5), np.percentile(aq, 95)
    for eff in ('nonlinear_viscous', 'stribeck'):
        if eff in effects and hi < SPEED_RATIO * lo:
            why[eff] = (f'sliding speeds span only {lo:.3g}..{hi:.3g} rad/s (5-95 %), a ratio '
                        f'below {SPEED_RATIO:g}')
    if 'presliding' in effects:
        moving = np.abs(data.qd) >= data.v_stick
        s, piece = np.sign(data.qd[moving]), data.piece[moving]
        # a change of direction across a gap between pieces is not seen (the state restarts)
        rev = int(np.count_nonzero((s[1:] != s[:-1]) & (piece[1:] == piece[:-1])))
        if rev < MIN_REVERSALS:
            why['presliding'] = (f'only {rev} velocity reversals (at least {MIN_REVERSALS} '
                                 'needed)')
    if 'inertia' in effects:
        jq = float(np.std(data.average(data.qdd))) * data.inertia
        if data.inertia <= 0:
            why['inertia'] = 'the base inertia is 0: no acceleration torque to rescale'
        elif jq < INERTIA_SPAN * level:
            why['inertia'] = (f'accelerations too small: std(J qdd) = {jq:.3g} Nm, less than '
                              f'{INERTIA_SPAN:g} x the friction level {level:.3g} Nm')
    if 'asymmetry' in effects:
        for sgn, word in ((1, 'positive'), (-1, 'negative')):
            share = np.count_nonzero(np.sign(qd) == sgn) / max(len(qd), 1)
            if share < MIN_DIRECTION:
                why['asymmetry'] = (f'the joint slides in the {word} direction {100 * share:.1f} '
                                    f'% of the time (at least {100 * MIN_DIRECTION:g} % needed)')
                break
    if 'drift' in effects:
        qf = data.qf
        dq = np.abs(np.diff(qf))[data.piece[1:] == data.piece[:-1]]
        travel, stroke = float(np.sum(dq)), float(data.stroke)
        if not travel >= DRIFT_STROKES * stroke or stroke <= 0:
            why['drift'] = (f'the joint travels {travel:.4g} rad in all, less than '
                            f'{DRIFT_STROKES:g} strokes of {stroke:.4g} rad')
    return why


def acceleration_noise(data: DiagnosisData, seed: int = 0) -> float:
    """
    Return the std (rad/s^2) of the encoder's quantisation in the bin-averaged acceleration.

    The quantisation error of this recording's own motion is drawn: the motion
    is reconstructed from the encoder's transitions (the position crosses the
    boundary between two counts between the samples where the count changes:
    linear between those crossings), quantised again at the data's resolution
    (a random sub-count offset per piece) minus itself, passed through the
    data's zero-phase derivative and averaged over the used bins.  Unlike a white
    error it keeps the staircase of a slow or short motion, whose steps fall
    within the derivative's band (a white error of one count's variance
    underestimates it up to threefold there).
    """
    from .data import BIN
    from .._filters import zero_phase_derivatives
    rng = np.random.default_rng(seed)
    res = float(data.resolution)
    qdd = np.zeros(len(data.t))
    for p in np.unique(data.piece):
        m = np.flatnonzero(data.piece == p)
        dt = float(data.dt[m[0]])
        cutoff = min(float(getattr(data, 'cutoff', 0.0) or np.inf), 0.2 / dt, 100.0)
        if res <= 0 or len(m) < 20 * max(1, int(round(BIN / dt))) or not 0 < cutoff < 0.5 / dt:
            continue
        motion = _through_transitions(data.t[m], data.q[m], data.qf[m])
        off = rng.uniform(0.0, res)
        e = res * np.round((motion - off) / res) + off - motion
        qdd[m] = zero_phase_derivatives(e, dt, cutoff=cutoff)[1]
    acc = data.average(qdd)
    return float(np.std(acc)) if len(acc) > 1 else 0.0


def _through_transitions(t: NDArray[np.float64], q: NDArray[np.float64],
                         qf: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the motion linear between the count changes of ``q`` (``qf`` if under two)."""
    i = np.flatnonzero(np.diff(q) != 0)
    if len(i) < 2:
        return qf
    out: NDArray[np.float64] = np.interp(t, 0.5 * (t[i] + t[i + 1]), 0.5 * (q[i] + q[i + 1]))
    return out


def inertia_noise_mse(data: DiagnosisData) -> float:
    """
    Return the mean squared torque (Nm^2) a refitted J removes from the quantisation alone.

    The measured friction torque holds ``-J n`` (n the acceleration's
    quantisation noise, :func:`acceleration_noise`) and the refitted inertia's
    regressor holds ``n`` too: a refit removes ``J^2 s_n^4 / s_a^2`` of the mean
    squared error (s_a^2 the variance of the measured bin acceleration), whatever
    the true J (errors in variables).
    """
    sn = acceleration_noise(data)
    sa2 = float(np.var(data.average(data.qdd)))
    if sn <= 0 or sa2 <= 0:
        return 0.0
    return float(data.inertia ** 2 * sn ** 4 / sa2)


def inertia_noise_gain(data: DiagnosisData, mse: float, removed: float | None = None) -> float:
    """
    Return the held-out gain a refitted J would show from the encoder's quantisation alone.

    ``mse`` is the current model's held-out mean squared error; ``removed`` the
    :func:`inertia_noise_mse` of ``data`` (computed when not given).
    """
    removed = inertia_noise_mse(data) if removed is None else removed
    if removed <= 0 or mse <= 0:
        return 0.0
    return 1.0 - math.sqrt(max(1.0 - removed / mse, 0.0))
