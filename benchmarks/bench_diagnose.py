#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Wall time of ``friction_joint diagnose`` on a 90 s, 1 kHz recording, end to end.

    .venv/bin/python benchmarks/bench_diagnose.py                    # thermal hidden, 90 s
    .venv/bin/python benchmarks/bench_diagnose.py --effect position_ripple --seconds 60
    .venv/bin/python benchmarks/bench_diagnose.py --effect none

What it does
------------
1. Simulates (:func:`friction_joint.experiments.hidden.simulate_recording`) a 90 s
   measured-style recording of ``config/csd25_base.yaml`` plus one hidden effect
   of mid-range size (default ``thermal``) into a temporary directory: three
   temperature segments, /joint_states, /link_torque and /joint_command at
   1 kHz, /joint_temperature at 4 Hz.  Not timed (printed separately).
2. Runs ``python -m friction_joint diagnose REC --model config/csd25_base.yaml
   --out DIR`` as a subprocess and times it (wall time, including the Python
   start-up and imports).
3. Prints the named causes and the per-stage times of ``report.json``
   (``timing``, if the report has it).

Target: <= 10 s for the command (<= 30 s at worst).  The last line is always

    generate_s=<a> diagnose_s=<b> named=<causes>
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import friction_joint  # noqa: E402
from friction_joint.experiments.hidden import (  # noqa: E402
    apply_effect, HIDEABLE, RecordingOptions, simulate_recording)

BASE = os.path.join(ROOT, 'config', 'csd25_base.yaml')


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument('--effect', default='thermal', choices=list(HIDEABLE) + ['none'])
    ap.add_argument('--seconds', type=float, default=90.0)
    ap.add_argument('--seed', type=int, default=5)
    args = ap.parse_args(argv)

    base = friction_joint.load_gear(BASE)
    truth = base if args.effect == 'none' else apply_effect(base, args.effect)
    with tempfile.TemporaryDirectory(prefix='bench_diagnose.') as tmp:
        rec = os.path.join(tmp, 'rec')
        t0 = time.perf_counter()
        _, summary = simulate_recording(truth, rec, options=RecordingOptions(
            duration=args.seconds, seed=args.seed, base_gear=base))
        gen = time.perf_counter() - t0
        print(f'recording: {summary["duration_s"]:.1f} s, {summary["samples"]} samples at 1 kHz, '
              f'segments at {", ".join(f"{x:.1f}" for x in summary["temperatures"])} degC, '
              f'hidden {args.effect}; generated in {gen:.1f} s')
        out = os.path.join(tmp, 'out')
        cmd = [sys.executable, '-m', 'friction_joint', 'diagnose', rec, '--model', BASE,
               '--out', out]
        t0 = time.perf_counter()
        res = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
        wall = time.perf_counter() - t0
        if res.returncode != 0:
            print(res.stdout)
            print(res.stderr, file=sys.stderr)
            print(f'diagnose failed with exit status {res.returncode}')
            return 1
        with open(os.path.join(out, 'report.json'), encoding='utf-8') as fh:
            report = json.load(fh)
    print(f'diagnose wall time: {wall:.2f} s (target <= 10 s, <= 30 s at worst)')
    timing = report.get('timing')
    if isinstance(timing, dict):
        print('per-stage times from report.json:')
        for k, v in timing.items():
            print(f'  {k:<28} {v:.3f} s' if isinstance(v, (int, float)) else f'  {k:<28} {v}')
    else:
        print('report.json has no timing section')
    for c in report.get('candidates', []):
        print(f'  candidate {c.get("effect"):<18} gain {c.get("gain", float("nan")):.3f} '
              f'significant {c.get("significant")}')
    print(f'baseline {report.get("baseline")}  extended {report.get("extended")}')
    named = ','.join(report.get('named_causes', [])) or 'none'
    print(f'generate_s={gen:.2f} diagnose_s={wall:.2f} named={named}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
