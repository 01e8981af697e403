# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Physical least squares: the constraints F_c, F_s, F_v >= 0 of a design and the bounded fit.

A structure's coefficients (:mod:`~friction_joint.diagnosis.structures`) are
fitted by linear least squares from the normal equations; the fit is kept
when it is physical on a grid over the temperature range the fit is valid on
and over the data's load range (:func:`constraints`), otherwise the
quadratic problem is solved with those inequalities (:func:`solve_physical`).
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from .structures import drift_basis

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .structures import Column, Context

__all__ = ['N_DRIFT_CONSTRAINT', 'solve', 'constraints', 'solve_physical']

#: points of the travel grid of the physical constraints of ``drift``
N_DRIFT_CONSTRAINT = 9


def solve(g: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """Least squares from normal equations, columns scaled, tiny ridge for conditioning."""
    sc = np.sqrt(np.maximum(np.diag(g), 1e-300))
    gs = g / np.outer(sc, sc)
    bs = b / sc
    p = len(bs)
    beta = np.linalg.solve(gs + 1e-10 * np.eye(p), bs)
    return beta / sc


def constraints(names: Sequence[Column], ctx: Context) -> NDArray[np.float64] | None:
    """
    Rows ``A`` of the physical constraints ``A beta >= 0`` of a design's columns, or None.

    F_c, F_s and F_v (each with its load terms) at
    :data:`~friction_joint.diagnosis.structures.N_CONSTRAINT` temperatures of
    ``ctx.range`` and at zero and the largest load of the data; with a Stribeck
    term F_s - F_c >= 0 there too (a breakaway friction below the Coulomb level is
    no Stribeck hump but another low-speed effect).
    """
    groups = {g: [(j, kind[len(g):], i) for j, (kind, i) in enumerate(names)
                  if kind in (g, g + '_load', g + '_drift')] for g in ('fc', 'fs', 'fv')}
    groups = {g: c for g, c in groups.items() if c}
    n_drift = max([i for c in groups.values() for _, kind, i in c if kind == '_drift'] or [0])
    s_grid = np.linspace(0.0, 1.0, N_DRIFT_CONSTRAINT) if n_drift else np.zeros(1)
    phis = drift_basis(s_grid, n_drift) if n_drift else []

    def row(cols: list[tuple[int, str, int]], u: float, vl: float, m: int, sign: float,
            out: NDArray[np.float64]) -> NDArray[np.float64]:
        for j, kind, i in cols:
            out[j] += sign * (u ** i if kind == '' else vl ** i if kind == '_load'
                              else phis[i - 1][m])
        return out

    rows = []
    pairs = [(g, None) for g in groups] + ([('fs', 'fc')] if {'fs', 'fc'} <= set(groups) else [])
    for group, minus in pairs:
        own = any(k == '_drift' for _, k, _ in groups[group]) or minus
        for u in ctx.u_grid:
            for vl in {0.0, ctx.vl_max}:
                for m in range(len(s_grid)) if own else range(1):
                    r = row(groups[group], u, vl, m, 1.0, np.zeros(len(names)))
                    rows.append(row(groups[minus], u, vl, m, -1.0, r) if minus else r)
    return np.array(rows) if rows else None


def solve_physical(g: NDArray[np.float64], b: NDArray[np.float64],
                   a: NDArray[np.float64] | None) -> NDArray[np.float64]:
    """
    Least squares from normal equations with the constraints ``a beta >= 0`` (None: none).

    The unconstrained solution (:func:`solve`) when it satisfies them, else the
    bounded quadratic problem solved by SLSQP on scaled columns.
    """
    beta = solve(g, b)
    if a is None:
        return beta
    sc = np.sqrt(np.maximum(np.diag(g), 1e-300))
    scale = float(np.max(np.abs(a @ beta))) or 1.0
    if np.min(a @ beta) >= 0.0:
        return beta
    from scipy import optimize
    gs, bs, a_s = g / np.outer(sc, sc), b / sc, a / sc
    gs = gs + 1e-10 * np.eye(len(bs))
    z0 = beta * sc
    margin = 1e-9 * scale            # strictly inside: the gear file checks >= 0 exactly
    res = optimize.minimize(lambda z: z @ gs @ z - 2.0 * bs @ z, z0,
                            jac=lambda z: 2.0 * (gs @ z - bs), method='SLSQP',
                            constraints=[{'type': 'ineq', 'fun': lambda z: a_s @ z - margin,
                                          'jac': lambda z: a_s}],
                            options={'maxiter': 200, 'ftol': 1e-12})
    z: NDArray[np.float64] = res.x
    return z / sc
