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
:data:`WINDOW` samples of it.  A quick move of a joint that is otherwise at
rest is plausible where the position moves with it (``R`` large), a velocity
orders of magnitude beyond both the position's rate and its own spread is
not (a velocity on the motor side of a 1:160 gear is still accepted).

Generous on purpose: only values that no sensor, unit or excitation explains
are rejected (a float64 with a flipped exponent bit is off by a factor of
2^32 or more).  Signals with fewer than ``2k + 1`` samples, or with ``S = 0``
(constant apart from at most ``k`` samples), are not judged.
"""
import math

import numpy as np

from ..exceptions import RecordingError

__all__ = ['FACTOR', 'VELOCITY_FACTOR', 'WINDOW', 'implausible', 'check_values',
           'check_samples']

#: a sample further than this many robust spreads from the median is absurd
FACTOR = 1e6
#: a velocity further than this many times max(its spread, the position's rate) is absurd
VELOCITY_FACTOR = 1e3
#: samples either side over which a velocity is compared with the position's differences
WINDOW = 5
_FRACTION = 1e-3
_MIN_K = 3
_REL_FLOOR = 1e-3

_UNITS = {'q': 'rad', 'qd': 'rad/s', 'effort': 'N m', 'xi': 'degC', 'tau': 'N m',
          'q_d': 'rad', 'qd_d': 'rad/s', 'tau_ext': 'N m'}


def _position_rate(t, q):
    """Largest |dq/dt| of the position's differences within WINDOW samples of each sample."""
    dt = np.diff(t)
    rate = np.zeros(len(q))
    ok = dt > 0
    fd = np.zeros(len(dt))
    fd[ok] = np.abs(np.diff(q)[ok] / dt[ok])
    both = np.maximum(np.r_[0.0, fd], np.r_[fd, 0.0])        # steps either side of a sample
    padded = np.pad(both, WINDOW, mode='edge')
    rate[:] = np.lib.stride_tricks.sliding_window_view(padded, 2 * WINDOW + 1).max(axis=1)
    return rate


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
    fin = np.flatnonzero(np.isfinite(x))
    n = len(fin)
    k = max(_MIN_K, int(math.ceil(_FRACTION * n)))
    none = np.zeros(0, dtype=np.int64)
    if n < 2 * k + 1:
        return none, math.nan, math.nan
    v = x[fin]
    med = float(np.median(v))
    dev = np.abs(v - med)
    spread = max(float(np.partition(dev, n - k - 1)[n - k - 1]), _REL_FLOOR * abs(med))
    limit = np.full(n, spread)
    if reference is not None:
        limit = np.maximum(limit, np.asarray(reference, dtype=float)[fin])
    bad = np.flatnonzero((dev > factor * limit) & (limit > 0))
    if not len(bad):
        return none, med, spread
    bad = bad[np.argsort(-dev[bad] / limit[bad], kind='stable')]
    return fin[bad], med, spread


def check_samples(label, t, fields, position=None):
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

    Raises
    ------
    RecordingError
        Naming ``label``, the field, the value, its time and sample index, and the scale it
        was judged against.

    """
    t = np.asarray(t, dtype=float)
    ref = {}
    if position is not None and position[0] in fields and position[1] in fields:
        ref[position[1]] = _position_rate(t, np.asarray(fields[position[0]], dtype=float))
    for name, x in fields.items():
        factor = FACTOR if name not in ref else VELOCITY_FACTOR
        bad, med, spread = implausible(x, ref.get(name), factor)
        if not len(bad):
            continue
        i = int(bad[0])
        value = float(np.asarray(x, dtype=float)[i])
        unit = _UNITS.get(name, '')
        also = ''
        if name in ref:
            also = (f" and from the position's rate of change around then "
                    f'({ref[name][i]:.3g} {unit} at most over {2 * WINDOW + 1} samples)')
        raise RecordingError(
            f'{label}: implausible {name} {value:.6g} {unit} at t = {t[i]:.6f} s (sample {i}'
            f'{f", {len(bad)} such samples" if len(bad) > 1 else ""}): more than {factor:.0e} '
            f"times the signal's robust spread ({spread:.3g} {unit}) from its median "
            f'({med:.3g} {unit}){also}; a corrupt value (a flipped bit?)')


def check_values(recording):
    """
    Raise on the first absurd sample of a :class:`~friction_joint.bag.Recording`.

    Checks ``/joint_states`` (q, qd against the position, effort), ``/joint_temperature``
    (xi), ``/link_torque`` (tau), ``/joint_command`` (effort, q_d, qd_d) and
    ``/external_torque`` (effort).

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
