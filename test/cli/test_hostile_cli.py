# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Hostile command lines, round 2: sizes, output errors, options and messages end in one line.

Each case ends with exit 2 and one line naming the problem (or 130 after Ctrl-C), nothing
written, no temporary left, earlier outputs untouched.
"""
import errno
import os
import signal
import subprocess
import sys
import time

from friction_joint.bag import write_recording
from friction_joint.cli import main
from friction_joint.gear import load_gear
from friction_joint.models import StaticFriction
import numpy as np
import pytest

from refusal import one_line

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')


def _no_temporaries(directory):
    left = [e for e in os.listdir(directory) if e.startswith('.')]
    assert not left, f'temporaries left: {left}'


# ------------------------------------------------------------------ sizes ---

@pytest.mark.parametrize('name', ['chirp', 'compensation', 'estimation', 'gain_sweep',
                                  'identification'])
@pytest.mark.parametrize('scale', ['1e12', '1e308'])
def test_duration_scale_checked_before_allocation(tmp_path, capsys, name, scale):
    """``experiment chirp --duration-scale 1e12`` tried to allocate 426 PiB; 1e308 overflowed."""
    out = tmp_path / 'out'
    rc = main(['experiment', name, '--model', MODEL, '--truth', TRUTH, '--out', str(out),
               '--duration-scale', scale])
    one_line(capsys, rc, 'memory budget', '--duration-scale')
    assert not out.exists()
    _no_temporaries(tmp_path)


# ---------------------------------------------------------- output errors ---

def _enospc(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_full_disk_while_writing_a_recording(tmp_path, capsys, monkeypatch):
    """``experiment identification`` on a full disk: one line, old output kept, no temporary."""
    from friction_joint.experiments import runner
    import friction_joint.jobs.experiment as job

    def partial(path, topics, **kwargs):
        os.makedirs(path)
        with open(os.path.join(path, 'half.mcap'), 'wb') as fh:
            fh.write(b'\x89MCAP0\r\n')
        _enospc()
    exp = runner.EXPERIMENTS['identification']
    monkeypatch.setitem(runner.EXPERIMENTS, 'identification', exp._replace(
        func=lambda model, truth, scale, progress=None: ({}, {})))
    monkeypatch.setattr(job, 'write_recording', partial)
    out = tmp_path / 'rec'
    out.mkdir()
    (out / 'old.txt').write_text('old')
    rc = main(['experiment', 'identification', '--truth', TRUTH, '--out', str(out), '--force'])
    one_line(capsys, rc, str(out), 'No space left on device')
    assert sorted(os.listdir(out)) == ['old.txt'] and (out / 'old.txt').read_text() == 'old'
    _no_temporaries(tmp_path)


def test_full_disk_while_staging_results(tmp_path, capsys, monkeypatch):
    """A write failing with ENOSPC while the results are staged: one line, old output kept."""
    import friction_joint.output as output
    real = os.fdopen

    class Full:
        def __init__(self, fh):
            self.fh = fh

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

        def write(self, data):
            self.fh.write(data[:10])
            self.fh.flush()
            _enospc()

    def fdopen(fd, mode='r', *args, **kwargs):
        fh = real(fd, mode, *args, **kwargs)
        return Full(fh) if 'w' in mode else fh
    monkeypatch.setattr(output.os, 'fdopen', fdopen)
    out = tmp_path / 'out'
    out.mkdir()
    (out / 'old.txt').write_text('old')
    rc = main(['experiment', 'chirp', '--model', MODEL, '--truth', TRUTH, '--out', str(out),
               '--force', '--duration-scale', '0.01', '--quiet'])    # no progress: the error
    one_line(capsys, rc, 'No space left on device')
    assert sorted(os.listdir(out)) == ['old.txt']
    _no_temporaries(tmp_path)


def test_oserror_anywhere_is_one_line(tmp_path, capsys, monkeypatch):
    """An OSError a command does not expect (a read-only target found late) is one line."""
    from friction_joint.cli import identify

    def read_only(args):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(tmp_path / 'g.yaml'))
    monkeypatch.setattr(identify, 'run', read_only)
    rc = main(['identify', 'x', '--model', BASE, '--out', str(tmp_path / 'g.yaml')])
    one_line(capsys, rc, 'g.yaml', 'Read-only file system')


@pytest.mark.parametrize('device', ['/dev/null', '/dev/zero'])
def test_device_is_never_replaced_even_with_force(tmp_path, capsys, device):
    """``--out /dev/null --force`` would rename the machine's /dev/null away (as root)."""
    if not os.path.exists(device):
        pytest.skip(f'no {device}')
    before = os.lstat(device)
    rc = main(['experiment', 'chirp', '--model', MODEL, '--truth', TRUTH, '--out', device,
               '--force', '--duration-scale', '0.01'])
    one_line(capsys, rc, device, 'character device', 'never replaced')
    after = os.lstat(device)
    assert (after.st_ino, after.st_rdev) == (before.st_ino, before.st_rdev)


