# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Fleet monitoring: wear flagged, false alarms, onsets, against a naive monitor; throughput.

    .venv/bin/python benchmarks/bench_fleet.py                  # 50 fleets, 6 joints x 12 days
    .venv/bin/python benchmarks/bench_fleet.py --fleets 5 --throughput 100     # quick look

What it does
------------
1. Draws ``--fleets`` fleets (:func:`friction_joint.jobs.fleet_simulation.run_fleet_simulation`,
   seeds ``--seed`` + k): which joints wear, their onsets and rates, and the
   nuisances (ambient with a seasonal drift, duty, payload) are drawn per fleet.
   Every fleet is simulated on a 2-worker LocalCluster and monitored with
   :func:`friction_joint.jobs.run_fleet` (the manifest and the model gear file
   only); the truth file is read afterwards to score:

   * wearing joints flagged (target >= 95 %),
   * false alarms: non-wearing joints flagged (target <= 2 %),
   * onset within 2 days of the truth, of the wearing joints flagged;

   and the same for the **naive monitor** (the same hinge test on the raw mean
   friction of the plateaus: no temperature or load compensation), the baseline
   printed beside it on the same fleets.
2. Throughput: the per-recording task on ``--throughput`` recordings of these
   fleets, on a LocalCluster with 1 worker (the baseline) and with 2 workers,
   timed from submission to the last result (clusters started and warmed up
   before); prints recordings/s and the ratio (target >= 1.7x on 2 cores), and
   what 10 000 recordings a day need.

The last line is always

    fleets=<n> flagged=<a> false_alarms=<b> onset_2d=<c> naive_flagged=<d> naive_false=<e>
    rate_1w=<r1> rate_2w=<r2> speedup=<s>
