# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
The diagnose report opens with plain-language findings and what to do next.

A recording simulated with a known hidden effect must give a finding that
states the right direction and a size within tolerance of the truth; on the
shipped sample the report has the "What to do next" section with the
``extended.yaml`` command, and the console, the table and ``gains.png`` agree
on the first-round gain of a candidate that is not named (drift).
"""
import json
from pathlib import Path
import re

import friction_joint
from friction_joint.diagnosis import run_diagnose
from friction_joint.diagnosis.findings import effect_finding, next_step_lines, SENTENCES
from friction_joint.experiments.hidden import apply_effect, simulate_recording
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
SAMPLE = ROOT / 'bags' / 'csd25_sample'


def _poly(c, x):
    return float(np.polynomial.polynomial.polyval(x, c))


def _section(md, title):
    m = re.search(rf'^## {title}\n(.*?)(?=^## )', md, re.S | re.M)
    assert m, f'report.md has no "## {title}" section:\n{md[:2000]}'
    return m.group(1)


def _run(recordings, out):
    msgs = []
    run_diagnose([str(r) for r in recordings], str(BASE), str(out), progress=msgs.append)
    return (out / 'report.md').read_text(), json.loads((out / 'report.json').read_text()), msgs


def test_thermal_finding_matches_the_hidden_truth(tmp_path):
    base = friction_joint.load_gear(BASE)
    truth = apply_effect(base, 'thermal', {'fc_change': 0.35, 'fv_change': 0.2})
    rec = tmp_path / 'rec'
    simulate_recording(truth, rec, duration=30.0, seed=7, base_gear=base)
    md, rep, _ = _run([rec], tmp_path / 'out')
    assert rep['named_causes'] == ['thermal'], rep['named_causes']
    text = _section(md, 'Findings')
    m = re.search(r'Thermal: F_c (rises|falls) about (\d+) % and F_v (rises|falls) about '
                  r'(\d+) % from (-?\d+) to (-?\d+) degC', text)
    assert m, text
    lo, hi = rep['data']['xi_range']
    assert (int(m.group(5)), int(m.group(6))) == (round(lo), round(hi)), (text, lo, hi)
    fr = truth.friction
    mid = 0.5 * (lo + hi)
    true_fc = (_poly(fr.fc, hi) - _poly(fr.fc, lo)) / _poly(fr.fc, mid)
    true_fv = (_poly(fr.fv, hi) - _poly(fr.fv, lo)) / _poly(fr.fv, mid)
    assert m.group(1) == 'rises' and m.group(3) == 'falls', text
    assert abs(int(m.group(2)) - 100 * true_fc) <= 5, (text, true_fc)
    assert abs(int(m.group(4)) + 100 * true_fv) <= 5, (text, true_fv)
    assert 'the base model keeps them constant' in text, text
    explained = re.search(r'explains ([\d.e-]+) Nm RMS of the ([\d.e-]+) Nm', text)
    assert explained and float(explained.group(1)) <= float(explained.group(2)) * 1.05, text
    nxt = _section(md, 'What to do next')
    assert f'--model {tmp_path / "out"}/extended.yaml' in nxt, nxt
    assert '//' not in nxt, nxt


@pytest.mark.parametrize('sign', [1.0, -1.0])
def test_asymmetry_finding_states_the_direction(tmp_path, sign):
    base = friction_joint.load_gear(BASE)
    offset = 0.3 * sign
    truth = apply_effect(base, 'asymmetry', {'offset': 0.3, 'sign': sign})
    rec = tmp_path / 'rec'
    simulate_recording(truth, rec, duration=20.0, seed=11, base_gear=base, n_segments=1)
    md, rep, _ = _run([rec], tmp_path / 'out')
    assert 'asymmetry' in rep['named_causes'], rep['named_causes']
    text = _section(md, 'Findings')
    m = re.search(r'Asymmetry: friction is about ([\d.]+) Nm .*? larger moving in the '
                  r'(positive|negative) direction', text)
    assert m, text
    assert m.group(2) == ('positive' if sign > 0 else 'negative'), text
    assert abs(float(m.group(1)) - 2 * abs(offset)) <= 0.2 * 2 * abs(offset), text


def test_shipped_sample_report_findings_next_steps_and_drift_agree(tmp_path):
    out = tmp_path / 'd1'
    md, rep, msgs = _run([SAMPLE], out)
    assert rep['named_causes'] == ['thermal']
    lines = md.splitlines()
    assert lines[0] == '# Friction model diagnosis' and lines[2] == '## Findings', lines[:4]
    text = _section(md, 'Findings')
    # bags/README.md: Fc rises by 30 % and Fv falls by 25 % over the segment temperatures
    m = re.search(r'F_c rises about (\d+) % and F_v falls about (\d+) % from 22 to 38 degC',
                  text)
    assert m and abs(int(m.group(1)) - 30) <= 5 and abs(int(m.group(2)) - 25) <= 5, text
    nxt = _section(md, 'What to do next')
    assert (f'friction_joint diagnose {rep["data"]["recordings"][0]} --model '
            f'{out}/extended.yaml') in nxt, nxt
    assert 'friction_joint identify' in nxt and 'thermal and drift' in nxt, nxt
    assert '//' not in md

    # drift: first-round gain large, not named; console, table and the figure's data agree
    first = {c['effect']: c for c in rep['rounds'][0]['candidates']}
    g1 = 100 * first['drift']['gain_raw']
    assert g1 > 100 * rep['criterion']['min_gain'] and not first['drift']['significant']
    row = next(ln for ln in lines if ln.startswith('| drift |'))
    assert f'| +{g1:.1f} % |' in row, row
    said = [t for t in msgs if t.startswith('not named: drift')]
    assert said and f'{g1:.1f} %' in said[0] and 'thermal' in said[0], msgs
    note = next(ln for ln in lines if ln.startswith('**Not named despite'))
    assert f'drift gained {g1:.1f} %' in note and 'p (Holm)' in note, note
    assert (out / 'gains.png').stat().st_size > 0
    # jargon explained in plain words where it first appears
    cand = _section(md, 'Candidates')
    assert '*p (Holm)*: the same corrected' in cand and '*blocks improved*' in cand
    assert 'd_k > 0: the candidate predicted block k better' in _section(md, 'Criterion')


def _fake_rep(effect, fit):
    base_fit = {'fc': [2.0], 'fv': [0.6], 'fc_load': [], 'fv_load': []}
    full = dict(base_fit, **fit)
    return {'extended_fit': full, 'base_fit': base_fit, 'baseline': {'torque_rmse': 0.2},
            'rounds': [{'round': 1, 'model_torque_rmse': 0.2, 'candidates': []}],
            'candidates': [{'effect': effect, 'round': 1, 'explained_torque': 0.1}]}


RANGES = {'temperature': (22.0, 38.0), 'speed': (0.03, 2.5), 'load': (0.5, 9.0),
          'position': (-1.2, 1.3), 'travel': 40.0, 'level': 2.8, 'inertia': 0.05}

FITS = {
    'thermal': ({'fc': [1.0, 0.05], 'fv': [0.9, -0.01]}, r'F_c rises about \d+ % and F_v falls'),
    'load': ({'fc_load': [0.02]}, r'F_c rises by 0\.17 Nm'),
    'position_ripple': ({'position_ripple': {'cycles_per_rev': 200.0, 'amplitude': [0.1],
                                             'phase': [0.0]}}, r'\+-0\.1 Nm .*200 times'),
    'nonlinear_viscous': ({'delta_v': [0.6]}, r'speed\^0\.60, less than in proportion'),
    'stribeck': ({'fs': [2.6], 'vs': [0.05]}, r'F_s = 2\.6 Nm \(30 % above F_c = 2 Nm\) falls'),
    'presliding': ({'presliding': {'model': 'lugre', 'stiffness': 2000.0}}, r'about 1 mrad'),
    'inertia': ({'d_inertia': -0.01}, r'0\.04 kg m\^2 .*20 % less'),
    'asymmetry': ({'offset': -0.2}, r'about 0\.4 Nm .*negative direction'),
    'drift': ({'drift': {'fc_drift': [-0.1, 0.0]}}, r'Coulomb friction falls by 0\.2 Nm'),
    'gravity': ({'gravity': {'sin': 0.3, 'cos': 0.4}}, r'amplitude 0\.5 Nm'),
}


@pytest.mark.parametrize('effect', sorted(SENTENCES))
def test_every_effect_kind_has_a_sentence_in_physical_units(effect):
    fit, pattern = FITS[effect]
    text = effect_finding(effect, _fake_rep(effect, fit), RANGES)
    assert re.search(pattern, text), text
    assert 'nan' not in text and text.endswith('held out.'), text


def test_unknown_effect_gets_the_generic_sentence():
    text = effect_finding('backlash', _fake_rep('backlash', {}), RANGES)
    assert text.startswith('Backlash: missing from the base model; explains 0.1 Nm'), text


def test_gravity_finding_with_the_corrected_lever():
    """A named gravity effect states the corrected m g l and zero angle against the base's."""
    fit = {'gravity': {'sin': 0.3, 'cos': 0.4, 'lever': {
        'mgl': 12.0, 'angle_offset': 0.1, 'mgl_base': 10.0, 'angle_offset_base': 0.0}}}
    text = effect_finding('gravity', _fake_rep('gravity', fit), RANGES)
    assert 'm g l is 12 Nm (+20 %) instead of 10 Nm in the base model' in text, text
    assert 'zero at 0.1 rad instead of 0 rad' in text, text


def test_next_steps_say_what_to_record_for_the_untestable():
    """Each untestable effect gets its reason and what to record, in plain words."""
    rep = _fake_rep('thermal', {})
    rep.update({'named_causes': ['thermal'], 'extended_effects': ['thermal'],
                'untestable': {'asymmetry': 'the joint slides in the negative direction 0.0 % '
                                            'of the time (at least 5 % needed)',
                               'gravity': 'a linear device (imported with a radius) has no '
                                          'gravity torque'},
                'confounds': []})
    text = '\n'.join(next_step_lines(rep, 'out/', ['rec']))
    assert '--model out/extended.yaml --out out_check' in text, text
    assert 'asymmetry (the joint slides in the negative direction' in text, text
    assert 'move in both directions' in text, text
    assert 'nothing to record: a linear device has no gravity torque' in text, text
    assert '//' not in text
