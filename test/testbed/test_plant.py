# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Test bed sanity: energy, thermal balance, sensors, gain design, observer response."""
import math

from friction_joint import FrictionJointError, gear_from_dict, load_gear
from friction_joint.control.controller import Controller, pd_gains, step_metrics
from friction_joint.control.observer import DisturbanceObserver
from friction_joint.testbed.plant import Plant
from friction_joint.testbed.sensors import StreamingSOS
from friction_joint.testbed.thermal import ThermalModel
import numpy as np
import pytest
from scipy import signal


def frictionless(inertia=0.2, mgl=11.0):
    length = 0.14
    return gear_from_dict({'gear_ratio': 80.0, 'inertia': inertia,
                           'friction': {'fc': [0.0], 'fv': [0.0]},
                           'lever': {'mass': mgl / (9.81 * length), 'length': length}})


def energy(gear, q, qd):
    return 0.5 * gear.inertia * qd ** 2 + gear.mgl * (1.0 - np.cos(q))


def test_frictionless_pendulum_conserves_energy():
    g = frictionless()
    p = Plant(g, q0=1.0, ideal_sensors=True)
    out = p.run(np.zeros(3 * 3000))
    e = energy(g, out['q_true'], out['qd_true'])
    e0 = g.mgl * (1 - math.cos(1.0))
    assert np.max(np.abs(e - e0)) < 1e-4 * e0
    assert out['q_true'].min() < -0.99           # swings through to the other side


def test_unstable_loop_ends_with_a_named_error_not_garbage():
    from friction_joint.exceptions import SimulationError
    truth = load_gear('config/csd25_truth.yaml')
    p = Plant(truth, q0=0.01)
    samples = 0
    with pytest.raises(SimulationError, match='no longer finite'):
        for _ in range(200_000):                 # positive feedback: grows as exp(t sqrt(k/J))
            p.step(5e3 * p.last.q if p.last is not None else 0.0)
            samples += 1
    assert samples > 100                         # it ran, then stopped at the blow-up
    with pytest.raises(SimulationError, match='command inf'):
        Plant(truth).step(float('inf'))


def test_pendulum_with_friction_dissipates_and_sticks():
    truth = load_gear('config/csd25_truth.yaml')
    p = Plant(truth, q0=1.2, ideal_sensors=True, xi0=30.0)
    out = p.run(np.zeros(6 * 3000))
    e = energy(truth, out['q_true'], out['qd_true'])
    # energy (mechanical, plus at most the bristle's stored energy) never grows
    stored = 4.7 ** 2 / (2 * truth.friction.lugre.sigma0)
    assert np.all(np.diff(e) < stored)
    assert e[-1] < 0.2 * e[0]
    # at rest, gravity is held by friction below the break-away torque
    assert abs(out['qd_true'][-1]) < 1e-3
    assert truth.mgl * abs(math.sin(out['q_true'][-1])) <= 4.7 + 0.3


def test_thermal_model_energy_balance_and_steady_state():
    th = ThermalModel(450.0, 1.2, 25.0, initial=30.0)
    dt = 1.0 / 3000
    rng = np.random.default_rng(0)
    power = np.abs(rng.normal(8.0, 3.0, 30000))
    xi = np.array([th.step(p, dt) for p in power])
    # C dxi = P dt - (xi - amb)/R dt, integrated by the trapezoidal rule
    xi_all = np.concatenate([[30.0], xi])
    loss = np.sum(0.5 * (xi_all[1:] + xi_all[:-1]) - 25.0) / 1.2 * dt
    assert 450.0 * (xi[-1] - 30.0) == pytest.approx(np.sum(power) * dt - loss, rel=1e-3)
    for _ in range(4000):
        th.step(10.0, 5.0)
    assert th.xi == pytest.approx(25.0 + 10.0 * 1.2, abs=1e-9)


