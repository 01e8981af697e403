# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""``friction_joint import``: foreign logs (CSV/TSV/NPZ) into recordings, real data included."""
import json
import math
import os
from pathlib import Path
import shutil

from friction_joint.bag import read_recording, recording_topics
from friction_joint.bag.importer import FILE_GAP
from friction_joint.cli import main
import numpy as np
import pytest
import yaml

TRIBOMETER = Path(__file__).resolve().parents[1] / 'data' / 'tribometer' / \
    'test_data_2_every6.tsv'
TRIBO_COLUMNS = ['--time', 'Time [s]', '--position', 'Position [mm]',
                 '--friction', 'Friction [uN]']


def _import(capsys, *argv):
    """Run ``friction_joint import`` in-process; return (status, stdout, stderr)."""
    status = main(['import', *map(str, argv)])
    out, err = capsys.readouterr()
    return status, out, err


def _fails(capsys, out, *argv, expect=()):
    """Exit 2 with one line naming what is expected, nothing written at ``out``."""
    status, _, err = _import(capsys, *argv, '--out', out)
    assert status == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith('friction_joint import: error: '), err
    for word in expect:
        assert word in lines[0], lines[0]
    assert not os.path.lexists(out)
    assert not [p for p in os.listdir(os.path.dirname(out)) if p.endswith('.tmp')]
    return lines[0]


def _custom(rec):
    meta = yaml.safe_load(Path(rec, 'metadata.yaml').read_text())
    return json.loads(meta['rosbag2_bagfile_information']['custom_data']['friction_joint.import'])


# --------------------------------------------------------------------- real tribometer ---

def test_tribometer_import(tmp_path, capsys):
    """The shipped tribometer log (TSV, mm, uN) imported in friction mode and read back."""
    src = np.loadtxt(TRIBOMETER, skiprows=1)
    t, x, force = src[:, 0], src[:, 2], src[:, 3]
    rec = tmp_path / 'tribo'
    status, out, err = _import(capsys, TRIBOMETER, '--out', rec, *TRIBO_COLUMNS,
                               '--flip-friction')
    assert status == 0, err
    assert err == ''                                   # flipped: no sign warning
    assert 'inertia negligible' in out and 'radius 1 m' in out
    r = read_recording(rec)
    js = r.joint_states
    dt = float(np.median(np.diff(t)))
    assert dt == pytest.approx(0.03)
    n = int(math.floor((t[-1] - t[0]) / dt + 1e-9)) + 1    # the uniform grid of the median step
    assert len(js) == n == 7126
    np.testing.assert_allclose(np.diff(js.t), dt, atol=1e-8)
    assert js.t[0] == 0.0 and r.duration == pytest.approx((n - 1) * dt)
    assert r.duration == pytest.approx(213.75)
    # position: mm -> m -> rad (radius 1 m); the stroke is 0.24 mm
    assert js.q.min() == pytest.approx(x.min() * 1e-3, abs=2e-7)   # interpolated: 0.2 um
    assert js.q.max() == pytest.approx(x.max() * 1e-3, abs=2e-7)
    assert np.ptp(js.q) == pytest.approx(np.ptp(x) * 1e-3, rel=2e-3)
    assert np.ptp(js.q) == pytest.approx(0.24e-3, rel=0.01)
    # effort: -friction in N (uN -> N), the sign of the velocity while sliding
    np.testing.assert_allclose(js.effort, -np.interp(js.t, t - t[0], force) * 1e-6, atol=1e-9)
    sliding = np.abs(js.qd) > 0.5 * np.percentile(np.abs(js.qd), 99)
    assert np.mean(np.sign(js.effort[sliding]) == np.sign(js.qd[sliding])) > 0.6
    assert 2.0 < np.median(np.abs(js.effort[sliding])) < 2.6      # about 2.3 N (mu 0.46 at 5 N)
    # no temperature; a zero external torque (friction mode)
    topics = recording_topics(rec)
    assert '/joint_temperature' not in topics and r.temperature is None
    assert set(topics) == {'/joint_states', '/link_torque'}
    assert not np.any(r.link_torque.tau)
    info = _custom(rec)
    assert info['mode'] == 'friction' and info['friction_sign'] == 'flipped'
    assert info['radius_m'] == 1.0 and info['inertia'] == 'negligible'
    assert info['columns']['position']['unit'] == 'mm'
    assert info['columns']['friction']['unit'] == 'uN'


