# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Header stamps of one topic, in bag order: what is accepted and what is an error.

A bag holds messages in receive-time order; their header stamps say when each
sample was taken.  Per topic (and joint) they must run forward.  The rules
scale with the topic's own sample time ``dt`` (the median forward step of the
stamps in bag order):

* **gaps** of any length are fine; the consumers (``diagnose``,
  ``identify``) bridge short ones and cut the data into pieces at the others
  (:func:`split_pieces`, below);
* a message sent twice (same stamp, same bytes, one after the other: the
  lockstep simulator re-sends a state until it is answered) is read once; the
  copies are counted (``Recording.duplicates``);
* a message **delivered late** (a DDS re-send after a lost packet) is sorted
  into place and counted (``Recording.unordered``) when it fills a hole in the
  stamps seen so far (its neighbours in time lie at least :data:`HOLE` ``dt``
  apart) and is at most :data:`LATE` ``dt`` late;
* errors, each naming the topic, the message index (per topic, in bag order)
  and its stamp: stamps that go **backwards over consecutive messages** (a
  reversed stretch); a message that goes back into time **already covered**
  by other messages (overlapping time bases, e.g. two runs glued together);
  one **later** than :data:`LATE` ``dt``; two different messages with the
  **same stamp**.

Gaps: bridged or split (:func:`split_pieces`)
---------------------------------------------
A step of the stamps longer than :data:`GAP` median sample times is a gap
(a realtime simulator or a loaded logger skipped samples, or a pause between
runs).  A gap is **bridged** (the piece goes on across it; consumers
interpolate onto the regular grid and leave the samples around it out of
their fits) when it is short by both of these scale-free rules:

* at most :data:`BRIDGE_SAMPLES` median sample times (a bridge never invents
  more samples than that), and
* at most :data:`BRIDGE_FRACTION` of the motion's own time scale
  ``T = P90(|qd|) / P90(|qdd|)`` (velocity over acceleration, 90th
  percentiles over the whole series; qdd from the velocity smoothed over
  :data:`SMOOTH` samples), so the velocity changes across a bridged gap by
  only a fraction of its typical size and a linear bridge of the position
  stays close to the motion.

