# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""``friction_joint import``: special files, reading in chunks, the memory budget, a full disk."""
import errno
import os
from pathlib import Path
import shutil
import subprocess
import sys

import friction_joint.bag as bag
from friction_joint.bag import read_recording
import friction_joint.bag.importer as importer
import friction_joint.bag.tables as tables
from friction_joint.cli import main
import numpy as np
import pytest
from sourcetree import SHARED

COLS = ['--time', 'time', '--position', 'pos', '--torque', 'tau']
REAL = Path(SHARED, 'real-data', 'tribometer', 'test_data_2.txt')


def _import(capsys, *argv):
    status = main(['import', *map(str, argv)])
    out, err = capsys.readouterr()
    return status, out, err


def _one_line(status, err, *expect):
    assert status == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and 'error: ' in lines[0], err
    for word in expect:
        assert word in lines[0], lines[0]
    return lines[0]


def _log(path, n=100, header='time,pos,tau'):
    t = np.arange(n) * 0.01
    np.savetxt(path, np.c_[t, np.sin(t), np.cos(t)], delimiter=',', header=header, comments='',
               fmt='%.9g')
    return path


# ------------------------------------------------------------------ special files ---

_FIFOS = """
import sys
from friction_joint.cli import main
for argv in sys.argv[1:]:
    print('status', main(argv.split('|')), flush=True)
"""


def test_fifo_inputs_end_at_once(tmp_path):
    """A FIFO as CSV or NPZ log or as mapping: one line each, exit 2, no hang (subprocess)."""
    good = _log(tmp_path / 'good.csv')
    out = ['--out', str(tmp_path / 'rec')] + COLS
    runs = []
    for name in ('fifo.csv', 'fifo.npz', 'fifo.yaml'):
        os.mkfifo(tmp_path / name)
        argv = ([good, '--mapping', tmp_path / name] if name.endswith('yaml')
                else [tmp_path / name])
        runs.append('|'.join(['import', *map(str, argv), *out]))
    proc = subprocess.run([sys.executable, '-c', _FIFOS, *runs], capture_output=True,
                          text=True, timeout=120, stdin=subprocess.DEVNULL)
    assert proc.stdout.split() == ['status', '2'] * 3, proc.stdout + proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 3, proc.stderr
    for name, line in zip(('fifo.csv', 'fifo.npz', 'fifo.yaml'), lines, strict=True):
        assert str(tmp_path / name) in line and 'FIFO' in line, line
    assert not (tmp_path / 'rec').exists()


@pytest.mark.parametrize('device', ['/dev/zero', '/dev/urandom'])
def test_devices_refused_before_reading(tmp_path, capsys, device):
    _one_line(*_import(capsys, device, '--out', tmp_path / 'rec', *COLS)[::2], device, 'device')


def test_directory_and_unreadable_inputs(tmp_path, capsys):
    d = tmp_path / 'adir.csv'
    d.mkdir()
    _one_line(*_import(capsys, d, '--out', tmp_path / 'rec', *COLS)[::2], str(d), 'directory')
    _one_line(*_import(capsys, _log(tmp_path / 'g.csv'), '--mapping', d, '--out',
                       tmp_path / 'rec', *COLS)[::2], str(d), 'directory')
    if os.geteuid() == 0:
        pytest.skip('root reads files of mode 000')
    bad = _log(tmp_path / 'bad.csv')
    bad.chmod(0)
    _one_line(*_import(capsys, bad, '--out', tmp_path / 'rec', *COLS)[::2], str(bad),
              'permission')


# ------------------------------------------------------------ chunks and the budget ---

def test_chunked_reader_matches_whole_file(tmp_path, monkeypatch):
    """Tiny chunks: lines split anywhere, blank lines, CRLF, a BOM; rows still named right."""
    monkeypatch.setattr(tables, 'CHUNK', 7)
    t = np.arange(60) * 0.01
    lines = [f'{a:.2f},{np.sin(a):.6f},{np.cos(a):.6f}' for a in t]
    lines[10:10] = ['', '   ']
    text = '\ufeffpreamble\ntime,pos,tau\n' + '\r\n'.join(lines) + '\n\n'
    log = tmp_path / 'log.csv'
    log.write_text(text, encoding='utf-8')
    header, cols, rows = tables.read_table(log, skip_rows=1, pick=lambda h, w: [0, 2])
    assert header == ['time', 'pos', 'tau']
    np.testing.assert_allclose(cols[0], np.round(t, 2))
    np.testing.assert_allclose(cols[1], np.round(np.cos(t), 6))
    assert rows[0] == 3 and rows[9] == 12 and rows[10] == 15 and rows[59] == 64
    bad = text.replace(lines[40], lines[40].replace(',', ',1_0', 1))
    log.write_text(bad, encoding='utf-8')
    with pytest.raises(tables.RecordingError, match=r'row 43: .1_0'):
        tables.read_table(log, skip_rows=1)