def test_tribometer_sign_warning_and_identify_needs_temperature(tmp_path, capsys):
    """As logged the friction opposes motion: a one-line warning naming --flip-friction."""
    rec = tmp_path / 'tribo'
    status, _, err = _import(capsys, TRIBOMETER, '--out', rec, *TRIBO_COLUMNS, '--quiet')
    assert status == 0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and 'warning' in lines[0] and '--flip-friction' in lines[0], err
    assert _custom(rec)['friction_sign'] == 'as logged'
    # identify needs the temperature: a one-line error naming the topic, nothing written
    gear = Path(__file__).resolve().parents[2] / 'config' / 'csd25_base.yaml'
    status = main(['identify', str(rec), '--model', str(gear), '--out',
                   str(tmp_path / 'gear.yaml'), '--quiet'])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and '/joint_temperature' in err[0], err
    assert not (tmp_path / 'gear.yaml').exists()


def test_two_files_are_separate_pieces(tmp_path, capsys):
    """Every file is a run of its own: a gap of >= 10 s, no derivative across it."""
    second = tmp_path / 'second.tsv'
    shutil.copy(TRIBOMETER, second)
    rec = tmp_path / 'two'
    status, _, err = _import(capsys, TRIBOMETER, second, '--out', rec, *TRIBO_COLUMNS,
                             '--flip-friction')
    assert status == 0, err
    js = read_recording(rec).joint_states
    d = np.diff(js.t)
    gaps = np.flatnonzero(d > 5 * np.median(d))
    assert len(gaps) == 1 and d[gaps[0]] >= FILE_GAP
    k = gaps[0]
    assert len(js) == 2 * 7126 and k == 7125
    dt = js.t[k] - js.t[k - 1]
    # velocity at either side of the gap: one-sided within its own piece
    assert js.qd[k] == pytest.approx((js.q[k] - js.q[k - 1]) / dt, rel=1e-9)
    assert js.qd[k + 1] == pytest.approx((js.q[k + 2] - js.q[k + 1]) / dt, rel=1e-9)
    pieces = _custom(rec)['files']
    assert [len(f['pieces']) for f in pieces] == [1, 1]
    assert pieces[1]['pieces'][0][0] - pieces[0]['pieces'][0][1] >= FILE_GAP


# ------------------------------------------------------------------- synthetic round trips ---

