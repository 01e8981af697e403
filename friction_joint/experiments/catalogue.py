# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The experiments' names and one-line descriptions, without the experiments.

The command line lists them (``--help``, argument choices) without loading the
simulators; :data:`~friction_joint.experiments.runner.EXPERIMENTS` and
:data:`~friction_joint.experiments.classic.CLASSIC_EXPERIMENTS` are built on them.
"""
from typing import cast

from ..paper import PAPER

__all__ = ['EXPERIMENT_HELP', 'CLASSIC_HELP']

#: the paper's experiments on the test bed: command-line name -> what it runs
EXPERIMENT_HELP = {
    'chirp': 'open-loop chirp torques, measured vs LuGre/GMS simulation (Fig. 5)',
    'compensation': 'sine tracking with friction feed-forward none/LuGre/GMS at 27, 31 and '
                    '35 degC reached by self-heating (Fig. 6-7)',
    'estimation': 'external torque estimation with the disturbance observer, with and '
                  'without friction model (Fig. 8)',
    'gain_sweep': 'maximum tracking error without and with LuGre feed-forward against the '
                  "gains' design inertia: where the paper's {:g}-{:g} % regime lies".format(
                      *cast('tuple[float, float]', PAPER['uncompensated_band'].value)),
    'identification': 'constant-velocity plateaus at several temperatures and loads plus '
                      'pre-sliding sinusoids, written as a recording (--out BAG) for '
                      '"friction_joint identify" (Section V-A)',
}

#: the classic LuGre experiments: command-line name -> what it shows
CLASSIC_HELP = {
    'presliding': 'force below F_s',
    'lag': 'frictional lag loops',
    'breakaway': 'break-away force vs force rate',
    'stick-slip': 'spring-pulled mass',
}
