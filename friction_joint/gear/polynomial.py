# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Exact bounds of a polynomial on an interval (the physical-range check of a gear).

A polynomial p (coefficients of powers 0..n) takes its minimum on [lo, hi] at
an end point or at a zero of p'.  :func:`interval_minimum` evaluates p at
both ends and at the real part of every root of p' inside the interval (a
superset of the critical points, so nothing is missed between sample points);
:func:`polynomial_violation` also splits the interval at the roots of p to
report the first stretch, from ``lo`` up, where p has the wrong sign.
"""
import numpy as np
from numpy.polynomial import polynomial as _poly
import numpy.typing as npt

__all__ = ['interval_minimum', 'polynomial_violation']


def _roots_in(coef: npt.ArrayLike, lo: float, hi: float, *,
              real_only: bool = False) -> npt.NDArray[np.float64]:
    """Real parts of the roots of ``coef`` in [lo, hi] (``real_only``: nearly real roots)."""
    coef = np.trim_zeros(np.asarray(coef, dtype=float), 'b')
    if len(coef) < 2:
        return np.empty(0)
    with np.errstate(all='ignore'):
        roots = _poly.polyroots(coef)
    if real_only:
        roots = roots[np.abs(roots.imag) <= 1e-7 * np.maximum(1.0, np.abs(roots.real))]
    x = roots.real[np.isfinite(roots.real)]
    return np.sort(x[(x >= lo) & (x <= hi)])


def interval_minimum(coef: npt.ArrayLike, lo: float, hi: float) -> tuple[float, float]:
    """
    Return ``(value, x)``: the minimum of the polynomial on [lo, hi] and where it is taken.

    Parameters
    ----------
    coef : sequence of float
        Coefficients of powers 0..n.
    lo, hi : float
        The interval, lo <= hi.

    Returns
    -------
    (float, float)
        The minimum value and the lowest x at which it is taken; NaN (an
        overflowing polynomial) counts as the minimum.

    """
    coef = np.asarray(coef, dtype=float)
    crit = _roots_in(_poly.polyder(coef), lo, hi) if len(coef) > 1 else np.empty(0)
    x = np.unique(np.concatenate([[lo, hi], crit]))
    with np.errstate(all='ignore'):
        v = _poly.polyval(x, coef)
    nan = np.flatnonzero(np.isnan(v))
    i = int(nan[0]) if len(nan) else int(np.argmin(v))
    return float(v[i]), float(x[i])


def polynomial_violation(coef: npt.ArrayLike, lo: float, hi: float,
                         strict: bool = False) -> tuple[float, float] | None:
    """
    Return ``(value, x)`` where the polynomial leaves p >= 0 (p > 0) on [lo, hi], else None.

    Parameters
    ----------
    coef : sequence of float
        Coefficients of powers 0..n.
    lo, hi : float
        The interval, lo <= hi.
    strict : bool
        Require p > 0 (a zero is a violation) instead of p >= 0.

    Returns
    -------
    (float, float) or None
        The minimum of the first stretch (between roots of p, from ``lo`` up)
        where p has the wrong sign, and where it is taken; None if there is none.

    """
    def bad(v: float) -> bool:
        return not (v > 0.0 if strict else v >= 0.0)

    coef = np.asarray(coef, dtype=float)
    value, x = interval_minimum(coef, lo, hi)
    if not bad(value):
        return None
    roots = _roots_in(coef, lo, hi, real_only=True)
    edges = np.unique(np.concatenate([[lo, hi], roots]))
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        with np.errstate(all='ignore'):
            mid = float(_poly.polyval(0.5 * (a + b), coef))
        if bad(mid):
            return interval_minimum(coef, a, b)
    return value, x                   # a zero touched (strict), or at an end point
