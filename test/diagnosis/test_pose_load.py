# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A pose-dependent load error over a short stroke (issue 31): too short for a lever's sine.

Over 0.2-0.8 rad of stroke ``m g l sin(q - q0)`` is an offset, a slope and a
curvature; ``gravity`` is then tested as a direction-independent torque smooth
in position about the stroke's centre, said to stand for any pose-dependent load
error, and written to the extended gear file as ``lever.pose_torque``.  The
stroke, where on the lever's sine it lies, the lever error and the plant's
nuisances are drawn at random (seeded); ``diagnose`` sees the recording (without
``/link_torque``: the external torque comes from the base's lever) and the base.
"""
import math
import os

from friction_joint.diagnosis import diagnose
from friction_joint.experiments.hidden import (apply_effects, draw_effect, RecordingOptions,
                                               SEGMENT, simulate_recording)
from friction_joint.gear import load_gear, save_gear
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')


def _short_stroke(tmp_path, rng, hidden):
    """Record a short-stroke sweep (stroke drawn 0.2-0.8 rad) hiding ``hidden`` (or None)."""
    base = load_gear(BASE).replace(
        {'lever': {'angle_offset': float(rng.uniform(-math.pi, math.pi))}})
    stroke = float(rng.uniform(0.2, 0.8))
    k = 0.5 * stroke / sum(a for a, _, _ in SEGMENT['sweep'])
    cfg = {'sweep': tuple((a * k, lo, hi) for a, lo, hi in SEGMENT['sweep'])}
    truth = apply_effects(base, {hidden: draw_effect(rng, hidden)}) if hidden else base
    rec = str(tmp_path / 'rec')
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=float(rng.uniform(30, 40)), seed=int(rng.integers(1e6)), base_gear=base,
        n_segments=2, kinds=['sweep'], cfg=cfg, link_torque=False,
        noise_scale=float(rng.uniform(0.5, 2.0)), gain_scale=float(rng.uniform(0.7, 1.5))))
    return base, truth, rec, stroke


@pytest.mark.parametrize('seed', range(2))
def test_a_pose_load_error_over_a_short_stroke_is_named_and_written(tmp_path, seed):
    """Before: gravity untestable ('a constant and a slope'), nothing took the load up."""
    rng = np.random.default_rng([3101, seed])
    base, truth, rec, stroke = _short_stroke(tmp_path, rng, 'gravity')
    diag = diagnose([rec], base)
    rep = diag.report
    assert rep['named_causes'] == ['gravity'], (stroke, rep['headline'], rep['untestable'])
    entry = next(c for c in rep['candidates'] if c['effect'] == 'gravity')
    assert entry['form'] == 'pose' and 'pose-dependent load' in entry['caveat']
    assert any('lever.pose_torque' in n for n in rep['notes']), rep['notes']
    # the extended gear's lever torque is the truth's over the recorded positions
    q = diag.data.average(diag.data.q)
    x = np.linspace(q.min(), q.max(), 50)
    err = truth.lever_torque(x) - base.lever_torque(x)
    got = diag.gear.lever_torque(x) - base.lever_torque(x)
    assert diag.gear.section('lever')['pose_torque'], diag.gear.section('lever')
    assert np.max(np.abs(got - err)) < 0.05 * np.max(np.abs(err)) + 0.05, (stroke, got, err)


@pytest.mark.parametrize('seed', range(3))
def test_no_pose_load_is_named_on_a_short_stroke_without_one(tmp_path, seed):
    rng = np.random.default_rng([3102, seed])
    base, _, rec, stroke = _short_stroke(tmp_path, rng, None)
    rep = diagnose([rec], base).report
    assert 'gravity' not in rep['named_causes'], (stroke, rep['headline'])
    entry = next(c for c in rep['candidates'] if c['effect'] == 'gravity')
    assert entry['testable'] and entry['form'] == 'pose', entry


@pytest.mark.parametrize('seed', range(2))
def test_a_constant_offset_over_a_short_stroke_is_no_pose_load(tmp_path, seed):
    """The pose term holds a constant too: it must beat the offset alone to be named."""
    rng = np.random.default_rng([3104, seed])
    base, _, rec, stroke = _short_stroke(tmp_path, rng, 'asymmetry')
    rep = diagnose([rec], base).report
    assert 'gravity' not in rep['named_causes'], (stroke, rep['headline'])


def test_the_gear_file_carries_a_pose_torque(tmp_path):
    rng = np.random.default_rng(3103)
    base = load_gear(BASE)
    c = float(rng.uniform(-1, 1))
    coefs = [float(v) for v in rng.normal(0, 2, 3)]
    gear = base.replace({'lever': {'pose_center': c, 'pose_torque': coefs}})
    q = rng.uniform(-3, 3, 20)
    want = base.lever_torque(q) + np.polynomial.polynomial.polyval(q - c, coefs)
    assert np.allclose(gear.lever_torque(q), want)
    assert base.section('lever')['pose_torque'] == []          # old files: none
    path = tmp_path / 'g.yaml'
    save_gear(gear, str(path))
    assert np.allclose(load_gear(str(path)).lever_torque(q), want)
