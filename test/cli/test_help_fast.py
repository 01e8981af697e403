# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``--help`` is fast: building the command line loads none of the heavy libraries.

Every ``--help`` took 3.4-5.5 s (15 s on a loaded machine) because the parser
imported the simulators (scipy.signal alone is 2.4 s) for the names of the
experiments.  What is measured here is what makes it slow, not a time: the
modules imported by building the parser and by each command's ``--help``.
"""
import subprocess
import sys

from friction_joint.cli import SUBCOMMANDS
from friction_joint.experiments.catalogue import CLASSIC_HELP, EXPERIMENT_HELP
import pytest

HEAVY = ('scipy', 'numba', 'matplotlib', 'rclpy', 'dask', 'distributed', 'mcap', 'rosbags',
         'friction_joint.testbed', 'friction_joint.identification', 'friction_joint.diagnosis')

PROBE = """
import contextlib, io, sys
from friction_joint.cli import main
with contextlib.redirect_stdout(io.StringIO()):
    try:
        main({argv!r})
    except SystemExit:
        pass
heavy = sorted({{m for m in sys.modules for h in {heavy!r}
                if m == h or m.startswith(h + '.')}})
print(' '.join(heavy))
"""


def _command_names():
    from friction_joint.cli import build_parser
    actions = [a for a in build_parser()._actions if getattr(a, 'choices', None)]
    return sorted(actions[0].choices)


@pytest.mark.parametrize('argv', [['--help']] + [[name, '--help'] for name in _command_names()],
                         ids=lambda argv: ' '.join(argv))
def test_help_loads_no_heavy_module(argv):
    """The parser and every command's help come from light modules only."""
    done = subprocess.run([sys.executable, '-c', PROBE.format(argv=argv, heavy=HEAVY)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [], done.stdout


def test_the_catalogue_names_every_experiment():
    """The light catalogue and the experiments it describes have the same names."""
    from friction_joint.experiments.classic import CLASSIC_EXPERIMENTS
    from friction_joint.experiments.runner import EXPERIMENTS
    assert list(EXPERIMENTS) == list(EXPERIMENT_HELP)
    assert list(CLASSIC_EXPERIMENTS) == list(CLASSIC_HELP)
    assert len(SUBCOMMANDS) == len(_command_names())
