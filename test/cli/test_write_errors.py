# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A full disk, a quota, a read-only file system, a permission: one line per command.

Every command's outputs are staged and written through one layer
(:class:`~friction_joint.output.OutputSet`); an ``OSError`` there (ENOSPC,
EDQUOT, EROFS, EACCES) ends the command with exit 2 and one line naming the
file, nothing left at the output and no staging directory.  What a library
does with its own cache on the same full disk (numba's compiled functions,
matplotlib's font list) is not the command's business: numba's failed cache
write aborted the computation with ``error: No space left on device`` naming
no file, and matplotlib printed ``Could not save font_manager cache`` as a
second line.
"""
import errno
import os
import shutil
import subprocess
import sys
import types

from friction_joint.bag import write_recording
from friction_joint.cli import _console, main
from friction_joint.gear import load_gear
from friction_joint.jobs.fleet_simulation import run_fleet_simulation
from friction_joint.models import StaticFriction
import numpy as np
import pytest

from refusal import one_line

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')
ERRNOS = [errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES]


def _nothing_left(directory, *keep):
    left = sorted(e for e in os.listdir(directory) if e not in keep)
    assert not left, f'left behind: {left}'


def _failing_writes(monkeypatch, code):
    """Make every file the output layer writes fail with ``code`` after 10 bytes."""
    import friction_joint.output as output
    real = os.fdopen

    class Failing:
        def __init__(self, fh):
            self.fh = fh

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

        def write(self, data):
            self.fh.write(data[:10])
            self.fh.flush()
            raise OSError(code, os.strerror(code))      # as a file object's write: no name

    def fdopen(fd, mode='r', *args, **kwargs):
        fh = real(fd, mode, *args, **kwargs)
        return Failing(fh) if 'w' in mode else fh
    monkeypatch.setattr(output.os, 'fdopen', fdopen)


@pytest.fixture(scope='module')
def recording(tmp_path_factory):
    """Plateaus both ways at two speeds, 30 degC (identify and diagnose take it in seconds)."""
    gear = load_gear(BASE)
    dt = 1e-3
    prof = []
    for v in (0.2, -0.2, 1.0, -1.0):
        ramp = np.sin(np.linspace(0.0, np.pi / 2, 100)) ** 2 * v
        prof += [ramp, np.full(800, v), ramp[::-1], np.zeros(100)]
    qd = np.concatenate(prof)
    t = dt * np.arange(len(qd))
    q = np.cumsum(qd) * dt
    tau_ext = gear.mgl * np.sin(q)
    effort = (StaticFriction(gear.friction).torque(qd, np.full(len(t), 30.0), np.abs(tau_ext))
              + tau_ext + gear.inertia * np.gradient(qd, dt))
    topics = {'/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
              '/joint_temperature': {'t': t[::250], 'xi': np.full(len(t[::250]), 30.0)},
              '/link_torque': {'t': t, 'tau': tau_ext}}
    return write_recording(str(tmp_path_factory.mktemp('rec') / 'rec'), topics)


@pytest.fixture(scope='module')
def fleet(tmp_path_factory):
    root = tmp_path_factory.mktemp('fleet')
    run_fleet_simulation(root / 'fleet', joints=1, days=2, seed=3, cfg={'speeds': (0.5, 2.0)})
    return root / 'fleet'


def _argv(command, out, recording=None, fleet=None):
    return {
        'classic': ['classic', 'presliding', '--out', out],
        'experiment': ['experiment', 'chirp', '--model', MODEL, '--truth', TRUTH, '--out', out,
                       '--duration-scale', '0.01', '--quiet'],
        'identify': ['identify', str(recording), '--model', BASE, '--out', out + '.yaml',
                     '--presliding', 'skip', '--quiet'],
        'diagnose': ['diagnose', str(recording), '--model', BASE, '--out', out, '--quiet'],
        'fleet': ['fleet', '--manifest', str(fleet and fleet / 'manifest.csv'), '--model',
                  MODEL, '--out', out, '--workers', '1', '--quiet'],
    }[command]


@pytest.mark.parametrize('code', ERRNOS, ids=errno.errorcode.get)
def test_classic_every_write_error_is_one_line(tmp_path, capsys, monkeypatch, code):
    """ENOSPC, EDQUOT, EROFS, EACCES while writing: one line naming the file, nothing left."""
    _failing_writes(monkeypatch, code)
    out = str(tmp_path / 'out')
    rc = main(_argv('classic', out))
    one_line(capsys, rc, out, os.strerror(code))
    _nothing_left(tmp_path)


@pytest.mark.parametrize('command, code', [('experiment', errno.EDQUOT),
                                           ('identify', errno.ENOSPC),
                                           ('diagnose', errno.EROFS),
                                           ('fleet', errno.EACCES)])
def test_each_command_write_error_is_one_line(tmp_path, capsys, monkeypatch, recording, fleet,
                                              command, code):
    """Each command: the write error in one line naming the output, nothing half-written."""
    out = str(tmp_path / 'out')
    _failing_writes(monkeypatch, code)
    rc = main(_argv(command, out, recording, fleet))
    one_line(capsys, rc, out, os.strerror(code))
    _nothing_left(tmp_path)


def test_cached_fleet_on_a_full_disk_is_one_line(tmp_path, capsys, monkeypatch, fleet):
    """A fleet whose every result comes from the cache, rewritten on a full disk."""
    out = str(tmp_path / 'out')
    assert main(_argv('fleet', out, fleet=fleet)) == 0
    before = sorted(os.listdir(out))
    capsys.readouterr()
    _failing_writes(monkeypatch, errno.ENOSPC)
    rc = main(_argv('fleet', out, fleet=fleet) + ['--force'])
    one_line(capsys, rc, out, 'No space left on device')
    assert sorted(os.listdir(out)) == before
    _nothing_left(tmp_path, 'out')


@pytest.mark.parametrize('code', ERRNOS, ids=errno.errorcode.get)
def test_console_script_oserror_is_one_line(capsys, code):
    """``ros2 run friction_joint record``: an OSError found late was a traceback."""
    def run(args):
        raise OSError(code, os.strerror(code), '/media/usb/rec')
    module = types.SimpleNamespace(NAME='record', DESCRIPTION='', run=run,
                                   add_arguments=lambda parser: parser)
    rc = _console.console_main(module, ['record'])
    line = one_line(capsys, rc, '/media/usb/rec', os.strerror(code))
    assert line.startswith('record: error: '), line


def test_numba_cache_that_cannot_be_written_costs_a_compilation(tmp_path, monkeypatch):
    """Numba raised the cache's ENOSPC from inside the computation; the cache is optional."""
    numba = pytest.importorskip('numba')
    from numba.core import caching

    from friction_joint._jit import HAVE_NUMBA, njit
    if not HAVE_NUMBA:
        pytest.skip('numba disabled')

    def full(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(numba.config, 'CACHE_DIR', str(tmp_path))
    monkeypatch.setattr(caching.IndexDataCacheFile, 'save', full)
    monkeypatch.setattr(caching.IndexDataCacheFile, 'load', full)

    def twice(x):
        return 2.0 * x
    assert njit(twice)(1.5) == 3.0


@pytest.mark.skipif(shutil.which('unshare') is None, reason='needs unshare')
@pytest.mark.parametrize('full', ['blocks', 'inodes'])
def test_full_tmpfs_with_the_caches_on_it(tmp_path, full):
    """
    A real full tmpfs holding the output, HOME, numba's and matplotlib's caches: one line.

    Before, numba's failed cache write ended the command with ``error: No space left on
    device`` (no file named) and matplotlib added ``Could not save font_manager cache``
    (no block free) or ``mkdir -p failed for path`` (no inode free).
    """
    mnt = tmp_path / 'mnt'
    mnt.mkdir()
    if full == 'blocks':
        size, fill = 'size=256k', f'(head -c 1000000 /dev/zero > {mnt}/fill 2>/dev/null; true)'
    else:
        size, fill = ('size=256k,nr_inodes=64',
                      f'(i=0; while touch {mnt}/i$i 2>/dev/null; do i=$((i+1)); done)')
    cmd = (f'mount -t tmpfs -o {size} none {mnt} && mkdir {mnt}/home {mnt}/mpl && {fill} && '
           f'HOME={mnt}/home MPLCONFIGDIR={mnt}/mpl/sub NUMBA_CACHE_DIR={mnt}/numba '
           f'{sys.executable} -m friction_joint classic presliding --out {mnt}/out; '
           f'echo "status=$?"; ls -A {mnt}')
    proc = subprocess.run(['unshare', '-rm', 'sh', '-c', cmd], capture_output=True, text=True,
                          timeout=600, env=dict(os.environ, PYTHONPATH=ROOT))
    if 'status=' not in proc.stdout:
        pytest.skip(f'cannot mount a tmpfs here: {proc.stderr.strip()[:200]}')
    lines = proc.stderr.strip().splitlines()
    assert proc.stdout.split()[0] == 'status=2', proc.stdout + proc.stderr
    assert len(lines) == 1, proc.stderr
    where = f'{mnt}/out/presliding.png' if full == 'blocks' else f'directory {mnt}/out'
    assert f'{where}: No space left on device' in lines[0], lines[0]
    assert 'out' not in proc.stdout.split()[1:], proc.stdout     # nothing half-written
