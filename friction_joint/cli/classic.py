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
``friction_joint classic EXPERIMENT --out DIR``: the classic LuGre experiments.

See :mod:`friction_joint.experiments.classic`.
"""
import os

from ..experiments.classic import CLASSIC_EXPERIMENTS

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'classic'
HELP = 'the classic LuGre experiments of Canudas de Wit et al. (1995)'
DESCRIPTION = ('Run one of the four classic LuGre experiments of Canudas de Wit, Olsson, '
               'Astrom & Lischinsky (1995) with their Table I parameters on a unit mass, and '
               'write DIR/EXPERIMENT.png (figure) and DIR/EXPERIMENT.json (key numbers).')


def add_arguments(parser):
    """Add the ``classic`` arguments to ``parser``."""
    parser.add_argument('experiment', choices=tuple(CLASSIC_EXPERIMENTS),
                        help='presliding: force below F_s; lag: frictional lag loops; '
                             'breakaway: break-away force vs force rate; stick-slip: '
                             'spring-pulled mass')
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output directory (created if missing; it may hold other files, '
                             'but an existing EXPERIMENT.png or EXPERIMENT.json is an error '
                             'without --force)')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing EXPERIMENT.png and EXPERIMENT.json')
    return parser


def run(args):
    """Run the experiment and write its figure and numbers."""
    from ..jobs.classic import run_classic
    paths = run_classic(args.experiment, args.out, force=args.force)
    print('wrote ' + ', '.join(os.path.normpath(p) for p in paths))
    return 0
