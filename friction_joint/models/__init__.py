"""Friction models and the joint they act in (seed eq. 1, 5-7, 10-13; CONTRACT section 1).

* :mod:`~friction_joint.models.static`: static Stribeck curve with nonlinear
  viscous friction, temperature and load polynomials (eq. 1, 5-7);
* :mod:`~friction_joint.models.lugre`: modified LuGre model (eq. 10);
* :mod:`~friction_joint.models.gms`: modified GMS model (eq. 11-13);
* :mod:`~friction_joint.models.friction`: a model by name (``static``,
  ``lugre``, ``gms``, ``none``);
* :mod:`~friction_joint.models.joint`: the joint ``J q̈ = τ − τ_r − τ_ext``
  integrated together with its friction state.
"""
from .friction import FRICTION_KINDS, friction_model
from .gms import GMS
from .joint import Joint, JointTrajectory
from .lugre import LuGre
from .static import PARAMETERS, StaticFriction

__all__ = ['StaticFriction', 'LuGre', 'GMS', 'Joint', 'JointTrajectory', 'friction_model',
           'FRICTION_KINDS', 'PARAMETERS']
