# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""``friction_joint demo --out DIR``: the main job (see :mod:`friction_joint.jobs.demo`)."""
import argparse
import os

from ._console import progress_printer

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run', 'WRITTEN']

NAME = 'demo'
HELP = 'run the main job and write a report with figures'
DESCRIPTION = ('Bring the ROS 2 nodes up with a recording, run the classic and test-bed '
               'experiments, identify the model from a recorded excitation, and write '
               'DIR/report.md with figures. Progress: a line on stderr as each stage starts '
               'and ends (about 5 minutes in all).')
#: what the last lines name, if the run wrote it: (path in DIR, what it is)
WRITTEN = (('report.html', 'the report with its figures embedded (open it in a browser)'),
           ('bag', "the ROS 2 run's recording (rosbag2, MCAP)"),
           ('identification/identified.yaml', 'the gear file identified from a recording'),
           ('logs', "the node processes' logs"))


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``demo`` arguments to ``parser``."""
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output directory (an existing non-empty one is an error without '
                             '--force)')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing DIR as a whole (built next to it, swapped in '
                             'at the end)')
    parser.add_argument('--model', help='model gear file (default config/csd25.yaml)')
    parser.add_argument('--truth', help='truth gear file (default config/csd25_truth.yaml)')
    parser.add_argument('--duration-scale', type=float, default=1.0,
                        help='shorten experiments (e.g. 0.2)')
    parser.add_argument('--quiet', action='store_true', help='no progress messages')
    return parser


def run(args: argparse.Namespace) -> int:
    """Run the demo; prints the report's path and the other things written."""
    from ..jobs.demo import run_demo
    run = run_demo(args.out, model=args.model, truth=args.truth,
                   duration_scale=args.duration_scale, force=args.force,
                   progress=progress_printer(args.quiet))
    path = run.report
    print(f'report: {os.path.normpath(path)}')
    out = os.path.dirname(os.path.normpath(path))
    for name, what in WRITTEN:
        if os.path.exists(os.path.join(out, name)):
            print(f'        {os.path.join(out, name)}: {what}')
    return 0
