# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Signals stop a command as Ctrl-C does, and never leave a half-replaced or orphaned output.

``friction_joint import LOG --out rec --force`` over an existing ``rec`` runs
in a subprocess:

* deterministically: ``os.rename`` is wrapped so that the process sends
  itself SIGTERM, SIGINT or SIGHUP at a chosen rename of the publish (and
  optionally fails a later one); the signal waits until the swap is done:
  the new recording is complete (or, after the failure, the old one is back),
  the exit status is 128 + the signal number, no hidden ``.tmp`` remains;
* for real: SIGTERM at moments chosen by what is on disk (started, staging
  directory made, recording being staged, staged in full, the new recording
  in place: too short a window to hit the swap itself by polling), and
  SIGHUP when it was ignored at start (``nohup``): the old output untouched
  or the new one complete, nothing hidden left;
* killed outright (SIGKILL, no handler runs) in the middle of the swap: the
  next run's start-up sweep puts the old recording back (then refuses it
  without ``--force``) or removes the leftover old one, whichever the
  moment left.
"""
import os
from pathlib import Path
import signal
import subprocess
import sys
import time

from friction_joint.cli import main
import pytest

ROOT = Path(__file__).resolve().parents[2]
TRIBOMETER = ROOT / 'test' / 'data' / 'tribometer' / 'test_data_2_every6.tsv'
IMPORT = ['import', str(TRIBOMETER), '--time', 'Time [s]', '--position', 'Position [mm]',
          '--friction', 'Friction [uN]', '--flip-friction', '--quiet']
TIMEOUT = 120.0

#: run a command with ``os.rename`` wrapped: argv = OUTPUT STEP SIGNAL FAIL ARGS...
#: (at the STEP-th rename naming OUTPUT send SIGNAL to itself, or SIGKILL; at the
#: FAIL-th fail with EIO; 0: never)
HOOK = r"""
import errno, os, signal, sys
from friction_joint.cli import main
out, step, sig, fail = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
real, seen = os.rename, []

def rename(src, dst):
    if out not in (os.path.abspath(src), os.path.abspath(dst)):
        return real(src, dst)
    seen.append(dst)
    if len(seen) == fail:
        raise OSError(errno.EIO, 'Input/output error (injected)')
    if sig == 'SIGKILL':
        real(src, dst)
    if len(seen) == step:
        os.kill(os.getpid(), getattr(signal, sig))
    if sig != 'SIGKILL':
        real(src, dst)

