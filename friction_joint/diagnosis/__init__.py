# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Diagnosis: what a friction model gets wrong on measured data, and the extension that fixes it.

* :mod:`~friction_joint.diagnosis.data`: recordings -> measured friction torque on bins;
* :mod:`~friction_joint.diagnosis.structures`: candidate model structures, linear
  least squares with grids over their nonlinear parameters;
  :mod:`~friction_joint.diagnosis.physical`: the fits bounded to physical coefficients;
  :mod:`~friction_joint.diagnosis.crossval`: their block cross-validation;
* :mod:`~friction_joint.diagnosis.testability`: which candidates the data can tell
  (:func:`untestable`: a one-line reason per untestable effect);
* :mod:`~friction_joint.diagnosis.refine`: bounded continuous refinement of the
  nonlinear parameters after their grids (variable projection);
* :mod:`~friction_joint.diagnosis.ripple`: the ripple periods tried (each repeating
  three times within a piece);
* :mod:`~friction_joint.diagnosis.gravity`: the ``gravity`` candidate's testability
  and the corrected lever;
* :mod:`~friction_joint.diagnosis.criterion`: blocks, the signed-rank test, Holm,
  confounds, model adequacy and the report's verdict (headline, findings, next steps);
* :mod:`~friction_joint.diagnosis.pipeline`: base fit, candidates, greedy extension
  (:func:`diagnose`);
* :mod:`~friction_joint.diagnosis.velocity`: open-loop velocity of held-out windows;
* :mod:`~friction_joint.diagnosis.fitted_gear`: gear files of fitted structures, the
  physical ``extended.yaml`` (:func:`extended_model`);
* :mod:`~friction_joint.diagnosis.scan`: the open residual scan of the final
  model's residual against time, position, velocity, ... (:func:`residual_scan`);
* :mod:`~friction_joint.diagnosis.report`: figures and ``report.md`` (the
  ``diagnose`` command's files are written by :mod:`friction_joint.jobs`).
"""
from .crossval import cross_validate_structures
from .data import DiagnosisData, load_data
from .fitted_gear import extended_model
from .pipeline import (ALPHA, base_structure, diagnose, Diagnosis, EFFECTS, extend, MIN_GAIN,
                       UNREPRESENTABLE)
from .scan import residual_scan
from .structures import CandidateStructure
from .testability import untestable

__all__ = ['EFFECTS', 'ALPHA', 'MIN_GAIN', 'Diagnosis', 'diagnose', 'base_structure', 'extend',
           'DiagnosisData', 'load_data', 'CandidateStructure', 'cross_validate_structures',
           'untestable', 'extended_model', 'residual_scan',
           'UNREPRESENTABLE']
