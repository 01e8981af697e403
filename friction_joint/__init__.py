"""friction_joint: a simulated Harmonic Drive joint with thermal- and load-dependent friction.

The core (everything except :mod:`friction_joint.ros.nodes`) imports no ROS:

* :mod:`~friction_joint.gear`   gear parameter files (CONTRACT section 4)
* :mod:`~friction_joint.models.static` static curve, seed eq. 1, 5-7
* :mod:`~friction_joint.models.lugre`  modified LuGre model, eq. 10
* :mod:`~friction_joint.models.gms`    modified GMS model, eq. 11-13
* :mod:`~friction_joint.models.joint`  joint + friction integrated together
"""
from .exceptions import (ExcitationError, FrictionJointError, GearConfigError,
                         GearConfigWarning, RecordingError)
from .gear import FrictionParams, GearParams, gear_from_dict, load_gear, save_gear
from .models.gms import GMS
from .models.joint import Joint
from .models.lugre import LuGre
from .models.static import StaticFriction

__version__ = '0.1.0'

__all__ = ['FrictionJointError', 'GearConfigError', 'GearConfigWarning', 'RecordingError',
           'ExcitationError', 'FrictionParams', 'GearParams', 'gear_from_dict', 'load_gear',
           'save_gear', 'StaticFriction', 'LuGre', 'GMS', 'Joint']
