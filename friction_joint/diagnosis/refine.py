# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Continuous nonlinear parameters: a grid, then bounded scalar optimisation (variable projection).

For fixed nonlinear parameters a structure is linear in its coefficients, so
its (physically constrained) least-squares training error is a function of
the nonlinear parameters alone.  :class:`Refiner` minimises it: first over
the grid points given (the best one wins), then over every nonlinear
parameter of the winner in turn (one coordinate sweep, the gridded parameter
first) by :func:`scipy.optimize.minimize_scalar` (bounded Brent) between
the neighbouring grid points of the winner, or one grid step either side of
the value when the parameter was not gridded.  The refined value is kept
only when it fits the training data better than the grid point.  Which
parameters: those the grid varies; with no grid (a single structure) all
of the structure's (:meth:`Refiner.best`).

Parameters and their scales (``t``, in which the search is done):

* ``vs`` (Stribeck velocity): log; one step is the ratio of the ``vs`` grid;
* ``dv`` (delta_v level): linear; one step 0.1, bounded by the grid's ends;
* ``cyc`` (ripple fundamental, cycles per turn): linear; one step is half
  the width of a periodogram peak over the position range, pi / range;
* ``ps`` (pre-sliding stiffness, the model kept): log; one step is the
  ratio of the pre-sliding lengths of the grid.

Cost: the values are snapped to a lattice of :data:`LATTICE` points per step
and every structure's normal equations are computed once per refiner, so the
folds of a cross-validation, whose training sets overlap, share most
evaluations; the design's column groups that a parameter leaves alone come
from the context's cache (:func:`~friction_joint.diagnosis.structures.design`).
In a cross-validation each fold refines on its training blocks only.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import math
from typing import TYPE_CHECKING, TypedDict

import numpy as np
from scipy import optimize

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .structures import CandidateStructure, Column, Context

__all__ = ['LATTICE', 'NONLINEAR', 'active_params', 'varying_params', 'Refiner', 'Fitting',
           'Normal']

#: lattice points per step of a parameter (the resolution of the refinement)
LATTICE = 64
#: nonlinear parameters, in the order a coordinate sweep refines them
NONLINEAR = ('vs', 'dv', 'cyc', 'ps')


class Fitting(TypedDict):
    """The functions a :class:`Refiner` fits with (:mod:`~friction_joint.diagnosis.structures`)."""

    design: Callable[[CandidateStructure, Context],
                     tuple[NDArray[np.float64], list[Column]]]
    solve: Callable[[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None],
                    NDArray[np.float64]]
    constraints: Callable[[Sequence[Column], Context], NDArray[np.float64] | None]
    penalty: Callable[[CandidateStructure, Context], float]


#: design, column names, per-block normal equations (G, b, y'y) and constraints of a structure
Normal = tuple['NDArray[np.float64]', 'list[Column]', 'NDArray[np.float64]',
               'NDArray[np.float64]', 'NDArray[np.float64]', 'NDArray[np.float64] | None']


def active_params(s: CandidateStructure) -> list[str]:
    """Nonlinear parameters structure ``s`` has (a subset of :data:`NONLINEAR`, in order)."""
    flags = {'vs': bool(s.nfs), 'dv': bool(s.dv_free), 'cyc': bool(s.ripple),
             'ps': bool(s.presliding)}
    return [p for p in NONLINEAR if flags[p]]


def varying_params(structures: Sequence[CandidateStructure]) -> list[str]:
    """Nonlinear parameters whose values differ among ``structures`` (a grid's)."""
    return [p for p in NONLINEAR if len({getattr(s, p) for s in structures}) > 1]


def _t(s: CandidateStructure, p: str) -> float:
    v = getattr(s, p)
    if p == 'ps':
        return math.log(v[1])
    return math.log(v) if p == 'vs' else float(v)


def _at(s: CandidateStructure, p: str, t: float) -> CandidateStructure:
    if p == 'ps':
        return s.with_(ps=(s.ps[0], float(math.exp(t))))
    return s.with_(**{p: float(math.exp(t)) if p == 'vs' else float(t)})


