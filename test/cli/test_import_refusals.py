# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
What the reader refuses, ``import`` refuses, saying how to go on (issues 31, 33, 34).

``import`` ran the absurd-sample check only and wrote recordings that every reader then
refused (a temperature of 1e300 or 2000 degC, a velocity 2 or 1000 times its position's
derivative); it now runs the reader's own check on each file and on the whole.  A
velocity that disagrees with its position is refused with the fitted ratio, what it means
and the option that goes on with the position's derivative (``--velocity-from-position``,
for ``import``, ``diagnose`` and ``identify``, echoed and recorded).  Ambiguous inputs are
one line too: a header naming two columns alike, a polynomial given twice to
``--orders``, a ``.mcap`` output with a trailing separator.
"""
import os

from friction_joint.cli import main
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RECORDING = os.path.join(ROOT, 'bags', 'csd25_sample')
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')


def one_line(capsys, rc, *words):
    """Assert exit 2 and one stderr line holding ``words``; return the line."""
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and ': error: ' in lines[0], err
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


def motion(n=4000, dt=1e-3, seed=0):
    """Return the time, a moving position, its velocity and a torque (SI)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * dt
    q = 0.8 * np.sin(2 * np.pi * 0.5 * t) + 0.3 * np.sin(2 * np.pi * 1.3 * t)
    qd = (0.8 * np.pi * np.cos(2 * np.pi * 0.5 * t)
          + 0.3 * 2.6 * np.pi * np.cos(2 * np.pi * 1.3 * t))
    tau = 0.5 * np.tanh(qd / 0.01) + 0.2 * qd + 0.01 * rng.standard_normal(n)
    return t, q, qd, tau


def write_csv(path, header, *cols):
    """Write a comma-separated log with one header line; return its path as str."""
    np.savetxt(path, np.column_stack(cols), delimiter=',', header=header, comments='',
               fmt='%.12g')
    return str(path)


IMPORT = ['--time', 't', '--position', 'q', '--torque', 'tau']


def test_duplicate_header_name_is_refused_naming_it_and_the_file(tmp_path, capsys):
    """``t,q,q,tau``: ``--position q`` silently took the first ``q``."""
    t, q, qd, tau = motion()
    log = write_csv(tmp_path / 'dup.csv', 't,q,q,tau', t, q, 2 * q, tau)
    out = tmp_path / 'rec'
    rc = main(['import', log, '--out', str(out), *IMPORT, '--quiet'])
    one_line(capsys, rc, 'dup.csv', "'q'", 'columns 1, 2')
    assert not out.exists()
    # by index it is not ambiguous
    rc = main(['import', log, '--out', str(out), '--time', 't', '--position', '2', '--torque',
               'tau', '--quiet'])
    assert rc == 0 and out.exists()


def test_orders_with_a_polynomial_twice_is_one_line(tmp_path, capsys):
    """``--orders fc=1,fc=2`` silently took one of them."""
    out = tmp_path / 'g.yaml'
    rc = main(['identify', RECORDING, '--model', BASE, '--out', str(out), '--orders',
               'fc=1,fc=2', '--quiet'])
    one_line(capsys, rc, '--orders', 'fc', 'twice')
    assert not out.exists()


@pytest.mark.parametrize('orders', ['fc=\u0661', 'fc=\uff12', 'fv=\u0968,fc=1', 'fc=1_0'])
def test_orders_in_other_digits_are_one_line(tmp_path, capsys, orders):
    """``--orders fc=\u0661`` (an Arabic-Indic one) was read as fc=1: ASCII digits only."""
    out = tmp_path / 'g.yaml'
    rc = main(['identify', RECORDING, '--model', BASE, '--out', str(out), '--orders', orders,
               '--quiet'])
    one_line(capsys, rc, '--orders', 'expected')
    assert not out.exists()


def test_mcap_output_with_a_trailing_separator_is_one_line(tmp_path, capsys):
    """``--out DIR/x.mcap/`` wrote the file x.mcap as if the separator were not there."""
    t, q, qd, tau = motion()
    log = write_csv(tmp_path / 'log.csv', 't,q,tau', t, q, tau)
    out = str(tmp_path / 'x.mcap') + os.sep
    rc = main(['import', log, '--out', out, *IMPORT, '--quiet'])
    one_line(capsys, rc, 'x.mcap', 'directory separator')
    assert os.listdir(tmp_path) == ['log.csv']


# --------------------------------------------------- import refuses what the reader does ---