"""
import argparse
import json
import os
import shutil
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from friction_joint.fleet import (local_cluster, map_recordings, read_manifest,  # noqa: E402
                                  recording_task)
from friction_joint.jobs import run_fleet  # noqa: E402
from friction_joint.jobs.fleet_simulation import run_fleet_simulation  # noqa: E402

MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
DAY = 86400.0


def _score(truth, doc, entries):
    """Per joint: (wears, flagged, onset error days or None, naive flagged, naive error)."""
    start = {}
    for e in entries:
        start[e.joint] = min(start.get(e.joint, e.time), e.time)
    rows = []
    import datetime
    for jid, t in truth['joints'].items():
        got = doc['joints'][jid]
        err = None
        true_onset = datetime.datetime.fromisoformat(t['onset']) if t['wear'] else None
        if got['wear'] and t['wear']:
            err = abs((datetime.datetime.fromisoformat(got['onset']) - true_onset)
                      .total_seconds()) / DAY
        naive = got['evidence'].get('raw_mean_friction') or {'wear': False}
        nerr = None
        if naive['wear'] and t['wear']:
            onset = start[jid] + datetime.timedelta(days=naive['onset_day'])
            nerr = abs((onset - true_onset).total_seconds()) / DAY
        rows.append((t['wear'], got['wear'], err, naive['wear'], nerr))
    return rows


def _rates(rows, k_flag, k_err):
    wear = [r for r in rows if r[0]]
    clean = [r for r in rows if not r[0]]
    hit = [r for r in wear if r[k_flag]]
    return (len(hit) / max(len(wear), 1), sum(r[k_flag] for r in clean) / max(len(clean), 1),
            sum(r[k_err] is not None and r[k_err] <= 2.0 for r in hit) / max(len(hit), 1),
            len(wear), len(clean))


def _throughput(paths, workers, gear_text):
    with local_cluster(workers=workers) as (address, _):
        map_recordings(recording_task, paths[:2 * workers], args=(gear_text,),
                       scheduler=address)                                 # warm-up
        t0 = time.perf_counter()
        run = map_recordings(recording_task, paths, args=(gear_text,), scheduler=address)
        dt = time.perf_counter() - t0
    task = sum(r.get('time_s', 0.0) for r in run['results']) / len(paths)
    return len(paths) / dt, task


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument('--fleets', type=int, default=50)
    ap.add_argument('--joints', type=int, default=6)
    ap.add_argument('--days', type=int, default=12)
    ap.add_argument('--seed', type=int, default=1000)
    ap.add_argument('--throughput', type=int, default=400, metavar='N',
                    help='recordings for the throughput runs')
    args = ap.parse_args(argv)
    with open(MODEL, encoding='utf-8') as fh:
        gear_text = fh.read()
    rows, keep, t_sim, t_mon = [], [], 0.0, 0.0
    with tempfile.TemporaryDirectory(prefix='bench_fleet.') as tmp:
        with local_cluster(workers=2) as (address, executor):
            for k in range(args.fleets):
                sim = os.path.join(tmp, f'fleet{k}')
                t0 = time.perf_counter()
                simulated = run_fleet_simulation(sim, joints=args.joints, days=args.days,
                                                 seed=args.seed + k, executor=executor)
                truth = dict(simulated.truth, manifest=simulated.manifest)
                t1 = time.perf_counter()
                out = os.path.join(tmp, f'out{k}')
                run_fleet(truth['manifest'], MODEL, out, scheduler=address, seed=k)
                t2 = time.perf_counter()
                t_sim += t1 - t0
                t_mon += t2 - t1
                with open(os.path.join(out, 'fleet.json'), encoding='utf-8') as fh:
                    doc = json.load(fh)
                entries = read_manifest(truth['manifest'])
                got = _score(truth, doc, entries)
                rows += got
                wear = ''.join('W' if r[0] else '.' for r in got)
                flag = ''.join('F' if r[1] else '.' for r in got)
                naive = ''.join('F' if r[3] else '.' for r in got)
                print(f'fleet {k:2d}: truth {wear}  flagged {flag}  naive {naive}  onset err '
                      + ' '.join(f'{r[2]:.2f}' for r in got if r[2] is not None)
                      + f'  (sim {t1 - t0:.1f} s, monitor {t2 - t1:.1f} s)', flush=True)
                if len(keep) < args.throughput:
                    keep += [e.path for e in entries]
                else:
                    shutil.rmtree(sim)
                shutil.rmtree(out)
        flagged, false, onset, nw, nc = _rates(rows, 1, 2)
        n_flagged, n_false, n_onset, _, _ = _rates(rows, 3, 4)
        print(f'\n{args.fleets} fleets of {args.joints} joints x {args.days} days: {nw} wearing, '
              f'{nc} not; simulated in {t_sim:.0f} s, monitored in {t_mon:.0f} s')
        print(f'{"":28s}{"flagged":>10s}{"false alarms":>14s}{"onset <= 2 d":>14s}')
        print(f'{"reference friction":28s}{100 * flagged:9.1f}%{100 * false:13.1f}%'
              f'{100 * onset:13.1f}%   (targets >= 95 %, <= 2 %)')
        print(f'{"naive raw mean (baseline)":28s}{100 * n_flagged:9.1f}%{100 * n_false:13.1f}%'
              f'{100 * n_onset:13.1f}%')
        paths = keep[:args.throughput]
        rate1, task1 = _throughput(paths, 1, gear_text)
        rate2, task2 = _throughput(paths, 2, gear_text)
    speedup = rate2 / rate1
    print(f'\nthroughput on {len(paths)} recordings: 1 worker {rate1:.1f} recordings/s '
          f'(baseline), 2 workers {rate2:.1f} recordings/s: x{speedup:.2f} (target >= 1.7); '
          f'task time {1e3 * task1:.0f} ms (1 worker), {1e3 * task2:.0f} ms (2 workers)')
    per_day = 10000.0
    core_s = per_day / rate1
    print(f'10 000 recordings a day: {core_s / 60:.0f} worker-minutes at the 1-worker rate, '
          f'i.e. {core_s / DAY * 100:.1f} % of one core over 24 h; on 2 workers '
          f'{per_day / rate2 / 60:.0f} min.  Hashing for the cache reads each recording once '
          f'more on the client; the report grows by one figure per joint.')
    print(f'fleets={args.fleets} flagged={flagged:.3f} false_alarms={false:.3f} '
          f'onset_2d={onset:.3f} naive_flagged={n_flagged:.3f} naive_false={n_false:.3f} '
          f'rate_1w={rate1:.2f} rate_2w={rate2:.2f} speedup={speedup:.2f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
