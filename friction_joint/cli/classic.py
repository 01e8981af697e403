"""``friction_joint classic EXPERIMENT --out DIR``: the classic LuGre experiments.

See :mod:`friction_joint.experiments.classic`.
"""
from ..experiments.classic import EXPERIMENTS

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'classic'
HELP = 'the classic LuGre experiments of Canudas de Wit et al. (1995)'
DESCRIPTION = ('Run one of the four classic LuGre experiments of Canudas de Wit, Olsson, '
               'Astrom & Lischinsky (1995) with their Table I parameters on a unit mass, and '
               'write DIR/EXPERIMENT.png (figure) and DIR/EXPERIMENT.json (key numbers).')


def add_arguments(parser):
    """Add the ``classic`` arguments to ``parser``."""
    parser.add_argument('experiment', choices=tuple(EXPERIMENTS),
                        help='presliding: force below F_s; lag: frictional lag loops; '
                             'breakaway: break-away force vs force rate; stick-slip: '
                             'spring-pulled mass')
    parser.add_argument('--out', required=True, metavar='DIR',
                        help='output directory (created if missing)')
    return parser


def run(args):
    """Run the experiment and write its figure and numbers."""
    from ..experiments.classic_report import write_experiment
    result = EXPERIMENTS[args.experiment]()
    paths = write_experiment(args.experiment, result, args.out)
    print('wrote ' + ', '.join(paths))
    return 0
