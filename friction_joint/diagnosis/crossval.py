# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.
"""
Block cross-validation of the diagnosis's model structures, and their fit on all data.

:func:`cross_validate_structures` holds out each of K contiguous blocks of bins
in turn (the held-out loop is :func:`~friction_joint.identification.folds.held_out_sse`,
shared with the identification's order selection); :func:`fit_all` fits on every
bin.  Both choose the grid point with the least (penalised) training error and
refine its nonlinear parameters with :class:`~friction_joint.diagnosis.refine.Refiner`.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from .refine import Refiner
from .structures import CandidateStructure, constraints, Context, design, solve_physical
from ..identification.folds import held_out_sse

__all__ = ['CVResult', 'cross_validate_structures', 'fit_all']


@dataclasses.dataclass
class CVResult:
    """Held-out errors of one structure over K blocks."""

    sse: np.ndarray          # held-out SSE per block
    n: np.ndarray            # bins per block
    structures: list         # structure chosen per fold
    pred: np.ndarray         # held-out prediction per bin
    betas: list              # coefficients per fold
    names: list              # column names per fold

    @property
    def mse(self):
        return self.sse / self.n

    @property
    def rmse(self):
        return float(np.sqrt(self.sse.sum() / self.n.sum()))


def _penalty(s, ctx):
    """
    Training-error factor that makes the grid prefer simpler explanations.

    A ripple at N cycles per turn (whose 2nd harmonic is the 2 N tooth-engagement ripple)
    must fit 2 % better than one at 2 N.
    """
    return 1.02 if s.ripple and abs(s.cyc - 2.0 * ctx.gear_ratio) > 1e-9 else 1.0


def _refiner(ctx, y, block, k):
    return Refiner(ctx, y, block, k, {'design': design, 'solve': solve_physical,
                                      'constraints': constraints, 'penalty': _penalty})


def cross_validate_structures(structures: list[CandidateStructure], ctx: Context, y: np.ndarray,
                              block: np.ndarray, k: int) -> CVResult:
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
    chosen, betas, names = [], [], []
    pred = np.empty_like(y)

    def fit_predict(fold, train, test):
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


def fit_all(structures, ctx, y):
    """
    Fit on all bins: the best grid point, its nonlinear parameters refined continuously.

    Returns ``(structure, beta, names, prediction)``.
    """
    ref = _refiner(ctx, y, np.zeros(len(y), int), 1)
    s, beta, x, names = ref.best(structures)
    return s, beta, names, x @ beta
