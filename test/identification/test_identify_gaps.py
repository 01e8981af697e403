# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``identify`` bridges short gaps in the stamps and splits at long ones.

The identification excitation on the simulated test bed (with pre-sliding)
loses ~80 seeded random runs of 2-20 samples.  The identification must
bridge them and give what it gives without the holes: the static curve
within 0.5 % over +-0.01..3.5 rad/s at the recorded temperatures, the load
coefficient within 2 %, sigma0 within 5 %, the GMS k_total and c within 10 %.
A 0.2 s gap still splits.
"""
import json
import os
import warnings

from friction_joint.bag import write_recording
from friction_joint.cli import main
from friction_joint.exceptions import GearConfigWarning
from friction_joint.experiments.excitation import simulate_identification
from friction_joint.gear import load_gear
from friction_joint.identification.pipeline import identify_recordings
from friction_joint.models.static import StaticFriction
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STRUCTURE = os.path.join(ROOT, 'config', 'csd25.yaml')
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')
SEED = 20260122
V = np.geomspace(0.01, 3.5, 200)

pytestmark = pytest.mark.filterwarnings('ignore::friction_joint.exceptions.GearConfigWarning')


def punch_holes(topics, seed, n=80, shortest=2, longest=20):
    """Delete ``n`` seeded random runs of joint-state samples (and the same time spans)."""
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
    return _cut(topics, spans, len(t) // 10), np.array([b - a for a, b in
                                                        zip(edges[::2], edges[1::2], strict=True)])


def _cut(topics, spans, min_len=0):
    out = {}
    for name, spec in topics.items():
        tt = np.asarray(spec['t'])
        keep = np.ones(len(tt), dtype=bool)
        if len(tt) > min_len:
            for a, b in spans:
                keep &= ~((tt > a) & (tt < b))
        out[name] = {k: (v[keep] if isinstance(v, np.ndarray) and v.shape[:1] == tt.shape else v)
                     for k, v in spec.items()}
    return out


@pytest.fixture(scope='module')
def runs(tmp_path_factory):
    d = tmp_path_factory.mktemp('idgaps')
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', GearConfigWarning)
        truth = load_gear(TRUTH).replace({'simulation': {'seed': SEED}})
    topics, _ = simulate_identification(truth, duration_scale=0.1,
                                        cfg={'n_temperatures': 3, 'n_speeds': 10},
                                        presliding=True)
    holed, holes = punch_holes(topics, SEED)
    t = holed['/joint_states']['t']
    mid = float(t[len(t) // 3])
    out = {'holes': holes, 'dir': d}
    for name, top in (('clean', topics), ('holed', holed),
                      ('long', _cut(holed, [(mid, mid + 0.2)]))):
        out[name] = write_recording(d / name, top)
    out['run_clean'] = identify_recordings([out['clean']], STRUCTURE)
    out['run_holed'] = identify_recordings([out['holed']], STRUCTURE)
    return out


def _curve_diff(a, b, temps):
    fa, fb = StaticFriction(a.friction), StaticFriction(b.friction)
    return max(float(np.max(np.abs(fb.torque(s * V, x) / fa.torque(s * V, x) - 1.0)))
               for x in temps for s in (1.0, -1.0))


def test_identify_bridges_short_gaps(runs):
    a, b = runs['run_clean'], runs['run_holed']
    holes = runs['holes']
    print(f'\n{len(holes)} holes ({holes.min()}..{holes.max()} samples): gaps {b.gaps}')
    assert 60 <= b.gaps['bridged'] <= len(holes)
    assert b.gaps['longest_bridged_samples'] == pytest.approx(holes.max() + 1, abs=0.01)
    assert a.gaps['bridged'] == 0 and b.gaps['split'] == a.gaps['split']
    temps = (float(a.plateaus.xi.min()), float(a.plateaus.xi.mean()), float(a.plateaus.xi.max()))
    diff = _curve_diff(a.gear, b.gear, temps)
    load = b.gear.friction.fc_load[0] / a.gear.friction.fc_load[0] - 1.0
    print(f'plateaus {len(a.plateaus)} / {len(b.plateaus)}; static curve {100 * diff:.3f} %, '
          f'fc_load {100 * load:.2f} %')
    assert diff < 0.005 and abs(load) < 0.02
    assert len(b.plateaus) >= len(a.plateaus) - 2
    assert a.presliding.status == b.presliding.status == 'done'
    tol = {'sigma0': 0.05, 'k_total': 0.10, 'c': 0.10}
    for model, keys in (('lugre', ('sigma0',)), ('gms', ('k_total', 'c'))):
        pa, pb = a.presliding.models[model], b.presliding.models[model]
        assert pa['status'] == pb['status'] == 'done', (pa.get('reason'), pb.get('reason'))
        assert pb['segments_across_gaps_left_out'] > 0 and pa['segments_across_gaps_left_out'] == 0
        for k in keys:
            rel = pb['params'][k] / pa['params'][k] - 1.0
            print(f'{model} {k}: {pa["params"][k]:.5g} clean, {pb["params"][k]:.5g} holed '
                  f'({100 * rel:+.1f} %), {pb["segments"]} segments, '
                  f'{pb["segments_across_gaps_left_out"]} left out')
            assert abs(rel) < tol[k], (model, k)


def test_identify_command_reports_gaps(runs):
    d = runs['dir']
    out = d / 'gear.yaml'
    assert main(['identify', str(runs['holed']), '--model', STRUCTURE, '--out', str(out),
                 '--presliding', 'skip', '--quiet']) == 0
    rep = json.loads((d / 'gear_report' / 'identification.json').read_text())
    assert rep['gaps']['bridged'] == runs['run_holed'].gaps['bridged']
    assert 'bridged' in out.read_text().split('ros__parameters')[0]


def test_long_gap_still_splits(runs):
    run = identify_recordings([runs['long']], STRUCTURE, presliding='skip')
    assert run.gaps['split'] == runs['run_holed'].gaps['split'] + 1
    assert run.gaps['bridged'] == runs['run_holed'].gaps['bridged']
