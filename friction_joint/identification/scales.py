# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Scale check of identified parameters against the structure file: a column in other units.

A log exported in ms, deg, deg/s or mNm and imported without its units is read as SI:
the identification is then right for the numbers it was given, and its parameters are
off by the factor of the unit (a time in ms read as s makes every speed 1000 times
smaller and F_v 1000 times larger; the data cannot tell).  The structure file is the
user's own prior for the joint: an identified coefficient more than :data:`SCALE_FACTOR`
times above or below the structure file's value is reported with the readings that
would explain it and the way to import the log again.  Nothing is refused: a joint far
from its structure file is possible, and the check only says what to look at.
"""
from __future__ import annotations

import math

__all__ = ['SCALE_FACTOR', 'scale_lines']

#: an identified coefficient this many times above or below the structure file's is reported
SCALE_FACTOR = 100.0
#: (coefficient, unit, the columns whose unit would scale it)
_CHECKED = (('fc', 'Nm', 'the torque (mNm read as Nm)'),
            ('fs', 'Nm', 'the torque (mNm read as Nm)'),
            ('fv', 'Nm s/rad', 'the time (ms read as s), the position (deg read as rad) or '
                               'the velocity (deg/s read as rad/s)'),
            ('vs', 'rad/s', 'the time (ms read as s), the position (deg read as rad) or '
                            'the velocity (deg/s read as rad/s)'))


def scale_lines(gear: object, structure: object) -> list[str]:
    """
    Return one line per identified coefficient far from the structure file's value.

    Parameters
    ----------
    gear : GearParams
        The identified gear.
    structure : GearParams
        The structure file the identification started from.

    Returns
    -------
    list of str
        Empty when every checked coefficient (the constant term of F_c, F_s, F_v, v_s)
        is within :data:`SCALE_FACTOR` of the structure file's, or either is zero or absent.

    """
    lines = []
    for key, unit, columns in _CHECKED:
        got = getattr(getattr(gear, 'friction', None), key, None)
        prior = getattr(getattr(structure, 'friction', None), key, None)
        if not got or not prior:
            continue
        a, b = float(got[0]), float(prior[0])
        if not (math.isfinite(a) and math.isfinite(b)) or a <= 0.0 or b <= 0.0:
            continue
        ratio = a / b
        if 1.0 / SCALE_FACTOR <= ratio <= SCALE_FACTOR:
            continue
        lines.append(f"{key} = {a:.4g} {unit} is {ratio:.3g} x the structure file's "
                     f'{b:.4g}: if {columns} was logged in other units, import the log '
                     'again with them (e.g. --time COL:ms, --position COL:deg, '
                     '--torque COL:mNm) and identify that recording')
    return lines