def test_csv_irregular_stamps_resampled_and_split_at_gaps(tmp_path, capsys):
    """Jittered stamps go onto a uniform grid; a gap splits the run, nothing crosses it."""
    rng = np.random.default_rng(1)
    dt = 0.002
    t = np.arange(3000) * dt + rng.uniform(-0.3, 0.3, 3000) * dt
    t[1500:] += 0.5                                    # a pause of 0.5 s: two pieces
    q = np.sin(2 * np.pi * 0.5 * t)
    tau = 0.3 * np.cos(2 * np.pi * 0.5 * t)
    log = tmp_path / 'log.csv'
    with open(log, 'w') as fh:
        fh.write('t_ms,angle,drive\n')
        for row in zip(t * 1e3, np.degrees(q), tau * 1e3, strict=True):
            fh.write(','.join(f'{v:.9g}' for v in row) + '\n')
    rec = tmp_path / 'rec'
    status, out, err = _import(capsys, log, '--out', rec, '--time', 't_ms:ms',
                               '--position', 'angle:deg', '--torque', '2:Nmm')
    assert status == 0, err
    js = read_recording(rec).joint_states
    d = np.diff(js.t)
    med = float(np.median(d))
    assert med == pytest.approx(dt, rel=0.01)
    big = np.flatnonzero(d > 5 * med)
    assert len(big) == 1                               # the pause, not bridged
    np.testing.assert_allclose(np.delete(d, big), med, rtol=1e-6)
    assert js.t[big[0]] <= t[1499] - t[0] + 1e-9 and js.t[big[0] + 1] >= t[1500] - t[0] - 1e-9
    q_true = np.sin(2 * np.pi * 0.5 * (js.t + t[0]))
    np.testing.assert_allclose(js.q, q_true, atol=2e-4)
    np.testing.assert_allclose(js.effort, 0.3 * np.cos(2 * np.pi * 0.5 * (js.t + t[0])),
                               atol=1e-4)
    qd_true = np.pi * np.cos(2 * np.pi * 0.5 * (js.t + t[0]))
    inner = np.ones(len(js.t), dtype=bool)
    inner[[0, big[0], big[0] + 1, -1]] = False        # one-sided at the ends of a piece
    np.testing.assert_allclose(js.qd[inner], qd_true[inner], atol=5e-3)
    np.testing.assert_allclose(js.qd[~inner], qd_true[~inner], atol=0.02)
    assert 'centred difference' in out and 'resampled' in out


def test_non_increasing_stamps_name_file_and_row(tmp_path, capsys):
    log = tmp_path / 'log.tsv'
    log.write_text('time\tpos\ttorque\n0.0\t0\t0\n0.1\t0\t0\n0.1\t0\t0\n0.3\t0\t0\n')
    line = _fails(capsys, tmp_path / 'rec', log, '--time', 'time', '--position', 'pos',
                  '--torque', 'torque', expect=(str(log), 'row 4', 'does not increase'))
    assert 'Traceback' not in line


def test_unwrap_wrapped_encoder(tmp_path, capsys):
    """An angle logged modulo 2 pi: --unwrap gives the continuous position."""
    t = np.arange(2000) * 1e-3
    q = 3.0 * t * 2 * np.pi                            # 6 turns
    log = tmp_path / 'enc.txt'
    np.savetxt(log, np.c_[t, np.mod(q, 2 * np.pi), np.ones_like(t)], header='t q tau',
               comments='')
    status, _, err = _import(capsys, log, '--out', tmp_path / 'rec', '--time', '0',
                             '--position', '1:rad', '--torque', '2', '--unwrap')
    assert status == 0, err
    js = read_recording(tmp_path / 'rec').joint_states
    np.testing.assert_allclose(js.q, q, atol=1e-9)
    np.testing.assert_allclose(js.qd, 6 * np.pi, rtol=1e-6)
    status, _, _ = _import(capsys, log, '--out', tmp_path / 'wrapped', '--time', '0',
                           '--position', '1:rad', '--torque', '2')
    assert status == 0
    assert np.ptp(read_recording(tmp_path / 'wrapped').joint_states.q) < 2 * np.pi
    _fails(capsys, tmp_path / 'lin', log, '--time', '0', '--position', '1:mm', '--torque', '2',
           '--unwrap', expect=('--unwrap', 'mm'))


