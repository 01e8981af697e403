# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Inputs are never outputs: an ``--out`` that is, contains or lies inside anything a command reads.

Every command that reads inputs registers all of them with its output set
(:class:`~friction_joint.output.OutputSet`): ``fleet`` its manifest, model and
every recording of the manifest; ``diagnose`` and ``identify`` their model and
recordings (a ``.mcap`` file of a rosbag2 directory: the whole directory);
``import`` its logs and mapping.  Writing over, into or above one of them ends
in exit 2 and one line naming the input, ``--force`` or not, and nothing is
written or deleted.
"""
import hashlib
import os
import shutil

from friction_joint.cli import main
from friction_joint.jobs.fleet_simulation import run_fleet_simulation
import pytest

from refusal import one_line

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
SAMPLE = os.path.join(ROOT, 'bags', 'csd25_sample')
#: a short daily test motion: the tiny fleet is simulated in a few seconds
SHORT = {'speeds': (0.5, 2.0)}


def _tree(top):
    """Return {relative path: SHA-256 of the bytes, or 'dir'} of everything below ``top``."""
    found = {}
    for root, dirs, files in os.walk(top):
        for d in dirs:
            found[os.path.relpath(os.path.join(root, d), top)] = 'dir'
        for f in files:
            with open(os.path.join(root, f), 'rb') as fh:
                found[os.path.relpath(os.path.join(root, f), top)] = \
                    hashlib.sha256(fh.read()).hexdigest()
    return found


@pytest.fixture(scope='module')
def tiny_fleet(tmp_path_factory):
    """Simulate a fleet (2 joints x 2 days) as ``experiment fleet --out fleet`` writes it."""
    root = tmp_path_factory.mktemp('tiny')
    run_fleet_simulation(root / 'fleet', joints=2, days=2, seed=3, cfg=SHORT)
    return root


@pytest.fixture
def site(tiny_fleet, tmp_path):
    """Copy the tiny fleet; write its manifest outside, pointing into ``fleet/recordings/``."""
    shutil.copytree(tiny_fleet / 'fleet', tmp_path / 'fleet')
    with open(tmp_path / 'fleet' / 'manifest.csv', encoding='utf-8') as fh:
        text = fh.read()
    lines = text.splitlines()
    body = [('fleet/' + line) for line in lines[1:]]
    (tmp_path / 'manifest.csv').write_text('\n'.join([lines[0]] + body) + '\n',
                                           encoding='utf-8')
    return tmp_path


@pytest.mark.parametrize('out, words', [
    ('fleet', ('--out fleet contains the input', 'recording of', 'row 2', 'j01_')),
    ('.', ('--out . contains the input',)),
    ('fleet/recordings', ('contains the input', 'row 2')),
    ('fleet/recordings/j01_2026-03-02.mcap', ('is an input', 'j01_2026-03-02.mcap')),
    ('fleet/recordings/j01_2026-03-02.mcap/x', ('is inside the input',)),
    ('manifest.csv', ('is an input', '--manifest')),
])
def test_fleet_out_over_its_recordings_or_manifest_refused_with_force(site, capsys, monkeypatch,
                                                                      out, words):
    monkeypatch.chdir(site)
    before = _tree(site)
    rc = main(['fleet', '--manifest', 'manifest.csv', '--model', MODEL, '--out', out,
               '--force', '--workers', '1', '--quiet'])
    one_line(capsys, rc, *words)
    assert _tree(site) == before                # every recording (and truth.json) still there
    assert len([p for p in before if p.startswith('fleet/recordings/')]) == 4


def test_fleet_out_above_the_model_refused(site, capsys, monkeypatch):
    monkeypatch.chdir(site)
    os.mkdir(site / 'gears')
    shutil.copy(MODEL, site / 'gears' / 'gear.yaml')
    before = _tree(site)
    rc = main(['fleet', '--manifest', 'manifest.csv', '--model', 'gears/gear.yaml', '--out',
               'gears', '--force', '--quiet'])
    one_line(capsys, rc, 'contains the input', '--model gears/gear.yaml')
    assert _tree(site) == before


def test_fleet_out_inside_a_rosbag2_directory_of_the_manifest_refused(tmp_path, capsys,
                                                                      monkeypatch):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(SAMPLE, tmp_path / 'bag')
    (tmp_path / 'm.csv').write_text('recording,joint,time\nbag/csd25_sample.mcap,j1,'
                                    '2026-03-02T10:00:00\n', encoding='utf-8')
    before = _tree(tmp_path)
    rc = main(['fleet', '--manifest', 'm.csv', '--model', MODEL, '--out', 'bag/out', '--force',
               '--quiet'])
    one_line(capsys, rc, 'is inside the input', 'part of the rosbag2 directory')
    assert _tree(tmp_path) == before


@pytest.mark.parametrize('recording, out, words', [
    ('rec', 'rec', ('is an input',)),
    ('rec/csd25_sample.mcap', 'rec', ('contains the input',)),
    ('rec/csd25_sample.mcap', 'rec/out', ('is inside the input', 'rosbag2 directory')),
    ('rec', 'rec/out', ('is inside the input',)),
    ('rec/', 'rec/.', ('is an input',)),
])
def test_diagnose_out_in_its_recording_refused_with_force(tmp_path, capsys, monkeypatch,
                                                          recording, out, words):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(SAMPLE, tmp_path / 'rec')
    before = _tree(tmp_path)
    rc = main(['diagnose', recording, '--model', BASE, '--out', out, '--force', '--quiet'])
    one_line(capsys, rc, *words)
    assert _tree(tmp_path) == before


@pytest.mark.parametrize('recording, out, words', [
    ('rec/csd25_sample.mcap', 'rec/gear.yaml', ('is inside the input', 'rosbag2 directory')),
    ('rec', 'rec/gear.yaml', ('is inside the input',)),
    ('rec', 'rec/metadata.yaml', ('is inside the input',)),
])
def test_identify_out_in_its_recording_refused_with_force(tmp_path, capsys, monkeypatch,
                                                          recording, out, words):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(SAMPLE, tmp_path / 'rec')
    before = _tree(tmp_path)
    rc = main(['identify', recording, '--model', BASE, '--out', out, '--report', 'report',
               '--force', '--quiet'])
    one_line(capsys, rc, *words)
    assert _tree(tmp_path) == before


@pytest.mark.parametrize('out, words', [
    ('logs', ('contains the input', 'LOG')),
    ('logs/a.csv', ('is an input',)),
    ('logs/a.csv/rec', ('is inside the input',)),
])
def test_import_out_over_its_logs_refused_with_force(tmp_path, capsys, monkeypatch, out, words):
    monkeypatch.chdir(tmp_path)
    os.mkdir('logs')
    (tmp_path / 'logs' / 'a.csv').write_text('t,q,qd,tau\n0,0,0,0\n0.001,0,0,0\n',
                                             encoding='utf-8')
    before = _tree(tmp_path)
    rc = main(['import', 'logs/a.csv', '--out', out, '--force', '--quiet'])
    one_line(capsys, rc, *words)
    assert _tree(tmp_path) == before


@pytest.mark.parametrize('path, out, words', [
    ('rec/csd25_sample.mcap', 'rec/fixed.mcap', ('is inside the input', 'rosbag2 directory')),
    ('rec/csd25_sample.mcap', 'rec', ('contains the input',)),
    ('rec', 'rec/fixed', ('is inside the input',)),
])
def test_recover_out_in_its_recording_refused_with_force(tmp_path, capsys, monkeypatch,
                                                         path, out, words):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(SAMPLE, tmp_path / 'rec')
    before = _tree(tmp_path)
    rc = main(['recover', path, out, '--force'])
    one_line(capsys, rc, *words)
    assert _tree(tmp_path) == before
