# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
What the data can tell: velocity reversals for ``presliding`` are counted within a piece.

The pre-sliding state restarts relaxed at every gap between pieces (and
between recordings), so a change of direction across a gap is no reversal
the data show: five one-way runs in alternating directions test nothing,
the same motion without gaps has four reversals.
"""
from friction_joint.diagnosis.data import BIN, DiagnosisData
from friction_joint.diagnosis.testability import MIN_REVERSALS, untestable
import numpy as np


def _runs(pieces):
    """Diagnosis data of five 2 s runs at 0.1 rad/s, alternating in direction."""
    n_run = 200
    qd = np.concatenate([np.full(n_run, 0.1 * (-1) ** i) for i in range(5)])
    n = len(qd)
    t = np.arange(n) * BIN
    q = np.cumsum(qd) * BIN
    z = np.zeros(n)
    piece = np.repeat(np.arange(5), n_run) if pieces else np.zeros(n, dtype=np.int64)
    block = (np.arange(n) * 10) // n
    return DiagnosisData(
        t=t, q=q, qf=q, qd=qd, qdd=z, effort=z, tau_ext=z, xi=z, tl=z, piece=piece,
        dt=np.full(n, BIN), bin_of=np.arange(n), block_of=block, y=z, count=np.ones(n),
        t_bin=t, block=block, n_blocks=10, inertia=0.0, mgl_sim=0.0, link_torque=False,
        recordings=[], has_temperature=False, v_stick=0.01, resolution=1e-6,
        friction_level=1.0, stroke=float(np.ptp(q)))


def test_reversals_across_gaps_are_not_counted():
    """Five one-way pieces have no reversal; the same runs in one piece have four."""
    assert MIN_REVERSALS <= 4
    why = untestable(_runs(pieces=True), 50.0, ['presliding'])
    assert 'only 0 velocity reversals' in why.get('presliding', ''), why
    assert 'presliding' not in untestable(_runs(pieces=False), 50.0, ['presliding'])
