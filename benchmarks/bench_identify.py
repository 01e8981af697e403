#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Wall time of the identification of a 10-minute, 1 kHz recording.

    .venv/bin/python benchmarks/bench_identify.py              # 10 min recording
    .venv/bin/python benchmarks/bench_identify.py --minutes 3   # shorter
    .venv/bin/python benchmarks/bench_identify.py --regenerate  # simulate it again

What it does
------------
1. Generates once (cached in the temp directory, keyed by the length asked
   for) the identification experiment of ``friction_joint experiment
   identification`` on ``config/csd25_truth.yaml`` with the duration scale
   that makes it last the requested minutes: plateaus at four temperatures
   with the lever at four angles, plus pre-sliding sinusoids; /joint_states,
   /link_torque and /joint_command at 1 kHz.
2. Times, with the structure ``config/csd25.yaml``:
   * reading the recording and finding the plateaus,
   * steps 1-2 (static curve: temperature and load coefficients, standard
     errors, per-temperature fits),
   * step 3 (LuGre and GMS pre-sliding pattern search), if
     :mod:`friction_joint.identification.presliding` is available,
   * the report figures.
3. Prints the numbers and the accuracy against the truth.

Targets: steps 1-2 (with reading the recording) <= 30 s; everything
including step 3 <= 120 s.  The last line is always

    read_s=<a> steps12_s=<b> step3_s=<c> total_s=<d> curve_error_pct=<e>
"""
import argparse
import os
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from friction_joint.bag import write_recording  # noqa: E402
from friction_joint.experiments.excitation import (  # noqa: E402
    EXCITATION, plan_block, simulate_identification)
from friction_joint.gear import load_gear  # noqa: E402
from friction_joint.identification.pipeline import identify_recordings  # noqa: E402
from friction_joint.models.static import StaticFriction  # noqa: E402
import numpy as np  # noqa: E402

TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')
STRUCTURE = os.path.join(ROOT, 'config', 'csd25.yaml')


def planned_duration(truth, scale):
    dt = 1.0 / truth.section('simulation')['rate']
    n = EXCITATION['n_temperatures']
    return sum(plan_block(b, truth.gear_ratio, dt, scale).t_end for b in range(n)) \
        + (n - 1) * EXCITATION['gap']


def scale_for(truth, seconds):
    """Duration scale whose plan lasts about ``seconds`` (bisection on the plan)."""
    lo, hi = 0.05, 1.0
    while planned_duration(truth, hi) < seconds:
        hi *= 2.0
    for _ in range(25):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if planned_duration(truth, mid) < seconds else (lo, mid)
    return hi


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().split('\n')[0])
    ap.add_argument('--minutes', type=float, default=10.0)
    ap.add_argument('--regenerate', action='store_true')
    ap.add_argument('--no-report', action='store_true', help='skip timing the figures')
    args = ap.parse_args()
    truth = load_gear(TRUTH)
    bag = os.path.join(tempfile.gettempdir(), f'friction_joint_bench_identify_{args.minutes:g}min')
    if args.regenerate and os.path.exists(bag):
        import shutil
        shutil.rmtree(bag)
    if not os.path.exists(bag):
        scale = scale_for(truth, 60.0 * args.minutes)
        print(f'generating {args.minutes:g} min recording (duration scale {scale:.3f}) into {bag}',
              flush=True)
        t0 = time.perf_counter()
        topics, summary = simulate_identification(truth, duration_scale=scale,
                                                  progress=lambda m: print('  ' + m, flush=True))
        write_recording(bag, topics)
        print(f'  {summary["duration_s"]:.1f} s simulated, {summary["samples"]} joint states, '
              f'{time.perf_counter() - t0:.1f} s', flush=True)
    else:
        print(f'using the cached recording {bag} (--regenerate to simulate it again)')

    def progress(msg):
        print(f'  [{time.perf_counter() - start:7.2f} s] {msg}', flush=True)

    start = time.perf_counter()
    run = identify_recordings([bag], STRUCTURE, presliding='auto', progress=progress)
    total = time.perf_counter() - start
    tm = run.timings
    read_s = tm['time_read_and_plateaus_s']
    steps12 = tm['time_steps_1_2_s']
    step3 = tm['time_step_3_s']
    fig_s = float('nan')
    if not args.no_report:
        from friction_joint.output import render_png
        from friction_joint.identification.report import identification_figures
        t0 = time.perf_counter()
        for draw, size in identification_figures(run.identifier, run.recordings).values():
            render_png(draw, size)
        fig_s = time.perf_counter() - t0

    rec = run.recordings[0]
    p = run.plateaus
    v = np.geomspace(0.01, 3.5, 300)
    temps = (p.xi.min(), 0.5 * (p.xi.min() + p.xi.max()), p.xi.max())
    got, want = StaticFriction(run.gear.friction), StaticFriction(truth.friction)
    err = max(float(np.max(np.abs(got.torque(s * v, x) / want.torque(s * v, x) - 1.0)))
              for x in temps for s in (1.0, -1.0))
    load_err = abs(run.gear.friction.fc_load[0] / truth.friction.fc_load[0] - 1.0)
    print()
    print(f'recording: {rec.duration:.1f} s, {len(rec.joint_states)} joint states at '
          f'{(len(rec.joint_states) - 1) / rec.duration:.0f} Hz, {len(p)} plateaus')
    print(f'read + plateau detection : {read_s:7.2f} s')
    print(f'steps 1-2 (static curve) : {steps12:7.2f} s   '
          f'(read + steps 1-2 = {read_s + steps12:.2f} s, target <= 30 s)')
    s3 = run.presliding
    if s3['status'] == 'done':
        per = ', '.join(f'{m} {r["time_s"]:.1f} s' for m, r in s3['models'].items())
        print(f'step 3 (pre-sliding)     : {step3:7.2f} s   ({per})')
    else:
        print(f'step 3 (pre-sliding)     : {s3["status"]} ({s3["reason"]})')
    print(f'identification total     : {total:7.2f} s   (target <= 120 s)')
    print(f'report figures           : {fig_s:7.2f} s')
    print(f'accuracy vs truth        : static curve {100 * err:.2f} %, fc_load '
          f'{100 * load_err:.2f} %, RMS residual {run.identifier.rms:.4f} Nm')
    if s3['status'] == 'done':
        for m, r in s3['models'].items():
            if r['status'] == 'rejected':
                print(f'  step 3 {m}: rejected: {r["reason"]}')
                continue
            print(f'  step 3 {m}: '
                  + ', '.join(f'{k} = {val:.4g}' for k, val in r['params'].items())
                  + f', RMS {r["report"]["objective_final"]:.4f} Nm (undetermined: '
                  + f'{", ".join(r["kept_from_structure"]) or "none"})')
    print(f'read_s={read_s:.2f} steps12_s={steps12:.2f} step3_s={step3:.2f} total_s={total:.2f} '
          f'curve_error_pct={100 * err:.2f}')


if __name__ == '__main__':
    main()
