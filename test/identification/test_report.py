# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The identified parameters against the truth they came from, as a table with units."""
import os

from friction_joint.gear import load_gear
from friction_joint.identification.report import against_truth_markdown
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')

pytestmark = pytest.mark.filterwarnings('ignore::friction_joint.exceptions.GearConfigWarning')


def _row(lines, start):
    return next(ln for ln in lines if ln.startswith(start))


def test_against_truth_gives_relative_errors_with_units():
    truth = load_gear(TRUTH)
    f = truth.friction
    ident = truth.replace({'friction': {
        'fs': [1.02 * f.fs[0]], 'fc_load': [0.9 * f.fc_load[0]],
        'temperature_range': [23.0, 35.8], 'lugre': {'sigma0': 0.98 * f.lugre.sigma0}}})
    header = ['step 3 (lugre, pattern search): sigma0 = 20580 +- 65, sigma1 = 0.9 written, '
              'kept from the structure: undetermined by the data']
    lines = against_truth_markdown(ident, truth, header, (22.0, 27.0, 35.0))
    assert '| parameter | unit | identified | truth | error |' in lines
    assert _row(lines, '| F_s, every temperature | Nm |').endswith('| +2.0 % |')
    # polynomials by value at the temperatures inside the identified range only
    assert _row(lines, '| F_c, 27 °C | Nm |').endswith('| +0.0 % |')
    assert not any(ln.startswith('| F_c, 22 °C') for ln in lines)
    assert _row(lines, '| F_c load coefficient').endswith('| -10.0 % |')
    assert _row(lines, '| σ0 | Nm/rad |').endswith('| -2.0 % |')
    # sigma1 was not determined by the data: no error claimed
    assert 'undetermined by the data' in _row(lines, '| σ1 | Nm s/rad |')
    # the hardware's friction is LuGre: the GMS section is no truth for the GMS fit
    assert 'the hardware has LuGre friction' in _row(lines, '| GMS C | Nm/s |')
    # the static curve at reference velocities, without load and with the lever's
    # (near rest the curve is F_s, 2 % up, plus a little of F_c and the viscous part)
    err = float(_row(lines, '| static friction torque at 0.01 rad/s').split('|')[-2][:-2])
    assert 1.0 < err <= 2.0
    assert any(ln.startswith('| static friction torque at 1 rad/s') and
               f'load {truth.mgl:.3g} Nm | Nm |' in ln for ln in lines)
