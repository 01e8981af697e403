# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Plateaus in one direction only: identified with a load sensor, refused without one.

With /link_torque measuring tau_ext, one direction pins the static curve in that
direction; the other direction is assumed symmetric and said so.  Without it, friction
cannot be told from a torque offset or a gravity error: refused, naming what to record.
The plants and excitations are drawn at random (seeded) from continuous ranges
(:mod:`friction_joint.experiments.identification_draws`).
"""
import json
import warnings

from friction_joint.bag import write_recording
from friction_joint.cli import main
from friction_joint.exceptions import ExcitationError
from friction_joint.experiments.identification_draws import (
    draw_identification_case, draw_plateaus, simulate_case)
from friction_joint.gear import load_gear, save_gear
from friction_joint.identification import StaticIdentifier
from friction_joint.models.static import StaticFriction
import numpy as np
import pytest

pytestmark = pytest.mark.filterwarnings('ignore::friction_joint.exceptions.GearConfigWarning')

SEEDS = [int(s) for s in np.random.default_rng(4646).integers(1000, 10 ** 6, 8)]
SENSOR = {'link_sensor': 1.0}
#: the static curve in the measured direction, at the plateaus, where the identification
#: says the curve is pinned: the identification's own target
#: (benchmarks/bench_identify_plants.py: >= 95 % of the pinned plants within 2 %)
PINNED = 0.02
#: ... and over the whole recorded speed, temperature and load ranges (their corners, where
#: no plateau was): the worst of the pinned plants of bench_identify_plants.py
#: --one-direction --link-sensor (20 plants) and of 23 drawn plateau sets (2.2 %)
LOOSE = 0.03


def curve_error(gear, truth, plateaus, direction, *, at_plateaus=False):
    """Largest relative static-curve error in one direction over the plateaus' ranges."""
    if at_plateaus:                  # at each plateau's speed, temperature and load
        got, want = (StaticFriction(g.friction).torque(plateaus.qd, plateaus.xi, plateaus.load)
                     for g in (gear, truth))
        return float(np.max(np.abs(got / want - 1.0)))
    speed = np.abs(plateaus.qd)
    v = direction * np.geomspace(speed.min(), speed.max(), 150)
    got, want = StaticFriction(gear.friction), StaticFriction(truth.friction)
    return max(float(np.max(np.abs(got.torque(v, x, lo) / want.torque(v, x, lo) - 1.0)))
               for x in (plateaus.xi.min(), plateaus.xi.max())
               for lo in (plateaus.load.min(), plateaus.load.max()))


def side_names(direction):
    """Return (measured, assumed) direction names."""
    return ('positive', 'negative') if direction > 0 else ('negative', 'positive')


def test_the_one_direction_option_keeps_the_drawn_plant():
    """The same seed draws the same plant and speeds; only their signs are one."""
    for seed in SEEDS[:3]:
        both = draw_identification_case(seed)
        one = draw_identification_case(seed, one_direction=True)
        assert both.direction == 0 and one.direction in (-1, 1)
        assert one.truth == both.truth and one.structure == both.structure
        assert np.allclose(np.abs(one.speeds), np.abs(both.speeds))
        assert np.all(np.sign(one.speeds) == one.direction)
        assert sorted(np.sign(both.speeds)) != [one.direction] * len(both.speeds)