def test_npz_input_with_units_and_temperature(tmp_path, capsys):
    """NPZ columns by key; us, rev, rev/s, mN with a radius, K; temperature and load topics."""
    n = 500
    t = np.arange(n) * 1e-3
    z = tmp_path / 'run.npz'
    np.savez(z, stamp=(t + 7.0) * 1e6, turns=0.01 * np.sin(t), speed=0.01 * np.cos(t),
             force=np.full(n, 250.0), kelvin=np.full(n, 303.15), ext=np.full(n, 20.0))
    rec = tmp_path / 'rec.mcap'
    status, out, err = _import(capsys, z, '--out', rec, '--time', 'stamp:us', '--position',
                               'turns:rev', '--velocity', 'speed:rev/s', '--torque', 'force:mN',
                               '--load', 'ext:mN', '--temperature', 'kelvin:K', '--radius', '0.1')
    assert status == 0, err
    r = read_recording(rec)
    np.testing.assert_allclose(r.joint_states.t, t, atol=1e-9)
    np.testing.assert_allclose(r.joint_states.q, 2 * np.pi * 0.01 * np.sin(t), atol=1e-12)
    np.testing.assert_allclose(r.joint_states.qd, 2 * np.pi * 0.01 * np.cos(t), atol=1e-12)
    np.testing.assert_allclose(r.joint_states.effort, 0.25 * 0.1)
    np.testing.assert_allclose(r.link_torque.tau, 0.02 * 0.1)
    np.testing.assert_allclose(r.temperature.xi, 30.0, atol=1e-9)
    assert 'logged' not in out or 'centred' not in out


def test_yaml_mapping_semicolons_and_skip_rows(tmp_path, capsys):
    """A mapping file with the option keys; a command-line column overrides it."""
    t = np.arange(400) * 0.01
    log = tmp_path / 'log.csv'
    with open(log, 'w') as fh:
        fh.write('exported by some tool\nsecond preamble line\n')
        fh.write('Zeit [s];Weg [mm];Reibung [N];Other\n')
        for a, b, c in zip(t, np.sin(t), np.sign(np.cos(t)), strict=True):
            fh.write(f'{a:.4f};{b:.6f};{-c:.3f};0\n')
    mapping = tmp_path / 'map.yaml'
    mapping.write_text('time: Zeit [s]\nposition: Weg [mm]\nfriction: Reibung [N]:N\n'
                       'skip_rows: 2\nflip_friction: true\nradius: 0.5\n')
    status, out, err = _import(capsys, log, '--out', tmp_path / 'rec', '--mapping', mapping)
    assert status == 0, err
    js = read_recording(tmp_path / 'rec').joint_states
    np.testing.assert_allclose(js.q, np.sin(t) * 1e-3 / 0.5, atol=2e-9)
    np.testing.assert_allclose(js.effort, np.round(np.sign(np.cos(t)), 3) * 0.5)
    assert _custom(tmp_path / 'rec')['columns']['position']['unit'] == 'mm'   # from the header
    status, _, err = _import(capsys, log, '--out', tmp_path / 'rec2', '--mapping', mapping,
                             '--position', 'Weg [mm]:um')
    assert status == 0, err
    js = read_recording(tmp_path / 'rec2').joint_states
    np.testing.assert_allclose(js.q, np.sin(t) * 1e-6 / 0.5, atol=2e-12)
    bad = tmp_path / 'bad.yaml'
    bad.write_text('time: 0\nspeed: 1\n')
    _fails(capsys, tmp_path / 'rec3', log, '--mapping', bad, expect=(str(bad), 'speed'))


