# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The per-joint wear test: no wear against a hinge, over time and over travel.

For one joint the reference friction y_k of its recordings (standard errors
s_k) is compared under two models, each on two axes x (days since the
joint's first recording, and accumulated travel):

* **no wear**: ``y_k = a + e_k``;
* **hinge** (wear from an onset c): ``y_k = a + b max(0, x_k - c) + e_k``, b >= 0
  (wear only raises friction), c scanned over a grid between the first
  recording and the fourth-last (at least three recordings after an onset).

The errors are independent normal with variance ``s_k^2 + sigma^2``: sigma^2
is the *extra variance*, what the per-recording standard errors do not cover
(model error, conditions the model does not know), estimated over the whole
fleet by :func:`extra_variance` from the residuals of each recording against
the line through its neighbours (on the travel axis: wear at a constant rate
cancels).  The statistic is the largest drop of the weighted chi^2 from no
wear to a hinge, over onsets and both axes, divided by the hinge fit's
residual chi^2 per degree of freedom (a sup-F statistic: a scale error of the
variances cancels).  Its significance is
calibrated per joint by a **parametric bootstrap under no wear**: ``n_boot``
series drawn from the fitted flat model with the same s_k and sigma^2, scanned
the same way; the p-value is the share of bootstrap statistics at least as
large.  A joint is flagged when ``p < alpha`` (default 0.01, so at most about
1 % false alarms when the errors are as modelled; the benchmark measures it).

A flagged joint's onset, rate and their uncertainties come from the axis with
the larger chi^2 drop; the rate per day comes from the time axis and the rate
per unit travel from the travel axis (each at its best onset, standard error
for that onset, scaled by the residual scatter when it exceeds the assumed
variances).  ``onset_range`` are the onsets whose chi^2 is within one
residual variance of the best (a profile interval).
"""
from __future__ import annotations

from collections.abc import Iterable
import dataclasses
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = ['WEAR_ALPHA', 'BOOTSTRAP', 'MIN_AFTER', 'TrendResult', 'extra_variance', 'trend_test']

#: significance level per joint
WEAR_ALPHA = 0.01
#: bootstrap series per joint
BOOTSTRAP = 999
#: fewest recordings after an onset
MIN_AFTER = 3
#: grid points per interval between recordings
_SUBSTEPS = 4


@dataclasses.dataclass
class TrendResult:
    """
    The wear test of one joint (module docstring).

    Attributes
    ----------
    wear : bool
    p_value, statistic, threshold : float
        Bootstrap p-value, chi^2 drop, the bootstrap's 1 - alpha quantile.
    axis : str
        ``time`` or ``travel``: where the chi^2 drop is larger.
    onset_day, onset_range : float, (float, float)
        Onset in days since the joint's first recording (on ``axis``), profile interval.
    onset_travel : float
        The accumulated travel at the onset.
    rate_per_day, rate_per_day_se, rate_per_travel, rate_per_travel_se : float
        Hinge slopes (friction units per day, per unit travel) and standard errors.
    level, level_se : float
        The no-wear level a (before the onset for the hinge).
    extra_sd : float
        sigma used.
    n : int
        Recordings.
    gain : dict
        Axis -> chi^2 drop.

    """

    wear: bool
    p_value: float
    statistic: float
    threshold: float
    axis: str
    onset_day: float
    onset_range: tuple
    onset_travel: float
    rate_per_day: float
    rate_per_day_se: float
    rate_per_travel: float
    rate_per_travel_se: float
    level: float
    level_se: float
    extra_sd: float
    n: int
    gain: dict

    def to_dict(self) -> dict[str, Any]:
        """Return plain JSON types."""
        return {k: (list(v) if isinstance(v, tuple) else v)
                for k, v in dataclasses.asdict(self).items()}


def extra_variance(series: Iterable[tuple[ArrayLike, ArrayLike, ArrayLike]]) -> float:
    """
    Return the fleet's extra variance sigma^2 from local linear residuals.

    Each inner point of a joint's series is compared with the straight line
    through its two neighbours (on the axis given, e.g. travel):
    ``r_k = y_k - (l y_{k-1} + (1 - l) y_{k+1})``, ``l = (x_{k+1} - x_k) / (x_{k+1} -
    x_{k-1})``, whose variance is ``s_k^2 + l^2 s_{k-1}^2 + (1 - l)^2 s_{k+1}^2`` plus
    ``(1 + l^2 + (1 - l)^2) sigma^2``.  A linear trend (wear at a constant rate) cancels;
    a hinge disturbs one point per joint.

    Parameters
    ----------
    series : iterable of (x, y, se)
        Per joint, in order of x: axis values, values and their standard errors.

    Returns
    -------
    float
        ``max(0, sum (r_k^2 - known_k) / sum (1 + l^2 + (1 - l)^2))`` over the fleet.

    """
    num, den = 0.0, 0.0
    for x, y, se in series:
        x, y, se = (np.asarray(v, float) for v in (x, y, se))
        if len(y) < 3:
            continue
        span = x[2:] - x[:-2]
        lam = np.where(span > 0, (x[2:] - x[1:-1]) / np.where(span > 0, span, 1.0), 0.5)
        r = y[1:-1] - (lam * y[:-2] + (1.0 - lam) * y[2:])
        known = se[1:-1] ** 2 + lam ** 2 * se[:-2] ** 2 + (1.0 - lam) ** 2 * se[2:] ** 2
        num += float(np.sum(r * r - known))
        den += float(np.sum(1.0 + lam ** 2 + (1.0 - lam) ** 2))
    return max(num / den, 0.0) if den else 0.0


def _grid(x):
    """Onset candidates: the recordings up to the MIN_AFTER-th last, and between them."""
    top = len(x) - MIN_AFTER - 1
    if top < 0:
        return np.array([])
    pts = [x[0]]
    for k in range(top):
        pts += list(np.linspace(x[k], x[k + 1], _SUBSTEPS + 1)[1:])
    return np.unique(np.asarray(pts, float))


def _scan(x, ys, w, grid):
    """Chi^2 drop, slope, slope variance per (series, onset), flat chi^2 per series."""
    h = np.clip(x[None, :] - grid[:, None], 0.0, None)              # (m, n)
    sw = w.sum()
    hc = h - (h @ w / sw)[:, None]
    shh = np.maximum((hc * hc) @ w, 1e-300)                          # (m,)
    shy = (ys * w) @ hc.T                                            # (B, m)
    b = shy / shh
    gain = np.where(b > 0, shy * shy / shh, 0.0)
    yc = ys - ((ys @ w) / sw)[:, None]
    chi0 = (yc * yc) @ w                                             # (B,)
    return gain, b, 1.0 / shh, chi0


def _studentized(gain, chi0, n):
    """``gain / s^2`` with s^2 the hinge fit's residual chi^2 per degree of freedom."""
    rest = np.maximum(chi0[:, None] - gain, 1e-12 * np.maximum(chi0[:, None], 1e-300))
    return gain / (rest / (n - 3))


def _flat(y, w):
    a = float(y @ w / w.sum())
    return a, math.sqrt(1.0 / w.sum())


def trend_test(days: ArrayLike, travel: ArrayLike, y: ArrayLike, se: ArrayLike, *,
               extra_var: float = 0.0, alpha: float = WEAR_ALPHA, n_boot: int = BOOTSTRAP,
               seed: int = 0) -> TrendResult | None:
    """
    Test one joint for wear (module docstring).

    Parameters
    ----------
    days, travel, y, se : array_like
        Per recording, in time order: days since the joint's first recording,
        accumulated travel, reference friction and its standard error.
    extra_var : float
        sigma^2 (:func:`extra_variance`).
    alpha : float
        Significance level.
    n_boot : int
        Bootstrap series.
    seed : int
        Of the bootstrap draws.

    Returns
    -------
    TrendResult or None
        None when the joint has too few recordings for a hinge
        (``MIN_AFTER + 2``).

    """
    x_axes = {'time': np.asarray(days, float), 'travel': np.asarray(travel, float)}
    y = np.asarray(y, float)
    w = 1.0 / (np.asarray(se, float) ** 2 + extra_var)
    n = len(y)
    if n < MIN_AFTER + 2:
        return None
    grids = {k: _grid(v) for k, v in x_axes.items()}
    fits = {k: _scan(x_axes[k], y[None, :], w, grids[k]) for k in x_axes}
    gain = {k: float(f[0][0].max()) for k, f in fits.items()}
    axis = max(gain, key=lambda k: gain[k])
    stat = float(max(_studentized(f[0], f[3], n).max() for f in fits.values()))
    a0, _ = _flat(y, w)
    rng = np.random.default_rng(seed)
    ys = a0 + rng.standard_normal((n_boot, n)) / np.sqrt(w)
    scans = [_scan(x_axes[k], ys, w, grids[k]) for k in x_axes]
    boot = np.max([_studentized(f[0], f[3], n).max(axis=1) for f in scans], axis=0)
    p = float((1 + np.sum(boot >= stat * (1.0 - 1e-12))) / (n_boot + 1))
    threshold = float(np.quantile(boot, 1.0 - alpha))

    def best(k):
        g, b, var, chi0 = fits[k]
        i = int(np.argmax(g[0]))
        scale = max(float(chi0[0] - g[0][i]) / (n - 3), 1.0)      # residual scatter beyond w
        near = grids[k][g[0] >= g[0][i] - scale]
        return grids[k][i], float(b[0, i]), math.sqrt(var[i] * scale), (float(near.min()),
                                                                        float(near.max()))

    c_t, b_t, se_t, range_t = best('time')
    c_d, b_d, se_d, range_d = best('travel')
    xt, xd = x_axes['time'], x_axes['travel']
    if axis == 'time':
        onset_day, onset_range = float(c_t), range_t
        onset_travel = float(np.interp(c_t, xt, xd))
        h = np.clip(xt - c_t, 0.0, None)
        slope = b_t
    else:
        onset_day = float(np.interp(c_d, xd, xt))
        onset_range = (float(np.interp(range_d[0], xd, xt)), float(np.interp(range_d[1], xd, xt)))
        onset_travel = float(c_d)
        h = np.clip(xd - c_d, 0.0, None)
        slope = b_d
    level, level_se = _flat(y - slope * h, w)
    return TrendResult(
        wear=bool(p < alpha), p_value=p, statistic=stat, threshold=threshold, axis=axis,
        onset_day=onset_day, onset_range=onset_range, onset_travel=onset_travel,
        rate_per_day=b_t, rate_per_day_se=se_t, rate_per_travel=b_d, rate_per_travel_se=se_d,
        level=level, level_se=level_se, extra_sd=math.sqrt(extra_var), n=n, gain=gain)
