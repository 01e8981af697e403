# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
``import --current COL[:A|mA] --torque-constant K [--gear-ratio N]`` (issue 31, item 5).

Robot logs (UR RTDE, Kinova, Franka) carry the motor current, not a torque.  The
import converts it (tau = I K N, the joint torque), echoes the conversion, records it
in the recording's ``metadata.yaml``, and ``diagnose`` / ``identify`` say their
torque came from a current.  Bad K, N, unit or a current beside a torque column: one
line, exit 2, nothing written.
"""
import json
import os
from pathlib import Path

from friction_joint.bag import read_recording, recording_custom_data, torque_from_current
from friction_joint.cli import main
import numpy as np
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
RECORDING = ROOT / 'bags' / 'csd25_sample'
BASE = ROOT / 'config' / 'csd25_base.yaml'


def _custom(rec):
    meta = yaml.safe_load(Path(rec, 'metadata.yaml').read_text(encoding='utf-8'))
    return json.loads(meta['rosbag2_bagfile_information']['custom_data']['friction_joint.import'])


def _log(path, seed, *, milli):
    """Write a CSV whose joint torque is known; return (K, N, current in A, torque)."""
    rng = np.random.default_rng(seed)
    k, ratio = rng.uniform(0.02, 0.5), rng.uniform(30.0, 160.0)
    t = np.arange(3000) * 2e-3
    q = 0.6 * np.sin(2 * np.pi * 0.5 * t)
    qd = 0.6 * np.pi * np.cos(2 * np.pi * 0.5 * t)
    current = rng.uniform(-2.0, 2.0, len(t))          # A, drawn at random
    logged = current * 1e3 if milli else current
    with open(path, 'w', encoding='utf-8') as fh:
        fh.write(f't,q,qd,{"I_mA" if milli else "I"}\n')
        for row in zip(t, q, qd, logged, strict=True):
            fh.write(','.join(repr(float(v)) for v in row) + '\n')
    scale = 1e-3 if milli else 1.0
    return k, ratio, logged, logged * scale * k * ratio


@pytest.mark.parametrize('seed,milli', [(5, True), (11, False)])
def test_current_becomes_joint_torque_echoed_and_recorded(tmp_path, capsys, seed, milli):
    """Torque = current x K x N to 1e-12 relative; the conversion is printed and recorded."""
    log = tmp_path / 'ur.csv'
    k, ratio, _, torque = _log(log, seed, milli=milli)
    rec = tmp_path / 'rec'
    col = 'I_mA:mA' if milli else 'I:A'
    rc = main(['import', str(log), '--out', str(rec), '--time', 't', '--position', 'q',
               '--velocity', 'qd', '--current', col, '--torque-constant', repr(k),
               '--gear-ratio', repr(ratio)])
    out, err = capsys.readouterr()
    assert rc == 0, err
    js = read_recording(rec).joint_states
    assert len(js) == len(torque)
    np.testing.assert_allclose(js.effort, torque, rtol=1e-12, atol=0)
    echo = [ln for ln in out.splitlines() if ln.startswith('current: ')]
    assert len(echo) == 1 and f'torque constant {k:.9g} N m/A' in echo[0], out
    assert f'gear ratio {ratio:.9g}' in echo[0] and 'tau [Nm] :=' in echo[0]
    assert (' * 0.001 ' in echo[0]) == milli
    info = _custom(rec)['torque_from_current']
    assert info['torque_constant_Nm_per_A'] == k and info['gear_ratio'] == ratio
    assert info['unit'] == ('mA' if milli else 'A') and info['column'] == col.split(':')[0]
    assert info['conversion'] == echo[0][len('current: '):]


def test_mapping_file_keys_and_default_gear_ratio(tmp_path, capsys):
    """The same keys in --mapping; N defaults to 1; options on the command line win."""
    log = tmp_path / 'kinova.csv'
    k, _, logged, _ = _log(log, 3, milli=False)
    mapping = tmp_path / 'map.yaml'
    mapping.write_text('time: t\nposition: q\nvelocity: qd\ncurrent: I:A\n'
                       f'torque_constant: {k!r}\n', encoding='utf-8')
    rec = tmp_path / 'rec'
    assert main(['import', str(log), '--out', str(rec), '--mapping', str(mapping),
                 '--quiet']) == 0
    np.testing.assert_allclose(read_recording(rec).joint_states.effort, logged * k,
                               rtol=1e-12, atol=0)
    assert _custom(rec)['torque_from_current']['gear_ratio'] == 1.0
    mapping.write_text(mapping.read_text(encoding='utf-8') + 'gear_ratio: 50\n',
                       encoding='utf-8')
    rec2 = tmp_path / 'rec2'
    assert main(['import', str(log), '--out', str(rec2), '--mapping', str(mapping),
                 '--gear-ratio', '7', '--quiet']) == 0
    np.testing.assert_allclose(read_recording(rec2).joint_states.effort, logged * k * 7,
                               rtol=1e-12, atol=0)
    assert _custom(rec2)['torque_from_current']['gear_ratio'] == 7.0
    bare = tmp_path / 'rec.mcap'                       # a bare MCAP file keeps it too
    assert main(['import', str(log), '--out', str(bare), '--mapping', str(mapping),
                 '--quiet']) == 0
    src = torque_from_current(recording_custom_data(bare))
    assert src['gear_ratio'] == 50.0 and src['torque_constant_Nm_per_A'] == k
    assert src['text'] == f'friction torque from motor current x {k:.6g} N m/A x 50 (import)'
    capsys.readouterr()


_COLS = ['--time', 't', '--position', 'q', '--velocity', 'qd']


@pytest.mark.parametrize('argv,words', [
    (['--current', 'I', '--torque-constant', '0'], ['--torque-constant', '> 0']),
    (['--current', 'I', '--torque-constant', '-0.1'], ['--torque-constant']),
    (['--current', 'I', '--torque-constant', 'inf'], ['--torque-constant']),
    (['--current', 'I', '--torque-constant', 'nan'], ['--torque-constant']),
    (['--current', 'I', '--torque-constant', '0.1', '--gear-ratio', '0'], ['--gear-ratio']),
    (['--current', 'I', '--torque-constant', '0.1', '--gear-ratio', '-100'], ['--gear-ratio']),
    (['--current', 'I', '--torque-constant', '0.1', '--gear-ratio', 'inf'], ['--gear-ratio']),
    (['--current', 'I:V', '--torque-constant', '0.1'], ["'V'", 'A, mA']),
    (['--current', 'I:Nm', '--torque-constant', '0.1'], ["'Nm'", 'A, mA']),
    (['--current', 'I', '--torque-constant', '0.1', '--torque', 'qd'],
     ['--current', '--torque', 'not both']),
    (['--current', 'I', '--torque-constant', '0.1', '--friction', 'qd'],
     ['--current', '--friction', 'not both']),
    (['--current', 'I'], ['--torque-constant']),
    (['--torque', 'I', '--torque-constant', '0.1'], ['--torque-constant', '--current']),
    (['--torque', 'I', '--gear-ratio', '3'], ['--gear-ratio', '--current']),
])
def test_bad_motor_options_one_line_nothing_written(tmp_path, capsys, argv, words):
    """Bad K, N or unit, a current beside a torque column: exit 2, one line, nothing written."""
    log = tmp_path / 'franka.csv'
    _log(log, 1, milli=False)
    out = tmp_path / 'rec'
    rc = main(['import', str(log), '--out', str(out), *_COLS, *argv])
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith('friction_joint import: error:')
    for w in words:
        assert w in lines[0], lines[0]
    assert not os.path.lexists(out) and os.listdir(tmp_path) == ['franka.csv']


@pytest.mark.parametrize('extra,words', [
    ('current: I\ntorque_constant: 0\n', ['map.yaml', 'torque_constant', 'finite and > 0']),
    ('current: I\ntorque_constant: .nan\n', ['map.yaml', 'torque_constant', 'finite and > 0']),
    ('current: I\ntorque_constant: 0.1\ngear_ratio: -1\n',
     ['map.yaml', 'gear_ratio', 'finite and > 0']),
    ("current: I\ntorque_constant: '0.1'\n", ['map.yaml', 'torque_constant', 'finite and > 0']),
    ('current: I:uA\ntorque_constant: 0.1\n', ['map.yaml', "'uA'", 'A, mA']),
    ('current: I\ntorque: qd\ntorque_constant: 0.1\n', ['--current', '--torque', 'not both']),
])
def test_bad_mapping_file_one_line_nothing_written(tmp_path, capsys, extra, words):
    """The same refusals from --mapping, naming the file."""
    log = tmp_path / 'franka.csv'
    _log(log, 1, milli=False)
    mapping = tmp_path / 'map.yaml'
    mapping.write_text('time: t\nposition: q\nvelocity: qd\n' + extra, encoding='utf-8')
    out = tmp_path / 'rec'
    rc = main(['import', str(log), '--out', str(out), '--mapping', str(mapping)])
    lines = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(lines) == 1, lines
    for w in words:
        assert w in lines[0], lines[0]
    assert not os.path.lexists(out)
    assert sorted(os.listdir(tmp_path)) == ['franka.csv', 'map.yaml']


def test_diagnose_and_identify_say_the_torque_came_from_current(tmp_path, capsys):
    """The sample's torque logged as a current: diagnose and identify say so (console, JSON)."""
    rec = read_recording(RECORDING)
    js, temp = rec.joint_states, rec.temperature
    n = int(np.searchsorted(js.t, js.t[0] + 20.0))
    t = js.t[:n] - js.t[0]
    xi = np.interp(js.t[:n], temp.t, temp.xi)
    k, ratio = 0.12, 100.0
    log = tmp_path / 'ur.csv'
    np.savetxt(log, np.c_[t, js.q[:n], js.qd[:n], js.effort[:n] / (k * ratio), xi],
               delimiter=',', fmt='%.17g', header='t,q,qd,I,xi', comments='')
    out = tmp_path / 'rec'
    assert main(['import', str(log), '--out', str(out), '--time', 't', '--position', 'q',
                 '--velocity', 'qd', '--current', 'I:A', '--torque-constant', '0.12',
                 '--gear-ratio', '100', '--temperature', 'xi', '--joint', rec.joint_name,
                 '--quiet']) == 0
    text = 'friction torque from motor current x 0.12 N m/A x 100 (import)'
    diag = tmp_path / 'diag'
    assert main(['diagnose', str(out), '--model', str(BASE), '--out', str(diag),
                 '--quiet']) == 0
    echo = capsys.readouterr().out
    assert f'torque: {out}: {text}' in echo.splitlines(), echo
    report = json.loads((diag / 'report.json').read_text(encoding='utf-8'))
    (src,) = report['data']['torque_from_current']
    assert src['text'] == text and src['recording'] == str(out)
    assert src['torque_constant_Nm_per_A'] == 0.12 and src['gear_ratio'] == 100.0
    assert text in (diag / 'report.md').read_text(encoding='utf-8')
    gear = tmp_path / 'g.yaml'
    assert main(['identify', str(out), '--model', str(BASE), '--out', str(gear),
                 '--presliding', 'skip', '--quiet']) == 0
    echo = capsys.readouterr().out
    assert f'torque: {out}: {text}' in echo.splitlines(), echo
    ident = json.loads((tmp_path / 'g_report' / 'identification.json').read_text('utf-8'))
    assert [s['text'] for s in ident['torque_from_current']] == [text]
    assert text in gear.read_text(encoding='utf-8')


def test_recordings_not_from_current_say_nothing(tmp_path, capsys):
    """A recording without the conversion: an empty list, no line."""
    diag = tmp_path / 'diag'
    assert main(['diagnose', str(RECORDING), '--model', str(BASE), '--out', str(diag),
                 '--quiet']) == 0
    assert 'motor current' not in capsys.readouterr().out
    report = json.loads((diag / 'report.json').read_text(encoding='utf-8'))
    assert report['data']['torque_from_current'] == []
