# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""``friction_joint import`` against hostile logs: malformed NPZ, numbers, units, stamps."""
import io
import struct
import zipfile

from friction_joint.bag import read_recording
import numpy as np
import pytest
from test_import import _fails, _import

COLS = ['--time', 'time', '--position', 'pos', '--torque', 'tau']


def _csv(path, rows, header='time,pos,tau'):
    path.write_text(header + '\n' + ''.join(','.join(map(str, r)) + '\n' for r in rows))
    return path


def _rows(n=50, dt=0.01):
    return [(f'{i * dt:.6f}', f'{np.sin(i * dt):.6f}', '1.0') for i in range(n)]


# ------------------------------------------------------------------------------ NPZ ---

def _bomb(path, declared):
    """Write a small .npz whose zip directory declares a member of ``declared`` bytes."""
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {'descr': '<f8', 'fortran_order': False,
                                               'shape': ((declared - 128) // 8,)})
    with zipfile.ZipFile(path, 'w', compression=zipfile.ZIP_DEFLATED) as z:
        z.writestr('time.npy', buf.getvalue() + bytes(1 << 20))
    raw = bytearray(path.read_bytes())
    cd = raw.rindex(b'PK\x01\x02')                  # central directory entry
    raw[cd + 24:cd + 28] = struct.pack('<I', declared)
    lh = raw.index(b'PK\x03\x04')                   # local header too
    raw[lh + 22:lh + 26] = struct.pack('<I', declared)
    path.write_bytes(bytes(raw))


def test_npz_zip_bomb_refused_from_its_directory(tmp_path, capsys):
    """A member declaring 4 GiB is refused before anything is decompressed."""
    z = tmp_path / 'bomb.npz'
    _bomb(z, 0xF0000000)
    assert z.stat().st_size < 100_000
    _fails(capsys, tmp_path / 'rec', z, *COLS,
           expect=(str(z), 'declare 4026531840 bytes', 'memory budget'))


def test_npz_impostors_named_for_what_they_are(tmp_path, capsys):
    """A .npy renamed, a fake zip, a text file, strings, complex, objects: one line each."""
    t = np.arange(20) * 0.01
    npy = tmp_path / 'a.npy'
    np.save(npy, np.c_[t, t, t])
    renamed = tmp_path / 'renamed.npz'
    npy.rename(renamed)
    _fails(capsys, tmp_path / 'rec', renamed, *COLS, expect=(str(renamed), '.npy array'))
    fake = tmp_path / 'fake.npz'
    fake.write_bytes(b'PK\x03\x04' + bytes(200))
    _fails(capsys, tmp_path / 'rec', fake, *COLS, expect=(str(fake), 'not a valid zip'))
    text = tmp_path / 'text.npz'
    text.write_text('time,pos,tau\n0,0,0\n')
    line = _fails(capsys, tmp_path / 'rec', text, *COLS, expect=(str(text), 'a text file'))
    assert 'pickle' not in line
    strings = tmp_path / 'strings.npz'
    np.savez(strings, a=np.array([['1', '2', '3'], ['4', '5', '6']]))
    _fails(capsys, tmp_path / 'rec', strings, '--time', '0', '--position', '1', '--torque', '2',
           expect=(str(strings), "'a'", 'strings'))
    cplx = tmp_path / 'complex.npz'
    np.savez(cplx, time=t, pos=t + 1j, tau=t)
    _fails(capsys, tmp_path / 'rec', cplx, *COLS, expect=(str(cplx), "'pos'", 'complex'))
    obj = tmp_path / 'object.npz'
    np.savez(obj, time=t, pos=np.array([1.0, 'x'] * 10, dtype=object), tau=t)
    _fails(capsys, tmp_path / 'rec', obj, *COLS, expect=(str(obj), "'pos'", 'objects'))


def test_npz_datetime_and_timedelta_time_in_seconds(tmp_path, capsys):
    """datetime64[ms] and timedelta64[us] stamps become seconds, never read as numbers."""
    n = 200
    q = np.sin(np.arange(n) * 0.01)
    start = np.datetime64('2026-01-01T12:00:00.000', 'ms')
    cases = {'dt.npz': start + np.arange(n) * np.timedelta64(10, 'ms'),
             'td.npz': (np.arange(n) * 10_000).astype('timedelta64[us]')}
    for name, stamps in cases.items():
        z = tmp_path / name
        np.savez(z, time=stamps, pos=q, tau=np.ones(n))
        rec = tmp_path / f'{name}.rec'
        status, _, err = _import(capsys, z, '--out', rec, *COLS)
        assert status == 0, err
        js = read_recording(rec).joint_states
        np.testing.assert_allclose(js.t, np.arange(n) * 0.01, atol=1e-9)
        np.testing.assert_allclose(js.q, q)
    _fails(capsys, tmp_path / 'rec', tmp_path / 'dt.npz', '--time', 'time:ms', '--position',
           'pos', '--torque', 'tau', expect=('dt.npz', 'datetime64[ms]', 'without a unit'))
    _fails(capsys, tmp_path / 'rec', tmp_path / 'dt.npz', '--time', 'tau', '--position',
           'time', '--torque', 'tau', expect=('dt.npz', 'not a position'))
    nat = tmp_path / 'nat.npz'
    stamps = cases['dt.npz'].copy()
    stamps[7] = np.datetime64('NaT')
    np.savez(nat, time=stamps, pos=q, tau=np.ones(n))
    _fails(capsys, tmp_path / 'rec', nat, *COLS, expect=('nat.npz', 'row 8', 'NaT'))


# -------------------------------------------------------------------------- numbers ---

@pytest.mark.parametrize('value', ['1_000', '0x10', '\u0661\u0662', '1,5', '1.5.2', '--1'])
def test_numbers_are_plain_ascii_decimal(tmp_path, capsys, value):
    """Python's float() leniencies are refused naming the row and the value."""
    rows = _rows(20)
    rows[4] = (rows[4][0], value, '1.0')
    log = _csv(tmp_path / 'log.tsv', [('\t'.join(r),) for r in rows], header='time\tpos\ttau')
    _fails(capsys, tmp_path / 'rec', log, *COLS, expect=(str(log), 'row 6', repr(value)))


def test_infinity_and_nan_in_a_used_column(tmp_path, capsys):
    for value in ('infinity', 'nan', '-inf'):
        rows = _rows(20)
        rows[4] = (rows[4][0], value, '1.0')
        log = _csv(tmp_path / 'log.csv', rows)
        _fails(capsys, tmp_path / 'rec', log, *COLS, expect=(str(log), 'row 6', 'not finite'))
    rows = [r + ('nan',) for r in _rows(20)]          # an unused column may hold NaN
    log = _csv(tmp_path / 'unused.csv', rows, header='time,pos,tau,spare')
    assert _import(capsys, log, '--out', tmp_path / 'rec', *COLS, '--quiet')[0] == 0


# ---------------------------------------------------------------------------- units ---

def test_header_units_known_converted_unknown_refused(tmp_path, capsys):
    """min, degrees as °, kNm, °F converted; unknown brackets an error listing the units."""
    n = 40
    log = tmp_path / 'u.csv'
    rows = [(f'{i * 0.001:.4f}', f'{i * 0.5:.2f}', '0.002', '212') for i in range(n)]
    _csv(log, rows, header='Time [min],Angle [°],Torque [kNm],Temp [°F]')
    rec = tmp_path / 'rec'
    status, out, err = _import(capsys, log, '--out', rec, '--time', 'Time [min]', '--position',
                               'Angle [°]', '--torque', 'Torque [kNm]', '--temperature',
                               'Temp [°F]')
    assert status == 0, err
    r = read_recording(rec)
    np.testing.assert_allclose(r.joint_states.t, np.arange(n) * 0.06, atol=1e-9)
    np.testing.assert_allclose(r.joint_states.q, np.radians(np.arange(n) * 0.5), atol=1e-12)
    np.testing.assert_allclose(r.joint_states.effort, 2.0)
    np.testing.assert_allclose(r.temperature.xi, 100.0, atol=1e-9)
    for header, col, quantity, known in (('Temp [°R]', 'Temp [°R]', 'temperature', 'degF'),
                                         ('Torque [ft lbf]', 'Torque [ft lbf]', 'torque', 'kNm'),
                                         ('Sensor (left)', 'Sensor (left)', 'position', 'deg')):
        log = _csv(tmp_path / 'bad.csv', [(r[0], '1', '1') for r in rows],
                   header=f'time,{header},x')
        argv = {'temperature': ['--position', 'x', '--torque', 'x', '--temperature', col],
                'torque': ['--position', 'x', '--torque', col],
                'position': ['--position', col, '--torque', 'x']}[quantity]
        _fails(capsys, tmp_path / 'rec2', log, '--time', 'time', *argv,
               expect=(str(log), repr(col), quantity, known, 'override'))
    status, _, err = _import(capsys, log, '--out', tmp_path / 'rec3', '--time', 'time',
                             '--position', 'Sensor (left):deg', '--torque', 'x', '--quiet')
    assert status == 0, err                            # the unit given overrides the header


# ----------------------------------------------------------------- overflow, stamps ---

def test_conversion_overflow_and_radius(tmp_path, capsys):
    rows = _rows(20)
    rows[3] = (rows[3][0], '1e308', '1.0')
    log = _csv(tmp_path / 'big.csv', rows)
    _fails(capsys, tmp_path / 'rec', log, '--time', 'time', '--position', 'pos:rev',
           '--torque', 'tau', expect=(str(log), 'row 5', 'position', 'not finite', 'rev'))
    swing = _csv(tmp_path / 'swing.csv', [(f'{i}e-6', f'{(-1) ** i}e308', '1') for i in range(9)])
    _fails(capsys, tmp_path / 'rec', swing, *COLS, expect=(str(swing), 'qd', 'not finite'))
    ok = _csv(tmp_path / 'ok.csv', _rows(20))
    for radius in ('1e-320', '0', '-1', 'nan', 'inf', '1e300'):
        _fails(capsys, tmp_path / 'rec', ok, '--time', 'time', '--position', 'pos:mm',
               '--torque', 'tau', '--radius', radius, expect=('--radius',))
    mapping = tmp_path / 'map.yaml'
    mapping.write_text('radius: 1.0e-320\n')
    _fails(capsys, tmp_path / 'rec', ok, *COLS, '--mapping', mapping,
           expect=(str(mapping), 'radius'))


def test_stamps_below_1ns_or_beyond_int64_refused(tmp_path, capsys):
    """Sub-ns steps and 1e300 s would give a recording every reader refuses."""
    sub = _csv(tmp_path / 'sub.csv', [(f'{i * 1e-10:.3e}', '0.1', '1') for i in range(20)])
    _fails(capsys, tmp_path / 'rec', sub, *COLS, expect=(str(sub), 'row 3', '1 ns'))
    huge = _csv(tmp_path / 'huge.csv', [(f'{(1 + i) * 1e300:.3e}', '0.1', '1')
                                        for i in range(20)])
    _fails(capsys, tmp_path / 'rec', huge, *COLS, expect=(str(huge), 'row 2', 'int64'))
    span = _csv(tmp_path / 'span.csv', [(f'{i * 1e9:.3e}', '0.1', '1') for i in range(5)])
    _fails(capsys, tmp_path / 'rec', span, *COLS, expect=(str(span), 'spans'))
    fine = _csv(tmp_path / 'fine.csv', [(f'{i * 2e-9:.3e}', f'{i}e-9', '1') for i in range(50)])
    status, _, err = _import(capsys, fine, '--out', tmp_path / 'ns', *COLS, '--quiet')
    assert status == 0, err
    assert len(read_recording(tmp_path / 'ns').joint_states) == 50


def test_absurd_sample_and_below_absolute_zero_refused(tmp_path, capsys):
    """What the recording reader would refuse is refused at import, naming the file."""
    rows = [r + ('25',) for r in _rows(200)]
    rows[100] = (rows[100][0], rows[100][1], '1e12', '25')
    log = _csv(tmp_path / 'absurd.csv', rows, header='time,pos,tau,temp')
    _fails(capsys, tmp_path / 'rec', log, *COLS, expect=(str(log), 'implausible effort'))
    rows = [r + ('-300',) for r in _rows(20)]
    log = _csv(tmp_path / 'cold.csv', rows, header='time,pos,tau,temp')
    _fails(capsys, tmp_path / 'rec', log, *COLS, '--temperature', 'temp',
           expect=(str(log), 'row 2', 'absolute zero'))


# ------------------------------------------------------------------ joint, mapping ---

def test_empty_joint_name_refused(tmp_path, capsys):
    log = _csv(tmp_path / 'ok.csv', _rows(20))
    for name in ('', '   ', ' joint', 'a\nb'):
        _fails(capsys, tmp_path / 'rec', log, *COLS, '--joint', name, expect=('--joint',))


def test_deeply_nested_mapping_one_line(tmp_path, capsys):
    log = _csv(tmp_path / 'ok.csv', _rows(20))
    deep = tmp_path / 'deep.yaml'
    deep.write_text('[' * 100_000)
    _fails(capsys, tmp_path / 'rec', log, '--mapping', deep, expect=(str(deep), 'mapping'))
