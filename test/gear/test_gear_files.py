# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Reading gear files: number forms, bad bytes, duplicate keys, size and length limits.

Every bad file ends in one :class:`GearConfigError` whose message is one line
naming the file (and the key or line), never in another exception.
"""
import time

from friction_joint import gear_from_dict, GearConfigError, load_gear, save_gear
from friction_joint.gear import gear_from_flat
import pytest
import yaml

HEAD = '/**:\n  ros__parameters:\n'
BODY = """\
    gear_ratio: 80.0
    inertia: 0.12
    friction:
      model: lugre
      fc: [2.0]
      fv: [0.4]
      lugre:
        sigma0: 20000.0
        sigma1: 1.0
"""


def write(tmp_path, text, name='g.yaml'):
    p = tmp_path / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding='utf-8')
    return p


def rejected(path, *words):
    """Load ``path``, expect a one-line GearConfigError naming it and ``words``; return it."""
    with pytest.raises(GearConfigError) as err:
        load_gear(path)
    msg = str(err.value)
    assert '\n' not in msg, msg
    assert str(path) in msg, msg
    for w in words:
        assert w in msg, msg
    return msg


def test_numbers_are_read_as_yaml_1_2_floats(tmp_path):
    """``2e4``, ``1e-3``, ``.5`` are numbers (PyYAML's YAML 1.1 read them as strings)."""
    text = BODY.replace('fc: [2.0]', 'fc: [.5, 1e-3]').replace('fv: [0.4]', 'fv: [2, 1]')
    text = text.replace('sigma0: 20000.0', 'sigma0: 2e4').replace('sigma1: 1.0', 'sigma1: 1E+0')
    g = load_gear(write(tmp_path, HEAD + text))
    assert g.friction.lugre.sigma0 == 20000.0 and g.friction.lugre.sigma1 == 1.0
    assert g.friction.fc == (0.5, 0.001)
    assert g.friction.fv == (2.0, 1.0) and all(type(v) is float for v in g.friction.fv)
    assert type(g.gear_ratio) is float


def test_quoted_numbers_stay_strings(tmp_path):
    path = write(tmp_path, HEAD + BODY.replace('sigma0: 20000.0', "sigma0: '2e4'"))
    rejected(path, 'friction.lugre.sigma0', 'expected a number')


@pytest.mark.parametrize('data, words', [
    (b'\xff\xfe\x00g\x00e\x00a\x00r', ['UTF-8']),
    (bytes(range(256)) * 4, ['UTF-8']),
    ((HEAD + BODY).encode('latin-1') + b'    joint_name: caf\xe9\n', ['UTF-8', 'line 12']),
    (b'\x00' * 64, ['binary']),
])
def test_non_text_files_are_one_line_errors(tmp_path, data, words):
    rejected(write(tmp_path, data), *words)


@pytest.mark.parametrize('line, words', [
    ('    joint_name: [1, 2: }\n', ['not valid YAML', 'line 12']),
    ('  other: 1\n', ['ros__parameters']),
    ('other: 1\n', ['unexpected top-level key']),
    ('\tbad: 1\n', ['not valid YAML']),
    ('    joint_name: "a\x07b"\n', ['not valid YAML']),
])
def test_syntax_errors_are_one_line_naming_the_line(tmp_path, line, words):
    rejected(write(tmp_path, HEAD + BODY + line), *words)


@pytest.mark.parametrize('key, value', [('inertia', '9' * 400), ('simulation.seed', '9' * 400),
                                        ('simulation.seed', '9' * 20), ('inertia', '1' * 5000)])
def test_huge_integers_are_rejected(tmp_path, key, value):
    """A 400-digit integer raised OverflowError (float keys) or loaded (int keys)."""
    if key == 'inertia':
        text = BODY.replace('inertia: 0.12', f'inertia: {value}')
    else:
        text = BODY + f'    simulation:\n      seed: {value}\n'
    rejected(write(tmp_path, HEAD + text), '64-bit', 'line')


def test_float_overflow_is_not_finite(tmp_path):
    rejected(write(tmp_path, HEAD + BODY.replace('inertia: 0.12', 'inertia: 1e999')),
             'inertia', 'finite')


def test_duplicate_key_names_key_and_line(tmp_path):
    """A duplicated key silently took the last value."""
    text = BODY.replace('      fv: [0.4]\n', '      fv: [0.4]\n      fc: [3.0]\n')
    msg = rejected(write(tmp_path, HEAD + text), "duplicate key 'fc'", 'line 9')
    assert 'line 7' in msg                                  # where it was first given


def test_dotted_and_nested_spelling_of_one_key_is_a_duplicate(tmp_path):
    text = BODY + '    friction.fc: [3.0]\n'
    rejected(write(tmp_path, HEAD + text), 'friction.fc', 'twice')
    with pytest.raises(GearConfigError, match='friction.fv is given twice'):
        gear_from_flat({'gear_ratio': 80.0, 'inertia': 0.1, 'friction.fv': [0.1],
                        'friction': {'fc': [1.0], 'fv': [0.4]}})


def test_aliases_are_rejected_as_ros_does(tmp_path):
    """Aliases: rcl refuses them, the CLI accepted them."""
    text = BODY.replace('fc: [2.0]', 'fc: &c [2.0]').replace('fv: [0.4]', 'fv: *c')
    rejected(write(tmp_path, HEAD + text), 'alias', 'line')


def test_file_size_is_checked_before_parsing(tmp_path):
    """A 50 MB list took 5.6 GB; a file over 1 MB is now rejected by its size."""
    big = '      fc_load: [' + ', '.join(['0.0'] * 600_000) + ']\n'
    path = write(tmp_path, HEAD + BODY + big)
    assert path.stat().st_size > 1_000_000
    t0 = time.perf_counter()
    rejected(path, 'larger than', 'MiB')
    assert time.perf_counter() - t0 < 1.0


@pytest.mark.parametrize('key, n, longest, words', [
    ('fc', 10, 9, ['friction.fc', 'at most 9', 'order']),
    ('fv', 1001, 9, ['friction.fv', 'at most 9']),
    ('fc_load', 9, 8, ['friction.fc_load', 'at most 8']),
])
def test_polynomial_order_is_limited(tmp_path, key, n, longest, words):
    """A 1001-coefficient polynomial ran diagnose for more than 300 s."""
    def gear(length):
        params = yaml.safe_load(BODY)
        params['friction'][key] = [0.0] * (length - 1) + [1.0]
        return yaml.safe_dump({'/**': {'ros__parameters': params}})

    t0 = time.perf_counter()
    rejected(write(tmp_path, gear(n)), *words)
    assert time.perf_counter() - t0 < 1.0
    ok = load_gear(write(tmp_path, gear(longest), 'ok.yaml'))
    assert len(getattr(ok.friction, key)) == longest


def test_gms_elements_and_ripple_harmonics_are_limited():
    base = {'gear_ratio': 80.0, 'inertia': 0.12, 'friction': {'fc': [2.0], 'fv': [0.4]}}
    gms = dict(base, friction=dict(base['friction'], gms={'k': [1e3] * 101, 'c': 400.0}))
    with pytest.raises(GearConfigError, match=r'friction.gms.k: at most 100'):
        gear_from_dict(gms)
    gms['friction']['gms']['k'] = [1e3] * 100
    assert len(gear_from_dict(gms).friction.gms.k) == 100
    rip = dict(base, friction=dict(base['friction'], position_ripple={
        'cycles_per_rev': 160.0, 'amplitude': [0.01] * 101}))
    with pytest.raises(GearConfigError, match=r'friction.position_ripple.amplitude: at most 100'):
        gear_from_dict(rip)


def test_messages_do_not_echo_huge_values():
    with pytest.raises(GearConfigError) as err:
        gear_from_dict({'gear_ratio': 'x' * 100_000, 'inertia': 0.1,
                        'friction': {'fc': [1.0], 'fv': [1.0]}})
    assert len(str(err.value)) < 300


@pytest.mark.parametrize('name', ['2e4', 'yes', '0x10', 'null', 'a: b', '.5'])
def test_save_gear_round_trips_strings_that_look_like_numbers(tmp_path, name):
    g = gear_from_dict({'joint_name': name, 'gear_ratio': 80.0, 'inertia': 0.12,
                        'friction': {'fc': [2.0], 'fv': [1e-05]}})
    save_gear(g, tmp_path / 'g.yaml')
    g2 = load_gear(tmp_path / 'g.yaml')
    assert g2.joint_name == name and g2.friction == g.friction
    assert [p.name for p in tmp_path.iterdir()] == ['g.yaml']


def test_shipped_and_null_values_load(tmp_path):
    for name in ('csd25', 'csd25_truth', 'csd25_base'):
        load_gear(f'config/{name}.yaml')
    g = load_gear(write(tmp_path, HEAD + BODY + '    lever:\n      mass: ~\n'))
    assert g.section('lever')['mass'] == 0.0


@pytest.mark.parametrize('body, words', [
    ('    x: ' + '[' * 100_000 + ']' * 100_000 + '\n', ['nested deeper than']),
    ('    x: [' + ', '.join(['0'] * 300_000) + ']\n', ['a list of more than']),
])
def test_deep_or_long_yaml_is_refused_before_a_tree_is_built(tmp_path, body, words):
    """Under 1 MB: RecursionError before (pure-Python reader); no 300 000-item tree now."""
    path = write(tmp_path, HEAD + body)
    assert path.stat().st_size < 1_000_000
    t0 = time.perf_counter()
    rejected(path, *words, 'line 3')
    assert time.perf_counter() - t0 < 1.0
