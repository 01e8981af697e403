# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The drive's command watchdog on the simulated plant (no ROS)."""
from friction_joint import load_gear
from friction_joint.testbed import CommandWatchdog, InputLimits, Plant
import numpy as np
import pytest

TRUTH = 'config/csd25_truth.yaml'


def run(reaction, seed):
    """Drive with a valid command, then keep the last one applied beyond the timeout."""
    rng = np.random.default_rng(seed)
    gear = load_gear(TRUTH)
    plant = Plant(gear, q0=float(rng.uniform(0.3, 1.2)), seed=seed)
    timeout = float(rng.uniform(0.02, 0.3))
    dog = CommandWatchdog(plant.rate, timeout, reaction, inertia=gear.inertia,
                          torque_limit=InputLimits(gear).torque)
    tau_cmd = float(rng.uniform(20.0, 40.0))           # beyond gravity and friction: it runs
    events, qd, applied = [], [], []
    n_valid = int(0.2 * plant.rate)
    for k in range(int(2.0 * plant.rate)):
        if k < n_valid:
            dog.command(plant.k)
        tau, event = dog.torque(plant.k, tau_cmd, plant.last.qd)
        if event:
            events.append((plant.k, event))
        s = plant.step(tau)
        qd.append(s.qd)
        applied.append(tau)
    return dog, timeout, n_valid, events, np.array(qd), np.array(applied), plant.rate


@pytest.mark.parametrize('seed', [1, 2, 3])
def test_zero_reaction_turns_the_torque_off_after_the_timeout(seed):
    dog, timeout, n_valid, events, qd, applied, rate = run('zero', seed)
    trip = n_valid - 1 + int(np.floor(timeout * rate)) + 1
    assert events == [(trip, 'tripped')]
    assert np.all(applied[:trip] > 20.0) and np.all(applied[trip:] == 0.0)


@pytest.mark.parametrize('seed', [4, 5, 6])
def test_brake_reaction_stops_the_joint(seed):
    dog, timeout, n_valid, events, qd, applied, rate = run('brake', seed)
    assert dog.trips == 1 and dog.tripped
    trip = events[0][0]
    assert abs(qd[trip]) > 1.0                          # it was moving fast
    # a damping torque against the motion; the joint comes (nearly) to rest within 10
    # brake time constants, held against gravity only by friction and the brake
    assert np.all(applied[trip:] * qd[trip - 1:-1] <= 0)
    assert np.max(np.abs(qd[trip + int(0.5 * rate):])) < 0.1 * abs(qd[trip])


def test_a_valid_command_resumes_the_drive():
    dog = CommandWatchdog(1000.0, 0.01, 'zero', inertia=0.2, torque_limit=100.0)
    assert dog.torque(0, 5.0, 0.0) == (5.0, None)     # before any command: the initial one
    dog.command(0)
    assert dog.torque(10, 5.0, 0.0) == (5.0, None)
    assert dog.torque(11, 5.0, 0.0) == (0.0, 'tripped')
    dog.command(12)
    assert dog.torque(12, 7.0, 0.0) == (7.0, 'resumed')
    assert dog.trips == 1
    with pytest.raises(ValueError, match='reaction'):
        CommandWatchdog(1000.0, 0.01, 'coast', inertia=0.2, torque_limit=100.0)
