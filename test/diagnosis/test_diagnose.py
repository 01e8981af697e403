# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint diagnose`` finds an effect hidden in simulated measured-style data.

Each case draws WHICH effect (or pair, or none), its SIZE within the realistic
ranges of :data:`friction_joint.experiments.hidden.EFFECT_RANGES` and the recording SEED
at random, from a fixed master seed (override with the environment variable
``FRICTION_JOINT_TEST_SEED`` to explore other draws).  The truth gear = base +
the drawn effects runs on the simulated test bed; the recording goes into a
neutral temporary directory (``.../caseN/rec``) and the command sees nothing
but the recording and the base file.  The draw is printed in every assertion
message.
"""
import json
import math
import os
from pathlib import Path
import shutil
import subprocess
import sys
import warnings

import friction_joint
from friction_joint.bag import write_recording
from friction_joint.effects import EFFECTS
from friction_joint.exceptions import GearConfigWarning
from friction_joint.experiments.hidden import (apply_effects, draw_effect, HIDEABLE,
                                               RecordingOptions, simulate_recording)
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
MASTER_SEED = int(os.environ.get('FRICTION_JOINT_TEST_SEED', '20251121'))
DURATION = 45.0            # s of recording per case (three 15 s temperature segments)
TIMEOUT = 600


def _diagnose(recordings, model, out):
    cmd = [sys.executable, '-m', 'friction_joint', 'diagnose',
           *[str(r) for r in recordings], '--model', str(model), '--out', str(out)]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT, cwd=str(ROOT))


def _draws():
    """Per case: effects {name: size} and the recording seed (all from the master seed)."""
    rng = np.random.default_rng(MASTER_SEED)
    order = [str(e) for e in rng.permutation(list(HIDEABLE))]
    cases = {'case0': order[:1], 'case1': order[1:2], 'case2': order[2:4], 'case3': []}
    out = {}
    for i, (case, effects) in enumerate(cases.items()):
        r = np.random.default_rng([MASTER_SEED, i])
        sizes = {e: draw_effect(r, e) for e in effects}
        out[case] = (sizes, int(r.integers(0, 2**31 - 1)), bool(r.random() < 0.5))
    return out


DRAWS = _draws()


def _fmt(effects, seed, link):
    sizes = {e: {k: (round(v, 4) if isinstance(v, float) else v) for k, v in s.items()}
             for e, s in effects.items()}
    return (f'[master seed {MASTER_SEED}] hidden {sizes or "nothing"}, recording seed {seed}, '
            f'/link_torque {"recorded" if link else "absent"}')


def _visible(effects, link):
    """Return the effects a recording shows: a lever error is measured by a link torque sensor."""
    return {e: s for e, s in effects.items() if not (link and e == 'gravity')}


def _check_report(report, what):
    for key in ('named_causes', 'candidates', 'baseline', 'extended'):
        assert key in report, f'{what}: report.json lacks {key!r}'
    assert isinstance(report['named_causes'], list), what
    for part in ('baseline', 'extended'):
        for key in ('torque_rmse', 'velocity_rmse'):
            v = report[part][key]
            assert isinstance(v, (int, float)) and math.isfinite(v) and v >= 0, \
                f'{what}: {part}.{key} = {v!r}'
    for cand in report['candidates']:
        assert cand['effect'] in EFFECTS or isinstance(cand['effect'], str), what
        assert 0.0 <= cand['gain'] <= 1.0, f'{what}: gain out of 0..1 in {cand}'
        assert isinstance(cand['significant'], bool), f'{what}: {cand}'
    for name in report['named_causes']:
        assert name in EFFECTS, f'{what}: unknown effect name {name!r}'


@pytest.mark.slow
@pytest.mark.parametrize('case', sorted(DRAWS))
def test_diagnose_names_the_hidden_effect(case, tmp_path_factory):
    hidden, seed, link = DRAWS[case]
    what = _fmt(hidden, seed, link)
    base = friction_joint.load_gear(BASE)
    truth = apply_effects(base, hidden)
    effects = _visible(hidden, link)
    work = tmp_path_factory.mktemp('case')
    rec = work / 'rec'
    simulate_recording(truth, rec, options=RecordingOptions(
        duration=DURATION, seed=seed, base_gear=base, link_torque=link))

    out = work / 'out'
    res = _diagnose([rec], BASE, out)
    assert res.returncode == 0, f'{what}: diagnose failed ({res.returncode}):\n{res.stderr}'
    report = json.loads((out / 'report.json').read_text())
    _check_report(report, what)
    named = report['named_causes']
    summary = f'{what}; named {named}; candidates {report["candidates"]}'
    if len(effects) <= 1:
        assert named == list(effects), summary
    else:
        assert sorted(named) == sorted(effects) and len(named) == len(effects), summary
    if named:
        assert report['extended']['torque_rmse'] < report['baseline']['torque_rmse'], summary

    # the extended model loads and is complete: re-diagnosing with it names nothing
    extended = out / 'extended.yaml'
    with warnings.catch_warnings():
        warnings.simplefilter('error', GearConfigWarning)     # passive LuGre, nothing dubious
        friction_joint.load_gear(extended)
    out2 = work / 'out2'
    res = _diagnose([rec], extended, out2)
    assert res.returncode == 0, f'{what}: re-diagnosis failed:\n{res.stderr}'
    report2 = json.loads((out2 / 'report.json').read_text())
    _check_report(report2, what)
    assert report2['named_causes'] == [], \
        f'{what}; re-diagnosis with extended.yaml named {report2["named_causes"]}; ' \
        f'candidates {report2["candidates"]}'


# ----------------------------------------------------------------------------- bad input

@pytest.fixture(scope='module')
def good_topics():
    """Topics of a short, valid recording of the base (made once per module)."""
    base = friction_joint.load_gear(BASE)
    topics, _ = simulate_recording(base, None, options=RecordingOptions(
        duration=20.0, seed=7, n_segments=2))
    return topics


def _copy_topics(topics):
    return {t: {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in spec.items()}
            for t, spec in topics.items()}


def _assert_rejected(res, out, *words):
    assert res.returncode == 2, f'exit {res.returncode}; stderr:\n{res.stderr}'
    err = res.stderr.lower()
    assert any(w.lower() in err for w in words), \
        f'stderr does not name the problem ({" / ".join(words)}):\n{res.stderr}'
    assert 'Traceback' not in res.stderr, res.stderr
    assert not (out / 'report.json').exists(), 'report.json written for bad input'


def test_missing_temperature_topic(good_topics, tmp_path):
    """No /joint_temperature: thermal untestable (or, where the reader requires it, exit 2)."""
    topics = _copy_topics(good_topics)
    del topics['/joint_temperature']
    write_recording(tmp_path / 'rec', topics)
    res = _diagnose([tmp_path / 'rec'], BASE, tmp_path / 'out')
    if res.returncode != 0:                 # a reader that still requires the topic
        _assert_rejected(res, tmp_path / 'out', '/joint_temperature')
        return
    report = json.loads((tmp_path / 'out' / 'report.json').read_text())
    thermal = next(c for c in report['candidates'] if c['effect'] == 'thermal')
    assert thermal['testable'] is False, thermal
    assert thermal['reason'] == 'no temperature signal in the recordings', thermal
    assert 'thermal' not in report['named_causes']


def test_truncated_mcap(good_topics, tmp_path):
    path = tmp_path / 'rec.mcap'
    write_recording(path, good_topics)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    res = _diagnose([path], BASE, tmp_path / 'out')
    _assert_rejected(res, tmp_path / 'out', 'truncated', 'corrupt')


def test_nan_in_data(good_topics, tmp_path):
    topics = _copy_topics(good_topics)
    topics['/joint_states']['effort'][1234] = np.nan
    write_recording(tmp_path / 'rec', topics)
    res = _diagnose([tmp_path / 'rec'], BASE, tmp_path / 'out')
    _assert_rejected(res, tmp_path / 'out', 'nan', 'finite')


def test_unknown_key_in_base(good_topics, tmp_path):
    write_recording(tmp_path / 'rec', good_topics)
    text = BASE.read_text().replace('      fv: [0.6]\n', '      fv: [0.6]\n      fcc: [1.0]\n')
    assert 'fcc' in text
    model = tmp_path / 'model.yaml'
    model.write_text(text)
    res = _diagnose([tmp_path / 'rec'], model, tmp_path / 'out')
    _assert_rejected(res, tmp_path / 'out', 'fcc')


def test_existing_output_not_passed_off(good_topics, tmp_path):
    """A failing run leaves no report.json behind even where an output dir exists."""
    topics = _copy_topics(good_topics)
    topics['/joint_states']['q'][10] = np.inf
    write_recording(tmp_path / 'rec', topics)
    out = tmp_path / 'out'
    out.mkdir()
    res = _diagnose([tmp_path / 'rec'], BASE, out)
    _assert_rejected(res, out, 'nan', 'finite', 'inf')
    shutil.rmtree(out)
