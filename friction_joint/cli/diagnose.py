# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint diagnose``: what a model gets wrong on recordings, and the extension to fix it.

``friction_joint diagnose RECORDING ... --model BASE.yaml --out DIR``.

Outputs: docs/interfaces.md, ``diagnose`` outputs.

Fits BASE's structure to the recordings, names the missing effects and writes
``DIR/report.json``, ``DIR/extended.yaml``, ``DIR/report.md`` (and ``DIR/report.html``,
the same with the figures embedded) and figures
(method: :mod:`friction_joint.diagnosis`).  Everything is computed and rendered
first, then DIR is written as a whole (built next to it and renamed into
place); an existing non-empty DIR is an error unless ``--force``, which
replaces it as a whole; on an error nothing is written and the command exits
with status 2.
"""
import argparse
import os

from ._console import progress_printer
from ..effects import EFFECTS
from ..exceptions import ArgumentError

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run', 'parse_effects']

NAME = 'diagnose'
HELP = 'name the effects a friction model misses, extend it'
DESCRIPTION = ("Fit BASE.yaml's structure to recordings, test every candidate effect ("
               + ', '.join(EFFECTS) + ') on held-out data, name the significant ones and '
               'write DIR/report.json, DIR/extended.yaml, DIR/report.md with figures and '
               'DIR/report.html (the report as one page, open it in a browser).')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``diagnose`` arguments to ``parser``."""
    parser.add_argument('recordings', nargs='+', metavar='RECORDING',
                        help='rosbag2 directories or .mcap files')
    parser.add_argument('--model', required=True, metavar='BASE.yaml', help='base gear file')
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='result directory (an existing non-empty one is an error without '
                             '--force)')
    parser.add_argument('--effects', default=None, metavar='E1,E2,...',
                        help='candidate effects to test (default: all)')
    parser.add_argument('--joint', default=None, metavar='NAME',
                        help="joint to read (default: the gear's joint_name)")
    parser.add_argument('--velocity-from-position', action='store_true',
                        help="use the position's centred difference instead of the recorded "
                             'velocity (one that disagrees with the position: other units, the '
                             'opposite sign); recorded in the report')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing DIR as a whole (no file of an earlier run '
                             'remains)')
    parser.add_argument('--quiet', action='store_true', help='no progress messages')
    return parser


def parse_effects(text: str | None) -> tuple[str, ...]:
    """``--effects`` text -> tuple of effect names (default: all)."""
    if text is None:
        return EFFECTS
    effs = tuple(e.strip() for e in text.split(',') if e.strip())
    bad = [e for e in effs if e not in EFFECTS]
    if bad or not effs:
        raise ArgumentError(f'--effects: unknown effect(s) {", ".join(bad) or "(none given)"}; '
                            f'known: {", ".join(EFFECTS)}')
    return effs


def run(args: argparse.Namespace) -> int:
    """Diagnose and write the result directory; prints the named causes."""
    from ..jobs.diagnose import current_sources, run_diagnose
    for src in current_sources(args.recordings):     # recorded by import (--current)
        print(f'torque: {src["recording"]}: {src["text"]}')
    if args.velocity_from_position:
        print("velocity: the position's centred difference replaces the recorded velocity "
              '(--velocity-from-position)')
    run_ = run_diagnose(args.recordings, args.model, args.out,
                        effects=parse_effects(args.effects), joint_name=args.joint,
                        progress=progress_printer(args.quiet), force=args.force,
                        velocity_from_position=args.velocity_from_position)
    named = run_.named_causes
    out = os.path.normpath(args.out)                 # DIR/ or DIR// named as DIR
    files = ('report.json', 'extended.yaml', 'report.md', 'report.html')
    print(f'named causes: {", ".join(named) or "none"}; wrote '
          + ', '.join(os.path.join(out, f) for f in files))
    return 0
