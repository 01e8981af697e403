# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
``friction_joint fleet`` on a simulated fleet, on a LocalCluster with 2 worker processes.

One module-scoped fleet (8 joints x 10 days, wear drawn at random: which
joints, onset, rate; ambient, duty and payload drawn every day) is simulated
once (on a LocalCluster with 2 worker processes) and monitored twice through
the command line: first its first 9 days plus a corrupt recording on that
cluster (``--scheduler``), then all 10 days with ``--force`` into the same DIR
on an embedded LocalCluster (``--workers 2``; the cache: only the 8 new
recordings are analysed).  The monitor gets the
manifest and the model gear file only; the truth file is read by the test.
"""
import csv
import datetime
import json
import os
import shutil

from friction_joint.cli import main
from friction_joint.exceptions import InputFileError
from friction_joint.fleet import local_cluster, read_manifest
from friction_joint.jobs import run_fleet
from friction_joint.jobs.fleet_simulation import run_fleet_simulation
import pytest

MODEL = 'config/csd25.yaml'
JOINTS, DAYS, SEED = 8, 10, 11
#: a shorter daily test motion than the default (three speeds): the fleet simulates faster
SHORT = {'speeds': (0.3, 0.8, 2.0)}


def _rows(path):
    with open(path, encoding='utf-8') as fh:
        return list(csv.DictReader(fh))


def _write_manifest(path, rows):
    with open(path, 'w', encoding='utf-8') as fh:
        w = csv.DictWriter(fh, ['recording', 'joint', 'time', 'travel'], lineterminator='\n')
        w.writeheader()
        w.writerows(rows)


@pytest.fixture(scope='module')
def fleet(tmp_path_factory):
    root = tmp_path_factory.mktemp('fleet')
    sim = root / 'sim'
    with local_cluster(workers=2) as (address, executor):
        truth = run_fleet_simulation(sim, joints=JOINTS, days=DAYS, seed=SEED,
                                     executor=executor, cfg=SHORT).truth
        rows, first = _manifests(sim)
        rc1 = main(['fleet', '--manifest', str(sim / 'first.csv'), '--model', MODEL, '--out',
                    str(root / 'out'), '--scheduler', address, '--quiet'])
    out = root / 'out'
    with open(out / 'fleet.json', encoding='utf-8') as fh:
        first_doc = json.load(fh)
    rc2 = main(['fleet', '--manifest', str(sim / 'full.csv'), '--model', MODEL, '--out',
                str(out), '--workers', '2', '--quiet', '--force'])
    with open(out / 'fleet.json', encoding='utf-8') as fh:
        doc = json.load(fh)
    return {'root': root, 'sim': sim, 'truth': truth, 'out': out, 'rc': (rc1, rc2),
            'first': first_doc, 'doc': doc, 'n_first': len(first), 'n_full': len(rows) + 1}


def _manifests(sim):
    """Write first.csv (all days but the last, a corrupt recording) and full.csv."""
    rows = _rows(sim / 'manifest.csv')
    # a corrupt recording of j01 between its days 3 and 4: the first 4 kB of a real one
    j01 = [r for r in rows if r['joint'] == 'j01']
    with open(sim / j01[3]['recording'], 'rb') as fh:
        head = fh.read(4096)
    (sim / 'recordings' / 'j01_corrupt.mcap').write_bytes(head)
    t3 = datetime.datetime.fromisoformat(j01[3]['time'])
    corrupt = {'recording': 'recordings/j01_corrupt.mcap', 'joint': 'j01',
               'time': (t3 + datetime.timedelta(hours=1)).isoformat(), 'travel': j01[3]['travel']}
    last_day = sorted({r['time'][:10] for r in rows})[-1]
    first = [r for r in rows if r['time'][:10] != last_day] + [corrupt]
    _write_manifest(sim / 'first.csv', first)
    _write_manifest(sim / 'full.csv', rows + [corrupt])
    return rows, first


def test_wearing_joints_flagged_exactly_with_their_onset(fleet):
    assert fleet['rc'] == (0, 0)
    truth, joints = fleet['truth']['joints'], fleet['doc']['joints']
    assert set(joints) == set(truth)
    assert any(t['wear'] for t in truth.values()) and not all(t['wear'] for t in truth.values())
    for jid, t in truth.items():
        got = joints[jid]
        assert got['wear'] == t['wear'], (jid, got['evidence'])
        if t['wear']:
            onset = datetime.datetime.fromisoformat(got['onset'])
            true = datetime.datetime.fromisoformat(t['onset'])
            assert abs((onset - true).total_seconds()) <= 2 * 86400, (jid, got['onset'], t)
            assert got['rate']['per_day'] > 2 * got['rate']['per_day_se'] > 0
            assert got['rate']['per_travel'] > 0
        else:
            assert got['onset'] is None
            assert got['evidence']['p_value'] >= got['evidence']['alpha']


def test_corrupt_recording_reported_and_the_run_completes(fleet):
    rows = _rows(fleet['out'] / 'recordings.csv')
    assert len(rows) == fleet['n_full']
    bad = [r for r in rows if r['recording'] == 'recordings/j01_corrupt.mcap']
    assert len(bad) == 1 and bad[0]['status'] == 'failed'
    assert bad[0]['reason'] and '\n' not in bad[0]['reason']
    assert all(r['status'] == 'ok' for r in rows if r is not bad[0])
    assert all(float(r['reference_friction_se']) > 0 for r in rows if r['status'] == 'ok')
    assert fleet['doc']['joints']['j01']['failed'] == 1
    html = (fleet['out'] / 'report.html').read_text(encoding='utf-8')
    assert html.count('data:image/png;base64,') == JOINTS
    assert 'j01_corrupt.mcap' in html and 'Failed recordings' in html


def test_rerun_with_force_computes_only_the_new_recordings(fleet):
    first, second = fleet['first']['run'], fleet['doc']['run']
    assert first['computed'] == fleet['n_first'] and first['cached'] == 0
    assert first['workers'] == 2 and second['workers'] == 2
    assert second['computed'] == JOINTS                       # the last day's recordings
    assert second['cached'] == fleet['n_first']
    rows = _rows(fleet['out'] / 'recordings.csv')
    assert sum(r['cached'] == 'True' for r in rows) == fleet['n_first']
    assert sorted(os.listdir(fleet['out'])) == ['cache.json', 'fleet.json', 'recordings.csv',
                                                'report.html']


def test_run_from_the_cache_returns_the_same_verdict_and_plots_every_joint(fleet, tmp_path):
    """The job's API on a copy of DIR: everything cached, no task; FleetRun.plot draws."""
    out = tmp_path / 'again'
    shutil.copytree(fleet['out'], out)
    res = run_fleet(fleet['sim'] / 'full.csv', MODEL, out, force=True)
    assert (res.computed, res.cached, res.workers) == (0, fleet['n_full'], 0)
    doc = res.to_dict()['fleet']
    assert doc['joints'] == fleet['doc']['joints']
    figs = res.plot()
    assert list(figs) == list(res.assessment.joints) and len(figs) == JOINTS
    for joint, fig in figs.items():
        ax = fig.axes[0]
        points = res.assessment.joints[joint]['series']['points']
        assert ax.get_title().startswith(joint) and ax.has_data()
        assert len(ax.lines[0].get_xdata()) == len(points) > 0


