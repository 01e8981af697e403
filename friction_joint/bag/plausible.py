# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Physically absurd samples (a flipped bit, a garbage value) found before they reach a fit.

The rule is scale-free: each signal is measured against its own spread.  For
a signal of ``n`` samples with median ``m``, the *robust spread* ``S`` is the
``(k+1)``-th largest ``|x - m|`` with ``k = max(3, n/1000)`` (so up to ``k``
absurd samples do not set the scale, while any real excursion lasting more
than ``k`` samples does), and at least ``1e-3 |m|``.  A sample is absurd when

    |x - m| > FACTOR * S        (FACTOR = 1e6)

A velocity is measured against the position too, which is a physical anchor
and allows a tighter factor: a velocity sample is absurd when

    |qd - m| > VELOCITY_FACTOR * max(S, R)      (VELOCITY_FACTOR = 1e3)

with ``R`` the largest ``|dq/dt|`` of the position's differences within
:data:`RATE_WINDOW` samples of it.  A quick move of a joint that is otherwise at
rest is plausible where the position moves with it (``R`` large), a velocity
orders of magnitude beyond both the position's rate and its own spread is
not (a velocity on the motor side of a 1:160 gear is still accepted).

Whatever its spread, a sample beyond :data:`MAX_MAGNITUDE` (1e12 in the signal's
SI unit: N m, rad, rad/s; a temperature has its own range) is absurd too: a
signal scaled as a whole by a corrupt unit or a flipped exponent bit (a torque
of 1e300 N m) has a spread of its own size, and a fit's squares of it overflow.

