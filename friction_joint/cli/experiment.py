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
``friction_joint experiment NAME``: the paper's experiments on the simulated test bed.

See :mod:`friction_joint.experiments`.
"""
import os

from ._console import progress_printer
from ..experiments.runner import EXPERIMENTS

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'experiment'
HELP = "the paper's evaluation experiments on the simulated test bed"
DESCRIPTION = ("Run one of the seed paper's evaluation experiments (Section V B-D) on the "
               'simulated test bed (TRUTH gear file) with the identified MODEL gear file, and '
               'write its PNG figures and DIR/summary.json.')


def add_arguments(parser):
    """Add the ``experiment`` arguments to ``parser``."""
    parser.add_argument('name', choices=tuple(EXPERIMENTS), metavar='NAME',
                        help='; '.join(f'{k}: {v.help}' for k, v in EXPERIMENTS.items()))
    parser.add_argument('--model', metavar='M.yaml',
                        help='gear file of the identified model (controller, observer, '
                             'simulation); required by every experiment but identification')
    parser.add_argument('--truth', required=True, metavar='T.yaml',
                        help='gear file of the simulated hardware (plant)')
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output directory (created if missing; an existing non-empty one '
                             'is an error without --force); for identification the recording '
                             'to write (a rosbag2 directory, or a .mcap file)')
    parser.add_argument('--duration-scale', type=float, default=1.0, metavar='X',
                        help='multiply all run durations by X (default 1; small values for '
                             'quick tests)')
    parser.add_argument('--gains', metavar='DESIGN',
                        help='gain design of the controller (compensation, estimation): a '
                             'preset, paper (default: designed for 0.016 kg m^2, see README) or '
                             "full-inertia (the model's joint inertia); J=<kg m^2>; or "
                             'kp=<Nm/rad>,kd=<Nm s/rad>')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing --out as a whole (an --out that is or '
                             'contains --model or --truth is an error even then)')
    return parser


def run(args):
    """Run the experiment and write its results."""
    from ..experiments.runner import run_experiment
    paths = run_experiment(args.name, args.model, args.truth, args.out,
                           duration_scale=args.duration_scale, progress=progress_printer(),
                           force=args.force, gains=args.gains)
    print('wrote ' + ', '.join(os.path.normpath(p) for p in paths))
    return 0
