"""Diagnosis: what a friction model gets wrong on measured data, and the extension that fixes it.

* :mod:`~friction_joint.diagnosis.data`: recordings -> measured friction torque on bins;
* :mod:`~friction_joint.diagnosis.structures`: candidate model structures, linear
  least squares with grids over their nonlinear parameters, block cross-validation;
* :mod:`~friction_joint.diagnosis.pipeline`: base fit, candidates, the criterion,
  greedy extension (:func:`diagnose`);
* :mod:`~friction_joint.diagnosis.report`: figures, ``report.md`` and the files
  of the ``diagnose`` command (:func:`run_diagnose`).
"""
from .data import DiagnosisData, load_data
from .pipeline import ALPHA, EFFECTS, MIN_GAIN, Diagnosis, base_structure, diagnose, extend
from .report import run_diagnose
from .structures import CandidateStructure, cross_validate_structures

__all__ = ['EFFECTS', 'ALPHA', 'MIN_GAIN', 'Diagnosis', 'diagnose', 'base_structure', 'extend',
           'DiagnosisData', 'load_data', 'CandidateStructure', 'cross_validate_structures',
           'run_diagnose']
