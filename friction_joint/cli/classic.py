# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint classic EXPERIMENT --out DIR``: the classic LuGre experiments.

See :mod:`friction_joint.experiments.classic`.
"""
import argparse
import os

from ..experiments.catalogue import CLASSIC_HELP

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'classic'
HELP = 'the classic LuGre experiments of Canudas de Wit et al. (1995)'
DESCRIPTION = ('Run one of the four classic LuGre experiments of Canudas de Wit, Olsson, '
               'Astrom & Lischinsky (1995) with their Table I parameters on a unit mass, and '
               'write DIR/EXPERIMENT.png (figure) and DIR/EXPERIMENT.json (key numbers).')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``classic`` arguments to ``parser``."""
    parser.add_argument('experiment', choices=tuple(CLASSIC_HELP),
                        help='; '.join(f'{k}: {v}' for k, v in CLASSIC_HELP.items()))
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output directory (created if missing; it may hold other files, '
                             'but an existing EXPERIMENT.png or EXPERIMENT.json is an error '
                             'without --force)')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing EXPERIMENT.png and EXPERIMENT.json')
    return parser


def run(args: argparse.Namespace) -> int:
    """Run the experiment and write its figure and numbers."""
    from ..jobs.classic import run_classic
    run = run_classic(args.experiment, args.out, force=args.force)
    print('wrote ' + ', '.join(os.path.normpath(p) for p in run.written))
    return 0
