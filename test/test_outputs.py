# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Outputs of the commands: never overwritten without --force, replaced as a whole with it.

Every command that writes results (identify, diagnose, experiment, classic,
demo) refuses an existing output (file, symlink, FIFO, non-empty directory)
with exit status 2 and a message naming it; ``--force`` replaces the old
output as a whole (no stale file of an earlier run remains), all outputs of
one command together or not at all; an output that is an input is an error
even with ``--force``.  Inputs are small (a synthetic recording, a 20 s
simulated one, shortened experiments, stubs for the ROS part of ``demo``).
"""
import errno
import json
import os
from pathlib import Path
import signal
import socket
import stat
import subprocess
import sys
import time
import uuid

from friction_joint.bag import read_recording, write_recording
from friction_joint.cli import main
from friction_joint.exceptions import FrictionJointError
from friction_joint.experiments import classic, runner
from friction_joint.experiments.hidden import RecordingOptions, simulate_recording
from friction_joint.gear import load_gear, save_gear
from friction_joint.jobs import demo
from friction_joint.models.static import StaticFriction
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
STRUCTURE = ROOT / 'config' / 'csd25.yaml'
BASE = ROOT / 'config' / 'csd25_base.yaml'
MODEL = ROOT / 'config' / 'csd25.yaml'
TRUTH = ROOT / 'config' / 'csd25_truth.yaml'

pytestmark = pytest.mark.filterwarnings('ignore::friction_joint.exceptions.GearConfigWarning')


def normal_mode():
    """Return the mode a newly written file should have: 0o666 minus the umask."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def leftovers(*dirs):
    """Hidden temporary entries (staging directories, backups) left in ``dirs``."""
    return [f'{d}/{n}' for d in dirs if os.path.isdir(d) for n in os.listdir(d)
            if n.startswith('.')]


# ------------------------------------------------------------------ identify ---

@pytest.fixture(scope='module')
def ident_inputs(tmp_path_factory):
    """Return a one-temperature structure file and a synthetic plateau recording of it."""
    d = tmp_path_factory.mktemp('ident')
    gear = load_gear(STRUCTURE).replace({'friction': {
        'fc': [2.2], 'fv': [0.41], 'fs': [4.5], 'vs': [4.9], 'delta_v': [0.4],
        'fc_load': [0.02], 'temperature_range': [20.0, 40.0]}})
    structure = d / 'structure.yaml'
    save_gear(gear, structure)
    dt = 1e-3
    prof = []
    for v in [s * v for v in np.geomspace(0.01, 3.0, 12) for s in (1.0, -1.0)]:
        ramp = np.sin(np.linspace(0.0, np.pi / 2, 100)) ** 2 * v
        prof += [ramp, np.full(1000, v), ramp[::-1], np.zeros(200)]
    qd = np.concatenate(prof)
    t = dt * np.arange(len(qd))
    q = np.cumsum(qd) * dt + 0.3
    tau_ext = gear.mgl * np.sin(q)
    effort = (StaticFriction(gear.friction).torque(qd, 30.0, np.abs(tau_ext)) + tau_ext
              + gear.inertia * np.gradient(qd, dt))
    bag = write_recording(d / 'rec.mcap', {
        '/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
        '/joint_temperature': {'t': t[::250], 'xi': np.full(len(t[::250]), 30.0)},
        '/link_torque': {'t': t, 'tau': tau_ext}})
    return structure, Path(bag)


def identify(inputs, out, *extra):
    structure, bag = inputs
    return main(['identify', str(bag), '--model', str(structure), '--out', str(out),
                 '--presliding', 'skip', '--quiet', *extra])


def old_identify_output(tmp_path):
    """Write an earlier run's gear file (mode 0600) and report directory with a stale figure."""
    gear = tmp_path / 'gear.yaml'
    gear.write_text('old gear\n')
    gear.chmod(0o600)
    report = tmp_path / 'gear_report'
    report.mkdir()
    (report / 'identification.json').write_text('{"old": true}\n')
    (report / 'stale.png').write_bytes(b'old figure')
    return gear, report