def test_budget_refuses_before_decoding(tmp_path, capsys, monkeypatch):
    """A log over the memory budget: one line naming its size, no number decoded."""
    log = _log(tmp_path / 'log.csv', n=5000)
    monkeypatch.setattr(importer, 'IMPORT_BUDGET', 100_000)

    def no_parse(*args, **kwargs):
        raise AssertionError('decoded although over the budget')

    monkeypatch.setattr(tables.np, 'loadtxt', no_parse)
    _one_line(*_import(capsys, log, '--out', tmp_path / 'rec', *COLS)[::2], str(log),
              '5000 rows', 'MiB', 'memory budget')
    npz = tmp_path / 'log.npz'
    np.savez(npz, time=np.arange(5000.0), pos=np.zeros(5000), tau=np.zeros(5000))
    _one_line(*_import(capsys, npz, '--out', tmp_path / 'rec', *COLS)[::2], str(npz),
              'memory budget')
    monkeypatch.undo()
    one = 5000 * (importer.ROW_BYTES + 4 * 8 + importer.WRITE_BYTES)   # and the velocity
    monkeypatch.setattr(importer, 'IMPORT_BUDGET', int(1.5 * one))   # one file fits, not two
    assert _import(capsys, log, '--out', tmp_path / 'one', *COLS, '--quiet')[0] == 0
    _one_line(*_import(capsys, log, log, '--out', tmp_path / 'two', *COLS)[::2],
              'memory budget')


def test_long_line_without_newline_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(tables, 'MAX_LINE', 1000)
    monkeypatch.setattr(tables, 'CHUNK', 64)
    log = tmp_path / 'long.csv'
    log.write_text('time,pos,tau\n0,0,0\n' + '1' * 5000)
    _one_line(*_import(capsys, log, '--out', tmp_path / 'rec', *COLS)[::2], str(log), 'row 3',
              'longer than')


# --------------------------------------------------------------------- a full disk ---

def test_full_disk_one_line_old_output_kept(tmp_path, capsys, monkeypatch):
    """ENOSPC while writing: one line, exit 2, the old REC untouched, no temporary left."""
    log = _log(tmp_path / 'log.csv')
    rec = tmp_path / 'rec'
    assert _import(capsys, log, '--out', rec, *COLS, '--quiet')[0] == 0
    before = {p: p.read_bytes() for p in rec.iterdir()}

    def full(path, *args, **kwargs):                # a part written, then the disk is full
        os.mkdir(path)
        (Path(path) / 'part.mcap').write_bytes(bytes(1000))
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(bag, 'write_recording', full)
    _one_line(*_import(capsys, log, '--out', rec, *COLS, '--force')[::2], str(rec),
              'No space left')
    assert {p: p.read_bytes() for p in rec.iterdir()} == before
    assert sorted(os.listdir(tmp_path)) == ['log.csv', 'rec']


@pytest.mark.skipif(shutil.which('unshare') is None, reason='needs unshare')
def test_full_tmpfs(tmp_path):
    """A real 1 MiB tmpfs (a user and mount namespace): one line, nothing left on it."""
    mnt = tmp_path / 'mnt'
    mnt.mkdir()
    log = _log(tmp_path / 'log.csv', n=30_000)
    cmd = (f'mount -t tmpfs -o size=1m none {mnt} && {sys.executable} -m friction_joint import '
           f'{log} --out {mnt}/rec {" ".join(COLS)}; echo "status=$?"; ls -A {mnt}')
    proc = subprocess.run(['unshare', '-rm', 'sh', '-c', cmd], capture_output=True, text=True,
                          timeout=300)
    if 'status=' not in proc.stdout:
        pytest.skip(f'cannot mount a tmpfs here: {proc.stderr.strip()[:200]}')
    out = proc.stdout.strip().splitlines()
    assert out == ['status=2'], proc.stdout       # and nothing listed on the tmpfs
    _one_line(2, proc.stderr, f'{mnt}/rec', 'No space left')


# ---------------------------------------------------------------------- real data ---

@pytest.mark.skipif(not REAL.is_file(), reason='real tribometer log not present')
def test_real_tribometer_log_still_imports(tmp_path, capsys):
    rec = tmp_path / 'rec'
    status, _, err = _import(capsys, REAL, '--out', rec, '--time', 'Time [s]', '--position',
                             'Position [mm]', '--friction', 'Friction [uN]', '--flip-friction',
                             '--quiet')
    assert status == 0, err
    js = read_recording(rec).joint_states
    assert len(js) > 40_000 and np.all(np.isfinite(js.effort))
