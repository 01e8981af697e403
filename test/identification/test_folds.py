# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The held-out-block loop shared by the order selection and the diagnosis, and the folds."""
from friction_joint.identification.folds import held_out_sse, random_folds
import numpy as np


def test_random_folds_deal_a_seeded_permutation_round_robin():
    """The fold assignment of ``--orders auto``: fixed by the seed, not consecutive plateaus."""
    folds = random_folds(10, 3)
    assert [f.tolist() for f in folds] == [[4, 7, 9, 1], [6, 3, 0], [2, 5, 8]]
    assert sorted(np.concatenate(random_folds(14, 5, seed=3)).tolist()) == list(range(14))
    assert [f.tolist() for f in random_folds(10, 3, seed=1)] != [f.tolist() for f in folds]


def test_held_out_sse_fits_without_the_block_and_scores_it():
    """A mean predictor: each block is predicted by the mean of the others."""
    y = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    blocks = [np.array([0, 3]), np.array([4, 1]), np.array([2])]
    seen = []

    def fit_predict(fold, train, test):
        assert not train[test].any() and train.sum() == len(y) - len(test)
        seen.append(fold)
        return np.full(len(test), y[train].mean()) - y[test]

    sse, count = held_out_sse(blocks, len(y), fit_predict)
    assert seen == [0, 1, 2] and count.tolist() == [2.0, 2.0, 1.0]
    expected = [(22 / 3 - 1) ** 2 + (22 / 3 - 8) ** 2, (13 / 3 - 16) ** 2 + (13 / 3 - 2) ** 2,
                (27 / 4 - 4) ** 2]
    np.testing.assert_allclose(sse, expected, rtol=1e-14)