def test_identify_writes_gear_with_normal_mode(ident_inputs, tmp_path):
    out = tmp_path / 'gear.yaml'
    assert identify(ident_inputs, out) == 0
    assert stat.S_IMODE(out.stat().st_mode) == normal_mode()
    assert stat.S_IMODE((tmp_path / 'gear_report' / 'identification.json').stat().st_mode) \
        == normal_mode()
    assert load_gear(out).friction.fc_load
    assert leftovers(tmp_path) == []


def test_identify_refuses_existing_gear_file(ident_inputs, tmp_path, capsys):
    out = tmp_path / 'gear.yaml'
    out.write_text('keep me\n')
    assert identify(ident_inputs, out) == 2
    err = capsys.readouterr().err
    assert str(out) in err and 'exists' in err and '--force' in err
    assert len(err.strip().splitlines()) == 1
    assert out.read_text() == 'keep me\n'
    assert not (tmp_path / 'gear_report').exists()


def test_identify_refuses_existing_report_dir(ident_inputs, tmp_path, capsys):
    (tmp_path / 'gear_report').mkdir()
    (tmp_path / 'gear_report' / 'fig.png').write_bytes(b'old')
    assert identify(ident_inputs, tmp_path / 'gear.yaml') == 2
    assert str(tmp_path / 'gear_report') in capsys.readouterr().err
    assert not (tmp_path / 'gear.yaml').exists()
    assert os.listdir(tmp_path / 'gear_report') == ['fig.png']


@pytest.mark.parametrize('kind', ['symlink', 'fifo'])
def test_identify_refuses_symlink_and_fifo(ident_inputs, tmp_path, capsys, kind):
    out = tmp_path / 'gear.yaml'
    target = tmp_path / 'elsewhere.yaml'
    target.write_text('target\n')
    if kind == 'symlink':
        out.symlink_to(target)
    else:
        os.mkfifo(out)
    assert identify(ident_inputs, out) == 2
    assert str(out) in capsys.readouterr().err
    assert out.is_symlink() if kind == 'symlink' else stat.S_ISFIFO(os.lstat(out).st_mode)
    assert target.read_text() == 'target\n'


@pytest.mark.parametrize('force', [(), ('--force',)], ids=['', 'force'])
@pytest.mark.parametrize('which', ['model', 'recording', 'model symlink'])
def test_identify_out_is_an_input_even_with_force(ident_inputs, tmp_path, capsys, which, force):
    structure, bag = ident_inputs
    if which == 'model symlink':
        out = tmp_path / 'link.yaml'
        out.symlink_to(structure)
    else:
        out = structure if which == 'model' else bag
    before = Path(out).read_bytes()
    assert identify(ident_inputs, out, *force) == 2
    err = capsys.readouterr().err
    assert str(out) in err and 'input' in err
    assert Path(out).read_bytes() == before
    assert not (Path(out).parent / (Path(out).stem + '_report')).exists()


def test_identify_force_replaces_the_whole_set(ident_inputs, tmp_path):
    gear, report = old_identify_output(tmp_path)
    assert identify(ident_inputs, gear, '--force') == 0
    assert load_gear(gear).friction.fc_load
    assert stat.S_IMODE(gear.stat().st_mode) == normal_mode()
    assert not (report / 'stale.png').exists()
    assert 'old' not in json.loads((report / 'identification.json').read_text())
    assert leftovers(tmp_path) == []


def test_identify_unwritable_gear_leaves_no_report(ident_inputs, tmp_path, capsys):
    blocker = tmp_path / 'file'
    blocker.write_text('a file, not a directory\n')
    report = tmp_path / 'report'
    assert identify(ident_inputs, blocker / 'gear.yaml', '--report', str(report)) == 2
    assert str(blocker) in capsys.readouterr().err
    assert not report.exists()
    assert blocker.read_text() == 'a file, not a directory\n'