def test_friction_losses_heat_the_gear():
    truth = load_gear('config/csd25_truth.yaml').replace({'lever': {'mass': 0.0}})
    p = Plant(truth, xi0=27.0, seed=3)
    out = p.run(np.full(3 * 3000, 8.0))
    assert out['xi_true'][-1] > 27.0 + 0.02                  # ~10 W for 3 s
    # the sensor reads in 0.0625 degC steps and lags behind
    assert np.allclose(out['xi'] / 0.0625, np.round(out['xi'] / 0.0625))
    assert out['xi'][-1] <= out['xi_true'][-1] + 0.0625


def test_sensors():
    truth = load_gear('config/csd25_truth.yaml')
    p = Plant(truth, xi0=30.0, seed=1)
    out = p.run(8.0 * np.sin(2 * np.pi * 0.5 * np.arange(6000) / 3000))
    res = 2 * math.pi / 2 ** 25
    assert np.allclose(out['q'] / res, np.round(out['q'] / res))
    assert np.max(np.abs(out['q'] - out['q_true'])) <= res / 2 + 1e-15
    # filtered velocity follows the truth with a small lag
    assert (np.sqrt(np.mean((out['qd'] - out['qd_true']) ** 2))
            < 0.02 * np.max(np.abs(out['qd_true'])))
    noise = out['tau_link'] - out['tau_ext']
    assert 0.02 < np.std(noise) < 0.04
    sos = signal.butter(2, 250.0, fs=3000.0, output='sos')
    x = np.random.default_rng(2).normal(size=500)
    f = StreamingSOS(sos)
    np.testing.assert_allclose([f(v) for v in x], signal.sosfilt(sos, x), atol=1e-12)


@pytest.mark.parametrize('seed', [0, 1, 2])
def test_gains_meet_rise_time_and_overshoot(seed):
    rng = np.random.default_rng(seed)
    inertia = rng.uniform(0.05, 0.5)
    rise = rng.uniform(0.03, 0.08)
    overshoot = rng.uniform(0.02, 0.15)
    g = frictionless(inertia=inertia)
    kp, kd = pd_gains(inertia, rise_time=rise, overshoot=overshoot)
    for ideal, tol_rise, tol_os in ((True, 0.02, 0.005), (False, 0.05, 0.015)):
        p = Plant(g, ideal_sensors=ideal, seed=seed)
        c = Controller(g, kp, kd, friction='none', dt=p.dt)
        s = p.last
        q = []
        for _ in range(int(6 * rise * 3000)):
            s = p.step(c(s.q, s.qd, s.xi, 0.1))
            q.append(s.q_true)
        t = p.dt * np.arange(1, len(q) + 1)
        tr, os_ = step_metrics(t, np.array(q), 0.1)
        assert tr == pytest.approx(rise, rel=tol_rise)
        assert os_ == pytest.approx(overshoot, abs=tol_os)


def test_controller_dt_argument_advances_the_friction_state():
    model = load_gear('config/csd25.yaml')
    rng = np.random.default_rng(11)
    period = 1.0 / 3000.0
    k = int(rng.integers(2, 6))                  # a real-time loop that skipped k - 1 states
    a = Controller(model, 500.0, 10.0, friction='lugre', dt=period)
    b = Controller(model, 500.0, 10.0, friction='lugre', dt=k * period)
    c = Controller(model, 500.0, 10.0, friction='lugre', dt=period)
    for i in range(5):
        args = (0.1 + 0.01 * i, 0.05, 30.0, 0.12, 0.3, 0.0)
        ta, tb, tc = a(*args, dt=k * period), b(*args), c(*args)
        assert ta == tb
        assert abs(ta - tc) > 1e-6               # the bristle state moved by k periods, not one


def test_pd_gains_rejects_bad_specs():
    for inertia, rise, overshoot in ((0.1, 0.04, 0.0), (0.1, 0.04, 1.2), (0.1, -1.0, 0.06),
                                     (-0.1, 0.04, 0.06)):
        with pytest.raises(FrictionJointError):
            pd_gains(inertia, rise_time=rise, overshoot=overshoot)


