# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint experiment NAME``: the paper's experiments on the simulated test bed.

See :mod:`friction_joint.experiments`.
"""
import argparse
import os

from ._console import progress_printer
from ..experiments.catalogue import EXPERIMENT_HELP

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'experiment'
HELP = "the paper's evaluation experiments on the simulated test bed"
DESCRIPTION = ("Run one of the seed paper's evaluation experiments (Section V B-D) on the "
               'simulated test bed (TRUTH gear file) with the identified MODEL gear file, and '
               'write its PNG figures and DIR/summary.json.')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``experiment`` arguments to ``parser``."""
    parser.add_argument('name', choices=tuple(EXPERIMENT_HELP) + ('fleet',), metavar='NAME',
                        help='; '.join(f'{k}: {v}' for k, v in EXPERIMENT_HELP.items())
                        + '; fleet: a simulated robot fleet, one recording per joint and day, '
                          'some joints wearing: DIR/manifest.csv, the recordings and '
                          'DIR/truth.json for "friction_joint fleet" (docs/fleet.md)')
    parser.add_argument('--model', metavar='M.yaml',
                        help='gear file of the identified model (controller, observer, '
                             'simulation); required by every experiment but identification')
    parser.add_argument('--truth', metavar='T.yaml',
                        help='gear file of the simulated hardware (plant); required by every '
                             "experiment but fleet (there: the joints' nominal gear, default "
                             'config/csd25.yaml)')
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output directory (created if missing; an existing non-empty one '
                             'is an error without --force); for identification the recording '
                             'to write (a rosbag2 directory, or a .mcap file)')
    parser.add_argument('--duration-scale', type=float, metavar='X',
                        help='multiply all run durations by X (default 1; small values for '
                             'quick tests)')
    parser.add_argument('--gains', metavar='DESIGN',
                        help='gain design of the controller (compensation, estimation): a '
                             'preset, paper (default: designed for 0.016 kg m^2, see '
                             "docs/design.md) or full-inertia (the model's joint inertia); "
                             'J=<kg m^2>; or kp=<Nm/rad>,kd=<Nm s/rad>')
    parser.add_argument('--joints', type=int, metavar='J',
                        help='fleet: number of joints (default 8)')
    parser.add_argument('--days', type=int, metavar='D',
                        help='fleet: days, one recording per joint and day (default 30; '
                             'joints x days at most 20000)')
    parser.add_argument('--seed', type=int, metavar='S',
                        help='fleet: seed of every draw, >= 0 (default 0)')
    parser.add_argument('--quiet', action='store_true', help='no progress messages')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing --out as a whole (an --out that is or '
                             'contains --model or --truth is an error even then)')
    return parser


def run(args: argparse.Namespace) -> int:
    """Run the experiment and write its results."""
    from ..exceptions import ArgumentError
    from ..jobs.experiment import run_experiment
    # an option the experiment does not use is an error, not silently dropped
    fleet_only = {'--joints': args.joints, '--days': args.days, '--seed': args.seed}
    not_fleet = {'--model': args.model, '--duration-scale': args.duration_scale,
                 '--gains': args.gains}
    unused = [k for k, v in (not_fleet if args.name == 'fleet' else fleet_only).items()
              if v is not None]
    if unused:
        raise ArgumentError(f'{", ".join(unused)}: not an option of experiment {args.name} '
                            f'(see friction_joint experiment --help)')
    if args.name == 'fleet':
        from ..jobs.fleet_simulation import run_fleet_simulation
        fleet = run_fleet_simulation(args.out, joints=8 if args.joints is None else args.joints,
                                     days=30 if args.days is None else args.days,
                                     seed=0 if args.seed is None else args.seed,
                                     gear=args.truth, force=args.force,
                                     progress=progress_printer(args.quiet))
        truth = fleet.truth
        wearing = sorted(j for j, d in truth['joints'].items() if d['wear'])
        print(f'wrote {os.path.normpath(fleet.manifest)} ({len(truth["recordings"])} '
              f'recordings of {len(truth["joints"])} joints; the truth, {len(wearing)} '
              f'wearing, in {os.path.normpath(os.path.join(args.out, "truth.json"))})')
        return 0
    if args.truth is None:
        raise ArgumentError(f'experiment {args.name} needs --truth (the simulated hardware)')
    run = run_experiment(args.name, args.model, args.truth, args.out,
                         duration_scale=1.0 if args.duration_scale is None
                         else args.duration_scale,
                         progress=progress_printer(args.quiet), force=args.force,
                         gains=args.gains)
    print('wrote ' + ', '.join(os.path.normpath(p) for p in run.written))
    return 0