def test_bad_column_and_unit_and_existing_output(tmp_path, capsys):
    """One-line errors naming the file; nothing written; an existing REC needs --force."""
    log = tmp_path / 'log.tsv'
    t = np.arange(100) * 0.01
    np.savetxt(log, np.c_[t, t, t], delimiter='\t', header='time\tpos\ttorque', comments='')
    common = ['--time', 'time', '--position', 'pos']
    _fails(capsys, tmp_path / 'rec', log, *common, '--torque', 'Torque',
           expect=(str(log), "'Torque'", 'torque', "'time'"))
    _fails(capsys, tmp_path / 'rec', log, *common, '--torque', '7',
           expect=(str(log), 'no column 7'))
    _fails(capsys, tmp_path / 'rec', log, *common, '--torque', 'torque:furlong',
           expect=('unknown torque unit',))
    _fails(capsys, tmp_path / 'rec', log, *common, expect=('--torque', '--friction'))
    _fails(capsys, tmp_path / 'rec', tmp_path / 'missing.csv', *common, '--torque', 'torque',
           expect=('missing.csv',))
    lines = log.read_text().splitlines()
    lines[5] = 'abc' + lines[5][lines[5].index('\t'):]
    log.write_text('\n'.join(lines) + '\n')
    _fails(capsys, tmp_path / 'rec', log, *common, '--torque', 'torque',
           expect=(str(log), 'row 6', "'abc'"))
    good = tmp_path / 'good.tsv'
    np.savetxt(good, np.c_[t, t, t], delimiter='\t', header='time\tpos\ttorque', comments='')
    rec = tmp_path / 'rec'
    assert _import(capsys, good, '--out', rec, *common, '--torque', 'torque')[0] == 0
    before = sorted(os.listdir(rec))
    status, _, err = _import(capsys, good, '--out', rec, *common, '--torque', 'torque')
    assert status == 2 and 'exists already' in err and '--force' in err
    assert sorted(os.listdir(rec)) == before
    assert _import(capsys, good, '--out', rec, *common, '--torque', 'torque', '--force')[0] == 0


@pytest.mark.parametrize('seed', [1, 2, 3])
def test_results_quoted_back_in_the_logged_units(tmp_path, capsys, seed):
    """SI numbers of an imported recording are quoted in the units the columns were logged in."""
    from friction_joint.bag.provenance import import_mapping, ImportedUnits
    from friction_joint.bag.units import UNITS
    rng = np.random.default_rng([seed, 404])
    linear = bool(rng.integers(2))
    radius = float(rng.uniform(0.01, 2.0)) if linear else None
    kinds = {q: [u for u, (_, lin) in UNITS[q].items() if lin == linear or q == 'time']
             for q in ('time', 'position', 'velocity', 'torque')}
    units = {q: str(rng.choice(kinds[q])) for q in kinds}
    units['temperature'] = str(rng.choice(list(UNITS['temperature'])))
    n = 400
    t = np.arange(n) * 1e-3

    def to_logged(quantity, si):
        factor, lin = UNITS[quantity][units[quantity]]
        if lin:
            factor = factor / radius if quantity in ('position', 'velocity') else factor * radius
        return si / factor

    w = float(rng.uniform(0.5, 3.0))
    logged = {'time': to_logged('time', t), 'position': to_logged('position', 0.3 * np.sin(w * t)),
              'velocity': to_logged('velocity', 0.3 * w * np.cos(w * t)),
              'torque': to_logged('torque', np.full(n, float(rng.uniform(0.5, 5.0)))),
              'temperature': np.full(n, {'degC': 31.0, 'K': 304.15, 'degF': 87.8}[
                  units['temperature']])}
    z = tmp_path / 'log.npz'
    np.savez(z, **logged)
    rec = tmp_path / ('rec.mcap' if seed % 2 else 'rec')
    argv = [z, '--out', rec] + [a for q in logged for a in (f'--{q}', f'{q}:{units[q]}')]
    status, out, err = _import(capsys, *argv, *(['--radius', radius] if linear else []))
    assert status == 0, err
    quoted = ImportedUnits(import_mapping(rec))
    r = read_recording(rec)
    for quantity, si in (('position', r.joint_states.q[7]), ('velocity', r.joint_states.qd[7]),
                         ('torque', r.joint_states.effort[7]),
                         ('temperature', r.temperature.xi[0])):
        text = quoted.quote(quantity, float(si))
        if text is None:            # logged in SI: nothing to add
            assert units[quantity] in ('rad', 'rad/s', 'Nm', 'degC'), (quantity, units)
            continue
        value, unit = text.split(' ', 1)
        assert unit == units[quantity], (quantity, text)
        want = logged[quantity][7] if quantity != 'temperature' else logged[quantity][0]
        assert float(value) == pytest.approx(want, rel=1e-3), (quantity, text, want)
