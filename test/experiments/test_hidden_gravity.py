# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The hidden ``gravity`` effect: the truth's lever differs from the base's (mass, angle offset).

A recording without ``/link_torque`` is analysed as the diagnosis would (tau_ext from the
BASE's lever): the friction torque it gives carries m g l sin(q - q0) (truth) minus the
base's lever torque, the same in both directions of motion, of the drawn size.
"""
import math
import os

import friction_joint
from friction_joint.experiments.hidden import (apply_effect, draw_effect, EFFECT_RANGES, HIDEABLE,
                                               RecordingOptions, simulate_recording)
from friction_joint.experiments.hidden_plant import relative_size
import numpy as np
import pytest
from scipy import signal

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')


def _derivatives(topics):
    """Return position, velocity, acceleration and effort, zero-phase filtered per piece."""
    js = topics['/joint_states']
    t, q, effort = js['t'], js['q'], js['effort']
    dt = float(np.median(np.diff(t)))
    cut = np.flatnonzero(np.diff(t) > 1.5 * dt) + 1          # the gaps between segments
    bb, aa = signal.butter(2, 0.02 / dt, fs=1.0 / dt)       # 20 Hz at 1 kHz
    edge = int(round(0.1 / dt))
    out = []
    for a, b in zip(np.r_[0, cut], np.r_[cut, len(t)], strict=True):
        qf = signal.filtfilt(bb, aa, q[a:b])
        qd = np.gradient(qf, dt)
        cols = (q[a:b], qd, np.gradient(qd, dt), signal.filtfilt(bb, aa, effort[a:b]))
        out.append([c[edge:-edge] for c in cols])
    return [np.concatenate(c) for c in zip(*out, strict=True)]


def _gravity_fit(q, qd, r):
    """Per direction: fit r = c + f qd + a sin q + b cos q on sliding samples; (a, b) each."""
    v_slide = 0.1 * float(np.percentile(np.abs(qd), 95))
    fits = []
    for direction in (1.0, -1.0):
        m = direction * qd > v_slide
        assert m.sum() > 1000
        x = np.column_stack([np.ones(m.sum()), qd[m], np.sin(q[m]), np.cos(q[m])])
        coef = np.linalg.lstsq(x, r[m], rcond=None)[0]
        fits.append(coef[2:])
    return fits


@pytest.mark.parametrize('seed', [11, 12])
def test_gravity_truth_without_link_torque_shows_the_lever_error(seed):
    rng = np.random.default_rng(seed)
    base = friction_joint.load_gear(BASE)
    size = draw_effect(rng, 'gravity', strength=float(rng.uniform(0.0, 1.0)))
    truth = apply_effect(base, 'gravity', size=size)
    topics, _ = simulate_recording(
        truth, None, options=RecordingOptions(
            duration=float(rng.uniform(15.0, 25.0)), seed=int(rng.integers(2**31)),
            base_gear=base, link_torque=False,
            noise_scale=float(np.exp(rng.uniform(-0.7, 0.7)))))
    assert '/link_torque' not in topics
    q, qd, qdd, effort = _derivatives(topics)
    # expected error: a sin q + b cos q = truth lever torque - base lever torque
    mgl_t, q0 = truth.mgl, truth.lever_offset
    expect = np.array([mgl_t * math.cos(q0) - base.mgl, -mgl_t * math.sin(q0)])
    amplitude = relative_size(base, 'gravity', size) * base.friction.fc[0]
    assert float(np.hypot(*expect)) == pytest.approx(amplitude, rel=1e-9)
    what = f'seed {seed}, size {size}, error amplitude {amplitude:.3f} Nm'
    # against the base's lever (what a diagnosis without /link_torque computes)
    r_base = effort - base.inertia * qdd - base.lever_torque(q)
    up, down = _gravity_fit(q, qd, r_base)
    for fit in (up, down):
        assert np.hypot(*(fit - expect)) < 0.05 * amplitude, f'{what}: fit {fit}, {expect}'
    assert np.hypot(*(up - down)) < 0.05 * amplitude, f'{what}: {up} vs {down}'
    # against the truth's lever: nothing left
    r_truth = effort - base.inertia * qdd - truth.lever_torque(q)
    for fit in _gravity_fit(q, qd, r_truth):
        assert np.hypot(*fit) < 0.05 * amplitude, f'{what}: {fit}'


def test_gravity_sizes_are_drawn_in_their_ranges():
    assert 'gravity' in HIDEABLE
    base = friction_joint.load_gear(BASE)
    rng = np.random.default_rng(5)
    lo_c, hi_c = EFFECT_RANGES['gravity']['change']
    lo_a, hi_a = EFFECT_RANGES['gravity']['angle']
    mass, offsets, changes = base.section('lever')['mass'], [], []
    for _ in range(40):
        size = draw_effect(rng, 'gravity')
        truth = apply_effect(base, 'gravity', size=size)
        change = truth.section('lever')['mass'] / mass - 1.0
        assert lo_c <= abs(change) <= hi_c and lo_a <= abs(truth.lever_offset) <= hi_a
        assert truth.friction == base.friction and truth.inertia == base.inertia
        offsets.append(truth.lever_offset)
        changes.append(change)
    # both signs of both, and a continuum of sizes
    assert min(offsets) < 0 < max(offsets) and min(changes) < 0 < max(changes)
    assert len({round(abs(o), 6) for o in offsets}) == len(offsets)
    weak = apply_effect(base, 'gravity', size=draw_effect(rng, 'gravity', strength=0.0))
    strong = draw_effect(rng, 'gravity', strength=1.0)
    assert abs(weak.lever_offset) == pytest.approx(lo_a)
    assert strong['change'] == pytest.approx(hi_c) and strong['angle'] == pytest.approx(hi_a)
    assert (relative_size(base, 'gravity', strong)
            > relative_size(base, 'gravity', draw_effect(rng, 'gravity', strength=0.0)))
