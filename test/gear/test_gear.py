# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Gear parameter files: loading, validation errors that name the key, round trip."""
import copy
import warnings

from friction_joint import gear_from_dict, GearConfigError, GearConfigWarning, load_gear, save_gear
from friction_joint.gear import gear_from_flat
from friction_joint.models.static import StaticFriction
import numpy as np
import pytest
import yaml

BASE = {
    'joint_name': 'j1', 'gear_ratio': 80.0, 'inertia': 0.12,
    'friction': {'model': 'lugre', 'fc': [2.0], 'fv': [0.4], 'fs': [2.8], 'vs': [0.05],
                 'delta_v': [0.7], 'lugre': {'sigma0': 1e4, 'sigma1': 1.0}},
}


def write(tmp_path, params, name='g.yaml'):
    p = tmp_path / name
    p.write_text(yaml.safe_dump({'/**': {'ros__parameters': params}}))
    return p


def variant(**friction):
    d = copy.deepcopy(BASE)
    for k, v in friction.items():
        if v is None:
            d['friction'].pop(k, None)
        else:
            d['friction'][k] = v
    return d


def test_shipped_gear_files_load_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        g = load_gear('config/csd25.yaml')
    assert g.gear_ratio == 80.0 and g.friction.model == 'lugre'
    # Table I, second order in temperature; Fs constant
    assert len(g.friction.fc) == 3 and len(g.friction.fs) == 1
    # The paper's curve falls with temperature at speed and has a Stribeck dip
    sf = StaticFriction(g.friction)
    assert sf.torque(3.5, 27.0)[0] > sf.torque(3.5, 35.0)[0]
    assert sf.torque(0.1, 30.0)[0] < sf.torque(0.001, 30.0)[0]


def test_contract_example_defaults(tmp_path):
    d = {'gear_ratio': 80.0, 'inertia': 0.12, 'friction': {'fc': [2.0], 'fv': [0.4]}}
    g = load_gear(write(tmp_path, d))
    assert g.joint_name == 'joint' and g.friction.model == 'static'
    assert g.friction.fs is None and g.friction.delta_v == (1.0,) and g.friction.delta_s == 2.0
    # no Stribeck: Fs = Fc; linear viscous
    np.testing.assert_allclose(StaticFriction(g.friction).torque([0.5, -2.0], 25.0), [2.2, -2.8])


@pytest.mark.parametrize('params, words', [
    (variant(fcc=[1.0]), ['unknown key', 'friction.fcc']),
    (variant(fc=[float('nan')]), ['friction.fc[0]', 'finite']),
    (variant(vs=[-0.1]), ['friction.vs', '> 0']),
    (variant(vs=None), ['friction.fs', 'friction.vs']),
    (variant(fc='2.0'), ['friction.fc', 'list']),
    (variant(fv=[]), ['friction.fv', 'at least 1']),
    (variant(model='dahl'), ['friction.model', 'lugre']),
    (variant(lugre={'sigma0': 0.0}), ['friction.lugre.sigma0', '> 0']),
    (variant(lugre=None), ['friction.lugre', 'missing']),
    (variant(lugre={'sigma0': 1e4, 'stiffness': 3.0}),
     ['unknown key', 'friction.lugre.stiffness']),
    (variant(gms={'k': [1.0, 2.0], 'alpha': [0.3, 0.3], 'c': 1.0}),
     ['friction.gms.alpha', 'sum to 1']),
    (variant(temperature_range=[40.0, 20.0]), ['temperature_range', 'lo < hi']),
    (dict(BASE, inertia=-1.0), ['inertia', '> 0']),
    (dict(BASE, wheel=1.0), ['unknown key wheel']),
    ({k: v for k, v in BASE.items() if k != 'gear_ratio'}, ['missing required key gear_ratio']),
])
def test_bad_gear_names_the_key(tmp_path, params, words):
    path = write(tmp_path, params)
    with pytest.raises(GearConfigError) as err:
        load_gear(path)
    msg = str(err.value)
    assert str(path) in msg
    for w in words:
        assert w in msg


@pytest.mark.filterwarnings('ignore::friction_joint.GearConfigWarning')
def test_polynomial_leaving_physical_range_is_reported():
    # Table I's vs quadratic is negative at 0 degC: the default range exposes it
    bad = variant(fs=[4.48], vs=[-5.31 / 80, 0.549 / 80, -0.007 / 80])
    with pytest.raises(GearConfigError, match=r'friction.vs: evaluates to .* at xi = 0.0 degC'):
        gear_from_dict(bad)
    bad['friction']['temperature_range'] = [22.0, 37.0]
    gear_from_dict(bad)


def test_not_a_parameter_file(tmp_path):
    p = tmp_path / 'x.yaml'
    p.write_text('friction: {fc: [1.0]}\n')
    with pytest.raises(GearConfigError, match='/\\*\\*'):
        load_gear(p)
    p.write_text('/**: {ros__parameters: [1, 2: }\n')
    with pytest.raises(GearConfigError, match='not valid YAML'):
        load_gear(p)
    with pytest.raises(GearConfigError, match='cannot read'):
        load_gear(tmp_path / 'missing.yaml')


def test_a_path_source_is_kept_as_its_string():
    """A gear built with a pathlib source equals the one built with its string (its name)."""
    from pathlib import Path
    by_path = gear_from_dict(copy.deepcopy(BASE), source=Path('gears') / 'j1.yaml')
    by_name = gear_from_dict(copy.deepcopy(BASE), source=str(Path('gears') / 'j1.yaml'))
    assert isinstance(by_path.source, str) and by_path == by_name
    assert gear_from_dict(copy.deepcopy(BASE)).source is None


def test_passivity_violation_warns_but_loads():
    d = variant(lugre={'sigma0': 1e5, 'sigma1': 1e3})
    with pytest.warns(GearConfigWarning, match='passivity'):
        g = gear_from_dict(d)
    assert g.friction.lugre.sigma1 == 1e3
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        gear_from_dict(variant(lugre={'sigma0': 1e5, 'sigma1': 0.1}))


def test_round_trip_and_flat_names(tmp_path):
    g = load_gear('config/csd25.yaml')
    out = tmp_path / 'copy.yaml'
    save_gear(g, out, header='copied\nfor a test')
    assert out.read_text().startswith('# copied\n# for a test\n')
    g2 = load_gear(out)
    assert g2.friction == g.friction and g2.inertia == g.inertia
    flat = {'gear_ratio': 80.0, 'inertia': 0.12, 'friction.fc': [2.0], 'friction.fv': [0.4],
            'friction.model': 'lugre', 'friction.lugre.sigma0': 1e4}
    assert gear_from_flat(flat).friction.lugre.sigma0 == 1e4
    g3 = g.replace({'friction': {'fc_load': [0.05]}})
    assert g3.friction.fc_load == (0.05,) and g.friction.fc_load == (0.018,)


def test_saved_gear_file_has_the_normal_mode(tmp_path):
    """save_gear writes a file readable by others (0666 less the umask), not 0600."""
    import os
    import stat
    path = tmp_path / 'g.yaml'
    old = os.umask(0o022)
    try:
        save_gear(load_gear('config/csd25.yaml'), path)
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o644
    assert load_gear(path).joint_name == load_gear('config/csd25.yaml').joint_name