def _bad_log(tmp_path, case):
    """Return a log (t, q, qd, tau, xi) with one fault the reader refuses, and its words."""
    t, q, qd, tau = motion()
    xi = np.full(len(t), 30.0)
    words = []
    if case == 'temperature 1e300':
        xi[:] = 1e300
        words = ['/joint_temperature', '1e+300', 'degF']
    elif case == 'temperature 900':
        xi[:] = 900.0
        words = ['/joint_temperature', '900', '500']
    else:
        factor = {'velocity x2': 2.0, 'velocity x1000': 1000.0, 'velocity sign': -1.0}[case]
        qd = factor * qd
        words = ['--velocity-from-position', f'{factor:g} times', 'COL:UNIT']
    log = write_csv(tmp_path / 'bad.csv', 't,q,qd,tau,xi', t, q, qd, tau, xi)
    return log, words


@pytest.mark.parametrize('case', ['temperature 1e300', 'temperature 900', 'velocity x2',
                                  'velocity x1000', 'velocity sign'])
def test_import_refuses_what_the_reader_refuses(tmp_path, capsys, case):
    """Each was imported with exit 0 and refused by every reader of the recording."""
    log, words = _bad_log(tmp_path, case)
    out = tmp_path / 'rec'
    rc = main(['import', log, '--out', str(out), *IMPORT, '--velocity', 'qd', '--temperature',
               'xi', '--quiet'])
    one_line(capsys, rc, 'bad.csv', *words)
    assert not out.exists()


def test_import_velocity_from_position_goes_on_echoed_and_recorded(tmp_path, capsys):
    """The option named by the refusal imports the log with the position's derivative."""
    from friction_joint.bag import read_recording

    log, _ = _bad_log(tmp_path, 'velocity x2')
    out = tmp_path / 'rec'
    rc = main(['import', log, '--out', str(out), *IMPORT, '--velocity', 'qd',
               '--velocity-from-position'])
    echo = capsys.readouterr().out
    assert rc == 0 and '--velocity-from-position' in echo, echo
    rec = read_recording(out)
    t, q, qd, _ = motion()
    np.testing.assert_allclose(rec.joint_states.qd[1:-1], qd[1:-1], atol=1e-3 * np.abs(qd).max())
    import json

    import yaml
    meta = yaml.safe_load((out / 'metadata.yaml').read_text(encoding='utf-8'))
    info = json.loads(meta['rosbag2_bagfile_information']['custom_data'][
        'friction_joint.import'])
    assert '--velocity-from-position' in info['velocity'], info
    assert "'qd' not used" in info['velocity'] and info['velocity_from_position'], info


def _sample_with_velocity_x2(tmp_path):
    """Write 10 s of the shipped sample with its velocity doubled; return the path."""
    from friction_joint.bag import read_recording, write_recording

    rec = read_recording(RECORDING)
    js, temp = rec.joint_states, rec.temperature
    n = int(np.searchsorted(js.t, js.t[0] + 10.0))
    m = int(np.searchsorted(temp.t, js.t[n]))
    path = tmp_path / 'x2'
    write_recording(path, {'/joint_states': {'t': js.t[:n], 'q': js.q[:n], 'qd': 2 * js.qd[:n],
                                             'effort': js.effort[:n], 'name': rec.joint_name},
                           '/joint_temperature': {'t': temp.t[:m], 'xi': temp.xi[:m]}},
                    joint_name=rec.joint_name)
    return str(path)


def test_diagnose_and_identify_go_on_with_velocity_from_position(tmp_path, capsys):
    """A recording whose velocity is twice the position's: refused, then diagnosed."""
    import json

    rec = _sample_with_velocity_x2(tmp_path)
    out = tmp_path / 'diag'
    rc = main(['diagnose', rec, '--model', BASE, '--out', str(out), '--quiet'])
    one_line(capsys, rc, 'x2', '2 times', '--velocity-from-position')
    rc = main(['diagnose', rec, '--model', BASE, '--out', str(out), '--quiet',
               '--velocity-from-position'])
    echo = capsys.readouterr().out
    assert rc == 0 and '--velocity-from-position' in echo, echo
    report = json.loads((out / 'report.json').read_text(encoding='utf-8'))
    assert report['data']['velocity_from_position'] is True
    gear = tmp_path / 'g.yaml'
    rc = main(['identify', rec, '--model', BASE, '--out', str(gear), '--presliding', 'skip',
               '--quiet', '--velocity-from-position'])
    echo = capsys.readouterr().out
    assert rc == 0 and '--velocity-from-position' in echo, echo
    ident = json.loads((tmp_path / 'g_report' / 'identification.json').read_text('utf-8'))
    assert ident['velocity_from_position'] is True
