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
Experiments on the simulated test bed and in the literature.

* the paper's applications: :mod:`~friction_joint.experiments.chirp` (Fig. 5),
  :mod:`~friction_joint.experiments.compensation` (Fig. 6-7),
  :mod:`~friction_joint.experiments.estimation` (Fig. 8), run by name through
  :mod:`~friction_joint.experiments.runner`; each returns an
  :class:`~friction_joint.experiments._common.ExperimentData` whose figures
  :mod:`~friction_joint.experiments.plots` draws, beside the paper's own
  numbers of :data:`~friction_joint.paper.PAPER` (also read by the
  report text, :mod:`~friction_joint.experiments.testbed_report`);
* :mod:`~friction_joint.experiments.classic`: the classic LuGre experiments of
  Canudas de Wit et al. (1995), each returning a
  :class:`~friction_joint.experiments.classic.ClassicResult`; figures in
  :mod:`~friction_joint.experiments.classic_report`;
* :mod:`~friction_joint.experiments.excitation`: the identification excitation
  (Section V-A) recorded on the test bed;
* :mod:`~friction_joint.experiments.hidden`: recordings with a hidden effect,
  for testing the diagnosis;
* :mod:`~friction_joint.experiments.fleet`: a simulated robot fleet, some joints
  wearing, for testing the fleet monitor.
"""
from ._common import ExperimentData
from .chirp import chirp
from .classic import breakaway, ClassicResult, frictional_lag, presliding, stick_slip
from .compensation import compensation
from .estimation import estimation
from .excitation import simulate_identification
from .fleet import simulate_fleet
from .hidden import apply_effect, apply_effects, draw_effect, EFFECT_RANGES, simulate_recording
from .runner import EXPERIMENTS
from ..paper import PAPER, PaperNumber

__all__ = ['chirp', 'compensation', 'estimation', 'ExperimentData', 'EXPERIMENTS',
           'ClassicResult', 'PAPER', 'PaperNumber', 'presliding',
           'frictional_lag', 'breakaway', 'stick_slip', 'simulate_identification',
           'EFFECT_RANGES', 'apply_effect', 'apply_effects', 'draw_effect', 'simulate_recording',
           'simulate_fleet']