Longer gaps split the data into pieces; no derivative, plateau or fit
crosses them.
"""
from collections.abc import Iterable, Sequence
import dataclasses
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .topics import NS
from ..exceptions import RecordingError

__all__ = ['LATE', 'HOLE', 'GAP', 'BRIDGE_SAMPLES', 'BRIDGE_FRACTION', 'SMOOTH', 'stamp_order',
           'Pieces', 'split_pieces', 'motion_time_scale', 'uniform_grid', 'piece_on_grid',
           'gap_summary', 'BRIDGE_MARGIN']

#: samples this many derivative-filter time constants (1 / cut-off) around a bridged gap
#: of the stamps are unreliable: identification and diagnosis leave them out
BRIDGE_MARGIN = 2.0
#: a late message may lag at most this many sample times behind the newest stamp
LATE = 100
#: a late message must fill a hole this many sample times wide (its neighbours' spacing)
HOLE = 1.5
#: a step of the stamps longer than this many median sample times is a gap
GAP = 5.0
#: a gap is bridged only when at most this many median sample times long ...
BRIDGE_SAMPLES = 50.0
#: ... and at most this fraction of the motion's time scale P90(|qd|) / P90(|qdd|)
BRIDGE_FRACTION = 0.25
#: samples over which the velocity is smoothed before the time scale's acceleration
SMOOTH = 11
#: stamps further than this fraction of a sample time from a uniform grid are irregular
REGULAR = 0.01


def _sec(ns):
    return f'{ns / NS:.6f}'


def _reversed(s, d, index, label):
    """Raise if two consecutive steps go backwards (a reversed stretch)."""
    neg = d < 0
    both = np.flatnonzero(neg[:-1] & neg[1:])
    if not len(both):
        return
    a = int(both[0])
    b = a
    while b + 1 < len(d) and d[b + 1] < 0:
        b += 1
    first, last = a, b + 1
    raise RecordingError(
        f'{label}: header stamps go backwards over {last - first} consecutive steps, from '
        f'message {index[first]} (t = {_sec(s[first])} s) to message {index[last]} '
        f'(t = {_sec(s[last])} s), {(s[first] - s[last]) / NS:.3f} s: a reversed stretch of '
        'time stamps')


def _late(s, dt, index, label):
    """Return the number of late messages; raise for one that is too late or overlaps."""
    runmax = np.maximum.accumulate(s)[:-1]
    late = np.flatnonzero(s[1:] < runmax) + 1
    if not len(late):
        return 0
    lag = runmax[late - 1] - s[late]
    order = np.argsort(s, kind='stable')
    rank = np.empty(len(s), dtype=np.int64)
    rank[order] = np.arange(len(s))
    ss = s[order]
    r = rank[late]
    prev = np.where(r > 0, ss[np.maximum(r - 1, 0)], np.iinfo(np.int64).min // 2)
    nxt = np.where(r < len(s) - 1, ss[np.minimum(r + 1, len(s) - 1)],
                   np.iinfo(np.int64).max // 2)
    if dt is None:
        covered = np.ones(len(late), dtype=bool)
        too_late = covered
    else:
        covered = (nxt - prev < HOLE * dt) | (prev == s[late]) | (nxt == s[late])
        too_late = lag > LATE * dt
    bad = np.flatnonzero(covered | too_late)
    if not len(bad):
        return len(late)
    j = int(bad[0])
    i = int(late[j])
    where = (f'message {index[i]} (t = {_sec(s[i])} s) goes back {lag[j] / NS:.6f} s'
             + (f' ({lag[j] / dt:.0f} sample times)' if dt else '')
             + f' behind message {index[int(np.argmax(s[:i]))]} (t = {_sec(runmax[i - 1])} s)')
    if covered[j]:
        raise RecordingError(
            f'{label}: header stamps go backwards: {where}, into time already covered by '
            'other messages: overlapping time bases (two runs glued together?)')
    raise RecordingError(
        f'{label}: header stamps go backwards: {where}, more than {LATE} sample times '
        f'({LATE * dt / NS:.3g} s) late')


def stamp_order(stamp, same, index, label):
    """
    Check the header stamps of one topic in bag order; return the order to read them in.

    Parameters
    ----------
    stamp : numpy.ndarray of int64
        Header stamps (ns) in bag order.
    same : callable
        ``same(i, j)``: messages ``i`` and ``j`` have the same bytes.
    index : array_like of int
        Message index (per topic, in bag order) of each stamp, for the messages.
    label : str
        ``'<recording>: <topic>'``, the start of every error message.

    Returns
    -------
    order : numpy.ndarray of int
        Indices into ``stamp``: sorted by stamp, repeated copies left out.
    late : int
        Messages delivered late and sorted into place.
    duplicates : int
        Repeated copies left out.

    Raises
    ------
    RecordingError
        A reversed stretch, overlapping time, a message too late, or two different
        messages with the same stamp (see the module docstring).

    """
    stamp = np.asarray(stamp, dtype=np.int64)
    n = len(stamp)
    d = np.diff(stamp)
    if n < 2 or (d > 0).all():
        return np.arange(n), 0, 0
    keep = np.ones(n, dtype=bool)
    for i in np.flatnonzero(d == 0):
        if same(int(i), int(i) + 1):
            keep[i + 1] = False
    pos = np.flatnonzero(keep)
    s = stamp[pos]
    index = np.asarray(index)[pos]
    d = np.diff(s)
    fwd = d[d > 0]
    dt = float(np.median(fwd)) if len(fwd) else None
    _reversed(s, d, index, label)
    late = _late(s, dt, index, label)
    order = np.argsort(s, kind='stable')
    eq = np.flatnonzero(np.diff(s[order]) == 0)
    if len(eq):
        a, b = sorted((int(order[eq[0]]), int(order[eq[0] + 1])))
        raise RecordingError(
            f'{label}: message {index[b]} has the same header stamp (t = {_sec(s[b])} s) as '
            f'message {index[a]} but other contents: two samples claim the same time '
            '(overlapping runs, or stamps coarser than the sampling)')
    return pos[order], late, n - len(pos)


# ------------------------------------------------------------------ gaps


@dataclasses.dataclass(frozen=True)
class Pieces:
    """
    A sampled series cut into pieces at its long gaps, its short gaps bridged.

    Attributes
    ----------
    ranges : tuple of (int, int)
        Index ranges ``[a, b)`` of the pieces (in order; a piece may be short).
    bridged : numpy.ndarray of int
        Indices ``i`` of the bridged steps ``t[i] -> t[i + 1]``.
    bridged_s : numpy.ndarray
        Their lengths (s).
    split : int
        Gaps that split the series (too long to bridge).
    dt : float
        Median sample time (s).
    time_scale : float
        The motion's time scale ``T`` (s; inf for a series without acceleration).
    limit : float
        Longest gap that is bridged (s): ``min(BRIDGE_SAMPLES dt, BRIDGE_FRACTION T)``.

    """

    ranges: tuple
    bridged: np.ndarray
    bridged_s: np.ndarray
    split: int
    dt: float
    time_scale: float
    limit: float

    def summary(self):
        """Plain-JSON counts: see :func:`gap_summary`."""
        return gap_summary([self])


def motion_time_scale(t, qd):
    """
    Return the motion's time scale P90(|qd|) / P90(|qdd|) in s (see the module docstring).

    qdd is the gradient (over the stamps) of the velocity smoothed over :data:`SMOOTH`
    samples; a series that never accelerates has an infinite time scale, one that never
    moves a zero one.
    """
    t = np.asarray(t, dtype=float)
    qd = np.asarray(qd, dtype=float)
    if len(t) < 3:
        return float('inf')
    m = min(SMOOTH, len(qd))
    c = np.concatenate(([0.0], np.cumsum(qd)))
    i = np.arange(len(qd))
    lo = np.clip(i - m // 2, 0, len(qd))
    hi = np.clip(i - m // 2 + m, 0, len(qd))
    v = (c[hi] - c[lo]) / (hi - lo)
    acc = float(np.percentile(np.abs(np.gradient(v, t)), 90))
    vel = float(np.percentile(np.abs(qd), 90))
    if not acc > 0:
        return float('inf')
    return vel / acc


def split_pieces(t: ArrayLike, qd: ArrayLike, *, gap: float = GAP) -> Pieces:
    """
    Cut a series at its long gaps, bridging the short ones (module docstring).

    Parameters
    ----------
    t : array_like
        Sample times (s), increasing.
    qd : array_like
        Velocity at the samples (rad/s, or any unit): gives the motion's time scale.
    gap : float
        A step longer than this many median sample times is a gap (default :data:`GAP`).

    Returns
    -------
    Pieces

    """
    t = np.asarray(t, dtype=float)
    d = np.diff(t)
    if len(d) == 0:
        return Pieces(((0, len(t)),) if len(t) else (), np.zeros(0, dtype=np.int64),
                      np.zeros(0), 0, 0.0, float('inf'), 0.0)
    pos = d[d > 0]
    dt = float(np.median(pos)) if len(pos) else 0.0
    scale = motion_time_scale(t, qd)
    limit = min(BRIDGE_SAMPLES * dt, BRIDGE_FRACTION * scale)
    long = d > gap * dt
    short = long & (d <= limit)
    cuts = np.flatnonzero((long & ~short) | (d <= 0)) + 1
    bounds = np.concatenate(([0], cuts, [len(t)]))
    bridged = np.flatnonzero(short)
    return Pieces(tuple((int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:], strict=True)),
                  bridged, d[bridged], int(np.count_nonzero(long & ~short)), dt, scale, limit)


def uniform_grid(t: ArrayLike) -> tuple[float, NDArray[np.float64] | None]:
    """
    Return a piece's sample time and its uniform grid (None when the stamps are regular).

    The sample time is the median step; the stamps are regular when there is one per
    grid point within :data:`REGULAR` of a sample time.

    Parameters
    ----------
    t : array_like
        The piece's stamps (s), increasing.

    Returns
    -------
    dt : float
        The sample time (s).
    grid : ndarray or None
        The uniform grid, or None when the stamps are regular.

    """
    t = np.asarray(t, dtype=float)
    dt = float(np.median(np.diff(t)))
    span = t[-1] - t[0]
    if len(t) > 1 and span > 0:
        # one stamp per grid point: the sample time is the mean step.  Not the median
        # step: stamps rounded to whole nanoseconds, and epoch seconds in float64
        # (quantised to about 0.24 us at 1.7e9 s), make single steps differ from the
        # sample time, so a median step times the sample count can miss the span by
        # dozens of samples on a long regular recording
        mean = span / (len(t) - 1)
        if np.max(np.abs((t - t[0]) - np.arange(len(t)) * mean)) <= REGULAR * mean:
            return float(mean), None
    m = int(np.floor(span / dt + 1e-6)) + 1
    return dt, t[0] + np.arange(m) * dt


def piece_on_grid(t: NDArray[np.float64], arrays: Sequence[NDArray[np.float64]], steps: ArrayLike,
                  margin: float = 0.0
                  ) -> tuple[NDArray[np.float64], list[NDArray[np.float64]], NDArray[np.bool_]]:
    """
    One piece on its uniform grid, with the samples in and next to bridged gaps marked.

    Parameters
    ----------
    t : numpy.ndarray
        The piece's stamps (s).
    arrays : sequence of numpy.ndarray
        Series at the stamps.
    steps : array_like of int
        Bridged steps ``t[i] -> t[i + 1]`` of the piece (indices into ``t``).
    margin : float
        Grid samples up to this many seconds outside a bridged gap are marked too.

    Returns
    -------
    t : numpy.ndarray
        The uniform grid (the stamps themselves when they are regular).
    arrays : list of numpy.ndarray
        The series on it (linear interpolation when resampled).
    ok : numpy.ndarray of bool
        False in and within ``margin`` of a bridged gap.

    """
    step, grid = uniform_grid(t)
    if grid is None:
        # regular stamps: the samples stay as they are, on the exact grid (stamps read as
        # float seconds carry rounding that would otherwise enter every derivative)
        return (t[0] + step * np.arange(len(t)), [np.asarray(x) for x in arrays],
                np.ones(len(t), dtype=bool))
    ok = np.ones(len(grid), dtype=bool)
    for i in np.asarray(steps, dtype=np.int64):
        lo = np.searchsorted(grid, t[i] - margin, side='right')
        hi = np.searchsorted(grid, t[i + 1] + margin, side='left')
        ok[lo:hi] = False
    return grid, [np.interp(grid, t, x) for x in arrays], ok


def gap_summary(pieces: Iterable[Pieces]) -> dict[str, Any]:
    """
    Gaps of one or more series (:class:`Pieces`) for a report, plain JSON types.

    Keys: ``bridged`` (count), ``longest_bridged_s``, ``longest_bridged_samples`` (in
    median sample times), ``split`` (gaps too long to bridge), ``bridge_limit_s``
    (the shortest limit over the series), ``rule`` (in words).
    """
    pieces = list(pieces)
    n = sum(len(p.bridged) for p in pieces)
    longest, samples = 0.0, 0.0
    for p in pieces:
        if len(p.bridged_s):
            k = int(np.argmax(p.bridged_s))
            if p.bridged_s[k] > longest:
                longest, samples = float(p.bridged_s[k]), float(p.bridged_s[k] / p.dt)
    limits = [p.limit for p in pieces if np.isfinite(p.limit)]
    return {'bridged': int(n), 'longest_bridged_s': longest,
            'longest_bridged_samples': samples,
            'split': int(sum(p.split for p in pieces)),
            'bridge_limit_s': float(min(limits)) if limits else None,
            'rule': f'a step longer than {GAP:g} median sample times is a gap; it is bridged '
                    f'(interpolated, samples around it left out of fits) when at most '
                    f'{BRIDGE_SAMPLES:g} median sample times and at most {BRIDGE_FRACTION:g} x '
                    'the motion time scale P90(|qd|)/P90(|qdd|), else it splits the data'}