def test_identify_failed_gear_rename_keeps_the_old_set(ident_inputs, tmp_path, monkeypatch,
                                                       capsys):
    gear, report = old_identify_output(tmp_path)
    real_rename, real_replace = os.rename, os.replace

    failed = []

    def failing(real):
        def move(src, dst, *args, **kwargs):
            if os.path.abspath(dst) == str(gear) and not failed:      # once
                failed.append(src)
                raise OSError(errno.EIO, 'Input/output error (injected)')
            return real(src, dst, *args, **kwargs)
        return move
    monkeypatch.setattr(os, 'rename', failing(real_rename))
    monkeypatch.setattr(os, 'replace', failing(real_replace))
    assert identify(ident_inputs, gear, '--force') == 2
    assert failed and str(gear) in capsys.readouterr().err
    assert gear.read_text() == 'old gear\n'
    assert json.loads((report / 'identification.json').read_text()) == {'old': True}
    assert (report / 'stale.png').read_bytes() == b'old figure'
    assert leftovers(tmp_path) == []


def test_identify_inside_a_staged_directory_names_final_paths(ident_inputs, tmp_path):
    """As in ``demo``: built in a staging directory, the files name where they end up."""
    from friction_joint.jobs.identify import run_identify
    from friction_joint.output import OutputSet
    structure, bag = ident_inputs
    out = tmp_path / 'demo_out'
    with OutputSet() as outputs:
        outputs.add_directory(out)
        stage = Path(outputs.staging_path(out))
        stage.mkdir()
        (stage / 'rec.mcap').write_bytes(bag.read_bytes())
        run_identify([str(stage / 'rec.mcap')], str(structure), str(stage / 'gear.yaml'),
                     presliding='skip', relocate=outputs.final_path)
        outputs.publish()
    for path in (out / 'gear.yaml', out / 'gear_report' / 'identification.json'):
        text = path.read_text()
        assert str(stage) not in text and str(out / 'rec.mcap') in text, path
    assert leftovers(tmp_path, out) == []


# ------------------------------------------------------------------ diagnose ---

@pytest.fixture(scope='module')
def diag_recording(tmp_path_factory):
    """Return a short valid recording of the base (20 s, two temperature segments)."""
    base = load_gear(BASE)
    path = tmp_path_factory.mktemp('diag') / 'rec'
    simulate_recording(base, path, options=RecordingOptions(duration=20.0, seed=7, n_segments=2))
    return path


def diagnose(rec, out, *extra):
    return main(['diagnose', str(rec), '--model', str(BASE), '--out', str(out),
                 '--effects', 'thermal,load', '--quiet', *extra])


def test_diagnose_refuses_non_empty_out(diag_recording, tmp_path, capsys):
    out = tmp_path / 'out'
    out.mkdir()
    (out / 'notes.txt').write_text('mine\n')
    assert diagnose(diag_recording, out) == 2
    err = capsys.readouterr().err
    assert str(out) in err and '--force' in err
    assert os.listdir(out) == ['notes.txt']


def test_diagnose_accepts_empty_out(diag_recording, tmp_path):
    out = tmp_path / 'out'
    out.mkdir()
    assert diagnose(diag_recording, out) == 0
    assert json.loads((out / 'report.json').read_text())['named_causes'] == []


def test_diagnose_force_leaves_no_stale_figures(diag_recording, tmp_path):
    out = tmp_path / 'out'
    out.mkdir()
    (out / 'cause_thermal.png').write_bytes(b'figure of an earlier run')
    (out / 'report.json').write_text('{"named_causes": ["thermal"]}\n')
    assert diagnose(diag_recording, out, '--force') == 0
    assert json.loads((out / 'report.json').read_text())['named_causes'] == []
    assert sorted(os.listdir(out)) == ['extended.yaml', 'gains.png', 'report.html',
                                       'report.json', 'report.md', 'residual_scan.png',
                                       'torque.png', 'velocity.png']
    assert stat.S_IMODE((out / 'report.json').stat().st_mode) == normal_mode()
    assert leftovers(tmp_path) == []


