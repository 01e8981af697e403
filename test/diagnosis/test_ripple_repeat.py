# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A ripple must repeat: a position torque slower than a third of the stroke is never a ripple.

The truth carries a direction-independent position torque whose period is
drawn between about half the stroke of a piece and the whole stroke (seen
once, or not even twice, in any piece); ``diagnose`` must not call it
``position_ripple``, and every ripple period it tries repeats at least three
times within a piece.
"""
import math
import os
from pathlib import Path

import friction_joint
from friction_joint.diagnosis.pipeline import diagnose
from friction_joint.diagnosis.structures import ripple_cycles
from friction_joint.diagnosis.testability import untestable
from friction_joint.experiments.hidden import draw_effect, RecordingOptions, simulate_recording
import numpy as np
import pytest

BASE = Path(__file__).resolve().parents[2] / 'config' / 'csd25_base.yaml'
#: a ripple repeats at least this often within the stroke of a piece
MIN_REPEATS = 3
MASTER_SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20251127'))


def _stroke(topics):
    """Largest position range of a segment (the pieces are the segments)."""
    js = topics['/joint_states']
    t, q = np.asarray(js['t'], float), np.asarray(js['q'], float)
    cuts = np.flatnonzero(np.diff(t) > 0.25) + 1
    return max(float(np.ptp(part)) for part in np.split(q, cuts) if len(part) > 1)


@pytest.mark.parametrize('case', [0, 1])
def test_slow_position_torque_is_no_ripple(case, tmp_path):
    rng = np.random.default_rng([MASTER_SEED, 100 + case])
    base = friction_joint.load_gear(BASE)
    seed = int(rng.integers(0, 2**31 - 1))
    topics, _ = simulate_recording(base, None, options=RecordingOptions(duration=30.0, seed=seed))
    stroke = _stroke(topics)
    period = float(rng.uniform(0.55, 0.95)) * stroke
    size = draw_effect(rng, 'position_ripple')
    amplitude = 2.0 * size['amplitude']
    truth = base.replace({'friction': {'position_ripple': {
        'cycles_per_rev': 2.0 * math.pi / period, 'amplitude': [amplitude],
        'phase': [size['phase']]}}})
    rec = tmp_path / 'rec'
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=30.0, seed=seed, base_gear=base))
    what = (f'[master seed {MASTER_SEED}] seed {seed}: position torque {amplitude:.3g} Nm of '
            f'period {period:.3g} rad on a stroke of {stroke:.3g} rad')
    diag = diagnose([str(rec)], base)
    data = diag.data
    longest = max(2.0 * math.pi / c for c in ripple_cycles(data, base.gear_ratio))
    assert longest <= data.stroke / MIN_REPEATS * (1 + 1e-9), \
        f'{what}: a ripple period of {longest:.3g} rad is tried on a {data.stroke:.3g} rad stroke'
    named = diag.report['named_causes']
    assert 'position_ripple' not in named, \
        f'{what}: named {named}; candidates {diag.report["candidates"]}'
    # a gear whose tooth ripple repeats only 2-2.9 times within the stroke: untestable, and
    # the reason gives the stroke and the period
    repeats = float(rng.uniform(2.0, 2.9))
    ratio = math.pi * repeats / data.stroke
    why = untestable(data, ratio, ['position_ripple']).get('position_ripple', '')
    assert f'{data.stroke:.4g}' in why and f'{math.pi / ratio:.4g}' in why, \
        f'{what}: {repeats:.2f} periods 2 pi / (2 N) in the stroke; reason {why!r}'