@pytest.mark.parametrize('text, words', [
    ('recording,joint\nrecordings/a.mcap,j1\n', ('row 1', 'no column time')),
    ('recording,joint,time\nrecordings/a.mcap,j1,yesterday\n', ('row 2', 'ISO 8601')),
    ('recording,joint,time\nrecordings/a.mcap,,2026-03-02T10:00:00\n', ('row 2', 'empty joint')),
])
def test_bad_manifest_exit_2_one_line_nothing_written(tmp_path, capsys, text, words):
    manifest = tmp_path / 'bad.csv'
    manifest.write_text(text, encoding='utf-8')
    out = tmp_path / 'out'
    assert main(['fleet', '--manifest', str(manifest), '--model', MODEL, '--out',
                 str(out), '--quiet']) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(manifest) in err
    assert all(w in err for w in words), err
    assert not out.exists() and sorted(os.listdir(tmp_path)) == ['bad.csv']


def test_manifest_keeps_extra_columns_and_rejects_a_decreasing_odometer(tmp_path):
    m = tmp_path / 'm.csv'
    m.write_text('recording,joint,time,travel,robot\na.mcap,j1,2026-03-02T10:00:00,5,r7\n'
                 'b.mcap,j1,2026-03-03T10:00:00Z,7,r7\n', encoding='utf-8')
    entries = read_manifest(m)
    assert [e.metadata for e in entries] == [{'robot': 'r7'}] * 2
    assert entries[0].path == str(tmp_path / 'a.mcap') and entries[1].travel == 7.0
    assert entries[0].time.tzinfo is not None
    m.write_text('recording,joint,time,travel\na.mcap,j1,2026-03-02T10:00:00,5\n'
                 'b.mcap,j1,2026-03-03T10:00:00,4\n', encoding='utf-8')
    with pytest.raises(InputFileError, match='row 3.*never decreases'):
        read_manifest(m)