os.rename = rename
sys.exit(main(sys.argv[5:]))
"""


def snapshot(path):
    """Return ``{relative path: bytes}`` of the files under directory ``path``."""
    return {str(p.relative_to(path)): p.read_bytes()
            for p in sorted(Path(path).rglob('*')) if p.is_file()}


def hidden(directory):
    """Return the hidden entries (staging directories) in ``directory``."""
    return sorted(n for n in os.listdir(directory) if n.startswith('.'))


@pytest.fixture(scope='module')
def new_recording(tmp_path_factory):
    """Return the files of the recording the import writes (imported in-process once)."""
    out = tmp_path_factory.mktemp('reference') / 'rec'
    assert main([*IMPORT, '--out', str(out)]) == 0
    return snapshot(out)


@pytest.fixture
def old_output(tmp_path):
    """Return ``rec`` (an earlier output: two files, one in a subdirectory) and its files."""
    rec = tmp_path / 'rec'
    (rec / 'sub').mkdir(parents=True)
    (rec / 'metadata.yaml').write_text('an earlier run\n')
    (rec / 'sub' / 'old.mcap').write_bytes(b'old bytes')
    return rec, snapshot(rec)


def default_signals():
    """Give a child the default signal actions (a suite run in the background ignores SIGINT)."""
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, signal.SIG_DFL)


def start(args, **options):
    """Start ``friction_joint ARGS`` in a subprocess (stdout, stderr piped)."""
    options.setdefault('preexec_fn', default_signals)
    return subprocess.Popen([sys.executable, '-m', 'friction_joint', *map(str, args)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=str(ROOT), **options)


def hooked(out, step, sig, fail=0):
    """Run the import over ``out`` with the rename hook; return (status, stderr)."""
    proc = subprocess.run([sys.executable, '-c', HOOK, str(out), str(step), sig, str(fail),
                           *IMPORT, '--out', str(out), '--force'],
                          capture_output=True, text=True, cwd=str(ROOT), timeout=TIMEOUT,
                          preexec_fn=default_signals)
    return proc.returncode, proc.stderr


def wait_until(condition, proc):
    """Poll ``condition()`` until it holds or ``proc`` has ended; return whether it held."""
    deadline = time.monotonic() + TIMEOUT
    while proc.poll() is None and time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.0005)
    return False


def stage_has(directory, name):
    """Return a condition: some staging directory of ``rec`` in ``directory`` holds ``name``."""
    def condition():
        try:
            return any(os.path.lexists(os.path.join(directory, s, name))
                       for s in os.listdir(directory) if s.startswith('.rec.'))
        except OSError:
            return False
    return condition


# ------------------------------------------------------- a signal in the swap ---

@pytest.mark.parametrize('step,sig', [(1, 'SIGTERM'), (2, 'SIGTERM'), (1, 'SIGINT'),
                                      (2, 'SIGHUP')])
def test_signal_during_the_swap_completes_it(new_recording, old_output, step, sig):
    """Step 1: the old output is being moved aside; 2: the new one moved into place."""
    rec, _ = old_output
    status, err = hooked(rec, step, sig)
    assert status == 128 + getattr(signal, sig), err
    what = 'interrupted' if sig == 'SIGINT' else f'stopped by {sig}'
    assert err.strip() == f'friction_joint import: {what}'
    assert snapshot(rec) == new_recording
    assert hidden(rec.parent) == []


def test_signal_and_a_failed_swap_keep_the_old_output(old_output):
    """SIGTERM while the old output is moved aside, then the new one cannot be: all old."""
    rec, old = old_output
    status, err = hooked(rec, 1, 'SIGTERM', fail=2)
    assert status == 143, err
    assert snapshot(rec) == old
    assert hidden(rec.parent) == []


# ----------------------------------------------------------- real SIGTERMs ---

@pytest.mark.parametrize('moment', ['started', 'staging', 'staged', 'written', 'replaced'])
def test_sigterm_leaves_old_or_new(new_recording, old_output, moment):
    """SIGTERM once a condition holds (or the run has ended): old untouched or new complete."""
    rec, old = old_output
    tmp = str(rec.parent)
    conditions = {
        'started': lambda: True,
        'staging': lambda: any(n.startswith('.rec.') for n in os.listdir(tmp)),
        'staged': stage_has(tmp, 'rec'),
        'written': stage_has(tmp, 'rec/metadata.yaml'),
        'replaced': lambda: (rec / 'rec.mcap').exists(),
    }
    proc = start([*IMPORT, '--out', rec, '--force'])
    if wait_until(conditions[moment], proc):
        proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=TIMEOUT)
    assert proc.returncode in (0, 143, -signal.SIGTERM), err
    if proc.returncode == 143:
        assert err.strip() == 'friction_joint import: stopped by SIGTERM'
    assert snapshot(rec) in (old, new_recording)
    if proc.returncode == 0:
        assert snapshot(rec) == new_recording
    assert hidden(tmp) == []


def test_an_ignored_sighup_stays_ignored(new_recording, old_output):
    """Under ``nohup`` (SIGHUP ignored at start) a hang-up does not stop the command."""
    rec, _ = old_output
    proc = start([*IMPORT, '--out', rec, '--force'],
                 preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN))
    if wait_until(stage_has(str(rec.parent), 'rec'), proc):
        proc.send_signal(signal.SIGHUP)
    _, err = proc.communicate(timeout=TIMEOUT)
    assert proc.returncode == 0, err
    assert snapshot(rec) == new_recording
    assert hidden(rec.parent) == []


# ---------------------------------------------- killed outright: the sweep ---

def test_sweep_puts_back_the_old_output_of_a_killed_run(new_recording, old_output, capsys):
    """SIGKILL just after the old output was moved aside: the next run restores it."""
    rec, old = old_output
    status, _ = hooked(rec, 1, 'SIGKILL')
    assert status == -signal.SIGKILL
    assert not rec.exists() and len(hidden(rec.parent)) == 1      # the measured problem
    assert main([*IMPORT, '--out', str(rec)]) == 2                # restored, so refused
    assert str(rec) in capsys.readouterr().err
    assert snapshot(rec) == old
    assert hidden(rec.parent) == []
    assert main([*IMPORT, '--out', str(rec), '--force']) == 0
    assert snapshot(rec) == new_recording and hidden(rec.parent) == []


def test_sweep_removes_the_replaced_output_of_a_killed_run(new_recording, old_output):
    """SIGKILL just after the new output was moved into place: the old one is garbage."""
    rec, _ = old_output
    status, _ = hooked(rec, 2, 'SIGKILL')
    assert status == -signal.SIGKILL
    assert snapshot(rec) == new_recording and len(hidden(rec.parent)) == 1
    assert main([*IMPORT, '--out', str(rec), '--force']) == 0
    assert snapshot(rec) == new_recording and hidden(rec.parent) == []


def test_main_restores_the_signal_handlers(tmp_path):
    """In-process, ``main`` leaves the handlers as it found them."""
    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    assert main([*IMPORT, '--out', str(tmp_path / 'rec')]) == 0
    assert {s: signal.getsignal(s) for s in before} == before


# ------------------------------------------ a stop after the command has ended ---

#: run ``friction_joint`` whose command returns 0 at once, with a SIGTERM arriving at a
#: chosen place after it: argv[1] = 'imports' (while the Ctrl-C guard of the imports is
#: taken down) or 'handlers' (while the SIGTERM and SIGHUP handlers are put back)
LATE = r"""
import contextlib, os, signal, sys
import friction_joint.cli as cli
where = sys.argv[1]
cli._main = lambda argv, prog: 0
real_guard, real_signal = cli.interrupts_between_imports, signal.signal