@pytest.mark.parametrize('seed', [5, 6])
def test_observer_recovers_contact_torque_step(seed):
    """Exact model, joint held by the controller: tau_ext^ = Q(s) tau_ext (first order)."""
    rng = np.random.default_rng(seed)
    beta = rng.uniform(30.0, 150.0)
    step = rng.uniform(-5.0, 5.0)
    g = frictionless()
    p = Plant(g, ideal_sensors=True)
    c = Controller(g, *pd_gains(g.inertia), friction='none', dt=p.dt)
    o = DisturbanceObserver(g, beta=beta, dt=p.dt, friction='none', gravity=True)
    s = p.last
    k0 = 300
    est = []
    for k in range(k0 + int(8 / beta * 3000)):
        tau = c(s.q, s.qd, s.xi, 0.0)
        s = p.step(tau, tau_contact=step if k >= k0 else 0.0)
        est.append(o(s.effort, s.q, s.qd, s.xi))
    est = np.array(est[k0:])
    t = p.dt * np.arange(1, len(est) + 1)
    np.testing.assert_allclose(est, step * (1 - np.exp(-beta * t)), atol=0.02 * abs(step))


def test_observer_with_exact_friction_model_sees_only_the_contact():
    truth = load_gear('config/csd25.yaml').replace({'friction': {
        'offset': 0.2,
        'position_ripple': {'cycles_per_rev': 160.0, 'amplitude': [0.1], 'phase': [0.5]}}})
    p = Plant(truth, ideal_sensors=True, xi0=30.0)
    c = Controller(truth, *pd_gains(truth.inertia), friction='lugre', dt=p.dt)
    with_f = DisturbanceObserver(truth, beta=60.0, dt=p.dt, friction='lugre', gravity=True)
    without = DisturbanceObserver(truth, beta=60.0, dt=p.dt, friction='none', gravity=True)
    s = p.last
    err_with, err_without = [], []
    for k in range(4 * 3000):
        t = k * p.dt
        contact = 3.0 if 1.0 <= t < 3.0 else 0.0
        qd_ = 0.8 * math.sin(1.5 * t)
        s = p.step(c(s.q, s.qd, s.xi, qd_, 1.2 * math.cos(1.5 * t), -1.8 * math.sin(1.5 * t)),
                   tau_contact=contact)
        e1, e2 = with_f(s.effort, s.q, s.qd, s.xi), without(s.effort, s.q, s.qd, s.xi)
        if t > 0.3:
            err_with.append(e1 - s.tau_ext + truth.mgl * math.sin(s.q_true))
            err_without.append(e2 - s.tau_ext + truth.mgl * math.sin(s.q_true))
    # the ideal estimate is Q(s) applied to the contact torque: compare with it
    contact = np.array([3.0 if 1.0 <= k * p.dt < 3.0 else 0.0 for k in range(4 * 3000)])
    num, den, _ = signal.cont2discrete(([60.0], [1.0, 60.0]), p.dt, method='bilinear')
    ideal = signal.lfilter(np.ravel(num), den, contact)[-len(err_with):]
    rms_with = np.sqrt(np.mean(np.square(np.array(err_with) + contact[-len(err_with):] - ideal)))
    rms_without = np.sqrt(np.mean(np.square(err_without)))
    assert rms_with < 0.1 and rms_without > 1.5


