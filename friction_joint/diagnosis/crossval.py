# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Block cross-validation of the diagnosis's model structures, and their fit on all data.

:func:`cross_validate_structures` holds out each of K contiguous blocks of bins
in turn (the held-out loop is :func:`~friction_joint.identification.folds.held_out_sse`,
shared with the identification's order selection); :func:`fit_all` fits on every
bin.  Both choose the grid point with the least (penalised) training error and
refine its nonlinear parameters with :class:`~friction_joint.diagnosis.refine.Refiner`.
"""
from __future__ import annotations

from collections.abc import Sequence
import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from .physical import constraints, solve_physical
from .refine import Refiner
from .structures import CandidateStructure, Context, design
from ..identification.folds import held_out_sse

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from .structures import Column

__all__ = ['CVResult', 'cross_validate_structures', 'fit_all']


@dataclasses.dataclass
class CVResult:
    """Held-out errors of one structure over K blocks."""

    sse: NDArray[np.float64]                # held-out SSE per block
    n: NDArray[np.float64]                  # bins per block
    structures: list[CandidateStructure]    # structure chosen per fold
    pred: NDArray[np.float64]               # held-out prediction per bin
    betas: list[NDArray[np.float64]]        # coefficients per fold
    names: list[list[Column]]               # column names per fold

    @property
    def mse(self) -> NDArray[np.float64]:
        return self.sse / self.n

    @property
    def rmse(self) -> float:
        return float(np.sqrt(self.sse.sum() / self.n.sum()))


def _penalty(s: CandidateStructure, ctx: Context) -> float:
    """
    Training-error factor that makes the grid prefer simpler explanations.

    A ripple at N cycles per turn (whose 2nd harmonic is the 2 N tooth-engagement ripple)
    must fit 2 % better than one at 2 N.
    """
    return 1.02 if s.ripple and abs(s.cyc - 2.0 * ctx.gear_ratio) > 1e-9 else 1.0


def _refiner(ctx: Context, y: NDArray[np.float64], block: NDArray[np.int64], k: int) -> Refiner:
    return Refiner(ctx, y, block, k, {'design': design, 'solve': solve_physical,
                                      'constraints': constraints, 'penalty': _penalty})


def cross_validate_structures(structures: list[CandidateStructure], ctx: Context,
                              y: NDArray[np.float64], block: NDArray[np.int64],
                              k: int) -> CVResult:
    """
    Cross-validate a grid of structures over K contiguous blocks, refined per fold.

    Per fold the grid point with the least training error wins and the
    gridded parameter is refined continuously on the training blocks
    (:class:`~friction_joint.diagnosis.refine.Refiner`); the held-out block
    never takes part in the choice.  A single structure (no grid) keeps its
    nonlinear parameters (fitted on all data by :func:`fit_all`).

    Parameters
    ----------
    structures : list of CandidateStructure
        The grid (one structure: no grid).
    ctx : Context
        The data's design context.
    y : ndarray
        Binned friction torque (Nm).
    block : ndarray of int
        Block of each bin.
    k : int
        Number of blocks.

    Returns
    -------
    CVResult

    """
    ref = _refiner(ctx, y, block, k)
    one = len(structures) == 1             # the parameters of a structure are fitted already
    chosen: list[CandidateStructure] = []
    betas: list[NDArray[np.float64]] = []
    names: list[list[Column]] = []
    pred = np.empty_like(y)

    def fit_predict(fold: int, train: NDArray[np.int64],
                    test: NDArray[np.int64]) -> NDArray[np.float64]:
        """Choose and fit on the other blocks (the refiner's own sums); residuals on ``fold``."""
        if one:
            s = structures[0]
            beta, (x, nm) = ref.train(s, fold)[1], ref.normal(s)[:2]
        else:
            s, beta, x, nm = ref.best(structures, fold)
        pred[test] = x[test] @ beta
        chosen.append(s)
        betas.append(beta)
        names.append(nm)
        return y[test] - pred[test]

    sse, n = held_out_sse(ref.rows, len(y), fit_predict)
    return CVResult(sse, n, chosen, pred, betas, names)


def fit_all(structures: Sequence[CandidateStructure], ctx: Context, y: NDArray[np.float64]
            ) -> tuple[CandidateStructure, NDArray[np.float64], list[Column], NDArray[np.float64]]:
    """
    Fit on all bins: the best grid point, its nonlinear parameters refined continuously.

    Returns ``(structure, beta, names, prediction)``.
    """
    ref = _refiner(ctx, y, np.zeros(len(y), int), 1)
    s, beta, x, names = ref.best(structures)
    return s, beta, names, x @ beta
