# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``diagnose`` bridges short gaps in the stamps and splits at long ones.

A simulated measured-style recording (a hidden ``thermal`` effect) loses ~80
seeded random runs of 2-20 samples, as a realtime simulator or logger on a
loaded machine skips ticks.  ``diagnose`` must bridge them (not refuse or
shred the recording) and give what it gives without the holes: the same named
causes, the extended (thermal) friction curve within 1 % at the recorded
temperatures (the base, which misses the effect, within 2 %), held-out torque
RMSE within 25 %.
A gap of 0.2 s (200 samples) is too long to bridge and still splits.
"""
import json
from pathlib import Path
import subprocess
import sys

import friction_joint
from friction_joint.bag import write_recording
from friction_joint.bag.stamps import BRIDGE_SAMPLES, GAP, split_pieces
from friction_joint.diagnosis.data import load_data
from friction_joint.experiments.hidden import (apply_effect, draw_effect, RecordingOptions,
                                               simulate_recording)
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
SEED = 20260121


def punch_holes(topics, seed, n=80, shortest=2, longest=20):
    """
    Delete ``n`` seeded random runs of ``shortest``..``longest`` joint-state samples.

    The 1 kHz topics lose the same time spans (a skipped tick loses every topic
    of it); the 4 Hz temperature is left alone.  Returns the topics and the
    run lengths.
    """
    rng = np.random.default_rng(seed)
    t = topics['/joint_states']['t']
    dt = float(np.median(np.diff(t)))
    drop = np.zeros(len(t), dtype=bool)
    starts = rng.choice(np.arange(200, len(t) - 200), size=n, replace=False)
    for s, k in zip(starts, rng.integers(shortest, longest + 1, size=n), strict=True):
        drop[s:s + k] = True
    edges = np.flatnonzero(np.diff(np.r_[0, drop.astype(int), 0]))
    spans = [(t[a] - 0.5 * dt, t[b - 1] + 0.5 * dt)
             for a, b in zip(edges[::2], edges[1::2], strict=True)]
    out = {}
    for name, spec in topics.items():
        tt = np.asarray(spec['t'])
        keep = np.ones(len(tt), dtype=bool)
        if len(tt) > len(t) // 10:
            for a, b in spans:
                keep &= ~((tt > a) & (tt < b))
        out[name] = {k: (v[keep] if isinstance(v, np.ndarray) and v.shape[:1] == tt.shape else v)
                     for k, v in spec.items()}
    return out, np.array([b - a for a, b in zip(edges[::2], edges[1::2], strict=True)])


@pytest.fixture(scope='module')
def recordings(tmp_path_factory):
    """Gap-free, holed and holed + one long gap recordings of one simulated run."""
    d = tmp_path_factory.mktemp('gaps')
    base = friction_joint.load_gear(BASE)
    truth = apply_effect(base, 'thermal', size=draw_effect(np.random.default_rng(SEED), 'thermal'))
    topics, _ = simulate_recording(truth, None, options=RecordingOptions(
        duration=30.0, seed=SEED, base_gear=base, n_segments=2))
    holed, runs = punch_holes(topics, SEED)
    t = holed['/joint_states']['t']
    mid = float(t[len(t) // 4])                     # inside the first segment
    long_gap = {name: {k: (v[~((spec['t'] > mid) & (spec['t'] < mid + 0.2))]
                           if isinstance(v, np.ndarray) and v.shape[:1] == spec['t'].shape
                           else v) for k, v in spec.items()}
                for name, spec in holed.items()}
    return {'base': base, 'runs': runs,
            'clean': write_recording(d / 'clean', topics),
            'holed': write_recording(d / 'holed', holed),
            'long': write_recording(d / 'long', long_gap), 'dir': d}


def _diagnose(rec, out):
    cmd = [sys.executable, '-m', 'friction_joint', 'diagnose', str(rec), '--model', str(BASE),
           '--out', str(out)]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=600, cwd=str(ROOT))
    assert res.returncode == 0, res.stderr
    return json.loads((Path(out) / 'report.json').read_text()), (Path(out) / 'report.md')


def test_split_pieces_rule():
    """Gaps up to the limit are bridged, longer ones split; the rule is scale-free in time."""
    for scale in (1.0, 100.0):
        t = np.arange(20000) * 1e-3 * scale
        qd = np.sin(2 * np.pi * 0.5 * t / scale) / scale          # time scale ~0.3 s
        keep = np.ones(len(t), dtype=bool)
        keep[5000:5010] = False                                    # 11 sample times
        keep[10000:10100] = False                                  # 101 sample times
        cut = split_pieces(t[keep], qd[keep])
        assert len(cut.ranges) == 2 and cut.split == 1
        assert len(cut.bridged) == 1
        assert cut.bridged_s[0] == pytest.approx(11e-3 * scale)
        assert cut.limit <= BRIDGE_SAMPLES * 1e-3 * scale + 1e-12
    # a motion ten times faster: the same 11-sample gap is no longer short against it
    t = np.arange(20000) * 1e-3
    qd = np.sin(2 * np.pi * 20.0 * t)
    keep = np.ones(len(t), dtype=bool)
    keep[5000:5010] = False
    cut = split_pieces(t[keep], qd[keep])
    assert cut.split == 1 and len(cut.bridged) == 0


def test_diagnose_bridges_short_gaps(recordings):
    d = recordings['dir']
    clean, clean_md = _diagnose(recordings['clean'], d / 'out_clean')
    holed, holed_md = _diagnose(recordings['holed'], d / 'out_holed')
    runs = recordings['runs']
    gaps = holed['data']['gaps']
    # steps of more than GAP sample times (a step of exactly GAP may go either way in floats)
    lo, hi = int(np.count_nonzero(runs + 1 > GAP)), int(np.count_nonzero(runs + 1 >= GAP))
    print(f'\n{len(runs)} holes ({runs.min()}..{runs.max()} samples), gaps {gaps}; '
          f'clean {clean["named_causes"]} {clean["baseline"]["torque_rmse"]:.4f} Nm, '
          f'holed {holed["named_causes"]} {holed["baseline"]["torque_rmse"]:.4f} Nm, '
          f'fits {clean["base_fit"]} / {holed["base_fit"]}')
    assert lo <= gaps['bridged'] <= hi and gaps['split'] == clean['data']['gaps']['split']
    assert gaps['longest_bridged_samples'] == pytest.approx(runs.max() + 1, abs=0.01)
    assert clean['data']['gaps']['bridged'] == 0
    assert 'bridged' in holed_md.read_text()
    assert holed['named_causes'] == clean['named_causes'] == ['thermal']
    # the base misses the thermal effect, so its fit is a temperature average that depends
    # on which bins are used: 2 %; the extended (thermal) fit at the recorded temperatures: 1 %
    for key in ('fc', 'fv'):
        assert holed['base_fit'][key][0] == pytest.approx(clean['base_fit'][key][0], rel=0.02)
        for xi in clean['data']['xi_range']:
            a = np.polyval(clean['extended_fit'][key][::-1], xi)
            b = np.polyval(holed['extended_fit'][key][::-1], xi)
            print(f'{key}({xi:.1f} degC): {a:.4f} clean, {b:.4f} holed')
            assert b == pytest.approx(a, rel=0.01), (key, xi)
    for which in ('baseline', 'extended'):
        a, b = clean[which]['torque_rmse'], holed[which]['torque_rmse']
        assert abs(b / a - 1.0) < 0.25, (which, a, b)
    assert holed['data']['sliding_s'] > 0.75 * clean['data']['sliding_s']


def test_long_gap_still_splits(recordings):
    base = recordings['base']
    holed = load_data([recordings['holed']], base)
    long_ = load_data([recordings['long']], base)
    assert long_.gaps['split'] == holed.gaps['split'] + 1
    assert long_.piece.max() == holed.piece.max() + 1
    jump = np.flatnonzero(np.diff(long_.t) > 0.15)
    assert len(jump) >= 1 and all(long_.piece[j] != long_.piece[j + 1] for j in jump)
    # no bin holds a bridged (interpolated) sample
    assert not np.any(holed.bridged & (holed.bin_of >= 0))
    assert holed.bridged.any()
