# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

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
(500 °C: no gear, lubricant or seal survives it) is an error.

The same checks, with :mod:`~friction_joint.bag.plausible`'s, are the one check of the
reader and of ``import`` (:func:`check_contents`, :func:`check_signals`): a log that
``import`` writes is one every reader accepts.  Each refusal says what to change.
"""
import math

import numpy as np

from .blockwise import BLOCK, gradient
from .plausible import check_values
from .stamps import GAP
from .topics import JointStates, LinkTorque, Recording, Temperature
from ..exceptions import RecordingError
from ..gear.schema import ABSOLUTE_ZERO

__all__ = ['CLOCK_TOLERANCE', 'CLOCK_COVER', 'CLOCK_OUTSIDE', 'MISMATCH', 'MIN_WINDOWS',
           'COHERENT', 'NOISE',
           'MAX_TEMPERATURE', 'check_clocks', 'check_negative_stamps',
           'VELOCITY_HINT', 'velocity_mismatch', 'ratio_reading', 'check_position_velocity',
           'check_ranges', 'check_recording', 'check_contents', 'check_signals',
           'position_derivative']

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
#: highest plausible housing temperature (°C): above it every gear lubricant has decomposed
#: (greases and oils below about 300 °C), seals have melted and gear steel loses its temper;
#: 900 °C is a wrong unit or a corrupt value, not a gear
MAX_TEMPERATURE = 500.0
#: noise floors are this many spreads of the noise
NOISE = 5.0
#: a velocity is a motion over a window when its mean is this many times its spread there
COHERENT = 3.0
_WINDOWS = 200
_MIN_WINDOW = 10


def _median_step(t):
    """Return the median of the positive steps of ``t`` (one scratch copy of its steps)."""
    d = np.diff(t)
    if not (d > 0).all():
        d = d[d > 0]
    return float(np.median(d, overwrite_input=True)) if len(d) else 0.0


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
            f'(t = {t[i]:.9f} s): ROS time starts at 0; an unset or shifted clock: stamp '
            'the messages with the time they were measured')


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
                '/joint_states (an epoch clock against a simulation clock, shifted stamps?): '
                'stamp every topic on one clock (use_sim_time alike for the nodes and the '
                'recorder)')
        inside = max(overlap, 0.0)
        outside = (d - c) - inside
        if inside < CLOCK_COVER * span and outside > CLOCK_OUTSIDE * max(inside, tol):
            raise RecordingError(
                f'{where}: covers {100 * inside / span:.2g} % of /joint_states and lies '
                f'{outside:.6g} s outside it: not on the clock of /joint_states (shifted '
                'stamps?): stamp every topic on one clock')


class _Spread:
    """
    Root mean square of a signal about its moving average over ``w`` samples, fed in blocks.

    The deviation of each sample ``w // 2`` into a window of ``w`` from the window's mean, over
    every complete window; the standard deviation of a signal of at most ``w`` samples.
    """

    def __init__(self, w):
        self.w, self.tail, self.sum2, self.count, self.short = w, np.zeros(0), 0.0, 0, []

    def add(self, x):
        x = np.concatenate((self.tail, x))
        w = self.w
        if len(x) < w:
            self.tail = x
            return
        c = np.concatenate(([0.0], np.cumsum(x - x[0])))
        dev = (x[w // 2:w // 2 + len(c) - w] - x[0]) - (c[w:] - c[:-w]) / w
        self.sum2 += float(np.dot(dev, dev))
        self.count += len(dev)
        self.tail = x[len(x) - (w - 1):]

    def value(self):
        return math.sqrt(self.sum2 / self.count) if self.count else float(np.std(self.tail))


def _quantum(steps):
    """Return the position's smallest step, the 1st percentile of its |steps| (0: none)."""
    if not len(steps):
        return 0.0
    return float(np.percentile(steps, 1, overwrite_input=True))


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
    return _judge(t, q, qd)[:3]


def _judge(t, q, qd):
    """:func:`velocity_mismatch` and the ratio of the velocity to the position's derivative."""
    with np.errstate(all='ignore'):               # overflowing values: not judged (NaN)
        return _mismatch(*(np.asarray(x, dtype=float) for x in (t, q, qd)))


