# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Identification of the friction model from recordings (seed Section V-A, three steps).

* :mod:`~friction_joint.identification.plateaus`: constant-velocity plateau detection;
* :mod:`~friction_joint.identification.static_structure`: model structure and
  excitation checks; :mod:`~friction_joint.identification.static_problem`: the
  least-squares problem; :mod:`~friction_joint.identification.static_fit`:
  steps 1-2 (:class:`StaticIdentifier`, order selection);
  :mod:`~friction_joint.identification.folds`: the held-out-block loop of
  cross-validation (:func:`held_out_sse`), shared with the diagnosis;
* :mod:`~friction_joint.identification.presliding_data`,
  :mod:`~friction_joint.identification.pattern_search`,
  :mod:`~friction_joint.identification.presliding`: step 3, the LuGre/GMS
  pre-sliding parameters;
* :mod:`~friction_joint.identification.pipeline`: recordings -> identified gear
  (written by :mod:`friction_joint.jobs.identify`);
  :mod:`~friction_joint.identification.report`: its figures.
"""
from .folds import held_out_sse, random_folds
from .pattern_search import pattern_search, PatternSearchResult
from .pipeline import IdentificationRun, identify_recordings
from .plateaus import DETECTION, find_plateaus, Plateaus, plateaus_from_arrays
from .presliding import fit_presliding, presliding_rmse, PreslidingFit
from .presliding_data import EXPERIMENT_ADVICE, presliding_segments, PreslidingOptions, Segment
from .static_fit import cross_validate_orders, select_orders, StaticIdentifier
from .static_structure import check_excitation, StaticStructure

__all__ = ['Plateaus', 'find_plateaus', 'plateaus_from_arrays', 'DETECTION', 'StaticStructure',
           'check_excitation', 'StaticIdentifier', 'cross_validate_orders', 'select_orders',
           'PatternSearchResult', 'pattern_search', 'Segment', 'presliding_segments',
           'EXPERIMENT_ADVICE', 'PreslidingFit', 'PreslidingOptions', 'fit_presliding',
           'presliding_rmse',
           'IdentificationRun', 'identify_recordings', 'held_out_sse', 'random_folds']
