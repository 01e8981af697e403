# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Fuzz ``import`` then ``diagnose`` (and ``identify``) with one column in the wrong unit.

A log a user exports in ms, deg, deg/s or mNm and imports without the units is read as
SI: one column is then off by a factor 10^3 or 10^-3.  Before, ``diagnose`` ended in a
traceback (``range() arg 3 must not be zero`` in ``diagnosis/velocity.py``: a sample
time of 1 s) on such a recording that ``import`` had written with exit 0.  Each case
takes 10 s of the shipped sample in SI (time, position, velocity, drive torque,
temperature), scales one column drawn at random by 10^3 or 10^-3, maps the velocity or
not (drawn), imports it without units and, if that succeeds, diagnoses it (and
identifies it, drawn).  Every command must end with exit 0 and its outputs, or exit 2
and one line ``friction_joint COMMAND: error: ...`` with nothing written; never a
traceback.  ``identify`` cannot tell a time in ms read as s from a slow joint (its result
is right for the numbers it was given, F_v 1000 times too large): exit 0 then needs its
F_c and F_v within a factor 10 of the structure file's, or a warning line naming the
units and how to import the log again.  The draws are derandomized hypothesis
examples, few and short.
"""
import os
import warnings

from friction_joint.bag import read_recording
from friction_joint.exceptions import UnitsWarning
from friction_joint.gear import load_gear
from hypothesis import example, given, strategies as st
import numpy as np
import pytest

from test_fuzz import fuzz
from test_fuzz_inputs import guarded

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RECORDING = os.path.join(ROOT, 'bags', 'csd25_sample')
BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')
COLUMNS = ('time', 'position', 'velocity', 'torque', 'temperature')
#: generated cases (each an import, most a diagnose; about 10 s each)
CASES = 6
SECONDS = 10.0


@pytest.fixture(scope='module')
def si_log():
    """Return 10 s of the shipped sample as columns in SI (time from 0)."""
    rec = read_recording(RECORDING)
    js = rec.joint_states
    n = int(np.searchsorted(js.t, js.t[0] + SECONDS))
    xi = rec.temperature_at(t=js.t[:n])
    return np.column_stack([js.t[:n] - js.t[0], js.q[:n], js.qd[:n], js.effort[:n], xi])


def _ends_well(capsys, rc, command, *outputs):
    """Assert exit 0 with every output there, or exit 2, one line and none of them."""
    cap = capsys.readouterr()
    lines = [ln for ln in cap.err.strip().splitlines() if ': warning: ' not in ln]
    assert rc in (0, 2), cap.err
    if rc == 2:
        assert len(lines) == 1 and lines[0].startswith(f'friction_joint {command}: error: '), \
            cap.err
        assert not any(os.path.exists(p) for p in outputs), outputs
    else:
        assert all(os.path.exists(p) for p in outputs), outputs
    return rc, cap.err


def _off_by(gear_path, key):
    """Return how many times the identified ``key`` is from the structure file's (>= 1)."""
    got, prior = load_gear(gear_path).friction, load_gear(BASE).friction
    ratio = getattr(got, key)[0] / getattr(prior, key)[0]
    return max(ratio, 1.0 / ratio)


@pytest.mark.slow
@fuzz(CASES)
@given(column=st.sampled_from(COLUMNS), exponent=st.sampled_from([3, -3]),
       velocity=st.booleans(), identify=st.booleans())
@example(column='time', exponent=3, velocity=False, identify=True)      # the traceback
@example(column='velocity', exponent=3, velocity=True, identify=False)   # deg/s vs rad
def test_one_column_in_the_wrong_unit_never_a_traceback(si_log, tmp_path_factory, capsys,
                                                        column, exponent, velocity, identify):
    """Import then diagnose (and identify) a log with one column off by 10^3 or 10^-3."""
    if column == 'velocity':
        velocity = True                              # a velocity column that is not mapped
    d = tmp_path_factory.mktemp('unit')
    log = si_log.copy()
    log[:, COLUMNS.index(column)] *= 10.0 ** exponent
    path = str(d / 'log.csv')
    np.savetxt(path, log, delimiter=',', header=','.join(COLUMNS), comments='', fmt='%.12g')
    rec = str(d / 'rec')
    argv = ['import', path, '--out', rec, '--quiet'] + [
        a for q in COLUMNS if q != 'velocity' or velocity for a in (f'--{q}', q)]
    if _ends_well(capsys, guarded(argv), 'import', rec)[0] == 2:
        return
    out = str(d / 'diag')
    _ends_well(capsys, guarded(['diagnose', rec, '--model', BASE, '--out', out, '--quiet']),
               'diagnose', out)
    if identify:
        gear = str(d / 'g.yaml')
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter('always')
            rc, _ = _ends_well(capsys, guarded(['identify', rec, '--model', BASE, '--out',
                                                gear, '--presliding', 'skip', '--quiet']),
                               'identify', gear)
        # exit 0: a result within a factor 10 of the structure file (itself within tens of
        # percent of the plant), or a warning naming the units and how to import again
        off = max(_off_by(gear, k) for k in ('fc', 'fv')) if rc == 0 else 1.0
        said = [str(w.message) for w in caught if issubclass(w.category, UnitsWarning)]
        assert off < 10.0 or (said and 'import the log again' in said[0]), (off, said)