def test_diagnose_out_is_the_recording(diag_recording, tmp_path, capsys):
    before = sorted(os.listdir(diag_recording))
    assert diagnose(diag_recording, diag_recording, '--force') == 2
    err = capsys.readouterr().err
    assert str(diag_recording) in err and 'input' in err
    assert sorted(os.listdir(diag_recording)) == before
    read_recording(diag_recording)


# ---------------------------------------------------------------- experiment ---

def experiment(name, out, *extra, truth=TRUTH):
    return main(['experiment', name, '--model', str(MODEL), '--truth', str(truth),
                 '--out', str(out), '--duration-scale', '0.05', *extra])


def test_experiment_refuses_non_empty_out(tmp_path, capsys):
    out = tmp_path / 'out'
    out.mkdir()
    (out / 'summary.json').write_text('{"experiment": "compensation"}\n')
    assert experiment('chirp', out) == 2
    assert str(out) in capsys.readouterr().err
    assert os.listdir(out) == ['summary.json']


def test_experiment_force_replaces_the_directory(tmp_path):
    out = tmp_path / 'out'
    out.mkdir()
    (out / 'compensation_bars.png').write_bytes(b'earlier experiment')
    assert experiment('chirp', out, '--force') == 0
    assert sorted(os.listdir(out)) == ['chirp.png', 'summary.json']
    assert json.loads((out / 'summary.json').read_text())['experiment'] == 'chirp'
    assert leftovers(tmp_path) == []


def test_experiment_out_containing_an_input(tmp_path, capsys):
    truth = tmp_path / 'cfg' / 'truth.yaml'
    truth.parent.mkdir()
    truth.write_bytes(TRUTH.read_bytes())
    assert experiment('chirp', truth.parent, '--force', truth=truth) == 2
    err = capsys.readouterr().err
    assert str(truth.parent) in err and str(truth) in err
    assert truth.read_bytes() == TRUTH.read_bytes()


@pytest.fixture
def tiny_excitation(monkeypatch):
    """Replace the identification excitation by two seconds of a sine (written as a recording)."""
    def excitation(model, truth, scale, progress=None):
        t = 1e-3 * np.arange(2000)
        q = 0.1 * np.sin(t)
        return ({'/joint_states': {'t': t, 'q': q, 'qd': 0.1 * np.cos(t), 'effort': q},
                 '/joint_temperature': {'t': t[::250], 'xi': np.full(8, 30.0)}},
                {'plateaus': [], 'duration_s': 2.0})
    exp = runner.EXPERIMENTS['identification']
    monkeypatch.setitem(runner.EXPERIMENTS, 'identification', exp._replace(func=excitation))


@pytest.mark.parametrize('name', ['bag', 'bag.mcap'])
def test_experiment_recording_force(tiny_excitation, tmp_path, capsys, name):
    out = tmp_path / name
    if name.endswith('.mcap'):
        out.write_bytes(b'not a recording')
    else:
        out.mkdir()
        (out / 'old.mcap').write_bytes(b'not a recording')
    args = ['experiment', 'identification', '--truth', str(TRUTH), '--out', str(out)]
    assert main(args) == 2
    assert str(out) in capsys.readouterr().err
    assert main(args + ['--force']) == 0
    assert len(read_recording(out).joint_states) == 2000
    assert not (out / 'old.mcap').exists()
    assert leftovers(tmp_path) == []


# ------------------------------------------------------------------- classic ---

@pytest.fixture
def fast_lag(monkeypatch):
    monkeypatch.setitem(classic.CLASSIC_EXPERIMENTS, 'lag',
                        lambda: classic.frictional_lag(samples_per_period=2000))


def test_classic_refuses_its_own_files(fast_lag, tmp_path, capsys):
    (tmp_path / 'lag.json').write_text('{"old": true}\n')
    assert main(['classic', 'lag', '--out', str(tmp_path)]) == 2
    assert str(tmp_path / 'lag.json') in capsys.readouterr().err
    assert sorted(os.listdir(tmp_path)) == ['lag.json']


