"""``friction_joint experiment NAME``: the paper's experiments on the simulated test bed.

See :mod:`friction_joint.experiments`.
"""
from ..experiments.runner import EXPERIMENTS
from ._console import progress_printer

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
                        help='output directory (created if missing); for identification the '
                             'recording to write (a rosbag2 directory, or a .mcap file)')
    parser.add_argument('--duration-scale', type=float, default=1.0, metavar='X',
                        help='multiply all run durations by X (default 1; small values for '
                             'quick tests)')
    return parser


def run(args):
    """Run the experiment and write its results."""
    from ..experiments.runner import run_experiment
    paths = run_experiment(args.name, args.model, args.truth, args.out,
                           duration_scale=args.duration_scale, progress=progress_printer())
    print('wrote ' + ', '.join(paths))
    return 0