@pytest.mark.skipif(not hasattr(os, 'mkfifo'), reason='no FIFOs')
def test_fifo_output_is_never_replaced_even_with_force(tmp_path, capsys):
    """A FIFO given as --out belongs to another program: refused even with --force."""
    fifo = tmp_path / 'out'
    os.mkfifo(fifo)
    rc = main(['experiment', 'chirp', '--model', MODEL, '--truth', TRUTH, '--out', str(fifo),
               '--force', '--duration-scale', '0.01'])
    one_line(capsys, rc, str(fifo), 'FIFO')
    assert os.path.exists(fifo) and not os.path.isdir(fifo)


def test_file_output_with_trailing_slash_refused(tmp_path, capsys):
    """``--out DIR/x.yaml/`` wrote the report to ``DIR/_report``; now refused in one line."""
    rec = _recording(tmp_path / 'rec')
    out = str(tmp_path / 'x.yaml') + os.sep
    rc = main(['identify', rec, '--model', BASE, '--out', out, '--quiet'])
    one_line(capsys, rc, out, 'directory separator')
    assert sorted(os.listdir(tmp_path)) == ['rec']


# ----------------------------------------------------------------- options ---

def _recording(path, xi=30.0, t0=0.0):
    gear = load_gear(BASE)
    dt = 1e-3
    prof = []
    for v in (0.2, -0.2, 1.0, -1.0):
        ramp = np.sin(np.linspace(0.0, np.pi / 2, 100)) ** 2 * v
        prof += [ramp, np.full(800, v), ramp[::-1], np.zeros(100)]
    qd = np.concatenate(prof)
    t = t0 + dt * np.arange(len(qd))
    q = np.cumsum(qd) * dt
    x = np.full(len(t), 30.0)
    tau_ext = gear.mgl * np.sin(q)
    effort = (StaticFriction(gear.friction).torque(qd, x, np.abs(tau_ext)) + tau_ext
              + gear.inertia * np.gradient(qd, dt))
    topics = {'/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
              '/joint_temperature': {'t': t[::250], 'xi': np.full(len(t[::250]), xi)},
              '/link_torque': {'t': t, 'tau': tau_ext}}
    return write_recording(str(path), topics)


@pytest.mark.parametrize('orders, words', [
    ('fc=-1', ['--orders', 'fc=-1', 'from 0 to']),
    ('fc=100', ['--orders', 'fc=100', 'from 0 to']),
    ('friction=1', ['--orders', 'unknown polynomial']),
])
def test_orders_blames_the_option(tmp_path, capsys, orders, words):
    """``--orders fc=-1`` blamed the data; it is the option that is wrong."""
    rc = main(['identify', 'nowhere', '--model', BASE, '--out', str(tmp_path / 'g.yaml'),
               '--orders', orders])
    line = one_line(capsys, rc, *words)
    assert 'recording' not in line and 'csd25_base' not in line, line


@pytest.mark.parametrize('argv', [
    ['experiment', 'chirp', '--model', MODEL, '--truth', TRUTH, '--duration-scale', 'nan'],
    ['experiment', 'chirp', '--model', MODEL, '--truth', TRUTH, '--duration-scale', 'inf'],
    ['demo', '--duration-scale', 'nan'],
    ['demo', '--duration-scale=-inf'],
])
def test_float_options_must_be_finite(tmp_path, capsys, argv):
    """Check every float option: argparse's ``float`` takes nan and inf; one line."""
    argv = argv + ['--out', str(tmp_path / 'out')]
    one_line(capsys, main(argv), '--duration-scale', 'finite')
    assert not (tmp_path / 'out').exists()


