"""Identification of the friction model from recordings (seed Section V-A, three steps).

* :mod:`~friction_joint.identification.plateaus`: constant-velocity plateau detection;
* :mod:`~friction_joint.identification.static_structure`: model structure and
  excitation checks; :mod:`~friction_joint.identification.static_problem`: the
  least-squares problem; :mod:`~friction_joint.identification.static_fit`:
  steps 1-2 (:class:`StaticIdentifier`, order selection);
* :mod:`~friction_joint.identification.presliding_data`,
  :mod:`~friction_joint.identification.pattern_search`,
  :mod:`~friction_joint.identification.presliding`: step 3, the LuGre/GMS
  pre-sliding parameters;
* :mod:`~friction_joint.identification.pipeline`: recordings -> gear file;
  :mod:`~friction_joint.identification.report`: its figures.
"""
from .pattern_search import PatternSearchResult, pattern_search
from .pipeline import IdentificationRun, identify_recordings, run_identify
from .plateaus import DETECTION, Plateaus, find_plateaus, plateaus_from_arrays
from .presliding import PreslidingFit, fit_presliding, presliding_rmse
from .presliding_data import EXPERIMENT_ADVICE, Segment, presliding_segments
from .static_fit import StaticIdentifier, cross_validate_orders, select_orders
from .static_structure import StaticStructure, check_excitation

__all__ = ['Plateaus', 'find_plateaus', 'plateaus_from_arrays', 'DETECTION', 'StaticStructure',
           'check_excitation', 'StaticIdentifier', 'cross_validate_orders', 'select_orders',
           'PatternSearchResult', 'pattern_search', 'Segment', 'presliding_segments',
           'EXPERIMENT_ADVICE', 'PreslidingFit', 'fit_presliding', 'presliding_rmse',
           'IdentificationRun', 'identify_recordings', 'run_identify']
