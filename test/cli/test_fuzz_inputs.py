# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Fuzz ``friction_joint import`` with generated logs whose truth is known.

Every case writes a log of a known motion (time, position, velocity, drive
torque, temperature, load) in units drawn from a vocabulary that holds the
known units and others a user might write (``min``, ``grad``, ``rpm``,
``kNm``, ``°F``, ...), each with its true conversion to SI; the unit is put in
the header's brackets, in the mapping (``COL:unit``) or nowhere (then the
values are in SI).  A mutation is drawn on top: none, a number spelt in a way
Python's ``float`` reads but a log does not mean (``1_000``, ``0x10``,
``infinity``, Arabic-Indic digits), values that overflow once converted,
sub-nanosecond or absurd time stamps, a quoted, CRLF or BOM file, a ragged row,
an empty joint name, a binary NPZ with odd dtypes.  A case passes when the
command ends

* with exit 0 and a recording that every reader accepts and whose
  ``/joint_states``, ``/joint_temperature`` and ``/link_torque`` hold the truth in SI
  (no silent misread: a unit taken for another, a number read wrong), or
* with exit 2, one line ``friction_joint import: error: ...`` naming the log
  or the option, and nothing written;

within a time guard (a blocking read or a runaway allocation fails the case
instead of hanging the suite).  The cases are derandomized hypothesis draws.
"""
import math
import os
import signal

from friction_joint.bag import read_recording
from friction_joint.cli import main
from friction_joint.exceptions import RecordingError
from hypothesis import event, given, strategies as st
import numpy as np
import pytest

from test_fuzz import fuzz

#: generated import cases (with the other fuzz files: >= 500 new cases, issue 23)
IMPORT_CASES = 300
#: seconds one case may take before it counts as a hang
GUARD_S = 60


class Hang(Exception):
    """A case ran longer than :data:`GUARD_S`."""


def _alarm(signum, frame):
    raise Hang(f'no answer within {GUARD_S} s')


def guarded(argv):
    """Run ``friction_joint argv`` in-process under a time guard; return the exit status."""
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(GUARD_S)
    try:
        return main(argv)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


# ------------------------------------------------------------------- unit vocabulary ---

def _lin(k):
    return (lambda si: si / k), (lambda x: x * k)


#: quantity -> unit spelling -> (SI -> file value, file value -> SI)
UNITS = {
    'time': {'s': _lin(1.0), 'ms': _lin(1e-3), 'us': _lin(1e-6), 'sec': _lin(1.0),
             'min': _lin(60.0), 'h': _lin(3600.0), 'ns': _lin(1e-9)},
    'position': {'rad': _lin(1.0), 'deg': _lin(math.pi / 180), '°': _lin(math.pi / 180),
                 'rev': _lin(2 * math.pi), 'grad': _lin(math.pi / 200),
                 'mrad': _lin(1e-3), 'arcmin': _lin(math.pi / 10800)},
    'velocity': {'rad/s': _lin(1.0), 'deg/s': _lin(math.pi / 180), 'rev/s': _lin(2 * math.pi),
                 'rpm': _lin(2 * math.pi / 60), '°/s': _lin(math.pi / 180),
                 'rad/min': _lin(1 / 60)},
    'torque': {'Nm': _lin(1.0), 'Nmm': _lin(1e-3), 'N m': _lin(1.0), 'kNm': _lin(1e3),
               'mNm': _lin(1e-3), 'lbf ft': _lin(1.3558179483314004)},
    'temperature': {'degC': _lin(1.0), '°C': _lin(1.0), 'C': _lin(1.0),
                    'K': ((lambda c: c + 273.15), (lambda k: k - 273.15)),
                    '°F': ((lambda c: c * 9 / 5 + 32), (lambda f: (f - 32) * 5 / 9)),
                    'degF': ((lambda c: c * 9 / 5 + 32), (lambda f: (f - 32) * 5 / 9))},
}
UNITS['load'] = UNITS['torque']
_SI = {'time': 's', 'position': 'rad', 'velocity': 'rad/s', 'torque': 'Nm', 'load': 'Nm',
       'temperature': 'degC'}
MUTATIONS = ('none', 'none', 'none', 'underscore', 'hex', 'infinity', 'arabic', 'overflow',
             'subns', 'time_huge', 'quoted', 'crlf', 'bom', 'ragged', 'empty_joint',
             'negative_kelvin', 'blank_field', 'plus_sign', 'comma_decimal')


def _truth(draw):
    """Draw a known motion: dict quantity -> SI array (uniform time)."""
    n = draw(st.integers(20, 300))
    dt = draw(st.sampled_from([1e-3, 2e-3, 5e-3, 0.01, 0.1, 1.0]))
    t0 = draw(st.sampled_from([0.0, 0.5, 12.0, 3600.0]))
    k = np.arange(n)
    t = t0 + k * dt
    w = 2 * math.pi / (n * dt) * draw(st.integers(1, 4))
    amp = draw(st.sampled_from([0.01, 0.5, 3.0]))
    q = amp * np.sin(w * (t - t0))
    truth = {'time': t, 'position': q, 'velocity': amp * w * np.cos(w * (t - t0)),
             'torque': 2.0 * np.tanh(50 * amp * w * np.cos(w * (t - t0))) + 0.3 * q}
    if draw(st.booleans()):
        truth['temperature'] = 25.0 + 10.0 * k / n
    if draw(st.booleans()):
        truth['load'] = 5.0 * np.sin(0.5 * w * (t - t0))
    return truth


@st.composite
def import_cases(draw):
    """Draw (truth, columns spec, file spec, mutation, extra argv)."""
    truth = _truth(draw)
    cols = []
    for qty in truth:
        unit = draw(st.sampled_from(sorted(UNITS[qty])))
        where = draw(st.sampled_from(['header', 'mapping', 'none']))
        if where == 'none':
            unit = _SI[qty]
        cols.append((qty, unit, where))
    fmt = draw(st.sampled_from(['csv', 'tsv', 'semicolon', 'space', 'npz']))
    mutation = draw(st.sampled_from(MUTATIONS))
    row = draw(st.integers(0, len(truth['time']) - 1))
    col = draw(st.integers(0, len(cols) - 1))
    return truth, cols, fmt, mutation, row, col


_ARABIC = str.maketrans('0123456789', '٠١٢٣٤٥٦٧٨٩')


def _token(x):
    return repr(float(x))


def _mutated_token(mutation, x):
    """Return the text of a number after a token mutation, or None if the case is not one."""
    s = _token(x)
    return {'underscore': '1_000', 'hex': '0x10', 'infinity': 'infinity',
            'arabic': s.translate(_ARABIC), 'blank_field': '', 'plus_sign': '+' + s,
            'comma_decimal': s.replace('.', ',') if '.' in s else s + ',5'}.get(mutation)


def _write_log(path, truth, cols, fmt, mutation, row, col):
    """Write the log; return the file name and the command-line column options."""
    names, values, opts = [], [], []
    for qty, unit, where in cols:
        fwd, _ = UNITS[qty][unit]
        name = f'{qty.capitalize()} [{unit}]' if where == 'header' else qty.capitalize()
        names.append(name)
        values.append(fwd(truth[qty]))
        spec = f'{name}:{unit}' if where == 'mapping' else name
        opts += [f'--{qty}', spec]
    data = np.column_stack(values)
    t_idx = [c[0] for c in cols].index('time')
    if mutation == 'overflow':
        data[row, col] = 1e308
    elif mutation == 'subns':
        data[:, t_idx] = UNITS['time'][cols[t_idx][1]][0](np.arange(len(data)) * 1e-12)
    elif mutation == 'time_huge':
        data[row:, t_idx] += 1e300
    elif mutation == 'negative_kelvin' and 'temperature' in truth:
        qi = [c[0] for c in cols].index('temperature')
        fwd, _ = UNITS['temperature'][cols[qi][1]]
        data[row, qi] = fwd(-300.0)
    if fmt == 'npz':
        np.savez(path + '.npz', **{n: data[:, i] for i, n in enumerate(names)})
        return path + '.npz', opts
    delim = {'csv': ',', 'tsv': '\t', 'semicolon': ';', 'space': ' '}[fmt]
    if fmt == 'space':
        names = [n.replace(' ', '_') for n in names]
        opts = [o.replace(' ', '_') if not o.startswith('--') else o for o in opts]
    lines = [delim.join(f'"{n}"' if mutation == 'quoted' else n for n in names)]
    for i, r in enumerate(data):
        toks = [_token(x) for x in r]
        if i == row:
            alt = _mutated_token(mutation, r[col])
            if alt is not None:
                toks[col] = alt
            if mutation == 'ragged':
                toks.append('1.0')
        lines.append(delim.join(toks))
    text = ('\r\n' if mutation == 'crlf' else '\n').join(lines) + '\n'
    with open(path + '.csv', 'w', encoding='utf-8-sig' if mutation == 'bom' else 'utf-8') as fh:
        fh.write(text)
    return path + '.csv', opts


def _assert_truth(out, truth):
    """Assert the recording at ``out`` holds ``truth`` in SI (it must also be readable)."""
    try:
        rec = read_recording(out)
    except RecordingError as exc:
        pytest.fail(f'import wrote a recording the reader refuses: {exc}')
    js = rec.joint_states
    t = truth['time']
    assert len(js.t) == len(t), 'samples lost or invented'
    np.testing.assert_allclose(js.t - js.t[0], t - t[0], rtol=0, atol=2e-9 + 1e-12 * t[-1],
                               err_msg='time misread')
    for name, got in (('position', js.q), ('velocity', js.qd), ('torque', js.effort)):
        scale = np.max(np.abs(truth[name])) + 1e-300
        np.testing.assert_allclose(got, truth[name], rtol=1e-9, atol=1e-9 * scale,
                                   err_msg=f'{name} misread')
    if 'temperature' in truth:
        np.testing.assert_allclose(rec.temperature.xi, truth['temperature'], rtol=1e-9,
                                   atol=1e-9, err_msg='temperature misread')
    if 'load' in truth:
        np.testing.assert_allclose(rec.link_torque.tau, truth['load'], rtol=1e-9, atol=1e-9,
                                   err_msg='load misread')


@pytest.mark.slow
@fuzz(IMPORT_CASES)
@given(case=import_cases())
def test_fuzzed_imports(case, tmp_path_factory, capsys):
    truth, cols, fmt, mutation, row, col = case
    d = tmp_path_factory.mktemp('imp')
    log, opts = _write_log(str(d / 'log'), truth, cols, fmt, mutation, row, col)
    out = str(d / 'rec')
    joint = ['--joint', ' '] if mutation == 'empty_joint' else []
    rc = guarded(['import', log, '--out', out, '--quiet'] + opts + joint)
    err = capsys.readouterr().err
    event(f'{mutation}: exit {rc}')
    if rc == 0:
        _assert_truth(out, truth)
    else:
        assert rc == 2, f'exit {rc}: {err}'
        lines = [ln for ln in err.strip().splitlines()
                 if not ln.startswith('friction_joint import: warning: ')]
        assert len(lines) == 1 and lines[0].startswith('friction_joint import: error: '), err
        assert not os.path.lexists(out), 'partial output'
        assert not [p for p in os.listdir(d) if p.endswith('.tmp')], 'temporary left'
