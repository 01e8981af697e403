# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
``friction_joint identify RECORDING ... --model STRUCTURE.yaml --out GEAR.yaml``.

See :mod:`friction_joint.identification`.
"""
import os

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


def add_arguments(parser):
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
    parser.add_argument('--force', action='store_true',
                        help='replace an existing GEAR.yaml and report directory (as a whole; '
                             '--out or --report equal to an input is an error even then)')
    parser.add_argument('--quiet', action='store_true', help='no progress messages')
    return parser


def parse_orders(text):
    """``--orders`` text -> None (the structure's), ``'auto'`` or ``{name: order}``."""
    if text is None or text == 'structure':
        return None
    if text == 'auto':
        return 'auto'
    out = {}
    for item in text.split(','):
        key, _, val = item.partition('=')
        key = key.strip()
        try:
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
        out[key] = order
    return out


def run(args):
    """Identify and write the gear file and its report."""
    from ..jobs.identify import run_identify
    paths = run_identify(args.recordings, args.model, args.out, orders=parse_orders(args.orders),
                         report_dir=args.report, presliding=args.presliding,
                         joint_name=args.joint, progress=progress_printer(args.quiet),
                         force=args.force)
    print('wrote ' + ', '.join(os.path.normpath(p) for p in paths))
    return 0
