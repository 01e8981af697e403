# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
``fleet`` and ``experiment fleet``: options and manifests checked before use.

Each case ends in exit 2 and one line naming the problem (the option, or the
manifest and its row), nothing written, no hang: malformed ``--scheduler``
addresses, a port that answers garbage or stays silent, a scheduler without
workers, ``--workers`` beyond the machine, manifest times outside
1970..2199, NUL and control characters, non-ASCII or ``_``-separated travel,
a recording listed twice through a symlink; a simulated fleet too large
(with an estimate) or a negative seed.  Hypothesis fuzzes manifests and
scheduler strings.
"""
import os
import shutil
import socket
import threading
import time

from friction_joint.cli import main
from friction_joint.exceptions import ArgumentError, InputFileError
from friction_joint.fleet import cluster
from friction_joint.fleet.cluster import check_scheduler
from friction_joint.fleet.manifest import read_manifest, TIME_RANGE
from hypothesis import given, settings, strategies as st
import pytest

from refusal import one_line

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
SAMPLE = os.path.join(ROOT, 'bags', 'csd25_sample')


@pytest.fixture
def site(tmp_path, monkeypatch):
    """Write a manifest of one real recording in ``tmp_path`` (the current directory)."""
    monkeypatch.chdir(tmp_path)
    shutil.copytree(SAMPLE, tmp_path / 'rec')
    (tmp_path / 'm.csv').write_text('recording,joint,time\nrec,j1,2026-03-02T10:00:00\n',
                                    encoding='utf-8')
    return tmp_path


def _fleet(*extra):
    return main(['fleet', '--manifest', 'm.csv', '--model', MODEL, '--out', 'out', '--quiet',
                 *extra])


# ------------------------------------------------------------------ --scheduler ---

@pytest.mark.parametrize('address, words', [
    ('tcp://', 'not HOST:PORT'), ('foo', 'not HOST:PORT'), ('127.0.0.1', 'not HOST:PORT'),
    ('tcp://[::1', 'not HOST:PORT'), ('inproc://x', "protocol 'inproc'"),
    ('ucx://127.0.0.1:1', "protocol 'ucx'"), ('tls://127.0.0.1:1', 'TLS'),
    ('http://127.0.0.1:8786', "protocol 'http'"), ('tcp://host:8786/extra', 'not HOST:PORT'),
    (' ', 'empty'), ('', 'empty'), ('tcp://127.0.0.1:0', 'port 0'),
    ('tcp://127.0.0.1:65536', 'port 65536'), ('tcp://[zz::1]:8786', 'IPv6'),
    ('tcp://a b:8786', 'host name'), ('tcp://user@host:8786', 'host name'),
    ('tcp://h\x00:1', 'host name'), ('tcp://h:1\n', 'not HOST:PORT'),
    ('tcp://127.0.0.1:٨٧٨٦', 'not HOST:PORT'),
])
def test_malformed_scheduler_is_one_line(site, capsys, address, words):
    one_line(capsys, _fleet('--scheduler', address), '--scheduler', words)
    assert not (site / 'out').exists()


def _server(answer):
    """Start a TCP server that accepts and sends ``answer`` (b'': stays silent)."""
    srv = socket.socket()
    srv.bind(('127.0.0.1', 0))
    srv.listen(8)
    conns = []

    def serve():
        while True:
            try:
                c, _ = srv.accept()
            except OSError:
                return
            conns.append(c)
            if answer:
                try:
                    c.sendall(answer)
                except OSError:
                    pass

    threading.Thread(target=serve, daemon=True).start()

    def close():
        for c in conns:
            c.close()
        srv.close()
    return srv.getsockname()[1], close


@pytest.mark.parametrize('answer', [b'HTTP/1.0 200 OK\r\n\r\n' * 50, b'\xff' * 64,
                                    b'\x00' * 8])
def test_port_answering_garbage_is_one_line(site, capsys, monkeypatch, answer):
    monkeypatch.setattr(cluster, 'CONNECT_TIMEOUT', 2)
    port, close = _server(answer)
    try:
        one_line(capsys, _fleet('--scheduler', f'tcp://127.0.0.1:{port}'),
                 'cannot connect to the Dask scheduler')
    finally:
        close()
    assert not (site / 'out').exists()


def test_silent_port_times_out(site, capsys, monkeypatch):
    monkeypatch.setattr(cluster, 'CONNECT_TIMEOUT', 1)
    port, close = _server(b'')
    t0 = time.monotonic()
    try:
        one_line(capsys, _fleet('--scheduler', f'tcp://127.0.0.1:{port}'), 'no answer within')
    finally:
        close()
    assert time.monotonic() - t0 < 120          # a deadline (not a rate): it did not hang
    assert not (site / 'out').exists()


def test_scheduler_without_workers_is_refused_after_a_wait(site, capsys, monkeypatch):
    from distributed import LocalCluster
    monkeypatch.setattr(cluster, 'WORKER_WAIT', 2)
    with LocalCluster(n_workers=0, processes=False, protocol='tcp://', host='127.0.0.1',
                      dashboard_address=':0') as empty:
        rc = _fleet('--scheduler', empty.scheduler_address)
    one_line(capsys, rc, 'has no workers', 'dask worker')
    assert not (site / 'out').exists()


# -------------------------------------------------------------------- --workers ---

@pytest.mark.parametrize('workers, words', [
    ('99999999999999999999', 'more than this machine'), ('100000', 'more than this machine'),
    ('0', '>= 1'), ('-3', '>= 1')])
def test_workers_bounded_by_the_machine(site, capsys, workers, words):
    one_line(capsys, _fleet('--workers', workers), '--workers', words)
    assert not (site / 'out').exists()


# -------------------------------------------------------------------- manifests ---

@pytest.mark.parametrize('row, words', [
    ('rec,j1,9999-12-31T23:59:59', ('row 2', 'outside 1970..2199')),
    ('rec,j1,0001-01-01T00:00:00', ('row 2', 'outside')),
    ('rec,j1,9999-12-31T23:59:59-12:00', ('row 2', 'outside')),
    ('rec,j1,0001-01-01T00:00:00+14:00', ('row 2', 'outside')),
    ('rec,j1,1969-12-31T23:59:59Z', ('row 2', 'outside')),
    ('rec,j1,２０２６-03-02T10:00:00', ('row 2', 'ISO 8601')),
    ('rec\x00x,j1,2026-03-02T10:00:00', ('row 2', 'NUL')),
    ('rec,j\x001,2026-03-02T10:00:00', ('row 2', 'NUL')),
    ('re\x07c,j1,2026-03-02T10:00:00', ('row 2', 'control character')),
    ('rec,j\x1b[31m1,2026-03-02T10:00:00', ('row 2', 'joint', 'control character')),
    ('rec,j\x9b1,2026-03-02T10:00:00', ('row 2', 'joint', 'control character')),
    ('rec,j\u202e10,2026-03-02T10:00:00', ('row 2', 'joint', 'U+202E', 'invisible')),
    ('rec,j\u200b1,2026-03-02T10:00:00', ('row 2', 'joint', 'U+200B', 'invisible')),
    ('re\u2066c,j1,2026-03-02T10:00:00', ('row 2', 'recording', 'U+2066', 'invisible')),
])
def test_bad_manifest_rows_are_one_line(site, capsys, row, words):
    (site / 'm.csv').write_text(f'recording,joint,time\n{row}\n', encoding='utf-8')
    one_line(capsys, _fleet(), 'm.csv', *words)
    assert not (site / 'out').exists()


def test_too_many_recordings_refused_before_any_work(site, capsys, monkeypatch):
    from friction_joint.fleet import manifest
    monkeypatch.setattr(manifest, 'MAX_ROWS', 50)
    rows = ''.join(f'r{k}.mcap,j1,2026-03-02T10:00:00\n' for k in range(51))
    (site / 'm.csv').write_text('recording,joint,time\n' + rows, encoding='utf-8')
    one_line(capsys, _fleet(), 'm.csv', 'row 52', 'more than 50 recordings', 'split')


def test_a_real_million_row_manifest_is_refused_quickly(site, capsys):
    """Refused at the first row beyond the bound, before the rest is read (not a timing)."""
    rows = ''.join(f'recordings/r{k:07d}.mcap,robot07/j3,2026-03-02T10:00:00\n'
                   for k in range(300000))
    rows += 'a malformed row beyond the bound\n' * 700000     # never reached
    (site / 'm.csv').write_text('recording,joint,time\n' + rows, encoding='utf-8')
    line = one_line(capsys, _fleet(), 'm.csv', 'more than 250000 recordings')
    assert 'row 250002' in line and not (site / 'out').exists(), line


@pytest.mark.parametrize('travel', ['1_000', '١٢', '１２', '1e999', 'nan', '-1', '0x10', '1,5'])
def test_travel_must_be_a_plain_decimal(site, capsys, travel):
    (site / 'm.csv').write_text(f'recording,joint,time,travel\nrec,j1,2026-03-02T10:00:00,'
                                f'"{travel}"\n', encoding='utf-8')
    one_line(capsys, _fleet(), 'm.csv', 'row 2', 'travel')


@pytest.mark.parametrize('header, row, words', [
    ('recording,joint,time,travel', 'rec,j1,2026-03-02T10:00:00,' + '9' * 100000, 'travel'),
    ('recording,joint,time', 'rec,j1,' + '2' * 100000, 'time'),
    ('recording,joint,time', 'rec,j\x07' + 'x' * 100000 + ',2026-03-02T10:00:00', 'joint'),
    ('recording,' + ','.join('c%d' % i for i in range(30000)), 'rec', 'no column'),
])
def test_a_huge_field_is_shown_clipped(site, capsys, header, row, words):
    """The line named a 100000-digit travel in full: it shows 60 characters and the length."""
    (site / 'm.csv').write_text(f'{header}\n{row}\n', encoding='utf-8')
    line = one_line(capsys, _fleet(), 'm.csv', words, 'characters)')
    assert len(line) < 600, len(line)


@pytest.mark.parametrize('second', ['link', './rec', 'rec/', 'rec/../rec'])
def test_a_recording_listed_twice_is_refused(site, capsys, second):
    os.symlink('rec', site / 'link')
    (site / 'm.csv').write_text('recording,joint,time\nrec,j1,2026-03-02T10:00:00\n'
                                f'{second},j2,2026-03-03T10:00:00\n', encoding='utf-8')
    one_line(capsys, _fleet(), 'row 3', 'already listed in row 2')


# ----------------------------------------------------------------- experiment fleet ---

@pytest.mark.parametrize('argv, words', [
    (['--joints', '1000000'], ('1000000 x --days 30', 'h of simulation', 'GB')),
    (['--days', '100000'], ('--days 100000', 'h of simulation')),
    (['--joints', '1000000', '--days', '100000'], ('recordings',)),
    (['--seed', '-5'], ('--seed must be >= 0',)),
    (['--joints', '0'], ('>= 1 joint',)), (['--days', '1'], ('>= 2 days',)),
])
def test_simulated_fleet_bounded_before_any_work(tmp_path, capsys, argv, words):
    rc = main(['experiment', 'fleet', '--out', str(tmp_path / 'fleet'), '--quiet', *argv])
    one_line(capsys, rc, *words)
    assert os.listdir(tmp_path) == []        # refused before any work: nothing simulated


@pytest.mark.parametrize('name, argv, words', [
    ('fleet', ['--duration-scale', '-1'], '--duration-scale'),
    ('fleet', ['--gains', 'paper'], '--gains'),
    ('fleet', ['--model', 'config/csd25.yaml', '--duration-scale', '0'],
     '--model, --duration-scale'),
    ('chirp', ['--joints', '5'], '--joints'),
    ('identification', ['--seed', '3', '--days', '2'], '--days, --seed'),
])
def test_an_option_the_experiment_does_not_use_is_refused(tmp_path, capsys, name, argv,
                                                          words):
    """``experiment fleet --duration-scale -1`` and ``chirp --joints 5`` were silently run."""
    models = [] if name == 'fleet' else ['--model', MODEL, '--truth', MODEL]
    rc = main(['experiment', name, '--out', str(tmp_path / 'x'), '--quiet', *models, *argv])
    one_line(capsys, rc, words, f'not an option of experiment {name}')
    assert os.listdir(tmp_path) == []


# ------------------------------------------------------------------------ fuzz ---

_CELLS = ['rec', 'link', './rec', 'missing.mcap', '', ' ', 'j1', 'j2', '2026-03-02T10:00:00',
          '2026-03-03', '9999-12-31T23:59:59', '0001-01-01', 'yesterday', '2026-03-02T10:00:00Z',
          '2026-03-02T10:00:00+25:00', '1_000', '12', '-1', 'nan', '1e999', '٣', '"', ',',
          '\n', '\r', '\x00', '\t', 'x' * 300]
_COLUMNS = ['recording', 'joint', 'time', 'travel', 'robot', '', 'time']


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(header=st.lists(st.sampled_from(_COLUMNS), min_size=1, max_size=5),
       rows=st.lists(st.lists(st.one_of(st.sampled_from(_CELLS), st.text(max_size=6)),
                              max_size=6), max_size=6),
       raw=st.booleans())
def test_fuzz_manifests_are_read_or_refused_in_one_line(tmp_path_factory, header, rows, raw):
    d = tmp_path_factory.mktemp('m')
    path = d / 'm.csv'
    lines = [','.join(header)] + [','.join(r) for r in rows]
    text = '\n'.join(lines) + '\n'
    path.write_bytes(text.encode('utf-8', 'surrogatepass') if raw else
                     text.encode('utf-8', 'replace'))
    try:
        entries = read_manifest(path)
    except InputFileError as exc:
        assert '\n' not in str(exc) and str(path) in str(exc)
        return
    assert entries
    for e in entries:
        assert TIME_RANGE[0] <= e.time < TIME_RANGE[1]
        assert '\x00' not in e.path and e.joint
        assert e.travel is None or 0 <= e.travel < float('inf')
    assert len({os.path.realpath(e.path) for e in entries}) == len(entries)


@settings(max_examples=400, deadline=None, derandomize=True, database=None)
@given(st.one_of(st.text(max_size=30),
                 st.builds(lambda s, h, p: f'{s}{h}:{p}',
                           st.sampled_from(['', 'tcp://', 'tls://', 'TCP://', 'ws://', '//']),
                           st.one_of(st.sampled_from(['127.0.0.1', '[::1]', 'host', '', '[::1',
                                                      'a..b', '-a', 'h_1', '1.2.3.4.5']),
                                     st.text(max_size=8)),
                           st.one_of(st.integers(-5, 70000).map(str), st.text(max_size=4)))))
def test_fuzz_scheduler_strings(address):
    try:
        out = check_scheduler(address)
    except ArgumentError as exc:
        assert '\n' not in str(exc) and str(exc).startswith('--scheduler')
        return
    assert out.startswith('tcp://') and out.isascii() and out.isprintable()
    port = int(out.rsplit(':', 1)[1])
    assert 1 <= port <= 65535 and ' ' not in out and '/' not in out[6:]
