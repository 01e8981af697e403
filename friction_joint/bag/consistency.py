# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
Checks across the topics and signals of a recording: one clock, one motion, physics.

Each rule scales with the recording's own data (its span, its sample times, the
noise of its signals); every error names the file and the topic.

Header stamps (:func:`check_clocks`)
------------------------------------
* No stamp is negative (ROS time starts at 0; a negative stamp is an unset or
  shifted clock), on any topic.
* Every topic is on the clock of ``/joint_states``.  With ``/joint_states``
  spanning ``[a, b]`` (median sample time ``dt``) and the topic ``[c, d]``
  (median sample time ``dx``; for a single message, whose sample time is
  unknown, the joint states' span ``b - a``), and the tolerance
  ``g = max(2 dt, 2 dx, CLOCK_TOLERANCE (b - a))``:

  - the spans must overlap, give or take ``g`` (a temperature sensor at 1 Hz
    whose first message comes a little after the joint states start, or one
    sample just before, is fine; a topic stamped 1000 s later, or on an epoch
    clock against a simulation clock, is not);
  - a topic that covers less than :data:`CLOCK_COVER` of the joint states' span
    must not lie more than :data:`CLOCK_OUTSIDE` times the overlap (or ``g``)
    outside it (mostly elsewhere, touching the joint states at one end only).

Position and velocity (:func:`velocity_mismatch`)
-------------------------------------------------
The velocity must be the derivative of the position.  The joint states are cut
into consecutive windows of ``W = max(10, n / 200)`` samples; over each window
the change of the position ``Δq`` is compared with the integral of the velocity
``I`` (trapezoids over the stamps, so irregular sampling is exact; steps longer
than :data:`~friction_joint.bag.stamps.GAP` median sample times are left out of
both, and a position that wraps at ±π is unwrapped where that agrees with the
velocity and the position stays within one turn).  A window is judged when
``max(|Δq|, |I|)`` exceeds its noise floor ``2 r + K (√2 s_q + s_v dt W)``
(``K`` = :data:`NOISE`; ``r`` the position's quantum, its smallest step;
``s_q`` and ``s_v`` the spreads of position and velocity about their moving
averages over 10 samples, their noise, the velocity's counted as if it did not
average out over the window: noise, quantisation and filtered velocity noise
do not count as motion); a window whose position does not exceed the floor is
judged on its velocity only when the velocity's mean there is more than
:data:`COHERENT` times its spread there (a motion, not noise about zero at
rest).  The statistic

    M = sum |Δq - I| / sum max(|Δq|, |I|)        (judged windows)

(``|Δq - I|`` less the position's own error ``r + K √2 s_q``: a quantised
position is off by up to one quantum) is 0 for a consistent pair and 1 for a
frozen position (or a velocity in other units: degrees, the motor side of a
gear), 2 for a velocity of the opposite sign.  ``M >`` :data:`MISMATCH` is an
error; with fewer than :data:`MIN_WINDOWS` judged windows (a joint at rest, a
short recording) the pair is not judged.

Physical ranges (:func:`check_ranges`)
--------------------------------------
A temperature below absolute zero (-273.15 °C) or above :data:`MAX_TEMPERATURE`
(no gear, lubricant or sensor survives it) is an error.
"""
import math

import numpy as np

from .stamps import GAP
from ..exceptions import RecordingError
from ..gear.schema import ABSOLUTE_ZERO

__all__ = ['CLOCK_TOLERANCE', 'CLOCK_COVER', 'CLOCK_OUTSIDE', 'MISMATCH', 'MIN_WINDOWS',
           'COHERENT', 'NOISE',
           'MAX_TEMPERATURE', 'check_clocks', 'check_negative_stamps',
           'velocity_mismatch', 'check_position_velocity', 'check_ranges', 'check_recording']

#: fraction of the joint states' span a topic may lie beside it (with 2 sample times)
CLOCK_TOLERANCE = 0.05
#: a topic covering less than this fraction of the joint states' span ...
CLOCK_COVER = 0.01
#: ... must not lie more than this many times its overlap outside it
CLOCK_OUTSIDE = 10.0
#: the position/velocity mismatch M above which the velocity is refused
MISMATCH = 0.25
#: judged windows needed before the position/velocity mismatch is judged
MIN_WINDOWS = 10
#: lowest temperature (°C)
#: highest plausible housing temperature (°C): above the decomposition of any lubricant
MAX_TEMPERATURE = 1000.0
#: noise floors are this many spreads of the noise
NOISE = 5.0
#: a velocity is a motion over a window when its mean is this many times its spread there
COHERENT = 3.0
_WINDOWS = 200
_MIN_WINDOW = 10


def _median_step(t):
    d = np.diff(t)
    d = d[d > 0]
    return float(np.median(d)) if len(d) else 0.0


def check_negative_stamps(label, t, index=None):
    """
    Raise if a header stamp (s) is negative.

    ``index`` maps positions in ``t`` to message indices (default: the positions).
    """
    t = np.asarray(t, dtype=float)
    neg = np.flatnonzero(t < 0)
    if len(neg):
        i = int(neg[0])
        k = int(index[i]) if index is not None else i
        raise RecordingError(
            f'{label}: {len(neg)} negative header stamps, the first at message {k} '
            f'(t = {t[i]:.9f} s): ROS time starts at 0; an unset or shifted clock')


def check_clocks(recording):
    """
    Raise if a topic's stamps are not on the clock of ``/joint_states`` (module docstring).

    Raises
    ------
    RecordingError
        Naming the file, the topic and both spans.

    """
    js = recording.joint_states.t
    if len(js) < 2:
        return
    a, b = float(js[0]), float(js[-1])
    span = b - a
    dt = _median_step(js)
    for topic, data in recording.series().items():
        if topic == '/joint_states' or len(data.t) == 0:
            continue
        c, d = float(data.t[0]), float(data.t[-1])
        own = _median_step(data.t) if len(data.t) > 1 else span   # one message: unknown
        tol = max(2 * dt, 2 * own, CLOCK_TOLERANCE * span)
        overlap = min(b, d) - max(a, c)
        where = (f'{recording.path}: {topic}: header stamps {c:.6f}..{d:.6f} s, '
                 f'/joint_states {a:.6f}..{b:.6f} s')
        if overlap < -tol:
            raise RecordingError(
                f'{where}: {-overlap:.6g} s apart, no overlap: not on the clock of '
                '/joint_states (an epoch clock against a simulation clock, shifted stamps?)')
        inside = max(overlap, 0.0)
        outside = (d - c) - inside
        if inside < CLOCK_COVER * span and outside > CLOCK_OUTSIDE * max(inside, tol):
            raise RecordingError(
                f'{where}: covers {100 * inside / span:.2g} % of /joint_states and lies '
                f'{outside:.6g} s outside it: not on the clock of /joint_states (shifted '
                'stamps?)')


def _moving_spread(x, w):
    """Root mean square of ``x`` about its moving average over ``w`` samples."""
    if len(x) <= w:
        return float(np.std(x))
    c = np.concatenate(([0.0], np.cumsum(x - x[0])))
    avg = (c[w:] - c[:-w]) / w
    centre = x[w // 2:w // 2 + len(avg)] - x[0]
    return float(np.sqrt(np.mean((centre - avg) ** 2)))


def _quantum(dq):
    """Return the position's smallest step (its resolution, 0 if it never moves)."""
    steps = np.abs(dq[dq != 0])
    if not len(steps):
        return 0.0
    return float(np.percentile(steps, 1))


def velocity_mismatch(t, q, qd):
    """
    Return the position/velocity mismatch ``M`` and the judged windows (module docstring).

    Parameters
    ----------
    t, q, qd : array_like
        Stamps (s, increasing), position and velocity.

    Returns
    -------
    mismatch : float
        ``M`` (NaN when not judged).
    judged : int
        Windows judged.
    worst : int
        Index of the first sample of the window of largest ``|Δq - I|`` (-1 if none).

    """
    with np.errstate(all='ignore'):               # overflowing values: not judged (NaN)
        return _mismatch(*(np.asarray(x, dtype=float) for x in (t, q, qd)))


def _mismatch(t, q, qd):
    n = len(t)
    w = max(_MIN_WINDOW, n // _WINDOWS)
    if n < 2 * w:
        return math.nan, 0, -1
    dt = np.diff(t)
    step = _median_step(t)
    dq = np.diff(q)
    integral = 0.5 * (qd[1:] + qd[:-1]) * dt
    turns = np.round(dq / (2 * np.pi))
    wrapped = ((np.abs(dq) > np.pi) & (np.abs(dq - 2 * np.pi * turns - integral)
                                       < np.abs(dq - integral))
               & (np.ptp(q) <= 2 * np.pi * (1 + 1e-9)))         # an angle within one turn
    dq = np.where(wrapped, dq - 2 * np.pi * turns, dq)
    ok = (dt > 0) & (dt <= GAP * step)
    dq, integral = np.where(ok, dq, 0.0), np.where(ok, integral, 0.0)
    m = len(dq) // w
    if m < MIN_WINDOWS:
        return math.nan, 0, -1
    dq_w = dq[:m * w].reshape(m, w).sum(axis=1)
    int_w = integral[:m * w].reshape(m, w).sum(axis=1)
    qc = np.concatenate(([q[0]], q[0] + np.cumsum(dq)))      # unwrapped, gaps removed
    slack = _quantum(dq) + NOISE * math.sqrt(2) * _moving_spread(qc, _MIN_WINDOW)
    floor = slack + _quantum(dq) + NOISE * _moving_spread(qd, _MIN_WINDOW) * step * w
    size = np.maximum(np.abs(dq_w), np.abs(int_w))
    # a window whose position stands still is judged on its velocity only where that keeps
    # its sign and level (a motion, not noise about zero)
    spread = qd[:m * w].reshape(m, w).std(axis=1)
    steady = np.abs(int_w) > COHERENT * spread * np.where(ok, dt, 0)[:m * w].reshape(
        m, w).sum(axis=1)
    judged = (np.abs(dq_w) > floor) | ((np.abs(int_w) > floor) & steady)
    if np.count_nonzero(judged) < MIN_WINDOWS:
        return math.nan, int(np.count_nonzero(judged)), -1
    err = np.maximum(np.abs(dq_w - int_w) - slack, 0.0)
    mismatch = float(err[judged].sum() / size[judged].sum())
    if not math.isfinite(mismatch):
        return math.nan, 0, -1
    worst = int(np.flatnonzero(judged)[np.argmax(err[judged])]) * w
    return mismatch, int(np.count_nonzero(judged)), worst


def check_position_velocity(label, t, q, qd):
    """
    Raise if the velocity is not the derivative of the position (module docstring).

    Raises
    ------
    RecordingError
        Naming ``label`` (the recording and topic), ``M`` and where the worst window is.

    """
    mismatch, judged, worst = velocity_mismatch(t, q, qd)
    if mismatch > MISMATCH:
        raise RecordingError(
            f'{label}: the velocity disagrees with the position: over {judged} windows the '
            f'position changes by other amounts than the integral of the velocity (mismatch '
            f'{mismatch:.3g}, at most {MISMATCH:g}; 1 = a frozen position or a velocity in '
            f'other units, 2 = the opposite sign), worst from t = {t[worst]:.6f} s')


def check_ranges(recording):
    """
    Raise on a temperature outside the physical range (module docstring).

    Raises
    ------
    RecordingError
        Naming the file, the topic, the value and its time.

    """
    temp = recording.temperature
    if temp is None or len(temp) == 0:
        return
    xi = np.asarray(temp.xi, dtype=float)
    for bad, what in ((xi < ABSOLUTE_ZERO, f'below absolute zero ({ABSOLUTE_ZERO} °C)'),
                      (xi > MAX_TEMPERATURE, f'above {MAX_TEMPERATURE:g} °C, which no gear '
                                             'survives')):
        idx = np.flatnonzero(bad)
        if len(idx):
            i = int(idx[0])
            raise RecordingError(
                f'{recording.path}: /joint_temperature: temperature {xi[i]:.6g} °C at '
                f't = {temp.t[i]:.6f} s ({len(idx)} such samples) is {what}: a wrong unit '
                'or a corrupt value')


def check_recording(recording):
    """Run every check of this module on a :class:`~friction_joint.bag.Recording`."""
    check_ranges(recording)
    check_clocks(recording)
    js = recording.joint_states
    check_position_velocity(f'{recording.path}: /joint_states', js.t, js.q, js.qd)
