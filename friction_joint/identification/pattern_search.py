# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Bounded generalized pattern search in log space, evaluating a batch of points per poll.

Used by step 3 of the identification (:mod:`friction_joint.identification.presliding`):
scipy has no derivative-free bounded search that evaluates the poll points as
one batch, and the objective (a batch of LuGre/GMS simulations) is cheapest
evaluated that way.
"""
from __future__ import annotations

from collections.abc import Callable
import dataclasses
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import FloatArray
from ..results import json_clean

__all__ = ['PatternSearchResult', 'pattern_search']


@dataclasses.dataclass
class PatternSearchResult:
    """
    Result of :func:`pattern_search`.

    Attributes
    ----------
    x : ndarray
        Best point found.
    fun : float
        Objective at ``x``.
    nit : int
        Iterations (polls).
    nfev : int
        Points evaluated.
    ncalls : int
        Calls of the (batched) objective.
    step : float
        Final step (mesh size).
    success : bool
        True when the step fell below ``min_step``; False when an evaluation
        or iteration limit stopped the search.
    message : str

    """

    x: FloatArray
    fun: float
    nit: int
    nfev: int
    ncalls: int
    step: float
    success: bool
    message: str

    def to_dict(self) -> dict[str, Any]:
        """Return the result as plain JSON types."""
        return cast('dict[str, Any]', json_clean(dataclasses.asdict(self)))


def pattern_search(fun: Callable[[FloatArray], ArrayLike], x0: ArrayLike,
                   lower: ArrayLike, upper: ArrayLike, *, step: float = 0.5,
                   min_step: float = 1e-3, max_step: float | None = None, expand: float = 2.0,
                   contract: float = 0.5, scale: ArrayLike | None = None, max_iter: int = 1000,
                   max_evals: int = 20000) -> PatternSearchResult:
    """
    Minimise ``fun`` over a box by generalized (compass) pattern search.

    Parameters
    ----------
    fun : callable
        ``fun(X) -> f``: X of shape (m, n), returns m objective values.  All
        poll points of an iteration are passed in one call (batched).
    x0 : array_like, (n,)
        Start; projected onto the box.
    lower, upper : array_like, (n,)
        Bounds (finite, lower < upper).
    step : float
        Initial step (in units of ``scale``).
    min_step : float
        Stop when the step falls below this.
    max_step : float, optional
        Cap of the step when expanding (default: 4 * ``step``).
    expand, contract : float
        Step factors after a successful and an unsuccessful poll
        (expand >= 1 > contract > 0).
    scale : array_like, (n,), optional
        Per-coordinate step scale: the poll points are x +- step * scale_i e_i.
    max_iter, max_evals : int
        Limits on polls and evaluated points.

    Returns
    -------
    PatternSearchResult

    Notes
    -----
    A complete poll of the 2n coordinate directions is evaluated each
    iteration and the best improving point is taken (the batch costs little
    more than one point).  Poll points outside the box are projected onto it
    and dropped when the projection is the current point, so every point
    evaluated is feasible.

    """
    x = np.asarray(x0, dtype=float).ravel()
    n = x.size
    lo = np.broadcast_to(np.asarray(lower, dtype=float), (n,))
    hi = np.broadcast_to(np.asarray(upper, dtype=float), (n,))
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo < hi)):
        raise ValueError(f'bounds must be finite with lower < upper, got {lo}, {hi}')
    if not (step > 0 and min_step > 0 and expand >= 1.0 and 0.0 < contract < 1.0):
        raise ValueError('need step > 0, min_step > 0, expand >= 1, 0 < contract < 1')
    sc = np.ones(n) if scale is None else np.broadcast_to(np.asarray(scale, float), (n,))
    max_step = 4.0 * step if max_step is None else float(max_step)
    x = np.clip(x, lo, hi)
    directions = np.vstack([np.eye(n), -np.eye(n)])

    def poll_points(center: FloatArray, delta: float) -> FloatArray:
        pts = np.clip(center + delta * sc * directions, lo, hi)
        keep = np.any(pts != center, axis=1)
        return pts[keep]

    def evaluate(points: FloatArray) -> FloatArray:
        vals = np.asarray(fun(points), dtype=float).reshape(-1)
        if vals.shape[0] != points.shape[0]:
            raise ValueError(f'objective returned {vals.shape[0]} values '
                             f'for {points.shape[0]} points')
        return np.where(np.isfinite(vals), vals, np.inf)

    delta = float(step)
    pts = poll_points(x, delta)
    vals = evaluate(np.vstack([x[None, :], pts]))        # start and first poll together
    fx, vals = vals[0], vals[1:]
    nfev, ncalls, nit = 1 + len(pts), 1, 0
    success, message = False, ''
    while True:
        nit += 1
        if len(vals) and vals.min() < fx:
            i = int(np.argmin(vals))
            x, fx = pts[i].copy(), float(vals[i])
            delta = min(delta * expand, max_step)
        else:
            delta *= contract
        if delta < min_step:
            success, message = True, f'step {delta:.3g} below min_step {min_step:g}'
            break
        if nit >= max_iter:
            message = f'iteration limit {max_iter} reached (step {delta:.3g})'
            break
        pts = poll_points(x, delta)
        if nfev + len(pts) > max_evals:
            message = f'evaluation limit {max_evals} reached (step {delta:.3g})'
            break
        vals = evaluate(pts) if len(pts) else np.empty(0)
        nfev += len(pts)
        ncalls += 1 if len(pts) else 0
    return PatternSearchResult(x, float(fx), nit, nfev, ncalls, delta, success, message)
