# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Gear values bounded to physical ranges before they reach an exponent, a division or an allocation.

``sensors.encoder_bits: 1000000000000000000`` was accepted (``2 ** int(bits)`` then hung the
simulator; 2000 raised OverflowError); ``simulation.rate`` 1e15 gave LinAlgError, 1e-300 or 10
(and ``velocity_cutoff: 2000``) a ValueError traceback in ``experiment chirp``;
``friction.velocity_scale: 1.0e308`` a ValueError traceback in ``identify``.  Each is now one
line naming the file and the key; a FIFO given as a gear file is refused before it is opened.
"""
import os
import subprocess
import sys

from friction_joint import GearConfigError, load_gear
from friction_joint.cli import main
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')
RECORDING = os.path.join(ROOT, 'bags', 'csd25_sample')

HEAD = '/**:\n  ros__parameters:\n'
BODY = """\
    gear_ratio: 80.0
    inertia: 0.12
    friction:
      fc: [2.0]
      fv: [0.4]
"""


def _gear(tmp_path, extra):
    path = tmp_path / 'g.yaml'
    path.write_text(HEAD + BODY + extra, encoding='utf-8')
    return path


def _rejected(path, *words):
    with pytest.raises(GearConfigError) as err:
        load_gear(path)
    msg = str(err.value)
    assert '\n' not in msg and str(path) in msg, msg
    for w in words:
        assert w in msg, msg
    return msg


@pytest.mark.parametrize('extra, key', [
    ('    sensors:\n      encoder_bits: 1000000000000000000\n', 'sensors.encoder_bits'),
    ('    sensors:\n      encoder_bits: 2000\n', 'sensors.encoder_bits'),
    ('    sensors:\n      encoder_bits: 53\n', 'sensors.encoder_bits'),
    ('    simulation:\n      rate: 1.0e15\n', 'simulation.rate'),
    ('    simulation:\n      rate: 1.0e-300\n', 'simulation.rate'),
    ('    simulation:\n      rate: 10\n', 'sensors.velocity_cutoff'),
    ('    sensors:\n      velocity_cutoff: 2000\n', 'sensors.velocity_cutoff'),
    ('    sensors:\n      velocity_cutoff: 1.0e-5\n', 'sensors.velocity_cutoff'),
    ('    simulation:\n      temperature_rate: 5000\n', 'simulation.temperature_rate'),
    ('    sensors:\n      temperature_resolution: 1.0e-300\n',
     'sensors.temperature_resolution'),
    ('    friction.velocity_scale: 1.0e308\n', 'friction.velocity_scale'),
    ('    friction.velocity_scale: 1.0e-300\n', 'friction.velocity_scale'),
    ('    friction.delta_s: 1.0e300\n', 'friction.delta_s'),
    ('    friction.temperature_range: [-300.0, 40.0]\n', 'friction.temperature_range[0]'),
    ('    thermal:\n      ambient: 1.0e300\n', 'thermal.ambient'),
    ('    thermal:\n      initial: -274.0\n', 'thermal.initial'),
    ('    lever:\n      mass: 1.0e300\n      length: 1.0e300\n', 'lever'),
    ('    lever:\n      angle_offset: 1.0e20\n', 'lever.angle_offset'),
    ('    lever:\n      angle_offset: 90.0\n', 'lever.angle_offset'),
    ('    lever:\n      angle_offset: -6.3\n', 'lever.angle_offset'),
    ('    friction.position_ripple:\n      cycles_per_rev: 1.0e300\n      amplitude: [0.1]\n',
     'friction.position_ripple.cycles_per_rev'),
])
def test_out_of_range_value_is_one_line_naming_file_and_key(tmp_path, extra, key):
    """Every value that reaches an exponent, a division or an allocation is bounded."""
    _rejected(_gear(tmp_path, extra), key + ':')


@pytest.mark.parametrize('extra', [
    '    sensors:\n      encoder_bits: 52\n',
    '    sensors:\n      encoder_bits: 1\n',
    '    simulation:\n      rate: 1.0e6\n',
    '    simulation:\n      rate: 100.0\n    sensors:\n      velocity_cutoff: 20.0\n',
    '    friction.velocity_scale: 160.0\n',
    '    lever:\n      angle_offset: -3.14159\n',
    '    lever:\n      angle_offset: 6.28\n',
])
def test_physical_values_still_accepted(tmp_path, extra):
    """Coarse and fine encoders, slow and fast loops, a gear ratio as velocity scale load."""
    load_gear(_gear(tmp_path, extra))


def _run(args, timeout=120):
    return subprocess.run([sys.executable, '-m', 'friction_joint', *args], capture_output=True,
                          text=True, timeout=timeout, stdin=subprocess.DEVNULL)


def _one_line(proc, *words):
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr
    assert len(lines) == 1 and 'Traceback' not in proc.stderr, proc.stderr
    for w in words:
        assert w in lines[0], lines[0]


def _one_line_in_process(capsys, rc, *words):
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1, err
    for w in words:
        assert w in lines[0], lines[0]


def _truth(tmp_path, key, value):
    with open(TRUTH, encoding='utf-8') as fh:
        lines = fh.read().splitlines()
    out = [ln[:ln.index(':') + 1] + f' {value}' if ln.strip().startswith(key + ':') else ln
           for ln in lines]
    path = tmp_path / 'truth.yaml'
    path.write_text('\n'.join(out) + '\n', encoding='utf-8')
    return path


@pytest.mark.parametrize('key, value, named', [
    ('encoder_bits', '1000000000000000000', 'sensors.encoder_bits'),
    ('rate', '1.0e15', 'simulation.rate'),
    ('velocity_cutoff', '2000', 'sensors.velocity_cutoff'),
])
def test_experiment_chirp_refuses_truth_out_of_range(tmp_path, capsys, key, value, named):
    """``experiment chirp`` hung (2**1e18) or gave a traceback; now one line, nothing written."""
    truth = _truth(tmp_path, key, value)
    out = tmp_path / 'out'
    rc = main(['experiment', 'chirp', '--model', os.path.join(ROOT, 'config', 'csd25.yaml'),
               '--truth', str(truth), '--out', str(out), '--duration-scale', '0.01'])
    _one_line_in_process(capsys, rc, 'truth.yaml', named)
    assert not out.exists()


def test_identify_refuses_huge_velocity_scale(tmp_path, capsys):
    """``velocity_scale: 1.0e308`` gave a ValueError traceback in identify."""
    with open(BASE, encoding='utf-8') as fh:
        text = fh.read()
    text = text.replace('      fv:', '      velocity_scale: 1.0e308\n      fv:', 1)
    model = tmp_path / 'm.yaml'
    model.write_text(text, encoding='utf-8')
    out = tmp_path / 'g.yaml'
    rc = main(['identify', RECORDING, '--model', str(model), '--out', str(out), '--quiet'])
    _one_line_in_process(capsys, rc, 'm.yaml', 'friction.velocity_scale')
    assert not out.exists()


@pytest.mark.skipif(not hasattr(os, 'mkfifo'), reason='no FIFOs')
def test_model_fifo_refused_at_once(tmp_path):
    """``--model fifo.yaml`` blocked forever in open(); now one line before any read."""
    fifo = tmp_path / 'fifo.yaml'
    os.mkfifo(fifo)
    proc = _run(['identify', RECORDING, '--model', str(fifo), '--out', str(tmp_path / 'g.yaml')],
                timeout=60)
    _one_line(proc, 'fifo.yaml', 'FIFO')


def _offset_model(tmp_path, offset):
    with open(BASE, encoding='utf-8') as fh:
        text = fh.read()
    assert '      length: 0.14\n' in text
    text = text.replace('      length: 0.14\n',
                        f'      length: 0.14\n      angle_offset: {offset}\n')
    model = tmp_path / 'm.yaml'
    model.write_text(text, encoding='utf-8')
    return model


def test_identify_and_fleet_refuse_an_angle_offset_beyond_a_turn(tmp_path, capsys):
    """``lever.angle_offset: 1.0e20`` gave identify exit 0 and an absurd fc; fleet took it."""
    model = _offset_model(tmp_path, '1.0e20')
    out = tmp_path / 'g.yaml'
    rc = main(['identify', RECORDING, '--model', str(model), '--out', str(out),
               '--presliding', 'skip', '--quiet'])
    _one_line_in_process(capsys, rc, 'm.yaml', 'lever.angle_offset', '1e+20')
    assert not out.exists()
    manifest = tmp_path / 'fleet.csv'
    manifest.write_text(f'recording,joint,time\n{RECORDING},j1,2026-03-02T14:05:00\n',
                        encoding='utf-8')
    rc = main(['fleet', '--manifest', str(manifest), '--model', str(model), '--out',
               str(tmp_path / 'fleet_out'), '--quiet'])
    _one_line_in_process(capsys, rc, 'm.yaml', 'lever.angle_offset')
    assert not (tmp_path / 'fleet_out').exists()