Generous on purpose: only values that no sensor, unit or excitation explains
are rejected (a float64 with a flipped exponent bit is off by a factor of
2^32 or more).  Signals with fewer than ``2k + 1`` samples, or with ``S = 0``
(constant apart from at most ``k`` samples), are not judged.
"""
from __future__ import annotations

from functools import partial
import math
from typing import TYPE_CHECKING

import numpy as np

from .blockwise import BLOCK
from ..exceptions import RecordingError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from .topics import Recording

__all__ = ['FACTOR', 'VELOCITY_FACTOR', 'MAX_MAGNITUDE', 'RATE_WINDOW', 'implausible',
           'check_values', 'check_samples']

#: a sample further than this many robust spreads from the median is absurd
FACTOR = 1e6
#: a velocity further than this many times max(its spread, the position's rate) is absurd
VELOCITY_FACTOR = 1e3
#: no joint, sensor or unit reaches this magnitude in SI units (a fit squares the samples)
MAX_MAGNITUDE = 1e12
#: samples either side over which a velocity is compared with the position's differences
RATE_WINDOW = 5
#: samples judged at a time (the temporaries of a check are this long, but for one scratch
#: copy of the signal)
_FRACTION = 1e-3
_MIN_K = 3
_REL_FLOOR = 1e-3

_UNITS = {'q': 'rad', 'qd': 'rad/s', 'effort': 'N m', 'xi': 'degC', 'tau': 'N m',
          'q_d': 'rad', 'qd_d': 'rad/s', 'tau_ext': 'N m'}


def _rate(t, q, a, b, origin=0.0):
    """
    Return the largest |dq/dt| within RATE_WINDOW samples of samples ``a:b`` (of ``t - origin``).

    Computed from the samples ``a - RATE_WINDOW - 1 .. b + RATE_WINDOW`` only, value for value as
    over the whole signal (a window of the position's differences either side of each sample).
    """
    n = len(q)
    lo, hi = max(0, a - RATE_WINDOW), min(n, b + RATE_WINDOW)
    k0, k1 = max(0, lo - 1), min(n - 1, hi)         # the differences needed: [k0, k1)
    tt = t[k0:k1 + 1] - origin
    dt = np.diff(tt)
    fd = np.zeros(len(dt))
    ok = dt > 0
    fd[ok] = np.abs(np.diff(q[k0:k1 + 1])[ok] / dt[ok])
    ext = np.zeros(hi - lo + 1)                     # differences lo - 1 .. hi - 1, 0 outside
    ext[k0 - lo + 1:k1 - lo + 1] = fd
    both = np.maximum(ext[:-1], ext[1:])            # steps either side of a sample
    padded = np.pad(both, RATE_WINDOW, mode='edge')
    rate = np.lib.stride_tricks.sliding_window_view(padded, 2 * RATE_WINDOW + 1).max(axis=1)
    return rate[a - lo:b - lo]


def implausible(x, reference=None, factor=FACTOR):
    """
    Find the absurd samples of one signal (see the module docstring).

    Parameters
    ----------
    x : array_like
        The samples (NaN are ignored).
    reference : array_like, optional
        Per sample, a further scale the deviation may reach ``factor`` times (for a
        velocity: the position's rate of change around it).
    factor : float
        How many scales away a sample is absurd (default :data:`FACTOR`).

    Returns
    -------
    bad : numpy.ndarray of int
        Indices of the absurd samples, worst first.
    median, spread : float
        The signal's median and robust spread (NaN when it is not judged).

    """
    x = np.asarray(x, dtype=float)
    if reference is None:
        return _implausible(x, None, factor)
    reference = np.asarray(reference, dtype=float)
    return _implausible(x, partial(_slice, reference), factor)


def _slice(x, a, b):
    return x[a:b]


def _implausible(x, ref, factor):
    """
    :func:`implausible` with the reference given by ``ref(a, b)`` (its samples ``a:b``).

    Memory: one scratch copy of ``x`` (its median and spread, found in place), the rest
    :data:`BLOCK` samples at a time (a signal with non-finite samples: copies of the
    finite ones and of the reference).
    """
    fin = None
    if not np.isfinite(x).all():
        fin = np.flatnonzero(np.isfinite(x))
        if ref is not None:
            ref = partial(_slice, ref(0, len(x))[fin])
    v = x if fin is None else x[fin]
    n = len(v)
    k = max(_MIN_K, int(math.ceil(_FRACTION * n)))
    none = np.zeros(0, dtype=np.int64)
    if n < 2 * k + 1:
        return none, math.nan, math.nan
    scratch = v.copy()
    med = float(np.median(scratch, overwrite_input=True))
    np.subtract(v, med, out=scratch)
    np.abs(scratch, out=scratch)
    scratch.partition(n - k - 1)
    spread = max(float(scratch[n - k - 1]), _REL_FLOOR * abs(med))
    del scratch
    hits, scores = [], []
    for a in range(0, n, BLOCK):
        b = min(n, a + BLOCK)
        dev = np.abs(v[a:b] - med)
        limit = np.full(b - a, spread)
        if ref is not None:
            limit = np.maximum(limit, ref(a, b))
        bad = np.flatnonzero((dev > factor * limit) & (limit > 0))
        if len(bad):
            hits.append(bad + a)
            scores.append(-dev[bad] / limit[bad])
    if not hits:
        return none, med, spread
    bad = np.concatenate(hits)[np.argsort(np.concatenate(scores), kind='stable')]
    return (bad if fin is None else fin[bad]), med, spread


def check_samples(label: str, t: ArrayLike, fields: dict[str, ArrayLike], *,
                  position: tuple[str, str] | None = None, origin: float = 0.0) -> None:
    """
    Raise on the first absurd sample of some signals sampled at ``t``.

    Parameters
    ----------
    label : str
        Start of the error message (the recording and topic, or the data's name).
    t : array_like
        Sample times (s).
    fields : dict
        Field name -> samples.
    position : tuple of str, optional
        ``(position field, velocity field)``: the velocity is also measured against the
        position's differences.
    origin : float
        Time (s) subtracted from ``t`` (the times are ``t - origin``, computed a block at
        a time rather than as a copy).

    Raises
    ------
    RecordingError
        Naming ``label``, the field, the value, its time and sample index, and the scale it
        was judged against.

    Notes
    -----
    Memory beyond the arrays given: one scratch copy of a field at a time and
    :data:`BLOCK`-sized temporaries.

    """
    t = np.asarray(t, dtype=float)
    velocity, q = None, None
    if position is not None and position[0] in fields and position[1] in fields:
        velocity = position[1]
        q = np.asarray(fields[position[0]], dtype=float)

    def rate(a, b):
        return _rate(t, q, a, b, origin)
    for name, x in fields.items():
        x = np.asarray(x, dtype=float)
        if name != 'xi':                # a temperature has its range (consistency.py)
            _check_magnitude(label, name, t, x, origin)
        factor = FACTOR if name != velocity else VELOCITY_FACTOR
        bad, med, spread = _implausible(x, rate if name == velocity else None, factor)
        if not len(bad):
            continue
        i = int(bad[0])
        value = float(x[i])
        unit = _UNITS.get(name, '')
        also = ''
        if name == velocity:
            also = (f" and from the position's rate of change around then "
                    f'({rate(i, i + 1)[0]:.3g} {unit} at most over {2 * RATE_WINDOW + 1} samples)')
        raise RecordingError(
            f'{label}: implausible {name} {value:.6g} {unit} at t = {t[i] - origin:.6f} s '
            f'(sample {i}{f", {len(bad)} such samples" if len(bad) > 1 else ""}): more than '
            f"{factor:.0e} times the signal's robust spread ({spread:.3g} {unit}) from its "
            f'median ({med:.3g} {unit}){also}; a corrupt value (a flipped bit?)')


def _check_magnitude(label, name, t, x, origin):
    """Raise on the first sample of ``x`` beyond :data:`MAX_MAGNITUDE` (block by block)."""
    count, first = 0, None
    for a in range(0, len(x), BLOCK):
        bad = np.flatnonzero(np.abs(x[a:a + BLOCK]) > MAX_MAGNITUDE)
        if len(bad):
            count += len(bad)
            first = int(bad[0]) + a if first is None else first
    if first is None:
        return
    unit = _UNITS.get(name, '')
    raise RecordingError(
        f'{label}: implausible {name} {float(x[first]):.6g} {unit} at '
        f't = {t[first] - origin:.6f} s (sample {first}'
        f'{f", {count} such samples" if count > 1 else ""}): beyond {MAX_MAGNITUDE:.0e} '
        f'{unit}, which no joint, sensor or unit reaches; a corrupt value or a wrong unit')


def check_values(recording: Recording) -> None:
    """
    Raise on the first absurd sample of a :class:`~friction_joint.bag.Recording`.

    Checks ``/joint_states`` (q, qd against the position, effort), ``/joint_temperature``
    (xi), ``/link_torque`` (tau), ``/joint_command`` (effort, q_d, qd_d) and
    ``/external_torque`` (effort).

    Parameters
    ----------
    recording : Recording
        The recording.

    Raises
    ------
    RecordingError
        Naming the recording file, topic, field, value and time.

    """
    picks = {'/joint_states': ('q', 'qd', 'effort'), '/joint_temperature': ('xi',),
             '/link_torque': ('tau',), '/joint_command': ('effort', 'q_d', 'qd_d'),
             '/external_torque': ('effort',)}
    for topic, data in recording.series().items():
        check_samples(f'{recording.path}: {topic}', data.t,
                      {f: getattr(data, f) for f in picks[topic]},
                      position=('q', 'qd') if topic == '/joint_states' else None)