def test_classic_shares_the_directory_and_force_replaces_its_pair(fast_lag, tmp_path):
    (tmp_path / 'presliding.json').write_text('{"other": true}\n')
    (tmp_path / 'lag.png').write_bytes(b'old figure')
    (tmp_path / 'lag.json').write_text('{"old": true}\n')
    assert main(['classic', 'lag', '--out', str(tmp_path), '--force']) == 0
    assert (tmp_path / 'lag.png').read_bytes().startswith(b'\x89PNG')
    assert 'loop_width' in json.loads((tmp_path / 'lag.json').read_text())
    assert (tmp_path / 'presliding.json').read_text() == '{"other": true}\n'
    assert stat.S_IMODE((tmp_path / 'lag.png').stat().st_mode) == normal_mode()
    assert sorted(os.listdir(tmp_path)) == ['lag.json', 'lag.png', 'presliding.json']


# ---------------------------------------------------------------------- demo ---

@pytest.fixture
def fast_demo(monkeypatch, fast_lag):
    """Stub the ROS run and the identification, one classic experiment, no test bed."""
    calls = []

    def ros_run(out, model, truth, duration):
        calls.append('ros')
        Path(out, 'ros_run.png').write_bytes(b'png')
        return ['ros run (stub)', '']

    def identification(out, model, truth, duration_scale, **options):
        calls.append('identification')
        Path(out, 'identification').mkdir()
        return ['identification (stub)', '']
    monkeypatch.setattr(demo, '_ros_run', ros_run)
    monkeypatch.setattr(demo, '_identification', identification)
    monkeypatch.setattr(demo, 'CLASSIC', ('lag',))
    monkeypatch.setattr(demo, 'TESTBED', ())
    return calls


def test_demo_refuses_non_empty_out_before_working(fast_demo, tmp_path, capsys):
    out = tmp_path / 'demo_out'
    out.mkdir()
    (out / 'notes.txt').write_text('mine\n')
    assert main(['demo', '--out', str(out)]) == 2
    assert str(out) in capsys.readouterr().err
    assert fast_demo == []
    assert os.listdir(out) == ['notes.txt']


def test_demo_force_replaces_the_whole_directory(fast_demo, tmp_path):
    out = tmp_path / 'demo_out'
    (out / 'chirp').mkdir(parents=True)
    (out / 'chirp' / 'summary.json').write_text('{}\n')
    assert main(['demo', '--out', str(out), '--force']) == 0
    assert sorted(os.listdir(out)) == ['classic', 'identification', 'report.html',
                                       'report.md', 'ros_run.png']
    assert sorted(os.listdir(out / 'classic')) == ['lag.json', 'lag.png']
    assert 'ros run (stub)' in (out / 'report.md').read_text()
    assert leftovers(tmp_path, out, out / 'classic') == []


def test_demo_failure_keeps_the_old_output(fast_demo, tmp_path, monkeypatch, capsys):
    out = tmp_path / 'demo_out'
    out.mkdir()
    (out / 'report.md').write_text('old report\n')

    def broken(*args, **kwargs):
        raise FrictionJointError('identification failed (stub)')
    monkeypatch.setattr(demo, '_identification', broken)
    assert main(['demo', '--out', str(out), '--force']) == 2
    assert 'identification failed' in capsys.readouterr().err
    assert os.listdir(out) == ['report.md'] and (out / 'report.md').read_text() == 'old report\n'
    assert leftovers(tmp_path) == []


def test_demo_out_containing_the_model(fast_demo, tmp_path, capsys):
    out = tmp_path / 'demo_out'
    out.mkdir()
    model = out / 'model.yaml'
    model.write_bytes(MODEL.read_bytes())
    assert main(['demo', '--out', str(out), '--model', str(model), '--force']) == 2
    assert str(model) in capsys.readouterr().err
    assert fast_demo == []
    assert model.read_bytes() == MODEL.read_bytes()