class Refiner:
    """
    Training errors of structures over blocks, with grid and continuous search.

    Parameters
    ----------
    ctx : Context
        The design context (grids, scales, column cache).
    y : ndarray
        Friction torque per bin.
    block : ndarray of int
        Block of every bin (0..k-1).
    k : int
        Number of blocks.
    fns : dict
        ``design(s, ctx)``, ``solve(g, b, a)`` (physical least squares),
        ``constraints(names, ctx)`` and ``penalty(s, ctx)`` (training-error factor).

    """

    def __init__(self, ctx: Context, y: NDArray[np.float64], block: NDArray[np.int64], k: int,
                 fns: Fitting) -> None:
        self.ctx, self.y, self.k, self.fns = ctx, y, k, fns
        self.rows = [np.flatnonzero(block == i) for i in range(k)]
        self.memo: dict[CandidateStructure, Normal] = {}
        self.evaluations = 0
        self._steps: dict[str, float] | None = None

    def normal(self, s: CandidateStructure) -> Normal:
        """Design, names, per-block normal equations and constraints of ``s`` (memoised)."""
        out = self.memo.get(s)
        if out is None:
            x, names = self.fns['design'](s, self.ctx)
            g = np.empty((self.k, x.shape[1], x.shape[1]))
            b = np.empty((self.k, x.shape[1]))
            yy = np.empty(self.k)
            for i, r in enumerate(self.rows):
                xi, yi = x[r], self.y[r]
                g[i], b[i], yy[i] = xi.T @ xi, xi.T @ yi, yi @ yi
            out = (x, names, g, b, yy, self.fns['constraints'](names, self.ctx))
            self.memo[s] = out
            self.evaluations += 1
        return out

    def train(self, s: CandidateStructure,
              fold: int | None = None) -> tuple[float, NDArray[np.float64]]:
        """Penalised training SSE and coefficients of ``s`` without block ``fold`` (None: all)."""
        x, names, g, b, yy, a = self.normal(s)
        gt, bt, yt = g.sum(0), b.sum(0), yy.sum()
        if fold is not None:
            gt, bt, yt = gt - g[fold], bt - b[fold], yt - yy[fold]
        beta = self.fns['solve'](gt, bt, a)
        sse = (yt - 2.0 * beta @ bt + beta @ gt @ beta) * self.fns['penalty'](s, self.ctx)
        return float(sse), beta

    def steps(self) -> dict[str, float]:
        """One step (in the search scale) of every parameter."""
        if self._steps is None:
            c = self.ctx
            vs = c.vs_grid
            lengths = c.ps_lengths
            q = np.asarray(c.data.average(c.data.q)) if len(self.y) else np.zeros(1)
            span = float(np.ptp(q)) or 1.0
            self._steps = {
                'vs': math.log(vs[1] / vs[0]) if len(vs) > 1 else math.log(2.0),
                'dv': 0.1,
                'cyc': math.pi / span,
                'ps': math.log(lengths[1] / lengths[0]) if len(lengths) > 1 else math.log(2.0)}
        return self._steps

    def _bounds(self, s: CandidateStructure, p: str,
                grid: Sequence[CandidateStructure]) -> tuple[float, float]:
        """Search interval of ``p`` around ``s``: grid neighbours, else one step either side."""
        t0, step = _t(s, p), self.steps()[p]
        pts = sorted({_t(g, p) for g in grid if p != 'ps' or g.ps[0] == s.ps[0]})
        if p != 'cyc' and len(pts) > 1:
            i = pts.index(t0) if t0 in pts else int(np.argmin(np.abs(np.subtract(pts, t0))))
            lo, hi = pts[max(i - 1, 0)], pts[min(i + 1, len(pts) - 1)]
        else:
            lo, hi = t0 - step, t0 + step
        if p == 'dv':
            dv = self.ctx.dv_grid
            lo, hi = max(lo, float(min(dv[0], t0))), min(hi, float(max(dv[-1], t0)))
        elif p == 'cyc':
            lo = max(lo, 0.5 * t0)
        return lo, hi

    def search(self, s: CandidateStructure, p: str, grid: Sequence[CandidateStructure],
               fold: int | None, cur: float) -> tuple[float, CandidateStructure]:
        """Refine ``p`` of ``s`` (training error ``cur``); return the better (error, structure)."""
        lo, hi = self._bounds(s, p, grid)
        lat = self.steps()[p] / LATTICE
        if not hi - lo > 2.0 * lat:
            return cur, s

        def snapped(t: float) -> CandidateStructure:
            return _at(s, p, min(max(round(t / lat) * lat, lo), hi))

        res = optimize.minimize_scalar(lambda t: self.train(snapped(t), fold)[0],
                                       bounds=(lo, hi), method='bounded',
                                       options={'xatol': lat})
        s_new = snapped(float(res.x))
        err = self.train(s_new, fold)[0]
        return (err, s_new) if err < cur else (cur, s)

    def best(self, structures: Sequence[CandidateStructure], fold: int | None = None,
             every: bool = False) -> tuple[CandidateStructure, NDArray[np.float64],
                                           NDArray[np.float64], list[Column]]:
        """
        Best structure for the training blocks (all but ``fold``): grid, then refinement.

        The parameters the grid varies are refined; with ``every`` (or no grid)
        then every other nonlinear parameter of the winner too.  Returns
        ``(structure, beta, x, names)``.
        """
        errs = [self.train(s, fold)[0] for s in structures]
        i = int(np.argmin(errs))
        s, err = structures[i], errs[i]
        active = active_params(s)
        varying = [p for p in varying_params(structures) if p in active]
        order = varying + [p for p in active if p not in varying and (every or not varying)]
        for p in order:
            err, s = self.search(s, p, structures if p in varying else [s], fold, err)
        beta = self.train(s, fold)[1]
        x, names = self.normal(s)[:2]
        return s, beta, x, names
