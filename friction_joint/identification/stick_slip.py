# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Stick-slip: constant-speed windows the joint did not follow steadily.

:func:`stuck_and_slipped` says whether a window stuck and slipped (sub-windows of about eight
position steps of travel: sliding steadily each travels about as far, sticking and
slipping some barely move while others jump); :func:`stick_slip_scan` looks for such
windows outside the plateaus where ``/joint_command`` asked for a constant speed;
:func:`stick_slip_summary` says it in words.  The plateau detection
(:mod:`friction_joint.identification.plateaus`) leaves such windows out and keeps them
in ``Plateaus.stick_slip``.
"""
from __future__ import annotations

from collections.abc import Iterator
from typing import Protocol

import numpy as np

from ._arrays import FloatArray

__all__ = ['position_resolution', 'stuck_and_slipped', 'stick_slip_scan', 'stick_slip_summary']


def position_resolution(q: FloatArray) -> float:
    """Return the position's resolution: a low quantile of its non-zero steps (0: none)."""
    d = np.abs(np.diff(q))
    d = d[d > 0]
    if len(d) < 10:
        return 0.0
    return float(np.quantile(d, 0.05))


def stuck_and_slipped(t: FloatArray, q: FloatArray, tick: float,
                      parts: int | None = None) -> dict[str, float] | None:
    """
    Say whether a constant-speed window stuck and slipped; None when it slid steadily.

    The window is cut into ``parts`` sub-windows (default: as many as leave each about
    eight position steps of travel, 8 to 64); sliding steadily, each travels about the
    same distance (within a quarter of it plus two position steps); sticking and
    slipping, some barely move while others jump.  Returns ``{'speed', 'stuck'}``.
    """
    n = len(q)
    if parts is None:
        travel_steps = abs(q[-1] - q[0]) / tick if tick > 0 else np.inf
        parts = int(np.clip(travel_steps / 8.0, 8, 64))
    if n < 4 * parts:
        parts = n // 4
    if parts < 4:
        return None
    edges = np.linspace(0, n - 1, parts + 1).astype(int)
    travel = np.diff(q[edges])
    total = q[-1] - q[0]
    mean = total / parts
    if mean == 0.0:
        return None
    spread = float(np.std(travel))
    if spread <= 0.25 * abs(mean) + 2.0 * tick:
        return None
    still = np.abs(travel) < 0.25 * abs(mean)
    if still.sum() < 2 or not still[1:-1].any():     # a start or end transient is not it
        return None
    stuck = float(np.mean(still))
    return {'speed': float(abs(total) / (t[-1] - t[0])), 'stuck': stuck}


def stick_slip_scan(t: FloatArray, q: FloatArray,
                    command: FloatArray | None, tick: float,
                    segs: list[tuple[int, int]], opt: dict[str, float]
                    ) -> Iterator[tuple[int, int, dict[str, float]]]:
    """
    Windows outside the plateaus where a constant speed was commanded and not followed.

    Windows of four times the shortest plateau; a window counts when the commanded
    velocity stays within 5 % of its mean, at least ``v_floor``, the position travels
    one way, and :func:`stuck_and_slipped` finds it stuck and slipped; neighbouring windows of
    one sign merge.  Yields ``(i0, i1, info)``; nothing without a command.
    """
    n = len(t)
    if n < 10 or command is None:
        return
    dt = float(np.median(np.diff(t)))
    m = max(int(round(4.0 * opt['min_duration'] / dt)), 40)
    used = np.zeros(n, dtype=bool)
    for a, b in segs:
        used[a:b] = True
    found: list[tuple[int, int, float, float]] = []
    for a in range(0, n - m + 1, m):
        b = a + m
        if used[a:b].any():
            continue
        cmd = command[a:b]
        c_mean = float(np.mean(cmd))
        if abs(c_mean) < opt['v_floor'] or np.max(np.abs(cmd - c_mean)) > 0.05 * abs(c_mean):
            continue
        travel = q[b - 1] - q[a]
        v = travel / (t[b - 1] - t[a])
        step = np.diff(q[a:b])
        if abs(v) < opt['v_floor'] or np.any(np.sign(step) == -np.sign(travel)) and \
                np.sum(np.abs(step[np.sign(step) == -np.sign(travel)])) > 0.1 * abs(travel):
            continue
        info = stuck_and_slipped(t[a:b], q[a:b], tick)
        if info is None:
            continue
        if found and found[-1][1] == a and np.sign(found[-1][3]) == np.sign(travel):
            i0, _, stuck, tr = found[-1]
            found[-1] = (i0, b, max(stuck, info['stuck']), tr + travel)
        else:
            found.append((a, b, info['stuck'], travel))
    for i0, i1, stuck, travel in found:
        yield i0, i1, {'speed': float(abs(travel) / (t[i1 - 1] - t[i0])), 'stuck': stuck}


class _WithStickSlip(Protocol):
    """What :func:`stick_slip_summary` reads of a ``Plateaus``."""

    @property
    def stick_slip(self) -> tuple[dict[str, float], ...]:
        """Return the stick-slip windows."""

    @property
    def qd(self) -> FloatArray:
        """Return the plateaus' mean velocities."""


def stick_slip_summary(plateaus: _WithStickSlip) -> str | None:
    """
    Say in words which constant-speed commands stuck and slipped (None: none did).

    Parameters
    ----------
    plateaus : Plateaus
        The plateaus (their ``stick_slip`` and speeds).

    Returns
    -------
    str or None

    """
    ss = plateaus.stick_slip
    if not ss:
        return None
    speeds = sorted(x['speed'] for x in ss)
    steady = np.abs(plateaus.qd)
    slow = float(steady.min()) if len(steady) else None
    top = max(speeds)
    text = (f'{len(ss)} constant-speed window(s) stuck and slipped (mean speeds '
            f'{speeds[0]:.3g}..{top:.3g} rad/s, the position stuck in up to '
            f'{100 * max(x["stuck"] for x in ss):.0f} % of each): left out of the fit; ')
    if slow is not None and slow > top:
        text += (f'the joint slides steadily from {slow:.3g} rad/s up, not at or below '
                 f'{top:.3g} rad/s in these recordings (stiffen the speed loop or accept the '
                 'slowest plateau as the limit of the curve)')
    else:
        text += ('slower plateaus elsewhere did slide steadily (the stick-slip depends on the '
                 'load, temperature or controller there)')
    return text