# ------------------------------------------------------------- the mechanism ---

def test_force_replaces_a_symlink_not_its_target(tmp_path):
    from friction_joint.output import publish_outputs
    target = tmp_path / 'target.txt'
    target.write_text('target\n')
    link = tmp_path / 'out.txt'
    link.symlink_to(target)
    with pytest.raises(FrictionJointError, match='symlink'):
        publish_outputs([(link, b'new\n')])
    assert publish_outputs([(link, b'new\n')], force=True) == [str(link)]
    assert not link.is_symlink() and link.read_text() == 'new\n'
    assert target.read_text() == 'target\n'


def test_directory_containing_the_working_directory_is_never_replaced(tmp_path, monkeypatch):
    from friction_joint.output import publish_outputs
    out = tmp_path / 'out'
    (out / 'sub').mkdir(parents=True)
    monkeypatch.chdir(out / 'sub')
    with pytest.raises(FrictionJointError, match='current directory'):
        publish_outputs([(out, [('a.txt', b'x')])], force=True)
    assert os.listdir(out) == ['sub']


def test_kind_mismatch_is_an_error_even_with_force(tmp_path):
    from friction_joint.output import publish_outputs
    (tmp_path / 'd').mkdir()
    (tmp_path / 'd' / 'x').write_text('x')
    (tmp_path / 'f').write_text('f')
    with pytest.raises(FrictionJointError, match='is a directory'):
        publish_outputs([(tmp_path / 'd', b'data')], force=True)
    with pytest.raises(FrictionJointError, match='not a directory'):
        publish_outputs([(tmp_path / 'f', [('a', b'x')])], force=True)
    assert (tmp_path / 'd' / 'x').read_text() == 'x' and (tmp_path / 'f').read_text() == 'f'


def test_interrupt_while_swapping_restores_the_old_outputs(tmp_path, monkeypatch):
    from friction_joint.output import publish_outputs
    single = tmp_path / 'a.txt'
    single.write_text('old a\n')
    folder = tmp_path / 'd'
    folder.mkdir()
    (folder / 'x').write_text('old x\n')
    real_rename, interrupted = os.rename, []

    def rename(src, dst):
        if os.fspath(dst) == str(folder) and not interrupted:      # once
            interrupted.append(src)
            raise KeyboardInterrupt
        return real_rename(src, dst)
    monkeypatch.setattr(os, 'rename', rename)
    with pytest.raises(KeyboardInterrupt):
        publish_outputs([(single, b'new a\n'), (folder, [('y', b'new y\n')])], force=True)
    assert interrupted
    assert single.read_text() == 'old a\n'
    assert os.listdir(folder) == ['x'] and (folder / 'x').read_text() == 'old x\n'
    assert leftovers(tmp_path) == []


# ------------------------------------------------------- signals and the sweep ---

def old_set(tmp_path):
    """Write an earlier set (a file, a directory, a file); return the outputs and their state."""
    a, d, c = tmp_path / 'a.txt', tmp_path / 'd', tmp_path / 'c.txt'
    a.write_text('old a\n')
    d.mkdir()
    (d / 'x').write_text('old x\n')
    c.write_text('old c\n')
    return (a, d, c), set_state(a, d, c)


def set_state(a, d, c):
    """Return what the set holds: its file contents and the directory's files."""
    return (a.read_text(), {n: (d / n).read_text() for n in os.listdir(d)}, c.read_text())


NEW_SET = ('new a\n', {'y': 'new y\n'}, 'new c\n')


def new_set_targets(a, d, c):
    return [(a, b'new a\n'), (d, [('y', b'new y\n')]), (c, b'new c\n')]