@pytest.mark.parametrize('seed', SEEDS[:6])
def test_one_direction_with_a_load_sensor_is_identified_and_the_rest_said(seed):
    case = draw_identification_case(seed, one_direction=True, excitation_ranges=SENSOR)
    p = draw_plateaus(case, seed=seed)
    assert np.all(np.sign(p.qd) == case.direction) and p.torque_source == ('link_torque',)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        ident = StaticIdentifier(case.structure).fit(p)
    have, miss = side_names(case.direction)
    idf = ident.identifiability
    flag = idf['not_identified'][f'{miss} direction']
    assert 'assumed symmetric' in flag['kept'] and f'{miss} velocities' in flag['advice']
    assert any(line.startswith(f'{miss} direction not identified:') and 'assumed symmetric'
               in line for line in idf['lines'])
    assert any(f'{have} velocities only' in line for line in idf['lines'][:2])
    if idf['curve_identified']:
        assert curve_error(ident.gear, case.truth, p, case.direction, at_plateaus=True) <= PINNED
        assert curve_error(ident.gear, case.truth, p, case.direction) <= LOOSE
    else:                            # said: where (a speed band), or that it is not checked
        assert idf['lines'][0].startswith(('the static curve is NOT pinned',
                                           'the static curve is NOT checked'))
    # the written curve is the measured one mirrored
    v = np.geomspace(0.01, 2.0, 7)
    model = StaticFriction(ident.gear.friction)
    xm = float(np.mean(p.xi))
    assert np.allclose(model.torque(-v, xm, 1.0), -model.torque(v, xm, 1.0))


def test_one_direction_without_a_load_sensor_is_refused_naming_what_to_record():
    case = draw_identification_case(SEEDS[6], one_direction=True,
                                    excitation_ranges={'link_sensor': 0.0})
    p = draw_plateaus(case, seed=1)
    with pytest.raises(ExcitationError) as exc:
        StaticIdentifier(case.structure).fit(p)
    msg = str(exc.value)
    assert 'both directions' in msg and 'load sensor on /link_torque' in msg
    assert '\n' not in msg


@pytest.fixture(scope='module')
def one_way(tmp_path_factory):
    """One drawn plant's one-direction excitation simulated, with its load sensor."""
    case = draw_identification_case(SEEDS[7], one_direction=True, excitation_ranges=dict(
        SENSOR, n_speeds=(6, 7), repetitions=(1, 1), plateau=(1.2, 1.6)))
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        topics = simulate_case(case)
    d = tmp_path_factory.mktemp('one_way')
    structure = d / 'structure.yaml'
    save_gear(case.structure, structure)
    return case, topics, d, structure


def test_a_one_direction_recording_with_a_load_sensor_is_identified(one_way, capsys):
    case, topics, d, structure = one_way
    bag = write_recording(d / 'with_sensor', topics)
    out = d / 'gear.yaml'
    assert main(['identify', str(bag), '--model', str(structure), '--out', str(out),
                 '--presliding', 'skip']) == 0
    console = capsys.readouterr().err              # the progress messages
    have, miss = side_names(case.direction)
    assert f'{miss} direction not identified' in console
    header = out.read_text()
    assert f'{miss} direction not identified' in header and 'assumed symmetric' in header
    rep = json.loads((d / 'gear_report' / 'identification.json').read_text())
    idf = rep['identifiability']
    assert f'{miss} direction' in idf['not_identified']
    speeds = np.array(rep['plateaus']['qd'])
    assert np.sum(np.sign(speeds) == case.direction) >= 8 and \
        np.sum(np.sign(speeds) == -case.direction) < 2
    from friction_joint.identification.plateaus import Plateaus
    p = Plateaus.from_arrays(speeds, 0.0, np.array(rep['plateaus']['xi']),
                             load=np.array(rep['plateaus']['load']))
    if idf['curve_identified']:
        gear = load_gear(out)
        assert curve_error(gear, case.truth, p, case.direction, at_plateaus=True) <= PINNED
        assert curve_error(gear, case.truth, p, case.direction) <= LOOSE
    else:
        assert idf['lines'][0].startswith(('the static curve is NOT pinned',
                                           'the static curve is NOT checked'))


def test_a_one_direction_recording_without_a_load_sensor_is_refused(one_way, capsys):
    case, topics, d, structure = one_way
    bag = write_recording(d / 'no_sensor', {k: v for k, v in topics.items()
                                            if k != '/link_torque'})
    out = d / 'refused.yaml'
    assert main(['identify', str(bag), '--model', str(structure), '--out', str(out),
                 '--presliding', 'skip', '--quiet']) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert 'both directions' in err and 'load sensor on /link_torque' in err
    assert str(bag) in err
    assert not out.exists() and not (d / 'refused_report').exists()
