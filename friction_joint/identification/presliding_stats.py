# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Standard errors of step 3: the finite-difference Hessian, the covariance, the correlation time.

:func:`~friction_joint.identification.presliding.fit_presliding` takes its standard errors
from the curvature of the mean squared error at the optimum (module docstring of
:mod:`~friction_joint.identification.presliding`, Standard errors).
"""
from __future__ import annotations

from collections.abc import Callable
import math

import numpy as np

from ._arrays import FloatArray

__all__ = ['autocorr_time', 'fd_hessian', 'covariance_from_hessian', 'log_interval']


def autocorr_time(r: FloatArray, max_lag: int = 2000) -> float:
    """Return the integrated autocorrelation time (samples) of residual r: 1 + 2 sum rho_k."""
    # the sum runs up to the first lag with rho <= 0
    r = r - r.mean()
    n = r.size
    if n < 10 or not np.any(r):
        return 1.0
    m = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(r, m)
    acf = np.fft.irfft(f * np.conj(f), m)[:min(n, max_lag)]
    acf /= acf[0]
    neg = np.flatnonzero(acf[1:] <= 0.0)
    k = neg[0] + 1 if neg.size else acf.size
    return float(max(1.0, min(1.0 + 2.0 * acf[1:k].sum(), n / 10.0)))


def fd_hessian(f: Callable[[FloatArray], FloatArray], x: FloatArray, h: float
               ) -> tuple[FloatArray, int]:
    """Return the central-difference Hessian of f (batched) at x with step h, and its points."""
    n = x.size
    pts = [x]
    for i in range(n):
        for s in (1.0, -1.0):
            p = x.copy()
            p[i] += s * h
            pts.append(p)
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    for i, j in pairs:
        for si, sj in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
            p = x.copy()
            p[i] += si * h
            p[j] += sj * h
            pts.append(p)
    v = f(np.array(pts))
    f0 = v[0]
    hess = np.empty((n, n))
    for i in range(n):
        hess[i, i] = (v[1 + 2 * i] - 2.0 * f0 + v[2 + 2 * i]) / (h * h)
    base = 1 + 2 * n
    for m, (i, j) in enumerate(pairs):
        pp, pm, mp, mm = v[base + 4 * m: base + 4 * m + 4]
        hess[i, j] = hess[j, i] = (pp - pm - mp + mm) / (4.0 * h * h)
    return hess, len(pts)


def covariance_from_hessian(hess: FloatArray, scale: float) -> tuple[FloatArray, FloatArray]:
    """Return scale * inverse of hess, with infinite variance along non-positive curvature."""
    w, v = np.linalg.eigh(hess)
    tol = 1e-12 * max(float(np.max(np.abs(w))), 1e-300)
    good = w > tol
    inv_w = np.where(good, 1.0 / np.where(good, w, 1.0), 0.0)
    cov = scale * (v * inv_w) @ v.T
    var = np.diag(cov).copy()
    bad = np.any((v ** 2 > 1e-6) & ~good[None, :], axis=1)
    var[bad] = np.inf
    return cov, var


def log_interval(value: float, se_log: float) -> tuple[float, float]:
    """Return ``value`` x exp(-+se_log), the 68 % range of a log estimate ((0, inf) if wide)."""
    if not np.isfinite(se_log) or se_log > 700.0:
        return (0.0, math.inf)
    return (float(value * math.exp(-se_log)), float(value * math.exp(se_log)))
