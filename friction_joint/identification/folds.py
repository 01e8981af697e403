# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Cross-validation over held-out blocks: the one loop the order selection and the diagnosis share.

:func:`held_out_sse` holds out each block in turn, lets the caller fit on the
others and predict the held-out rows, and accumulates the held-out squared
error per block.  What a block is stays with the caller:

* the static identification's order selection
  (:func:`~friction_joint.identification.static_fit.cross_validate_orders`)
  deals the plateaus into seeded random folds (:func:`random_folds`);
* the diagnosis (:func:`~friction_joint.diagnosis.crossval.cross_validate_structures`)
  holds out contiguous time blocks of bins (the rows of each block label).

The module sits in :mod:`friction_joint.identification`, which the diagnosis
may import (not the other way round).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

__all__ = ['random_folds', 'held_out_sse']


def random_folds(n: int, k: int, *, seed: int = 0) -> list[np.ndarray]:
    """
    Deal ``n`` items into ``k`` folds at random (seeded), for k-fold cross-validation.

    The items are permuted with ``numpy.random.default_rng(seed)`` and dealt
    round-robin: fold ``i`` holds ``perm[i::k]`` (in that order), so the folds
    are random subsets of sizes differing by at most one, not runs of
    consecutive items.

    Parameters
    ----------
    n : int
        Number of items (e.g. plateaus).
    k : int
        Number of folds, 1 <= k <= n.
    seed : int
        Seed of the permutation.

    Returns
    -------
    list of ndarray of int
        The items of each fold.

    """
    perm = np.random.default_rng(seed).permutation(n)
    return [perm[i::k] for i in range(k)]


def held_out_sse(blocks: Sequence[np.ndarray], n: int,
                 fit_predict: Callable[[int, np.ndarray, np.ndarray], np.ndarray]
                 ) -> tuple[np.ndarray, np.ndarray]:
    """
    Hold out each block in turn: fit on the others, predict it, return its squared error.

    Parameters
    ----------
    blocks : sequence of ndarray of int
        The rows of each block (e.g. :func:`random_folds`).
    n : int
        Number of rows.
    fit_predict : callable
        ``fit_predict(fold, train, test)``: fit on the rows where the bool
        mask ``train`` is set (every row outside block ``fold``), predict the
        rows ``test`` (the block's) and return the held-out residuals
        (prediction minus observation, one per test row).

    Returns
    -------
    sse : ndarray (k,)
        Held-out sum of squared residuals per block.
    count : ndarray (k,)
        Residuals per block (float).

    """
    sse, count = np.zeros(len(blocks)), np.zeros(len(blocks))
    for fold, test in enumerate(blocks):
        train = np.ones(n, dtype=bool)
        train[test] = False
        r = np.asarray(fit_predict(fold, train, test), dtype=float)
        sse[fold] = float(np.sum(r * r))
        count[fold] = r.size
    return sse, count
