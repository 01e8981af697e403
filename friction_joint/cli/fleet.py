# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint fleet``: which joints of a fleet wear, since when, how fast.

``friction_joint fleet --manifest FLEET.csv --model GEAR.yaml --out DIR``.

Which joints of a fleet wear, since when, how fast (docs/fleet.md; method:
:mod:`friction_joint.fleet`; the command's work:
:func:`friction_joint.jobs.fleet.run_fleet`).  Writes ``DIR/fleet.json``, ``DIR/recordings.csv``,
``DIR/report.html`` and ``DIR/cache.json`` as one output set; an existing DIR is
an error unless ``--force``, which replaces it and reuses its cached
per-recording results.
"""
import argparse


__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'fleet'
HELP = 'flag wearing joints of a fleet from its recordings (on a Dask cluster)'
DESCRIPTION = ('Identify the static friction curve of every recording of a fleet manifest in '
               "GEAR.yaml's structure, evaluate it at a reference temperature, speed and no "
               'load, and test every joint for wear over time and travel (one Dask task per '
               'recording, an embedded LocalCluster or --scheduler).  Writes DIR/fleet.json, '
               'DIR/recordings.csv and DIR/report.html.')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``fleet`` arguments to ``parser``."""
    parser.add_argument('--manifest', required=True, metavar='FLEET.csv',
                        help='CSV with columns recording (relative to the manifest), joint, '
                             'time (ISO 8601), optional travel (rad); others kept')
    parser.add_argument('--model', required=True, metavar='GEAR.yaml',
                        help='model gear file (structure, temperature and load dependence)')
    parser.add_argument('--out', required=True, metavar='DIR', help='result directory')
    parser.add_argument('--scheduler', default=None, metavar='ADDRESS',
                        help='Dask scheduler, tcp://HOST:PORT, e.g. tcp://HOST:8786 (default: '
                             'an embedded LocalCluster)')
    parser.add_argument('--workers', type=int, default=None, metavar='N',
                        help='worker processes of the embedded cluster (default: the cores; at '
                             'most 4 per core)')
    parser.add_argument('--stall-timeout', type=float, default=None, metavar='S',
                        help='once a recording is done, S seconds without another make the '
                             'cluster stuck: the pending recordings are reported failed '
                             '(default: 20 x the median task time, at least 60 s; 600 s '
                             'before the first)')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing DIR, reusing its cached per-recording results')
    parser.add_argument('--quiet', action='store_true', help='no progress lines')
    return parser


def run(args: argparse.Namespace) -> int:
    """Monitor the fleet; prints the wearing joints."""
    from ._console import progress_printer
    from ..exceptions import ArgumentError
    from ..jobs import run_fleet

    from ..fleet.cluster import check_scheduler, check_workers

    if args.workers is not None and args.scheduler is not None:
        raise ArgumentError('--workers is for the embedded cluster: not with --scheduler')
    if args.scheduler is not None:
        check_scheduler(args.scheduler)
    if args.workers is not None:
        check_workers(args.workers)
    if args.stall_timeout is not None and not args.stall_timeout > 0:
        raise ArgumentError(f'--stall-timeout must be > 0 s, got {args.stall_timeout:g}')
    res = run_fleet(args.manifest, args.model, args.out, scheduler=args.scheduler,
                    workers=args.workers, force=args.force,
                    progress=progress_printer(args.quiet), stall_timeout=args.stall_timeout)
    for joint, d in sorted(res.assessment.joints.items()):
        if d['wear']:
            r = d['rate']
            print(f'{joint}: wear since {d["onset"]}, {r["per_day"]:.3g} +- '
                  f'{r["per_day_se"]:.2g} N m/day (p = {d["evidence"]["p_value"]:.3g})')
    failed = sum(r['status'] != 'ok' for r in res.assessment.recordings)
    flagged = sorted(j for j, d in res.assessment.joints.items() if d['wear'])
    print(f'{len(res.assessment.joints)} joints, {len(flagged)} wearing'
          + (f' ({", ".join(flagged)})' if flagged else '') + '; '
          f'{len(res.assessment.recordings)} recordings ({failed} failed; {res.computed} '
          f'computed, {res.cached} from the cache); wrote {args.out}')
    return 0
