# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A warm-up recording: the temperature only rises, so ``thermal`` and ``drift`` are one variable.

The thermal effect's size, the recording and the plant's nuisance parameters
are drawn at random (seeded); ``diagnose`` sees the recording and the base.
"""
import os

from friction_joint.diagnosis import diagnose
from friction_joint.experiments.hidden import (apply_effects, draw_effect, RecordingOptions,
                                               simulate_recording)
from friction_joint.gear import load_gear
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')


@pytest.mark.parametrize('seed', range(2))
def test_a_warm_up_names_the_temperature_and_states_the_confound(tmp_path, seed):
    """Before: drift competed with thermal on a rising temperature, and nothing said why."""
    rng = np.random.default_rng([1821, seed])
    base = load_gear(BASE)
    truth = apply_effects(base, {'thermal': draw_effect(rng, 'thermal')})
    rec = str(tmp_path / 'rec')
    _, summary = simulate_recording(truth, rec, options=RecordingOptions(
        duration=float(rng.uniform(40, 60)), seed=int(rng.integers(1e6)), base_gear=base,
        warmup=True, n_segments=int(rng.integers(2, 4)), noise_scale=float(rng.uniform(0.5, 2.0))))
    xi = [s['xi_end'] for s in summary['segments']]
    assert xi == sorted(xi)                                  # the temperature only rises
    rep = diagnose([rec], base).report
    assert rep['named_causes'] == ['thermal'], rep['headline']
    pair = next(c for c in rep['confounds'] if c['effects'] == ['thermal', 'drift'])
    assert pair['rank_correlation'] > 0.9 and 'temperature' in pair['separate_by']
    entry = next(c for c in rep['candidates'] if c['effect'] == 'thermal')
    assert 'drift' in entry['confounded_with']
