# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Observer, controller and filters never hold non-finite values, whatever they are fed.

A sample with a NaN/inf input is refused (``ValueError``) and leaves no trace:
the outputs afterwards are bit-identical to those of an object that never saw
it.  Finite inputs that overflow inside (1e308 rad/s) are refused too; the
state is reset to finite values and the outputs return to the clean ones.
"""
import math

from friction_joint import load_gear
from friction_joint.control.controller import Controller, pd_gains
from friction_joint.control.observer import DisturbanceObserver
from friction_joint.testbed.sensors import StreamingSOS
import numpy as np
import pytest
from scipy import signal

MODEL = load_gear('config/csd25.yaml')
DT = 1.0 / 3000.0
KINDS = ('none', 'static', 'lugre', 'gms')
NAN, INF = float('nan'), float('inf')


def clean(n):
    """Return (tau, q, qd, xi) rows of a sliding sine motion (no reversal after 0.1 s)."""
    t = 0.1 + DT * np.arange(n)
    q = 0.4 * np.sin(1.5 * t)
    qd = 0.6 * np.cos(1.5 * t)
    tau = MODEL.mgl * np.sin(q) + 3.0 * np.tanh(50 * qd) + 0.5 * np.sin(7.0 * t)
    return np.column_stack([tau, q, qd, np.full(n, 30.0)])


def refused(fn, *args, **kw):
    """Return whether ``fn`` refused the sample with a ValueError (it must not raise else)."""
    try:
        fn(*args, **kw)
    except ValueError:
        return True
    return False


def observer_state(obs):
    return [obs.estimate, obs.tau_friction] + [v for z in obs.q_filter._z for v in z]


@pytest.mark.parametrize('kind', KINDS)
def test_observer_refuses_non_finite_samples_without_a_trace(kind):
    data = clean(900)
    ref = DisturbanceObserver(MODEL, beta=60.0, dt=DT, friction=kind)
    obs = DisturbanceObserver(MODEL, beta=60.0, dt=DT, friction=kind)
    bad = [(NAN, 0.1, 0.2, 30.0), (0.0, INF, 0.2, 30.0), (0.0, 0.1, -INF, 30.0),
           (0.0, 0.1, 0.2, NAN), (0.0, 0.1, 1e308, 30.0), (1e308, 0.1, 1e308, 30.0)]
    out_ref, out, answers, finite = [], [], [], []
    for k, row in enumerate(data):
        if k % 100 == 50:
            for sample in bad:
                answers.append(refused(obs, *sample))
                finite.append(all(math.isfinite(v) for v in observer_state(obs)))
        out_ref.append(ref(*row))
        out.append(obs(*row))
    assert np.array_equal(out, out_ref)
    assert all(finite) and all(answers)


@pytest.mark.parametrize('kind', ['static', 'lugre', 'gms'])
def test_observer_overflow_inside_resets_to_finite_and_recovers(kind):
    """Finite inputs that overflow in the friction model (huge velocity) reset the observer."""
    data = clean(3 * 3000)
    ref = DisturbanceObserver(MODEL, beta=60.0, dt=DT, friction=kind)
    obs = DisturbanceObserver(MODEL, beta=60.0, dt=DT, friction=kind)
    out_ref, out = [], []
    for k, row in enumerate(data):
        if k == 600:
            # tau + beta J qd is finite, the friction curve is not
            answer = refused(obs, -1e308, 0.1, 7e306, 30.0)
            finite = all(math.isfinite(v) for v in observer_state(obs))
        out_ref.append(ref(*row))
        out.append(obs(*row))
    err = np.abs(np.array(out) - out_ref)
    assert np.all(np.isfinite(out)) and finite
    assert np.max(err[600 + 3000:]) < 1e-9         # back on the clean output within 1 s
    assert answer


def controller_rows(n):
    data = clean(n)
    return [(q, qd, xi, q + 0.01, qd, 0.0) for _, q, qd, xi in data]


@pytest.mark.parametrize('kind', KINDS)
def test_controller_refuses_non_finite_samples_without_a_trace(kind):
    gains = pd_gains(MODEL.inertia)
    ref = Controller(MODEL, *gains, friction=kind, dt=DT)
    ctrl = Controller(MODEL, *gains, friction=kind, dt=DT)
    rows = controller_rows(900)
    bad = [(NAN, 0.2, 30.0, 0.0), (0.1, INF, 30.0, 0.0), (0.1, 0.2, NAN, 0.0),
           (0.1, 0.2, 30.0, -INF), (0.1, 1e308, 30.0, 0.0)]
    out_ref, out, answers = [], [], []
    for k, row in enumerate(rows):
        if k % 100 == 50:
            answers += [refused(ctrl, *sample) for sample in bad]
            answers.append(refused(ctrl, *row, dt=NAN))
        out_ref.append(ref(*row))
        out.append(ctrl(*row))
    assert np.array_equal(out, out_ref)
    assert all(answers)


@pytest.mark.parametrize('kind', ['static', 'lugre', 'gms'])
def test_controller_feed_forward_overflow_resets_and_recovers(kind):
    gains = pd_gains(MODEL.inertia)
    ref = Controller(MODEL, *gains, friction=kind, dt=DT)
    ctrl = Controller(MODEL, *gains, friction=kind, dt=DT)
    out_ref, out = [], []
    for k, row in enumerate(controller_rows(3 * 3000)):
        if k == 600:
            answer = refused(ctrl, 0.1, 7e306, 30.0, 0.0)      # the friction curve overflows
        out_ref.append(ref(*row))
        out.append(ctrl(*row))
    err = np.abs(np.array(out) - out_ref)
    assert np.all(np.isfinite(out))
    assert np.max(err[600 + 3000:]) < 1e-9
    assert answer


def test_streaming_sos_refuses_what_would_make_its_state_non_finite():
    sos = signal.butter(2, 250.0, fs=3000.0, output='sos')
    x = np.random.default_rng(4).normal(size=300)
    f = StreamingSOS(sos)
    out, answers = [], []
    for k, v in enumerate(x):
        if k == 100:
            answers += [refused(f, bad) for bad in (NAN, INF, -INF)]
            assert all(math.isfinite(s) for z in f._z for s in z)
        out.append(f(v))
    np.testing.assert_allclose(out, signal.sosfilt(sos, x), rtol=0, atol=1e-12)
    assert all(answers)
