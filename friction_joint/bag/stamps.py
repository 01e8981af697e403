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
Header stamps of one topic, in bag order: what is accepted and what is an error.

A bag holds messages in receive-time order; their header stamps say when each
sample was taken.  Per topic (and joint) they must run forward.  The rules
scale with the topic's own sample time ``dt`` (the median forward step of the
stamps in bag order):

* **gaps** of any length are fine (the consumers cut the data into pieces
  there);
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
"""
import numpy as np

from .topics import NS
from ..exceptions import RecordingError

__all__ = ['LATE', 'HOLE', 'stamp_order']

#: a late message may lag at most this many sample times behind the newest stamp
LATE = 100
#: a late message must fill a hole this many sample times wide (its neighbours' spacing)
HOLE = 1.5


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