@pytest.mark.parametrize('key, lines', [('mass', 1), ('sigma1', 2)])
def test_every_line_of_a_failing_run_is_a_message(tmp_path, key, lines):
    """A numpy overflow warning (a 1e300 kg lever) or a gear warning printed source lines."""
    with open(TRUTH, encoding='utf-8') as fh:
        text = fh.read()
    truth = tmp_path / 'truth.yaml'
    truth.write_text(text.replace(f'  {key}: ', f'  {key}: 1.0e300 #', 1), encoding='utf-8')
    proc = subprocess.run([sys.executable, '-m', 'friction_joint', 'experiment', 'chirp',
                           '--model', MODEL, '--truth', str(truth), '--out',
                           str(tmp_path / 'out'), '--duration-scale', '0.01'],
                          capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
    got = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(got) == lines, proc.stderr
    assert all(line.startswith('friction_joint experiment: ') for line in got), proc.stderr
    assert got[-1].startswith('friction_joint experiment: error: '), proc.stderr
    assert not (tmp_path / 'out').exists()


@pytest.mark.parametrize('gains', ['J=1e308', 'kp=1e300,kd=1e300'])
def test_gains_beyond_the_plant_refused_before_the_run(tmp_path, capsys, gains):
    """``--gains J=1e308`` gave a ValueError traceback from the controller."""
    out = tmp_path / 'out'
    rc = main(['experiment', 'compensation', '--model', MODEL, '--truth', TRUTH, '--out',
               str(out), '--duration-scale', '0.05', '--gains', gains])
    one_line(capsys, rc, '--gains', 'unstable')
    assert not out.exists()


@pytest.mark.parametrize('command', ['identify', 'diagnose'])
def test_absurd_temperature_does_not_blame_the_gear_file(tmp_path, capsys, command):
    """A recording at 1e300 degC named config/csd25_base.yaml; the recording is at fault."""
    rec = _recording(tmp_path / 'hot', xi=1e300)
    out = tmp_path / ('g.yaml' if command == 'identify' else 'diag')
    rc = main([command, rec, '--model', BASE, '--out', str(out), '--quiet'])
    line = one_line(capsys, rc, 'hot', '/joint_temperature')
    assert 'csd25_base' not in line and 'record it' not in line, line
    assert not out.exists()


def test_recorded_temperature_out_of_range_blames_the_recordings(tmp_path, capsys):
    """
    Blame the recordings for temperatures the identified gear cannot have.

    Temperatures just below the reader's limit (then 1000 degC) made the identified gear
    invalid: that error named the structure file (``csd25_base.yaml``) and asked to lower
    its order.  The reader's limit is now 500 degC: the recording is refused, by name.
    """
    rec = _recording(tmp_path / 'hot', xi=999.99)
    rc = main(['identify', rec, '--model', BASE, '--out', str(tmp_path / 'g.yaml'), '--quiet'])
    line = one_line(capsys, rc, 'hot', '/joint_temperature', '500')
    assert 'csd25_base' not in line and 'order' not in line, line
    assert not (tmp_path / 'g.yaml').exists()


# ------------------------------------------------------------------ Ctrl-C ---

def _light_entry():
    """Whether ``import friction_joint.cli`` (before main runs) leaves numpy unloaded."""
    proc = subprocess.run([sys.executable, '-c', 'import sys, friction_joint.cli; '
                           'print("numpy" in sys.modules)'], capture_output=True, text=True,
                          timeout=120)
    return proc.stdout.strip() == 'False'


def _loaded(pid, marker):
    """Whether the process ``pid`` has mapped a shared library whose path holds ``marker``."""
    try:
        with open(f'/proc/{pid}/maps', encoding='utf-8', errors='replace') as fh:
            return marker in fh.read()
    except OSError:
        return False


def _signal_once_loaded(proc, marker):
    """Send SIGINT once ``proc`` has loaded ``marker`` (or has ended): a condition, no sleep."""
    deadline = time.monotonic() + 120
    while not _loaded(proc.pid, marker) and proc.poll() is None:
        assert time.monotonic() < deadline, f'{marker} never loaded'
        time.sleep(0.01)
    proc.send_signal(signal.SIGINT)


#: libraries loaded inside main() (the package import before it stays light): numpy's core
#: first, numba's dispatcher later
STAGES = ['_multiarray_umath', 'numba/_dispatcher']


@pytest.mark.parametrize('command', ['identify', 'diagnose'])
@pytest.mark.parametrize('stage', STAGES)
def test_ctrl_c_while_starting_is_one_line(tmp_path, command, stage):
    """
    SIGINT while the heavy modules import gave a KeyboardInterrupt traceback.

    main() turns an interrupt into one line and exit 130 from its first instruction on;
    before it, the package itself is imported, which must stay light (numpy unloaded) so
    that the signal, sent once a heavy library is loaded, reaches main().
    """
    assert _light_entry(), 'importing friction_joint.cli loads numpy before main() runs'
    rec = _recording(tmp_path / 'rec')
    out = tmp_path / ('g.yaml' if command == 'identify' else 'diag')
    proc = subprocess.Popen([sys.executable, '-m', 'friction_joint', command, rec, '--model',
                             BASE, '--out', str(out), '--quiet'], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True)
    _signal_once_loaded(proc, stage)
    _, err = proc.communicate(timeout=120)
    assert 'Traceback' not in err, err
    if proc.returncode != 0:                 # a fast machine may have finished already
        assert proc.returncode == 130, err
        assert len(err.strip().splitlines()) == 1, err
        assert not out.exists()


@pytest.mark.ros
@pytest.mark.parametrize('stage', ['_multiarray_umath', '_rclpy_pybind11'])
def test_ctrl_c_while_record_starts_is_one_line(tmp_path, stage):
    """SIGINT while ``record`` imports rclpy gave a KeyboardInterrupt traceback."""
    assert _light_entry(), 'importing friction_joint.cli loads numpy before main() runs'
    out = tmp_path / 'rec'
    proc = subprocess.Popen([sys.executable, '-c', 'import sys; from friction_joint.cli.record '
                             'import main; sys.exit(main())', str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            stdin=subprocess.DEVNULL, text=True)
    _signal_once_loaded(proc, stage)
    _, err = proc.communicate(timeout=120)
    assert 'Traceback' not in err, err
    assert proc.returncode in (0, 130), err       # 0: it had started and stopped cleanly
    if proc.returncode == 130:
        assert len(err.strip().splitlines()) == 1, err


#: sitecustomize of the test below: SIGINT to the process as module $SIGINT_AT starts loading
SIGINT_HOOK = """
import os, signal, sys

class _SigintAt:
    def find_spec(self, name, path=None, target=None):
        if name == os.environ.get('SIGINT_AT'):
            os.kill(os.getpid(), signal.SIGINT)
        return None

sys.meta_path.insert(0, _SigintAt())
"""


@pytest.mark.parametrize('entry', ['-m', 'script'])
@pytest.mark.parametrize('module', ['friction_joint._version', 'friction_joint.exceptions',
                                    'friction_joint.cli', 'argparse'])
def test_ctrl_c_while_the_package_loads_is_one_line(tmp_path, entry, module):
    """
    SIGINT as a module of the package's own import loads, before ``main()`` runs.

    It raised ``KeyboardInterrupt`` inside the import: a traceback, exit -2.  Now the
    package guards SIGINT from its first line in a program of its own (``python -m
    friction_joint``, the ``friction_joint`` console script): one line, exit 130.
    """
    hook = tmp_path / 'hook'
    hook.mkdir()
    (hook / 'sitecustomize.py').write_text(SIGINT_HOOK)
    script = tmp_path / 'bin' / 'friction_joint'            # as the console script is
    script.parent.mkdir()
    script.write_text('import sys\nfrom friction_joint.cli import main\nsys.exit(main())\n')
    env = dict(os.environ, SIGINT_AT=module,
               PYTHONPATH=os.pathsep.join([str(hook), ROOT, os.environ.get('PYTHONPATH', '')]))
    out = tmp_path / 'diag'
    argv = ['-m', 'friction_joint'] if entry == '-m' else [str(script)]
    proc = subprocess.run([sys.executable, *argv, 'diagnose', 'rec', '--model', BASE, '--out',
                           str(out)], capture_output=True, text=True, env=env, timeout=120,
                          stdin=subprocess.DEVNULL, preexec_fn=_default_sigint)
    assert 'Traceback' not in proc.stderr, proc.stderr
    assert proc.returncode == 130, proc.stderr
    assert proc.stderr.strip().splitlines() == ['friction_joint: interrupted'], proc.stderr
    assert proc.stdout == '' and not out.exists()


def _default_sigint():
    """Give the child Python's default SIGINT (a suite run in the background ignores it)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