@pytest.mark.parametrize('step', range(1, 7))
def test_signal_during_the_swap_waits_for_the_whole_set(tmp_path, monkeypatch, step):
    """SIGTERM at any of the six renames is handled once the set is new and staging is gone."""
    from friction_joint.output import publish_outputs
    (a, d, c), _ = old_set(tmp_path)
    real_rename, renames, handled = os.rename, [], []
    sigint = signal.getsignal(signal.SIGINT)    # (ignored when the suite runs in the background)

    def rename(src, dst):
        renames.append(dst)
        if len(renames) == step:
            os.kill(os.getpid(), signal.SIGTERM)
        return real_rename(src, dst)

    def handler(signum, frame):
        handled.append((len(renames), set_state(a, d, c), leftovers(tmp_path)))
        raise KeyboardInterrupt
    monkeypatch.setattr(os, 'rename', rename)
    previous = signal.signal(signal.SIGTERM, handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            publish_outputs(new_set_targets(a, d, c), force=True)
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert handled == [(6, NEW_SET, [])]
    assert signal.getsignal(signal.SIGINT) is sigint            # put back as it was


def test_signal_during_a_failed_swap_waits_for_the_rollback(tmp_path, monkeypatch):
    """SIGTERM, then a rename fails: handled once every old output is back."""
    from friction_joint.output import publish_outputs
    (a, d, c), old = old_set(tmp_path)
    real_rename, renames, handled = os.rename, [], []

    def rename(src, dst):
        renames.append(dst)
        if len(renames) == 2:
            os.kill(os.getpid(), signal.SIGTERM)
        if len(renames) == 6:
            raise OSError(errno.EIO, 'Input/output error (injected)')
        return real_rename(src, dst)

    def handler(signum, frame):
        handled.append((set_state(a, d, c), leftovers(tmp_path)))
        raise KeyboardInterrupt
    monkeypatch.setattr(os, 'rename', rename)
    previous = signal.signal(signal.SIGTERM, handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            publish_outputs(new_set_targets(a, d, c), force=True)
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert handled == [(old, [])]


def test_failed_move_aside_of_an_old_output_changes_nothing(tmp_path, monkeypatch):
    """A rename that fails moving an old output aside moved nothing: nothing to put back."""
    from friction_joint.output import publish_outputs
    (a, d, c), old = old_set(tmp_path)
    real_rename = os.rename

    def rename(src, dst):
        if os.fspath(src) == str(d):
            raise OSError(errno.EIO, 'Input/output error (injected)')
        return real_rename(src, dst)
    monkeypatch.setattr(os, 'rename', rename)
    with pytest.raises(FrictionJointError, match='nothing was changed'):
        publish_outputs(new_set_targets(a, d, c), force=True)
    assert set_state(a, d, c) == old
    assert leftovers(tmp_path) == []


PUBLISH_KILLED = r"""
import errno, os, signal, sys
from pathlib import Path
from friction_joint.output import publish_outputs
tmp, step, fail = Path(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
real, seen = os.rename, []

def rename(src, dst):
    seen.append(dst)
    if len(seen) == step:
        os.kill(os.getpid(), signal.SIGTERM)        # default action: the process ends
    if len(seen) == fail:
        raise OSError(errno.EIO, 'Input/output error (injected)')
    return real(src, dst)

os.rename = rename
try:
    publish_outputs([(tmp / 'a.txt', b'new a\n'), (tmp / 'd', [('y', b'new y\n')]),
                     (tmp / 'c.txt', b'new c\n')], force=True)
except Exception as exc:
    print(f'error: {exc}')
print('not killed')
"""


@pytest.mark.parametrize('step,fail', [(1, 0), (4, 0), (6, 0), (3, 5)])
def test_default_sigterm_during_the_swap_ends_the_process_after_it(tmp_path, step, fail):
    """Without a handler SIGTERM kills the process: only once the set is whole and unstaged."""
    (a, d, c), old = old_set(tmp_path)
    proc = subprocess.run([sys.executable, '-c', PUBLISH_KILLED, str(tmp_path), str(step),
                           str(fail)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == -signal.SIGTERM, proc.stderr
    assert proc.stdout == ''
    assert set_state(a, d, c) == (old if fail else NEW_SET)
    assert leftovers(tmp_path) == []


def stale_stage(parent, name, owner, contents=(), tag='abcd_123'):
    """Make a staging directory of output ``name`` with an owner record and ``contents``."""
    stage = parent / f'.{name}.{tag}.tmp'
    stage.mkdir()
    if owner is not None:
        (stage / f'{name}.owner').write_text(owner)
    for rel, data in contents:
        (stage / rel).parent.mkdir(parents=True, exist_ok=True)
        (stage / rel).write_bytes(data)
    return stage


def dead_owner():
    """Return the owner record of a process that cannot exist (pid above pid_max)."""
    pid_max = int(Path('/proc/sys/kernel/pid_max').read_text())
    return f'{socket.gethostname()} {pid_max + 1} 12345\n'


def test_sweep_restores_an_old_output_moved_into_a_dead_stage(tmp_path):
    """A run killed while swapping: its old output is put back, its half-built new one gone."""
    from friction_joint.output import OutputSet
    stage = stale_stage(tmp_path, 'out', dead_owner(),
                        [('out.old/report.json', b'old'), ('out/half.png', b'new, half')])
    with OutputSet() as outputs:
        outputs.add_directory(tmp_path / 'out')
        assert not stage.exists()
        assert snapshot_dir(tmp_path / 'out') == {'report.json': b'old'}
        with pytest.raises(FrictionJointError, match='exists already'):
            outputs.check()
    assert leftovers(tmp_path) == []


def snapshot_dir(path):
    return {n: (path / n).read_bytes() for n in os.listdir(path)}


def test_sweep_removes_only_dead_stages_of_that_output(tmp_path):
    """Not a live owner's, another host's, another output's, a recorder's or a fresh one."""
    from friction_joint.output import OutputSet
    (tmp_path / 'out.txt').write_text('current\n')
    dead = stale_stage(tmp_path, 'out.txt', dead_owner(), [('out.txt.old', b'replaced')])
    live = tmp_path / '.out.txt.live_123.tmp'
    live.mkdir()
    (live / 'out.txt.owner').write_text(f'{socket.gethostname()} {os.getpid()} -\n')
    reused = stale_stage(tmp_path, 'out.txt', f'{socket.gethostname()} {os.getpid()} 1\n',
                         tag='reus_123')             # this pid, but another process's
    elsewhere = tmp_path / '.out.txt.away_123.tmp'
    elsewhere.mkdir()
    (elsewhere / 'out.txt.owner').write_text(f'another-host-{uuid.uuid4().hex} 1 1\n')
    other = stale_stage(tmp_path, 'out', dead_owner(), [('out.old', b'data of another')])
    hours_ago = (time.time() - 7200, time.time() - 7200)
    unowned_old = stale_stage(tmp_path, 'out.txt', None, [('out.txt.old', b'replaced')],
                              tag='old_0123')
    os.utime(unowned_old, hours_ago)           # an earlier version's: no owner, an old output
    unowned_new = stale_stage(tmp_path, 'out.txt', None, [('out.txt.old', b'replaced')],
                              tag='new_0123')
    recorders = stale_stage(tmp_path, 'out.txt', None, [('out.txt/rec_0.mcap', b'kept'),
                                                        ('recorder.json', b'{}')], tag='reco_123')
    os.utime(recorders, hours_ago)             # a killed recorder's: kept for recovery
    named_alike = tmp_path / '.out.txt.abc.tmp'
    named_alike.mkdir()
    with OutputSet(force=True) as outputs:
        outputs.add_file(tmp_path / 'out.txt')
        outputs.check()
    assert (tmp_path / 'out.txt').read_text() == 'current\n'
    assert not dead.exists() and not unowned_old.exists() and not reused.exists()
    assert live.exists() and elsewhere.exists() and unowned_new.exists()
    assert other.exists() and named_alike.exists() and recorders.exists()