def _windows(t, q, qd, w, m, step):
    """
    Per window of ``w`` samples: Δq, I, the velocity's spread, the time judged; the noise.

    One pass over blocks of whole windows (memory: the position's steps, for its quantum,
    and block-sized temporaries); returns the window arrays (``m`` each), the quantum and
    the moving spreads of the unwrapped position and of the velocity.
    """
    n = len(t)
    circle = np.ptp(q) <= 2 * np.pi * (1 + 1e-9)              # an angle within one turn
    sums = np.zeros((4, m))
    steps, k = np.empty(n - 1), 0
    sq, sv = _Spread(_MIN_WINDOW), _Spread(_MIN_WINDOW)
    qc = q[0]
    block = max(1, BLOCK // w) * w
    for a in range(0, n - 1, block):
        b = min(n - 1, a + block)                           # steps a..b-1
        dt = np.diff(t[a:b + 1])
        dq = np.diff(q[a:b + 1])
        integral = 0.5 * (qd[a + 1:b + 1] + qd[a:b]) * dt
        turns = np.round(dq / (2 * np.pi))
        wrapped = ((np.abs(dq) > np.pi) & (np.abs(dq - 2 * np.pi * turns - integral)
                                           < np.abs(dq - integral)) & circle)
        dq = np.where(wrapped, dq - 2 * np.pi * turns, dq)
        ok = (dt > 0) & (dt <= GAP * step)
        dq, integral, okdt = np.where(ok, dq, 0.0), np.where(ok, integral, 0.0), \
            np.where(ok, dt, 0.0)
        nz = np.abs(dq[dq != 0])
        steps[k:k + len(nz)] = nz
        k += len(nz)
        cum = qc + np.cumsum(dq)                            # unwrapped, gaps removed
        sq.add(np.concatenate(([qc], cum)) if a == 0 else cum)     # samples a+1..b (0..b)
        qc = float(cum[-1])
        sv.add(qd[a:b] if b < n - 1 else qd[a:])
        j0, j1 = a // w, min(m, b // w)                     # whole windows in this block
        if j1 > j0:
            lo, hi = j0 * w - a, j1 * w - a
            for row, x in enumerate((dq, integral, okdt)):
                sums[row, j0:j1] = x[lo:hi].reshape(-1, w).sum(axis=1)
            sums[3, j0:j1] = qd[j0 * w:j1 * w].reshape(-1, w).std(axis=1)
    return sums, _quantum(steps[:k]), sq.value(), sv.value()


def _mismatch(t, q, qd):
    n = len(t)
    w = max(_MIN_WINDOW, n // _WINDOWS)
    if n < 2 * w:
        return math.nan, 0, -1, math.nan
    m = (n - 1) // w
    if m < MIN_WINDOWS:
        return math.nan, 0, -1, math.nan
    step = _median_step(t)
    (dq_w, int_w, okdt_w, spread), quantum, s_q, s_v = _windows(t, q, qd, w, m, step)
    slack = quantum + NOISE * math.sqrt(2) * s_q
    floor = slack + quantum + NOISE * s_v * step * w
    size = np.maximum(np.abs(dq_w), np.abs(int_w))
    # a window whose position stands still is judged on its velocity only where that keeps
    # its sign and level (a motion, not noise about zero)
    steady = np.abs(int_w) > COHERENT * spread * okdt_w
    judged = (np.abs(dq_w) > floor) | ((np.abs(int_w) > floor) & steady)
    if np.count_nonzero(judged) < MIN_WINDOWS:
        return math.nan, int(np.count_nonzero(judged)), -1, math.nan
    err = np.maximum(np.abs(dq_w - int_w) - slack, 0.0)
    mismatch = float(err[judged].sum() / size[judged].sum())
    if not math.isfinite(mismatch):
        return math.nan, 0, -1, math.nan
    worst = int(np.flatnonzero(judged)[np.argmax(err[judged])]) * w
    dq_j, int_j = dq_w[judged], int_w[judged]
    pos, vel = float(np.dot(dq_j, dq_j)), float(np.dot(int_j, int_j))
    ratio = (math.inf if pos <= 1e-12 * vel else
             float(np.dot(int_j, dq_j)) / pos)
    return mismatch, int(np.count_nonzero(judged)), worst, ratio


#: velocity/derivative ratios that a unit explains: ratio -> what it reads as
_UNIT_RATIOS = ((180 / math.pi, 'a velocity in deg/s against a position in rad'),
                (math.pi / 180, 'a position in deg against a velocity in rad/s'),
                (30 / math.pi, 'a velocity in rpm against a position in rad'),
                (1 / (2 * math.pi), 'a velocity in rev/s against a position in rad'),
                (1000.0, 'a time in ms read as s, or a velocity in milli-units'),
                (0.001, 'a time in s read as ms, or a position in milli-units'),
                (60.0, 'a time in min read as s, or a velocity per minute'))


def ratio_reading(ratio: float) -> str:
    """
    Return what a ratio of a velocity to its position's derivative most likely means.

    Parameters
    ----------
    ratio : float
        The fitted ratio (inf: the position stands still while the velocity moves).

    Returns
    -------
    str

    """
    if not math.isfinite(ratio):
        return 'the position stands still while the velocity moves (a frozen position)'
    if abs(ratio) < 0.05:
        return 'the velocity stays near 0 while the position moves (a frozen velocity)'
    if ratio < 0:
        return ('the opposite sign (a velocity or position sign-flipped)'
                + ('' if abs(ratio + 1) < 0.1 else f', {-ratio:.3g} times the size'))
    for k, what in _UNIT_RATIOS:
        if abs(ratio / k - 1) < 0.05:
            return what
    if abs(ratio - 1) < 0.1:
        return 'close to 1, yet off in places (a delayed or filtered velocity?)'
    return (f'stamps {ratio:.3g} times too far apart, or a velocity in other units'
            if ratio > 1 else f'stamps {1 / ratio:.3g} times too close together, or a '
            'velocity in other units')


#: how to go on past a velocity that disagrees with its position
VELOCITY_HINT = ('fix the unit of the velocity or of the time (import: --velocity COL:UNIT, '
                 "--time COL:UNIT), or use the position's derivative instead of the logged "
                 'velocity: --velocity-from-position (import, diagnose, identify)')


def check_position_velocity(label, t, q, qd):
    """
    Raise if the velocity is not the derivative of the position (module docstring).

    Raises
    ------
    RecordingError
        Naming ``label`` (the recording and topic), ``M``, the ratio of the velocity to the
        position's derivative and its likely reading, where the worst window is, and how
        to go on (:data:`VELOCITY_HINT`).

    """
    mismatch, judged, worst, ratio = _judge(t, q, qd)
    if mismatch > MISMATCH:
        raise RecordingError(
            f'{label}: the velocity disagrees with the position (mismatch {mismatch:.3g} over '
            f'{judged} windows, at most {MISMATCH:g}; worst from t = {t[worst]:.6f} s): it is '
            f"{ratio:.4g} times the position's derivative (1 = consistent, 2 = stamps twice "
            'too far apart or a velocity in other units, -1 = the opposite sign, 0 = a '
            f'frozen velocity, inf = a frozen position): {ratio_reading(ratio)}; '
            f'{VELOCITY_HINT}')


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
                '(import: --temperature COL:K or COL:degF) or a corrupt value')


def check_recording(recording):
    """Run every check of this module on a :class:`~friction_joint.bag.Recording`."""
    check_ranges(recording)
    check_clocks(recording)
    js = recording.joint_states
    check_position_velocity(f'{recording.path}: /joint_states', js.t, js.q, js.qd)


def check_contents(recording):
    """
    Run the reader's checks of a recording's values: absurd samples, then this module's.

    The one check of :func:`~friction_joint.bag.read_recording` and ``import``
    (:func:`~friction_joint.bag.plausible.check_values`, :func:`check_recording`).

    Raises
    ------
    RecordingError
        Naming the file, the topic and the problem.

    """
    check_values(recording)
    check_recording(recording)


def check_signals(path, joint_name, t, joint_states, *, xi=None, tau=None):
    """
    Run :func:`check_contents` on signals sampled at ``t`` (a log being imported).

    Parameters
    ----------
    path : str
        What the errors name (the log file).
    joint_name : str
        The joint.
    t : array_like
        Stamps (s).
    joint_states : tuple of array_like
        Position, velocity and drive torque at ``t`` (``/joint_states``).
    xi, tau : array_like, optional
        Temperature (degC, ``/joint_temperature``) and external torque (``/link_torque``),
        at ``t``.

    """
    rec = Recording(path=path, joint_name=joint_name,
                    joint_states=JointStates(t, t, *joint_states),
                    temperature=None if xi is None else Temperature(t, t, xi, xi),
                    link_torque=None if tau is None else LinkTorque(t, t, tau))
    with np.errstate(all='ignore'):                 # huge values: judged, not warned about
        check_contents(rec)


def position_derivative(t, q):
    """
    Return the centred difference of the position, piece by piece (split at gaps).

    A step longer than :data:`~friction_joint.bag.stamps.GAP` median sample times ends
    a piece; each piece is differentiated on its own (one-sided at its ends), so no
    derivative bridges a gap; a piece of one sample has velocity 0.
    """
    t, q = np.asarray(t, dtype=float), np.asarray(q, dtype=float)
    out = np.zeros(len(t))
    if len(t) < 2:
        return out
    cuts = np.flatnonzero(np.diff(t) > GAP * _median_step(t)) + 1
    bounds = np.concatenate(([0], cuts, [len(t)]))
    with np.errstate(all='ignore'):
        for a, b in zip(bounds[:-1], bounds[1:], strict=True):
            if b - a >= 2:
                gradient(q[a:b], t[a:b], out[a:b])
    return out
