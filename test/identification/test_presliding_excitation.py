# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Step 3 that cannot be fitted says why, from the data, and what to record.

The shipped sample (``bags/csd25_sample``) commands small position sinusoids,
but the joint sticks through them: the measured position has no reversal
within the pre-sliding range, so ``identify`` rejects the pre-sliding fits.
The console, ``identification.json`` and the gear file's header say so with
the range computed from the gear (the structure's stiffness, F_s of steps 1-2)
and the swings seen in the recording, and give swings to record.  On synthetic
positions the swings are found as drawn.
"""
import json
from pathlib import Path

from friction_joint.bag import read_recording
from friction_joint.cli import main
from friction_joint.gear import load_gear
from friction_joint.identification.presliding import presliding_excitation, reversal_swings
from friction_joint.identification.presliding_data import default_settle
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
SAMPLE = ROOT / 'bags' / 'csd25_sample'


def _mrad(x):
    return f'{1e3 * x:.3g} mrad'


def test_sample_step_3_says_the_reversals_are_too_large_and_what_to_record(tmp_path, capsys):
    """The sample's step 3: rejected, because no reversal is within the pre-sliding range."""
    out = tmp_path / 'id.yaml'
    assert main(['identify', str(SAMPLE), '--model', str(BASE), '--out', str(out)]) == 0
    err = capsys.readouterr().err
    s3 = json.loads((tmp_path / 'id_report' / 'identification.json').read_text())['presliding']
    assert {r['status'] for r in s3['models'].values()} == {'rejected'}, s3
    # the range from the gear: the structure's stiffness and F_s of steps 1-2 (fc constant)
    gear = load_gear(out)
    ranges = {m: default_settle(gear, m, 30.0) for m in ('lugre', 'gms')}
    ex = s3['excitation']
    assert ex['range_rad'] == {m: ex['range_rad'][m] for m in ranges}
    assert all(abs(ex['range_rad'][m] / v - 1) < 1e-6 for m, v in ranges.items()), ex
    # the recording: measured swings all beyond the range, commanded ones within it
    rec = read_recording(str(SAMPLE), joint_name=gear.joint_name)
    h = 0.1 * min(ranges.values())
    measured = reversal_swings(rec.joint_states.q, h)[0]
    commanded = reversal_swings(rec.joint_command.q_d, h)[0]
    assert measured.min() > max(ranges.values()) and ex['small_reversals'] == 0, ex
    assert ex['smallest_swing_rad'] == measured.min(), ex
    assert ex['commanded_small'] == np.count_nonzero(commanded < max(ranges.values())) > 0
    why, advice = s3['why'], s3['advice']
    lo, hi = sorted(ranges.values())
    assert why.startswith('the recordings hold no velocity reversal within the pre-sliding '
                          f'range: the smallest swing between two reversals is '
                          f'{_mrad(measured.min())}, but the friction remembers a reversal '
                          f'only over the first {_mrad(lo)} (lugre'), why
    assert f'to {_mrad(hi)} (gms' in why and 'did not follow them' in why, why
    assert advice.startswith(f'record, after a slide of at least {_mrad(hi)} in one direction, '
                             f'small sinusoids or triangles about standstill with swings from '
                             f'{_mrad(0.1 * lo)} to {_mrad(hi)}'), advice
    # said where a newcomer looks: the console and the gear file's header
    assert f'step 3: why: {why}\n' in err and f'step 3: to fit it, {advice}\n' in err, err
    header = out.read_text()
    assert f'# step 3: why: {why[:60]}' in header, header[:3000]


def _gear():
    return load_gear(BASE)


def test_swings_and_the_verdict_on_synthetic_positions():
    """Swings found as drawn; small ones make no complaint, large ones and stuck ones do."""
    rng = np.random.default_rng(5)
    gear = _gear()
    length = default_settle(gear, 'lugre', 30.0)
    t = np.arange(0.0, 4.0, 1e-3)
    slide = 3.0 * length * np.clip(t, 0.0, 1.0)
    amp = rng.uniform(0.1, 0.4) * length                # swing 2 amp, within the range
    small = slide + amp * np.sin(2 * np.pi * 2.0 * np.clip(t - 1.0, 0.0, None))
    noisy = small + rng.normal(0, 1e-3 * length, t.size)
    swings, _ = reversal_swings(noisy, 0.05 * length)
    assert swings.size == 11 and np.allclose(swings, 2 * amp, rtol=0.02), (swings, amp)
    piece = {'q': small, 'xi': np.full(t.size, 30.0)}
    ok = presliding_excitation([piece], gear, ['lugre'])
    assert ok['why'] is None and ok['small_reversals'] == 11, ok
    # 6 periods: 12 turning points, 11 swings; the same command, a joint that stuck after the
    # slide: no reversal, and it is said
    stuck = {'q': slide, 'xi': piece['xi']}
    bad = presliding_excitation([stuck], gear, ['lugre'], commands=[(t, small, t, stuck['q'])])
    assert bad['why'].startswith('the recordings hold no velocity reversal within the '
                                 'pre-sliding range: the joint never reverses'), bad
    assert bad['commanded_small'] == 11 and '/joint_command asked for 11 such small' in bad['why']
    assert f'the first {_mrad(length)} (lugre: 10 F_s / sigma0)' in bad['why'], bad['why']
