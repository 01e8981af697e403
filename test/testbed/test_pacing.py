# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Realtime pacing (:class:`~friction_joint.testbed.pacing.Pacing`) on the simulated plant, no ROS.

A starved controller answers the newest state only now and then, late: the loop
of a busy machine.  Without pacing the drive applies commands too old to keep
the lever up (the watchdog takes the torque off, the lever falls); with pacing
the simulation waits for the answers and the joint follows its reference.
The machine's stalls, the lever's start and the reference are drawn at random.
"""
from friction_joint import load_gear
from friction_joint.control import Controller, GainDesign, SineTrajectory
from friction_joint.testbed import CommandWatchdog, InputLimits, Pacing, Plant
import numpy as np
import pytest

MODEL, TRUTH = 'config/csd25.yaml', 'config/csd25_truth.yaml'
PUBLISH_RATE = 1000.0


def starved_loop(seed, lead_s, seconds=2.0):
    """
    Run the realtime loop on a wall clock of 0.1 ms with a controller that wakes rarely.

    Return the simulated positions, the reference and the pacing record.
    """
    rng = np.random.default_rng(seed)
    truth, model = load_gear(TRUTH), load_gear(MODEL)
    plant = Plant(truth, q0=0.0, seed=seed)
    per_tick = int(round(plant.rate / PUBLISH_RATE))
    timeout = 0.05
    dog = CommandWatchdog(plant.rate, timeout, 'zero', inertia=truth.inertia,
                          torque_limit=InputLimits(truth).torque)
    kp, kd = GainDesign().gains(model.inertia)
    ctrl = Controller(model, kp, kd, friction='lugre', dt=1.0 / PUBLISH_RATE)
    traj = SineTrajectory(float(rng.uniform(0.2, 0.4)), omega=float(rng.uniform(1.0, 2.0)))
    pace = Pacing(int(round(lead_s * plant.rate)), patience=10.0)
    pace.expect(plant.k)
    gap = float(rng.uniform(0.04, 0.12))             # mean wall time between wakes
    wall, next_tick, wake = 0.0, 0.0, 0.0
    tau_cmd, last_answer = 0.0, None
    inbox = []                                       # (arrival wall time, answered step, tau)
    q, ref = [], []
    step = 1e-4
    while plant.t < seconds:
        wall += step
        if wall >= wake:                             # the controller runs: the newest state
            s = plant.last
            t = plant.k / plant.rate
            q_d, qd_d, qdd_d = traj(t)
            dt = None if last_answer is None else max(t - last_answer, 1.0 / PUBLISH_RATE)
            tau = ctrl(s.q, s.qd, s.xi, q_d, qd_d, qdd_d, dt=dt)
            last_answer = t
            inbox.append((wall + float(rng.uniform(0.002, 0.03)), plant.k, tau))
            wake = wall + float(rng.exponential(gap))
        for item in [m for m in inbox if m[0] <= wall]:
            inbox.remove(item)
            if (plant.k - item[1]) / plant.rate <= timeout:      # else refused as stale
                tau_cmd = item[2]
                dog.command(plant.k)
                pace.answered(item[1])
        held, waited, _ = pace.hold(plant.k + per_tick, wall)
        next_tick += waited
        if held or wall < next_tick:
            continue
        next_tick += 1.0 / PUBLISH_RATE
        for _ in range(per_tick):
            plant.step(dog.torque(plant.k, tau_cmd, plant.last.qd)[0])
        q.append(plant.last.q)
        ref.append(traj(plant.k / plant.rate)[0])
    return np.asarray(q), np.asarray(ref), pace


@pytest.mark.parametrize('seed', [3, 17, 29])
def test_pacing_keeps_a_starved_loop_on_its_reference(seed):
    """With pacing the lever follows its reference; without it the same machine loses it."""
    q, ref, pace = starved_loop(seed, lead_s=0.02)
    amplitude = np.max(np.abs(ref))
    assert pace.pauses > 10 and pace.waited > 0.5      # the machine really was too slow
    assert np.max(np.abs(q - ref)) < 0.25 * amplitude, np.max(np.abs(q - ref))
    q_free, ref_free, free = starved_loop(seed, lead_s=0.0)
    assert free.pauses == 0
    assert np.max(np.abs(q_free - ref_free)) > 2 * np.max(np.abs(q - ref))


def test_pacing_gives_up_on_a_silent_controller_and_resumes_on_a_recent_answer():
    """A controller that never answers holds the joint ``patience`` s, then no longer."""
    pace = Pacing(20, patience=0.5)
    assert pace.hold(100, 0.0) == (False, 0.0, False)        # no answer yet: run
    pace.answered(100)
    assert pace.hold(120, 1.0)[0] is False                    # within the lead
    assert pace.hold(121, 1.0) == (True, 0.0, False)          # beyond it: wait
    assert pace.hold(121, 1.4) == (True, 0.0, False)
    held, waited, gave_up = pace.hold(121, 1.6)               # patience is over
    assert (held, gave_up) == (False, True) and waited == pytest.approx(0.6)
    assert pace.hold(500, 2.0)[0] is False                    # runs on without it
    pace.answered(499)                                        # a recent answer: paced again
    assert pace.hold(520, 2.1)[0] is True
    assert (pace.pauses, pace.given_up, pace.count) == (2, 1, 2)