@contextlib.contextmanager
def guard():
    with real_guard():
        yield
        if where == 'imports':
            os.kill(os.getpid(), signal.SIGTERM)

def put(sig, handler):
    if where == 'handlers' and sig == signal.SIGTERM and handler == signal.SIG_DFL:
        signal.signal = real_signal
        os.kill(os.getpid(), signal.SIGTERM)
    return real_signal(sig, handler)

cli.interrupts_between_imports = guard
sys.argv = ['friction_joint']
cli._stop_on_signals()              # the handlers main installs: main sees them as the originals
real_signal(signal.SIGTERM, signal.SIG_DFL)
real_signal(signal.SIGHUP, signal.SIG_DFL)
signal.signal = put
sys.exit(cli.main())
"""


@pytest.mark.parametrize('where,status', [('imports', 143), ('handlers', -signal.SIGTERM)])
def test_a_sigterm_after_the_command_ended_is_one_line_or_the_default_end(where, status):
    """A SIGTERM while main takes its handlers down: 143 with its line, or death by SIGTERM."""
    proc = subprocess.run([sys.executable, '-c', LATE, where], capture_output=True, text=True,
                          cwd=str(ROOT), timeout=TIMEOUT, preexec_fn=default_signals)
    assert proc.returncode == status, proc.stderr
    expected = 'friction_joint: stopped by SIGTERM' if status == 143 else ''
    assert proc.stderr.strip() == expected


#: a console script (``console_main``) whose command returns 0, with a Ctrl-C arriving while
#: the Ctrl-C guard of the imports is taken down
LATE_CONSOLE = r"""
import contextlib, os, signal, sys, types
from friction_joint.cli import _console
real_guard = _console.interrupts_between_imports

@contextlib.contextmanager
def guard():
    with real_guard():
        yield
        os.kill(os.getpid(), signal.SIGINT)

_console.interrupts_between_imports = guard
module = types.SimpleNamespace(NAME='node', DESCRIPTION='a node', run=lambda args: 0,
                               add_arguments=lambda parser: parser)
sys.argv = ['node']
sys.exit(_console.console_main(module))
"""


def test_a_ctrl_c_after_a_console_script_ended_is_one_line():
    """Before: the interrupt raised out of the guard's exit, a traceback and exit 1."""
    proc = subprocess.run([sys.executable, '-c', LATE_CONSOLE], capture_output=True, text=True,
                          cwd=str(ROOT), timeout=TIMEOUT, preexec_fn=default_signals)
    assert proc.returncode == 130, proc.stderr
    assert proc.stderr.strip() == 'node: interrupted'
