# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
What the experiments and their figures both use: the models compared, labels, keys, windows.

Kept apart from :mod:`._common` (the result type, checks, the closed loop), which
draws its figures through :mod:`.plots`: the figures read these names from here.
"""
import numpy as np

__all__ = ['MODELS', 'MODEL_LABELS', 'json_key', 'clip_window', 'reversal_window']

#: friction feed-forward / observer models compared
MODELS = ('none', 'lugre', 'gms')


def json_key(x):
    """JSON key of a temperature or amplitude: '27', '0.4'."""
    return f'{float(x):g}'


#: display name of each friction model in figures and progress messages
MODEL_LABELS = {'none': 'no friction model', 'lugre': 'LuGre', 'gms': 'GMS'}


def clip_window(t, t0, t1):
    """Shift ``(t0, t1)`` to lie inside the time range of ``t`` (width kept if possible)."""
    if t0 < t[0]:
        t0, t1 = t[0], min(t1 + t[0] - t0, t[-1])
    if t1 > t[-1]:
        t0, t1 = max(t0 - (t1 - t[-1]), t[0]), t[-1]
    return float(t0), float(t1)


def reversal_window(t, v, half_width, moving=0.05):
    """
    Zoom window ``(t0, t1)`` on the first velocity reversal of ``v``, or None.

    Samples with |v| below ``moving`` times the peak |v| count as standing
    still (stiction); the window is centred on the first moving sample after
    the first change of sign -- the break-away into the new direction --
    ``half_width`` either side.  None if ``v`` never reverses.
    """
    t, v = np.asarray(t), np.asarray(v)
    peak = float(np.max(np.abs(v))) if v.size else 0.0
    mv = np.flatnonzero(np.abs(v) > moving * peak) if peak > 0.0 else np.array([], int)
    sign = np.sign(v[mv])
    flips = np.flatnonzero(sign[1:] != sign[:-1])
    if flips.size == 0:
        return None
    k = mv[flips[0] + 1]
    return clip_window(t, t[k] - half_width, t[k] + half_width)
