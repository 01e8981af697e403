# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The lever's angle offset: gravity m g l sin(q - angle_offset) everywhere it is modelled."""
import glob
import math

from friction_joint import gear_from_dict, load_gear, save_gear
from friction_joint.control.controller import Controller, pd_gains
from friction_joint.control.observer import DisturbanceObserver
from friction_joint.models.joint import Joint
from friction_joint.testbed.plant import Plant
import numpy as np
import pytest


def damped_lever(rng):
    """Return a lever with viscous friction only (no stiction), and its angle offset."""
    inertia = rng.uniform(0.05, 0.5)
    mgl = rng.uniform(2.0, 20.0)
    length = rng.uniform(0.05, 0.5)
    offset = rng.choice([-1.0, 1.0]) * rng.uniform(0.1, 1.2)
    damping = 2.0 * math.sqrt(inertia * mgl)          # critically damped about the bottom
    gear = gear_from_dict({
        'gear_ratio': 50.0, 'inertia': inertia,
        'friction': {'model': 'static', 'fc': [0.0], 'fv': [damping]},
        'lever': {'mass': mgl / (9.81 * length), 'length': length, 'angle_offset': offset}})
    return gear, offset


@pytest.mark.parametrize('seed', [0, 1])
def test_plant_and_joint_hang_at_the_offset_and_agree(seed):
    rng = np.random.default_rng(seed)
    gear, offset = damped_lever(rng)
    assert gear.lever_offset == offset
    q_start = offset + rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 1.0)
    period = 2.0 * math.pi * math.sqrt(gear.inertia / gear.mgl)
    n = int(round(6.0 * period * 3000))
    plant = Plant(gear, q0=q_start, ideal_sensors=True)
    out = plant.run(np.zeros(n))
    # at rest where gravity vanishes: q = angle_offset (not q = 0)
    assert abs(out['qd_true'][-1]) < 1e-3 * math.sqrt(gear.mgl / gear.inertia)
    assert abs(out['q_true'][-1] - offset) < 0.01 * abs(q_start - offset)
    # the plant's external torque is the lever's m g l sin(q - offset)
    np.testing.assert_allclose(out['tau_ext'], gear.lever_torque(out['q_true']),
                               atol=1e-3 * gear.mgl)
    # the joint model with the offset follows the same trajectory
    joint = Joint(gear, mgl=gear.mgl, lever_offset=gear.lever_offset)
    joint.reset(q=q_start)
    sim = joint.simulate(np.zeros(n), plant.dt)
    np.testing.assert_allclose(sim.q, out['q_true'], atol=1e-9)
    np.testing.assert_allclose(sim.tau_ext, out['tau_ext'], atol=1e-9)
    # ... and a batch of joints holds an offset per member
    batch = Joint([gear, gear], mgl=gear.mgl, lever_offset=[0.0, offset])
    batch.reset(q=q_start)
    two = batch.simulate(np.zeros(n), plant.dt)
    np.testing.assert_allclose(two.q[1], out['q_true'], atol=1e-9)
    assert abs(two.q[0, -1]) < 0.01 * abs(q_start)


def test_controller_and_observer_use_the_offset():
    rng = np.random.default_rng(7)
    gear, offset = damped_lever(rng)
    q = rng.uniform(-math.pi, math.pi, 20)
    expected = gear.mgl * np.sin(q - offset)
    np.testing.assert_allclose(gear.lever_torque(q), expected)
    assert isinstance(gear.lever_torque(0.3), float)
    assert gear.lever_torque(offset) == pytest.approx(0.0, abs=1e-12)
    ctl = Controller(gear, *pd_gains(gear.inertia), friction='none')
    np.testing.assert_allclose([ctl.gravity(x) for x in q], expected, rtol=1e-12)
    # the observer at rest (drive torque holding gravity) sees no external torque
    obs = DisturbanceObserver(gear, friction='none', gravity=True)
    for x in q[:3]:
        obs.reset()
        for _ in range(200):
            est = obs(gear.lever_torque(x), x, 0.0, 25.0)
        assert abs(est) < 1e-9 * gear.mgl


def test_old_gear_files_hang_at_zero_and_round_trip(tmp_path):
    files = sorted(glob.glob('config/*.yaml'))
    assert files
    q = np.linspace(-math.pi, math.pi, 13)
    for path in files:
        gear = load_gear(path)
        assert gear.lever_offset == 0.0
        np.testing.assert_allclose(gear.lever_torque(q), gear.mgl * np.sin(q))
        # written back, a file without the key stays without it
        out = tmp_path / 'g.yaml'
        save_gear(gear, str(out))
        assert 'angle_offset' not in out.read_text()
    shifted = load_gear(files[0]).replace({'lever': {'angle_offset': -0.25}})
    save_gear(shifted, str(tmp_path / 's.yaml'))
    assert load_gear(str(tmp_path / 's.yaml')).lever_offset == -0.25
