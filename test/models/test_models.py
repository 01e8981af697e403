# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Friction models against known behaviour: steady state, exact update, stiffness, batching."""
import math

from friction_joint import GMS, Joint, load_gear, LuGre, StaticFriction
import numpy as np
import pytest

DT = 1.0 / 3000.0


@pytest.fixture(scope='module')
def gear():
    # CSD-25 Table I curve plus a load dependency on Fc and Fv
    return load_gear('config/csd25.yaml').replace(
        {'friction': {'fc_load': [0.03], 'fv_load': [0.004, -1e-4]}})


@pytest.mark.parametrize('xi', [22.0, 27.0, 33.0, 37.0, 45.0])
@pytest.mark.parametrize('tau_l', [0.0, 4.0, 11.0])
def test_steady_state_equals_static_curve(gear, xi, tau_l):
    sf = StaticFriction(gear.friction)
    v = np.array([-3.5, -0.4, -0.02, 0.005, 0.08, 1.0, 3.5])
    ref = sf.torque(v, xi, tau_l)
    lug = LuGre([gear.friction] * len(v))
    gms = GMS([gear.friction] * len(v))
    qd = np.repeat(v[:, None], 6000, axis=1)      # 2 s at 3 kHz
    t_l = lug.simulate(qd, xi, tau_l, DT)[:, -1]
    t_g = gms.simulate(qd, xi, tau_l, DT)[:, -1]
    np.testing.assert_allclose(t_l, ref, rtol=1e-6)
    np.testing.assert_allclose(t_g, ref, rtol=1e-6)


def test_temperature_and_load_flow_into_dynamic_models(gear):
    lug = LuGre(gear.friction)
    cold = lug.simulate(np.full(3000, 1.0), 25.0, 0.0, DT, z0=0.0)[-1]
    warm = lug.simulate(np.full(3000, 1.0), 35.0, 0.0, DT, z0=0.0)[-1]
    loaded = lug.simulate(np.full(3000, 1.0), 35.0, 10.0, DT, z0=0.0)[-1]
    assert cold > warm + 1.0            # Table I: friction falls with temperature
    assert loaded == pytest.approx(warm + 0.03 * 10 + StaticFriction(gear.friction).torque(
        1.0, 35.0, 10.0)[0] - StaticFriction(gear.friction).torque(1.0, 35.0, 0.0)[0] - 0.3,
        rel=1e-6)


def test_lugre_update_is_exact_for_constant_velocity(gear):
    """z(t) = zss + (z0 - zss) exp(-a t) with a = sigma0 |v| / |g| (eq. 10)."""
    f = gear.friction
    v, xi = 0.002, 30.0
    p = StaticFriction(f).parameters(xi)
    ga = p['fc'][0] + (p['fs'][0] - p['fc'][0]) * math.exp(-(80 * v / p['vs'][0]) ** 2)
    a = f.lugre.sigma0 * v / ga
    t = DT * np.arange(1, 301)
    z = ga / f.lugre.sigma0 * (1 - np.exp(-a * t))
    s = p['fv'][0] * (80 * v) ** p['delta_v'][0]
    expected = f.lugre.sigma0 * z + f.lugre.sigma1 * (v - a * z) + s
    got = LuGre(f).simulate(np.full(300, v), xi, 0.0, DT, z0=0.0)
    np.testing.assert_allclose(got, expected, rtol=1e-10)


def test_step_matches_simulate_and_batch_matches_single(gear):
    rng = np.random.default_rng(4)
    qd = np.cumsum(rng.normal(0, 0.02, 600))
    ref = LuGre(gear.friction).simulate(qd, 30.0, 2.0, DT, z0=0.0)
    one = LuGre(gear.friction)
    stepped = [one.step(v, 30.0, 2.0, DT) for v in qd]
    np.testing.assert_allclose(stepped, ref, rtol=0, atol=1e-12)
    other = gear.replace({'friction': {'lugre': {'sigma0': 5e4}}}).friction
    batch = LuGre([other, gear.friction]).simulate(qd, 30.0, 2.0, DT, z0=0.0)
    np.testing.assert_array_equal(batch[1], ref)
    g_one = GMS(gear.friction).simulate(qd, 30.0, 2.0, DT)
    g_b = GMS([other, gear.friction]).simulate(np.stack([qd, qd]), 30.0, 2.0, DT)
    np.testing.assert_array_equal(g_b[1], g_one)


