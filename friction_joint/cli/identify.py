# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint identify``: recordings -> an identified gear file (seed Section V-A).

``friction_joint identify RECORDING ... --model STRUCTURE.yaml --out GEAR.yaml``.

See :mod:`friction_joint.identification`.
"""
import argparse
import os
import re

from ._console import progress_printer
from ..exceptions import GearConfigError
from ..gear.schema import MAX_POLYNOMIAL_ORDER

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'ORDER_NAMES', 'add_arguments', 'run', 'parse_orders']

#: polynomials whose order ``--orders`` sets (temperature, then load)
ORDER_NAMES = ('fc', 'fv', 'fs', 'vs', 'delta_v', 'fc_load', 'fv_load', 'fs_load', 'vs_load',
               'delta_v_load')

NAME = 'identify'
HELP = 'identify the friction model from recordings (seed Section V-A)'
DESCRIPTION = ('Identify the temperature- and load-dependent static friction model (steps '
               '1-2: least squares over constant-velocity plateaus) and the LuGre/GMS '
               'pre-sliding parameters (step 3) from recordings, in the structure of '
               'STRUCTURE.yaml; write GEAR.yaml and a report with figures.')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``identify`` arguments to ``parser``."""
    parser.add_argument('recordings', nargs='+', metavar='RECORDING',
                        help='rosbag2 directories or .mcap files')
    parser.add_argument('--model', required=True, metavar='STRUCTURE.yaml',
                        help='gear file giving the model structure (list length = polynomial '
                             'order + 1), inertia and lever; its coefficient values are not used')
    parser.add_argument('--out', required=True, metavar='GEAR.yaml',
                        help='identified gear file to write (with its report directory: an '
                             'existing one is an error without --force)')
    parser.add_argument('--orders', default=None, metavar='auto|NAME=N,...',
                        help='polynomial orders: the structure\'s (default), "auto" (chosen by '
                             'held-out error) or e.g. "fc=2,fv=1,fc_load=1" (orders, not list '
                             'lengths: fc=2 gives fc: [c0, c1, c2])')
    parser.add_argument('--report', default=None, metavar='DIR',
                        help='report directory (default: GEAR_report next to GEAR.yaml)')
    parser.add_argument('--presliding', choices=('auto', 'skip', 'require'), default='auto',
                        help='step 3: run when possible and note why not (auto), never (skip), '
                             'or fail without it (require)')
    parser.add_argument('--joint', default=None, metavar='NAME',
                        help="joint to identify (default: the structure's joint_name; a "
                             'recording without it is an error); the gear file is named for it')
    parser.add_argument('--velocity-from-position', action='store_true',
                        help="use the position's centred difference instead of the recorded "
                             'velocity (one that disagrees with the position: other units, the '
                             'opposite sign); recorded in the report')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing GEAR.yaml and report directory (as a whole; '
                             '--out or --report equal to an input is an error even then)')
    parser.add_argument('--quiet', action='store_true', help='no progress messages')
    return parser


def parse_orders(text: str | None) -> str | dict[str, int] | None:
    """``--orders`` text -> None (the structure's), ``'auto'`` or ``{name: order}``."""
    if text is None or text == 'structure':
        return None
    if text == 'auto':
        return 'auto'
    out: dict[str, int] = {}
    for item in text.split(','):
        key, _, val = item.partition('=')
        key = key.strip()
        try:
            if not re.fullmatch(r'\s*[+-]?[0-9]+\s*', val):    # int() reads other scripts' digits
                raise ValueError(val)
            order = int(val)
        except ValueError:
            raise GearConfigError(f'--orders: expected auto, structure or NAME=ORDER,... '
                                  f'(e.g. fc=2,fv=2,fc_load=1), got {text!r}') from None
        if key not in ORDER_NAMES:
            raise GearConfigError(f'--orders: unknown polynomial {key!r} in {text!r}; known: '
                                  f'{", ".join(ORDER_NAMES)}')
        if not 0 <= order <= MAX_POLYNOMIAL_ORDER:
            raise GearConfigError(f'--orders: {key}={order}: an order is an integer from 0 to '
                                  f'{MAX_POLYNOMIAL_ORDER}')
        if key in out:
            raise GearConfigError(f'--orders: {key} given twice in {text!r} ({key}={out[key]} '
                                  f'and {key}={order}); give each polynomial once')
        out[key] = order
    return out


def run(args: argparse.Namespace) -> int:
    """Identify and write the gear file and its report."""
    from ..jobs.diagnose import current_sources
    from ..jobs.identify import run_identify
    for src in current_sources(args.recordings):     # recorded by import (--current)
        print(f'torque: {src["recording"]}: {src["text"]}')
    if args.velocity_from_position:
        print("velocity: the position's centred difference replaces the recorded velocity "
              '(--velocity-from-position)')
    run = run_identify(args.recordings, args.model, args.out, orders=parse_orders(args.orders),
                       report_dir=args.report, presliding=args.presliding,
                       joint_name=args.joint, progress=progress_printer(args.quiet),
                       force=args.force, velocity_from_position=args.velocity_from_position)
    print('wrote ' + ', '.join(os.path.normpath(p) for p in run.written))
    return 0
