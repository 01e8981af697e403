# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
One story per diagnosis report: headline, findings, next steps and adequacy table agree.

Every combination of named effects (none, one, two), a model that explains the
data or does not, an unconfirmed large gain or none, what the residual scan
found, and the candidates the recordings cannot test (their reasons from the
real testability rules on drawn data) is worded from one
:class:`~friction_joint.diagnosis.criterion.Verdict`; the sentences must not
contradict each other, and the numbers they quote (fit, strokes, limits) must
agree.  ``FRICTION_JOINT_TEST_SEED`` sets the master seed of the draws.
"""
import itertools
import os
import re
from types import SimpleNamespace

from friction_joint.diagnosis.criterion import INADEQUATE, LARGE_GAIN, verdict
from friction_joint.diagnosis.findings import (candidate_summary, finding_lines, next_step_lines,
                                               RECORD_ADVICE)
from friction_joint.diagnosis.gravity import gravity_untestable
from friction_joint.diagnosis.result import DataRanges, DiagnosisResult
from friction_joint.diagnosis.testability import untestable
import numpy as np
import pytest

MASTER_SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20261129'))
RANGES = DataRanges(temperature=(22.0, 38.0), speed=(0.03, 2.5), load=(0.5, 9.0),
                    position=(-1.2, 1.3), travel=40.0, level=2.8, inertia=0.05)
FITS = {'thermal': {'fc': [1.0, 0.05], 'fv': [0.9, -0.01]}, 'asymmetry': {'offset': -0.2}}
NUMBER = re.compile(r'(?<![\w.])-?\d+(?:\.\d+)?(?:e-?\d+)?')


def _data(rng):
    """Bins of a short one-way constant-speed run: most candidates cannot be tested."""
    n = 2000
    stroke = float(rng.uniform(0.2, 0.8))
    q = np.linspace(0.0, stroke, n) + float(rng.uniform(-1.0, 1.0))
    qd = np.full(n, float(rng.uniform(0.05, 1.0)))
    return SimpleNamespace(
        friction_level=float(rng.uniform(0.5, 5.0)), average=lambda x: x, q=q, qf=q, qd=qd,
        qdd=rng.normal(0.0, 1e-6, n), xi=25.0 + rng.normal(0.0, 0.01, n), has_temperature=True,
        tl=np.zeros(n), v_stick=1e-3, inertia=0.05, piece=np.zeros(n, dtype=int),
        stroke=stroke)


def _base_columns(data):
    return np.column_stack([np.sign(data.qd), data.qd])


def _reasons(rng):
    """Return ``{effect: reason}`` of the real rules on a drawn short run, and the data."""
    data = _data(rng)
    why = untestable(data, 80.0, ['thermal', 'load', 'nonlinear_viscous', 'stribeck',
                                  'presliding', 'inertia', 'asymmetry', 'drift'])
    why['gravity'] = gravity_untestable(data, _base_columns(data))
    assert all(why.values()) and len(why) == 9, why
    return why, data


def _fit(ratio, level, rng):
    return {'r2': float(1.0 - ratio ** 2 * rng.uniform(0.5, 2.0)), 'rmse': ratio * level,
            'friction_level': level, 'rmse_over_level': ratio, 'explains': ratio < INADEQUATE}


def _report(named, explains, unconfirmed, scan, why, rng):
    level = float(rng.uniform(0.5, 5.0))
    ext = float(rng.uniform(0.01, 0.45) if explains else rng.uniform(0.55, 2.0))
    base = ext if not named else float(rng.uniform(ext, 3.0))
    cands = [{'effect': e, 'testable': False, 'reason': r, 'gain': 0.0, 'significant': False}
             for e, r in why.items()]
    for i, e in enumerate(named):
        cands.append({'effect': e, 'testable': True, 'round': i + 1, 'gain': 0.5,
                      'gain_raw': 0.5, 'p_value': 1e-4, 'p_holm': 1e-3, 'blocks_improved': 20,
                      'blocks': 20, 'significant': True, 'explained_torque': 0.1})
    gain = float(rng.uniform(LARGE_GAIN, 0.6) if unconfirmed else rng.uniform(0.0, LARGE_GAIN))
    cands.append({'effect': 'stribeck', 'testable': True, 'round': len(named) + 1, 'gain': gain,
                  'gain_raw': gain, 'p_value': 0.01, 'p_holm': 0.2, 'blocks_improved': 13,
                  'blocks': 20, 'significant': False})
    fit = {'fc': [2.0], 'fv': [0.6]}
    for e in named:
        fit.update(FITS[e])
    return {'named_causes': list(named), 'extended_effects': list(named), 'candidates': cands,
            'adequacy': {'base': _fit(base, level, rng), 'extended': _fit(ext, level, rng)},
            'residual_scan': scan, 'untestable': dict(why), 'confounds': [],
            'extended_fit': fit, 'base_fit': {'fc': [2.0], 'fv': [0.6]},
            'baseline': {'torque_rmse': base * level},
            'rounds': [{'round': 1, 'model_torque_rmse': base * level, 'candidates': []}]}


SCANS = {
    'flagged': [{'variable': 'time', 'explained': 0.4, 'p_value': 0.001, 'flagged': True},
                {'variable': 'velocity', 'explained': 0.01, 'p_value': 0.5, 'flagged': False}],
    'nothing': [{'variable': 'time', 'explained': 0.01, 'p_value': 0.4, 'flagged': False}],
    'untestable': [{'variable': 'time', 'explained': None, 'p_value': None, 'flagged': False,
                    'untestable': 'too few blocks'}],
}
UNTESTED = [(), ('gravity',), ('gravity', 'drift', 'asymmetry', 'thermal', 'presliding',
                               'nonlinear_viscous', 'load', 'inertia')]
CASES = list(itertools.product([(), ('thermal',), ('thermal', 'asymmetry')], [True, False],
                               [False, True], sorted(SCANS), range(len(UNTESTED))))


def _numbers(text):
    return [float(x) for x in NUMBER.findall(text)]


@pytest.mark.parametrize('named,explains,unconfirmed,scan,untested', CASES)
def test_headline_findings_next_steps_and_table_tell_one_story(
        named, explains, unconfirmed, scan, untested):
    case = CASES.index((named, explains, unconfirmed, scan, untested))
    rng = np.random.default_rng([MASTER_SEED, case])
    reasons, _ = _reasons(rng)
    why = {e: reasons[e] for e in UNTESTED[untested]}
    rep = DiagnosisResult.from_dict(_report(named, explains, unconfirmed, SCANS[scan], why, rng))
    v = verdict(rep)
    head = v.headline
    find = '\n'.join(finding_lines(v, rep, RANGES))
    nxt = '\n'.join(next_step_lines(v, rep, 'out', ['rec']))
    table = v.adequacy_lines()
    what = f'{named} explains={explains} unconfirmed={unconfirmed} scan={scan} {why}'
    story = f'{what}\n{head}\n{find}\n{nxt}\n' + '\n'.join(table)
    # the base model stands only when it explains the data and nothing is missing
    nothing = not named and explains and not unconfirmed
    assert ('nothing to change' in nxt) == nothing, story
    assert ('No missing effect found' in find) == nothing, story
    if nothing:
        assert head.startswith('Nothing significant is missing'), story
    # adequacy: headline, findings, next steps and table say the same
    row = next(r for r in table if r.startswith('| explains the data'))
    assert row.endswith('| yes |' if explains else '| **no** |'), story
    assert ('does not explain' in head) == (not explains), story
    assert ('does not explain' in find) == (not explains), story
    if not explains:
        assert v.structure in head and v.structure in find and v.structure in nxt, story
        if scan == 'flagged':
            assert 'Largest unexplained structure: time' in find, story
    else:
        assert 'Largest unexplained structure' not in find + nxt, story
    # the numbers of the fit: the headline's are the table's, rounded
    r2 = float(re.search(r'R\^2 (-?[\d.]+)', head).group(1))
    t_r2 = float(next(r for r in table if r.startswith('| held-out R^2')).split('|')[3])
    assert abs(r2 - t_r2) <= 0.005 + 1e-9, story
    rmse = re.search(r'RMSE ([\d.e-]+) Nm against a friction level of ([\d.e-]+) Nm', head)
    t_ratio = float(next(r for r in table if r.startswith('| held-out RMSE')).split('|')[3])
    assert abs(float(rmse.group(1)) / float(rmse.group(2)) - t_ratio) <= 0.01 * t_ratio + 6e-4
    for m in re.finditer(r'RMSE ([\d.e-]+) Nm against a friction level of ([\d.e-]+) Nm', find):
        assert m.group(0) == rmse.group(0), story
    # named effects: in the headline, one finding each, in extended.yaml
    for e in named:
        assert e in head and f'* {e.capitalize()}:' in find, story
        assert f'with {", ".join(named)} added' in nxt, story
    # an unconfirmed large gain is said wherever the base model is judged
    if unconfirmed and not named:
        assert 'stribeck gains' in find, story
        if explains:
            assert 'stribeck gains' in head and 'confirm or rule out stribeck' in nxt, story
    # untestable: its reason and what to record, with limits that agree
    for e, reason in why.items():
        line = next((ln for ln in nxt.splitlines() if ln.startswith(f'  * {e} (')), None)
        assert line and reason in line, story
        if not named:
            assert e in find.split('Not tested:')[1], story
        advice = line[len(f'  * {e} ({reason}): '):]
        if re.search(r'needed|less than|below', reason):
            assert set(_numbers(advice)) <= set(_numbers(reason)), (e, line)


@pytest.mark.parametrize('case', range(4))
def test_gravity_stroke_needed_is_the_stroke_that_makes_it_testable(case):
    """Before: "covers 0.601 rad ... (at least about 0.3 rad)"; now the stroke it would take."""
    rng = np.random.default_rng([MASTER_SEED, 100 + case])
    reasons, data = _reasons(rng)
    reason = reasons['gravity']
    covered = float(re.search(r'covers ([\d.]+) rad', reason).group(1))
    need = float(re.search(r'over about ([\d.]+) rad would be enough', reason).group(1))
    assert covered == pytest.approx(np.ptp(data.q), rel=5e-3) and need > covered, reason
    assert not _numbers(RECORD_ADVICE['gravity']), RECORD_ADVICE['gravity']
    mid = 0.5 * (data.q.min() + data.q.max())
    for scale, testable in ((1.03, True), (0.97, False)):
        q = mid + (data.q - mid) * scale * need / np.ptp(data.q)
        stretched = SimpleNamespace(average=lambda x: x, q=q)
        assert (gravity_untestable(stretched, _base_columns(data)) is None) == testable, \
            (reason, scale)


def test_a_candidate_significant_in_round_one_is_not_called_not_significant():
    """Before: 'it was not significant' for a candidate significant in round 1, not named."""
    rng = np.random.default_rng([MASTER_SEED, 200])
    g1, p1 = float(rng.uniform(0.05, 0.5)), float(rng.uniform(1e-5, 0.04))
    first = {'effect': 'load', 'gain_raw': g1, 'p_holm': p1, 'significant': True,
             'blocks_improved': 18, 'blocks': 20}
    rep = {'named_causes': ['thermal'], 'criterion': {'min_gain': 0.03, 'alpha': 0.05},
           'rounds': [{'round': 1, 'candidates': [first]}],
           'candidates': [{'effect': 'thermal', 'testable': True, 'round': 1},
                          {'effect': 'load', 'testable': True, 'round': 2, 'gain': 0.001,
                           'significant': False}]}
    text = ' '.join(candidate_summary(DiagnosisResult.from_dict(rep)))
    assert f'load gained {100 * g1:.1f} %' in text and 'significant in round 1' in text, text
    assert 'it was not significant' not in text, text