def test_dynamic_models_are_continuous_at_reversal(gear):
    t = DT * np.arange(3000)
    qd = 0.05 * np.sin(2 * np.pi * 1.0 * t)
    for model in (LuGre(gear.friction), GMS(gear.friction)):
        tau = model.simulate(qd, 30.0, 0.0, DT)
        # a bristle/element torque can change at most by stiffness * |dq| per step
        assert np.max(np.abs(np.diff(tau))) < 0.2
    static = StaticFriction(gear.friction).torque(qd, 30.0)
    assert np.max(np.abs(np.diff(static))) > 8.0      # jumps by 2 Fs


def _reversing_torque(n, amp=9.0):
    t = DT * np.arange(n)
    return amp * np.sin(2 * np.pi * 0.7 * t) + 2.0 * np.sin(2 * np.pi * 5.3 * t)


@pytest.mark.parametrize('model', ['lugre', 'gms'])
@pytest.mark.parametrize('stiffness', [2e4, 1e6, 1e7])
def test_coupled_joint_stays_bounded_for_stiff_friction(gear, model, stiffness):
    """No divergence for sigma0 (or sum k_i) up to 1e7 Nm/rad at 3 kHz."""
    g = gear.replace({'friction': {'lugre': {'sigma0': stiffness, 'sigma1': 0.0},
                                   'gms': {'k': [0.6 * stiffness, 0.3 * stiffness,
                                                 0.1 * stiffness]}}})
    j = Joint(g, model=model, mgl=5.0)
    tr = j.simulate(_reversing_torque(9000), DT, xi=30.0)
    assert np.all(np.isfinite(tr.q)) and np.all(np.isfinite(tr.tau_r))
    # the drive can deliver at most 11 Nm; friction opposes it: |qd| stays moderate
    assert np.max(np.abs(tr.qd)) < 11.0 / 0.12 * 3.0
    # friction torque magnitude bounded by the largest static value plus what
    # inertia and gravity can pass on within the bristle compliance
    assert np.max(np.abs(tr.tau_r)) < 20.0
    # held below breakaway, the joint does not creep
    j.reset()
    small = j.simulate(np.full(6000, 2.0), DT, xi=30.0)
    assert abs(small.q[-1]) < 4.48 / (0.1 * stiffness) and abs(small.qd[-1]) < 1e-3


@pytest.mark.parametrize('model', ['static', 'lugre', 'gms'])
def test_joint_steady_sliding_balances_torque(gear, model):
    j = Joint(gear, model=model)
    tr = j.simulate(np.full(24000, 6.0), DT, xi=30.0)     # 8 s: ~30 viscous time constants
    v = tr.qd[-1]
    assert v > 0.05 and abs(tr.qd[-1] - tr.qd[-300]) < 1e-6
    assert StaticFriction(gear.friction).torque(v, 30.0)[0] == pytest.approx(6.0, rel=1e-5)
    assert tr.tau_r[-1] == pytest.approx(6.0, rel=1e-5)


def test_static_joint_sticks_below_breakaway(gear):
    j = Joint(gear, model='static')
    tr = j.simulate(np.full(3000, 4.0), DT, xi=30.0)
    assert np.all(tr.q == 0.0)
    tr = j.simulate(np.full(300, 5.0), DT, xi=30.0)
    assert tr.qd[-1] > 0.0


@pytest.mark.parametrize('offset', [-0.3, 0.25])
def test_offset_is_part_of_every_model(gear, offset):
    g = gear.replace({'friction': {'offset': offset}})
    v = np.array([-1.0, 0.05, 2.0])
    ref = StaticFriction(gear.friction).torque(v, 30.0, 3.0) + offset
    np.testing.assert_allclose(StaticFriction(g.friction).torque(v, 30.0, 3.0), ref, rtol=1e-12)
    qd = np.repeat(v[:, None], 6000, axis=1)
    np.testing.assert_allclose(LuGre([g.friction] * 3).simulate(qd, 30.0, 3.0, DT)[:, -1], ref,
                               rtol=1e-6)
    np.testing.assert_allclose(GMS([g.friction] * 3).simulate(qd, 30.0, 3.0, DT)[:, -1], ref,
                               rtol=1e-6)
    # in sliding the friction magnitude differs by direction by 2 |offset|
    j = Joint(g, model='static')
    up = j.simulate(np.full(24000, 6.0), DT, xi=30.0)
    assert up.tau_r[-1] == pytest.approx(6.0, rel=1e-5)
    assert StaticFriction(gear.friction).torque(up.qd[-1], 30.0)[0] == pytest.approx(
        6.0 - offset, rel=1e-5)