def test_plant_refuses_non_finite_inputs_and_keeps_running():
    """A NaN/inf command or contact torque is refused before anything changes."""
    from friction_joint.exceptions import SimulationError
    truth = load_gear('config/csd25_truth.yaml')
    ref, p = Plant(truth, xi0=30.0, seed=4), Plant(truth, xi0=30.0, seed=4)
    cmd = 14.0 * np.sin(np.arange(900) / 150.0)
    out_ref, out, errors = [], [], []
    for k, c in enumerate(cmd):
        if k in (100, 400):
            for bad in ((float('nan'), 0.0), (0.0, float('inf')), (float('-inf'), 1.0)):
                try:
                    p.step(bad[0], tau_contact=bad[1])
                except SimulationError as exc:
                    errors.append(str(exc))
        out_ref.append(ref.step(c).q)
        out.append(p.step(c).q)
    assert out == out_ref                                    # no trace of the refused steps
    assert len(errors) == 6
    assert 'command nan Nm' in errors[0] and 'contact torque inf Nm' in errors[1]


def test_runaway_error_names_the_contact_torque():
    from friction_joint.exceptions import SimulationError
    truth = load_gear('config/csd25_truth.yaml')
    with pytest.raises(SimulationError) as info:
        Plant(truth).step(0.0, tau_contact=1e308)
    assert 'contact torque 1e+308 Nm' in str(info.value)
    assert 'no longer finite' in str(info.value)


def test_input_limits_follow_the_documented_rule():
    from friction_joint.testbed.plant import (ACCELERATION_TIME, InputLimits, MAX_INPUT_SPEED,
                                              PLAUSIBILITY_FACTOR)
    from friction_joint.models.static import StaticFriction
    model = load_gear('config/csd25.yaml')
    lim = InputLimits(model)
    speed = max(MAX_INPUT_SPEED / model.gear_ratio, math.sqrt(4 * model.mgl / model.inertia))
    assert lim.speed == pytest.approx(speed)
    assert lim.velocity == pytest.approx(PLAUSIBILITY_FACTOR * speed)
    # friction: at least the break-away torque, at most the curve's value at speed V
    xi = np.linspace(*model.friction.temperature_range, 9)
    top = np.max(StaticFriction(model.friction).torque(speed, xi, model.mgl))
    friction = lim.torque_scale - model.mgl - model.inertia * speed / ACCELERATION_TIME
    assert max(4.48, top) - 1e-9 <= friction <= top + 1.0
    assert lim.torque == pytest.approx(PLAUSIBILITY_FACTOR * lim.torque_scale)
    # CSD-25 numbers: 10 x (11 Nm lever + ~19 Nm friction + 31 Nm inertia) ~ 600 Nm, 141 rad/s
    assert 400 < lim.torque < 900 and 100 < lim.velocity < 200
    assert lim.position > 1e8 and lim.temperature[0] < 0 < 100 < lim.temperature[1]
    assert lim.check('velocity', 0.6) is None and lim.check('torque', -lim.torque) is None
    for quantity, value in (('velocity', 1e308), ('torque', float('nan')),
                            ('torque', 1.01 * lim.torque), ('temperature', -300.0),
                            ('position', -1e12), ('velocity', float('-inf'))):
        reason = lim.check(quantity, value)
        assert reason and quantity in reason and f'{value:g}' in reason


def test_input_limits_scale_with_the_gear():
    from friction_joint.testbed.plant import InputLimits
    base = frictionless(inertia=0.2, mgl=11.0)
    lim = InputLimits(base)
    heavier = InputLimits(frictionless(inertia=0.2, mgl=44.0))
    slower = InputLimits(base.replace({'gear_ratio': 160.0}))
    assert heavier.torque > lim.torque and heavier.velocity > lim.velocity
    assert InputLimits(frictionless(inertia=0.8, mgl=11.0)).torque > lim.torque
    assert slower.velocity <= lim.velocity
    rough = InputLimits(base.replace({'friction': {'fc': [20.0], 'fv': [2.0]}}))
    assert rough.torque > lim.torque + 10 * 20.0
    bare = InputLimits(frictionless(inertia=0.01, mgl=0.0))      # no lever, no friction
    assert 0 < bare.torque < lim.torque and bare.velocity > 0
    assert InputLimits(base, factor=2.0).torque == pytest.approx(lim.torque / 5.0)
