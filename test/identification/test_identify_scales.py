# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
The scale check: an identified coefficient far from the structure file's is reported.

The structure file's F_c, F_s, F_v and v_s are drawn at random, then the identified gear
is the structure file with one coefficient scaled by a factor drawn log-uniform over
10^-4..10^4: a line naming that coefficient, its ratio and how to import again appears
exactly when the factor is outside 1/SCALE_FACTOR..SCALE_FACTOR; none for the others.
"""
import os

from friction_joint.gear import load_gear
from friction_joint.identification.scales import SCALE_FACTOR, scale_lines
import numpy as np
import pytest

BASE = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                    'config', 'csd25_base.yaml')

KEYS = ('fc', 'fs', 'fv', 'vs')


@pytest.mark.parametrize('seed', range(12))
def test_a_coefficient_far_from_the_structure_file_is_reported(seed):
    rng = np.random.default_rng([4747, seed])
    base = load_gear(BASE)
    fc = rng.uniform(0.2, 20.0)
    prior = {'fc': fc, 'fs': fc * rng.uniform(1.0, 2.0), 'fv': rng.uniform(0.01, 5.0),
             'vs': rng.uniform(0.005, 0.3)}
    structure = base.replace({'friction': {k: [v] for k, v in prior.items()}})
    key = KEYS[rng.integers(len(KEYS))]
    factor = 10.0 ** rng.uniform(-4.0, 4.0)
    fitted = structure.replace({'friction': {key: [prior[key] * factor]}})
    lines = scale_lines(fitted, structure)
    far = not 1.0 / SCALE_FACTOR <= factor <= SCALE_FACTOR
    assert len(lines) == int(far), (key, factor, lines)
    if far:
        assert lines[0].startswith(f'{key} = ') and f'{factor:.3g} x' in lines[0]
        assert 'import the log again' in lines[0]
    assert scale_lines(structure, structure) == []
