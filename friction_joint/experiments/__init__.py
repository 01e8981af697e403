# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Experiments on the simulated test bed and in the literature.

* the paper's applications: :mod:`~friction_joint.experiments.chirp` (Fig. 5),
  :mod:`~friction_joint.experiments.compensation` (Fig. 6-7),
  :mod:`~friction_joint.experiments.estimation` (Fig. 8), run by name through
  :mod:`~friction_joint.experiments.runner`; each returns an
  :class:`~friction_joint.results.ExperimentResult` whose figures
  :mod:`~friction_joint.experiments.plots` draws, beside the paper's own
  numbers of :data:`~friction_joint.paper.PAPER` (also read by the
  report text, :mod:`~friction_joint.experiments.testbed_report`);
* :mod:`~friction_joint.experiments.classic`: the classic LuGre experiments of
  Canudas de Wit et al. (1995), each returning an
  :class:`~friction_joint.results.ExperimentResult`; figures in
  :mod:`~friction_joint.experiments.classic_report`;
* :mod:`~friction_joint.experiments.excitation`: the identification excitation
  (Section V-A) recorded on the test bed;
* :mod:`~friction_joint.experiments.hidden`: recordings with a hidden effect,
  for testing the diagnosis;
* :mod:`~friction_joint.experiments.fleet`: a simulated robot fleet, some joints
  wearing, for testing the fleet monitor (written by
  :mod:`friction_joint.jobs.fleet_simulation`).
"""
from .._lazy import lazy_exports

#: where each public name lives: the package imports a module on first use only, so that
#: the command line's ``--help`` (names and help texts) does not load the simulators
_HOMES = {'ExperimentResult': '..results', 'chirp': '.chirp', 'breakaway': '.classic',
          'frictional_lag': '.classic', 'presliding': '.classic',
          'stick_slip': '.classic', 'compensation': '.compensation',
          'estimation': '.estimation', 'simulate_identification': '.excitation',
          'draw_fleet': '.fleet', 'apply_effect': '.hidden', 'apply_effects': '.hidden',
          'draw_effect': '.hidden', 'EFFECT_RANGES': '.hidden', 'simulate_recording': '.hidden',
          'RecordingOptions': '.hidden_plant',
          'EXPERIMENTS': '.runner', 'PAPER': '..paper', 'PaperNumber': '..paper'}

__all__ = ['chirp', 'compensation', 'estimation', 'ExperimentResult', 'EXPERIMENTS',
           'PAPER', 'PaperNumber', 'presliding',
           'frictional_lag', 'breakaway', 'stick_slip', 'simulate_identification',
           'EFFECT_RANGES', 'apply_effect', 'apply_effects', 'draw_effect', 'simulate_recording',
           'RecordingOptions',
           'draw_fleet']


__getattr__, __dir__ = lazy_exports(__name__, _HOMES)
