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
outside that span (a scale-free rule: about 0.3 rad of stroke).  A linear
device (imported with a radius: its "angle" is a length over a radius) has no
gravity candidate.

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
import json
import math
import os

import numpy as np

from ..bag.gate import read_metadata
from ..exceptions import RecordingError

__all__ = ['MIN_CURVATURE', 'gravity_untestable', 'linear_device', 'corrected_lever']

#: least share of the energy of a gravity column outside the span of the base, 1 and q
MIN_CURVATURE = 2e-3


def linear_device(paths):
    """Return whether any recording was imported as a linear device (with a radius)."""
    for path in paths:
        meta = os.path.join(os.fspath(path), 'metadata.yaml')
        if not os.path.isfile(meta):
            continue
        try:                                      # through the input gate: no FIFO, no device
            info = read_metadata(meta)
        except RecordingError:
            continue                              # the reader has named it already
        custom = info.get('custom_data') or {}
        text = custom.get('friction_joint.import') if isinstance(custom, dict) else None
        if not isinstance(text, str) or not text:
            continue
        try:
            if json.loads(text).get('radius_m') is not None:
                return True
        except (ValueError, AttributeError):
            continue
    return False


def gravity_untestable(data, base_columns, linear=False):
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
    g = np.column_stack([np.sin(q), np.cos(q)])
    span = np.column_stack([base_columns, np.ones_like(q), q])
    u, sv, _ = np.linalg.svd(span / np.maximum(np.linalg.norm(span, axis=0), 1e-300),
                             full_matrices=False)
    u = u[:, sv > 1e-10 * sv[0]]
    rest = g - u @ (u.T @ g)
    # the better-determined combination of sin and cos: the largest singular value of the rest
    share = float(np.linalg.svd(rest, compute_uv=False)[0] ** 2 / max(len(q), 1))
    if share < MIN_CURVATURE:
        stroke = float(np.ptp(q))
        return (f'the joint covers {stroke:.3g} rad: over so short a stroke m g l sin(q - q0) '
                f'is a constant and a slope (its curvature keeps {share:.2g} of its energy, '
                f'at least {MIN_CURVATURE:g} needed)')
    return None


def corrected_lever(base, coef):
    """
    Return the ``lever`` section of the extended gear and its gravity amplitude change.

    ``coef`` is the gravity part of a fit: ``{'sin': a, 'cos': b}`` (Nm).
    """
    lever = base.section('lever')
    q0 = float(lever.get('angle_offset', 0.0))
    mgl = lever['mass'] * lever['gravity'] * lever['length']
    big_a = mgl * math.cos(q0) + coef['sin']
    big_b = coef['cos'] - mgl * math.sin(q0)
    amp = math.hypot(big_a, big_b)
    q1 = math.atan2(-big_b, big_a) if amp > 0 else 0.0
    length = lever['length'] if lever['length'] > 0 else 1.0
    new = {'mass': amp / (lever['gravity'] * length), 'length': length, 'angle_offset': q1}
    return new, {'mgl_base': mgl, 'mgl': amp, 'angle_offset_base': q0, 'angle_offset': q1}
