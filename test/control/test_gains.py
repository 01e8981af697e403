# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Gain design separate from the plant: presets, parsing, and the loop the gains make."""
from friction_joint.control.controller import pd_gains, step_metrics
from friction_joint.control.gains import gain_design, GAIN_PRESETS, GainDesign, loop_metrics
from friction_joint.exceptions import FrictionJointError
import numpy as np
import pytest
from scipy.integrate import solve_ivp


def _step(kp, kd, inertia, t_end):
    """Step response of J e'' + kd e' + kp e = kp (unit set-point) by a tight ODE solve."""
    sol = solve_ivp(lambda t, y: [y[1], (kp * (1.0 - y[0]) - kd * y[1]) / inertia],
                    (0.0, t_end), [0.0, 0.0], rtol=1e-10, atol=1e-12, dense_output=True,
                    method='Radau')
    t = np.linspace(0.0, t_end, 200001)
    return t, sol.sol(t)[0]


@pytest.mark.parametrize('design,plant', [(0.016, 0.223), (0.22, 0.22), (0.05, 0.01),
                                          (1.0, 0.3)])
def test_loop_metrics_match_the_simulated_step_on_the_plant(design, plant):
    kp, kd = GainDesign(design_inertia=design).gains(0.22)
    m = loop_metrics(kp, kd, plant)
    t, y = _step(kp, kd, plant, 30.0 / m['omega_n'])
    rise, over = step_metrics(t, y, 1.0)
    assert rise == pytest.approx(m['rise_time'], rel=1e-3)
    assert over == pytest.approx(m['overshoot'], abs=1e-4)
    assert m['inertia'] == plant


def test_design_on_its_own_inertia_meets_the_specification():
    d = GainDesign(design_inertia=0.016, rise_time=0.04, overshoot=0.06)
    m = loop_metrics(*d.gains(123.0), 0.016)       # the model inertia is not used
    assert m['rise_time'] == pytest.approx(0.04, rel=1e-6)
    assert m['overshoot'] == pytest.approx(0.06, rel=1e-6)


def test_presets_and_parsing():
    assert gain_design('paper') is GAIN_PRESETS['paper']
    assert GAIN_PRESETS['full-inertia'].gains(0.22) == pd_gains(0.22, rise_time=0.04,
                                                                overshoot=0.06)
    assert gain_design('J=0.03').gains(0.22) == pd_gains(0.03, rise_time=0.04, overshoot=0.06)
    assert gain_design('kp=40, kd=1.5').gains(0.22) == (40.0, 1.5)
    paper = GAIN_PRESETS['paper'].to_dict(0.22)
    assert paper['design_inertia'] == 0.016 and paper['kp'] == pytest.approx(41.197, abs=1e-3)
    # the paper preset on the full joint: a soft, lightly damped loop
    m = loop_metrics(paper['kp'], paper['kd'], 0.223)
    assert 0.1 < m['zeta'] < 0.3 and m['omega_n'] < 20.0


@pytest.mark.parametrize('spec', ['fast', 'J=abc', 'kp=40', 'kd=1', 'J=-1', 'kp=-4,kd=1',
                                  'kp=4,kd=1,J=2', 'J=1,J=2', 'x=1'])
def test_bad_gain_specs_are_refused_in_one_line(spec):
    with pytest.raises(FrictionJointError) as err:
        gain_design(spec)
    assert '\n' not in str(err.value)
