# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ``gravity`` candidate: a lever, payload or link whose gravity model is off.

The lever error (mass change, angle offset) and the plant's nuisance
parameters are drawn at random (seeded); ``diagnose`` sees only the recording
(without ``/link_torque``: the external torque comes from the base's lever) and
the base gear.
"""
import json
import math
import os

from friction_joint.diagnosis import diagnose, EFFECTS
from friction_joint.diagnosis.gravity import gravity_untestable, linear_device
from friction_joint.experiments.hidden import (apply_effects, draw_effect, RecordingOptions,
                                               simulate_recording)
from friction_joint.gear import load_gear
import numpy as np
import pytest
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')


@pytest.mark.parametrize('seed', range(2))
def test_a_wrong_lever_is_named_gravity_and_corrected(tmp_path, seed):
    rng = np.random.default_rng([1818, seed])
    base = load_gear(BASE)
    size = draw_effect(rng, 'gravity')
    truth = apply_effects(base, {'gravity': size})
    rec = str(tmp_path / 'rec')
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=float(rng.uniform(30, 45)), seed=int(rng.integers(1e6)), base_gear=base,
        link_torque=False, n_segments=2, noise_scale=float(rng.uniform(0.5, 2.0)),
        gain_scale=float(rng.uniform(0.7, 1.5))))
    rep = diagnose([rec], base).report
    assert rep['named_causes'] == ['gravity'], (size, rep['headline'])
    got = rep['extended_fit']['gravity']['lever']
    assert got['mgl'] == pytest.approx(truth.mgl, rel=0.03), (size, got)
    assert abs(got['angle_offset'] - truth.lever_offset) < 0.02, (size, got)
    assert rep['adequacy']['extended']['explains']


class _Bins:
    """Bin averages of a position only (what the testability rule reads)."""

    def __init__(self, q):
        self.q = q

    def average(self, x):
        return x


def _base_columns(q, rng):
    v = np.gradient(q) * rng.uniform(0.5, 5.0)
    return np.column_stack([np.sign(v), v])


@pytest.mark.parametrize('seed', range(6))
def test_gravity_needs_a_stroke_that_shows_one_cycle_per_turn(seed):
    """Before: a 0.36 rad stroke took a 0.38 rad 'ripple'; the rule is the curvature's share."""
    rng = np.random.default_rng([1819, seed])
    centre = rng.uniform(-math.pi, math.pi)
    t = np.linspace(0.0, 1.0, int(rng.integers(1000, 6000)))
    short = centre + rng.uniform(0.01, 0.1) * np.sin(2 * math.pi * rng.uniform(3, 9) * t)
    long = centre + rng.uniform(0.6, 2.6) * np.sin(2 * math.pi * rng.uniform(3, 9) * t)
    sweep = centre + np.linspace(-1, 1, t.size) * rng.uniform(0.6, 2.6)     # one way
    reason = gravity_untestable(_Bins(short), _base_columns(short, rng))
    assert reason and 'constant and a slope' in reason
    assert gravity_untestable(_Bins(long), _base_columns(long, rng)) is None
    assert gravity_untestable(_Bins(sweep), _base_columns(sweep, rng)) is None
    assert 'linear device' in gravity_untestable(_Bins(long), _base_columns(long, rng),
                                                 linear=True)


def test_an_imported_linear_device_is_recognised(tmp_path):
    for name, radius in (('rot', None), ('lin', 0.01)):
        d = tmp_path / name
        d.mkdir()
        info = {'radius_m': radius, 'mode': 'drive_torque'}
        meta = {'rosbag2_bagfile_information': {
            'custom_data': {'friction_joint.import': json.dumps(info)}}}
        (d / 'metadata.yaml').write_text(yaml.safe_dump(meta))
    assert not linear_device([str(tmp_path / 'rot')])
    assert linear_device([str(tmp_path / 'rot'), str(tmp_path / 'lin')])


def test_a_model_that_explains_less_than_the_friction_says_so(tmp_path):
    """Before: "Nothing significant is missing" with a held-out RMSE above the friction level."""
    rng = np.random.default_rng(1820)
    base = load_gear(BASE)
    lever = base.section('lever')
    # a payload the base does not know: its gravity torque several times the friction level
    mass = lever['mass'] * float(rng.uniform(1.5, 2.5))
    truth = base.replace({'lever': {'mass': mass,
                                    'angle_offset': float(rng.uniform(-0.3, 0.3))}})
    rec = str(tmp_path / 'rec')
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=30.0, seed=int(rng.integers(1e6)), base_gear=base, link_torque=False,
        n_segments=2))
    effects = [e for e in EFFECTS if e != 'gravity']       # a candidate set without the cause
    rep = diagnose([rec], base, effects=effects).report
    assert not rep['adequacy']['extended']['explains']
    assert rep['adequacy']['base']['rmse_over_level'] > 0.5
    assert rep['headline'].startswith('The model does not explain the data'), rep['headline']
    assert 'Largest unexplained structure' in rep['headline']


def test_a_short_one_way_sweep_through_gravity(tmp_path):
    """Before: 'nothing missing' on a one-way sweep whose base has no lever; scan flagged time."""
    rng = np.random.default_rng(1823)
    base = load_gear(BASE)
    nolever = base.replace({'lever': {'mass': 0.0}})
    rec = str(tmp_path / 'rec')
    simulate_recording(base, rec, options=RecordingOptions(
        duration=float(rng.uniform(6, 10)), seed=int(rng.integers(1e6)), base_gear=base,
        kinds=['sweep_oneway'], n_segments=1, link_torque=False,
        cfg={'publish_rate': float(rng.uniform(200, 400))}))
    rep = diagnose([rec], nolever).report
    assert rep['named_causes'] == ['gravity'], rep['headline']
    got = rep['extended_fit']['gravity']['lever']
    assert got['mgl'] == pytest.approx(base.mgl, rel=0.02)
    untestable = {e['variable'] for e in rep['residual_scan'] if e.get('untestable')}
    assert any('time' in v and 'position' in v for v in untestable), rep['residual_scan']
    assert not any(e.get('flagged') for e in rep['residual_scan'])
