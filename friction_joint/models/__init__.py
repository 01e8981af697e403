# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Friction models and the joint they act in (seed eq. 1, 5-7, 10-13).

Sign convention: docs/interfaces.md.

* :mod:`~friction_joint.models.static`: static Stribeck curve with nonlinear
  viscous friction, temperature and load polynomials (eq. 1, 5-7);
* :mod:`~friction_joint.models.lugre`: modified LuGre model (eq. 10);
* :mod:`~friction_joint.models.gms`: modified GMS model (eq. 11-13);
* :mod:`~friction_joint.models.friction`: a model by name (``static``,
  ``lugre``, ``gms``, ``none``);
* :mod:`~friction_joint.models.joint`: the joint ``J q̈ = τ − τ_r − τ_ext``
  integrated together with its friction state;
* :mod:`~friction_joint.models.params`: their parameters (``FrictionParams``, ...),
  which :mod:`friction_joint.gear` reads from gear files and re-exports.

Argument order of every evaluating or simulating call: the signals first,
positionally, in the order input (velocity ``qd`` or drive torque ``tau``),
temperature ``xi``, load ``tau_l``; then the step ``dt`` where the call
integrates; then options, keyword-only::

    StaticFriction(f).torque(qd, xi, tau_l=0.0)
    LuGre(f).simulate(qd, xi, tau_l, dt, *, z0=None)
    GMS(f).simulate(qd, xi, tau_l, dt, *, reset=False)
    friction_model(gear, kind).step(qd, xi, tau_l, dt, *, q=0.0)
    Joint(gear).simulate(tau, dt, *, xi=25.0, tau_ext=0.0)
    Joint(gear).step(tau, dt, *, xi, tau_ext=0.0)

The static curve's load ``tau_l`` defaults to an unloaded gear.  The joint
takes only its input ``tau`` before ``dt``: its temperature and external
torque are keyword arguments (defaults 25 degC and 0 Nm in :meth:`Joint.simulate`).
"""
from .._lazy import lazy_exports

#: where each public name lives: the package imports a module on first use only (PEP 562),
#: so the parameter classes (:mod:`.params`, which the gear files' layer imports) load
#: without the models and numba
_HOMES = {'StaticFriction': '.static', 'PARAMETERS': '.static', 'LuGre': '.lugre',
          'GMS': '.gms', 'Joint': '.joint', 'JointTrajectory': '.joint',
          'friction_model': '.friction', 'FRICTION_KINDS': '.friction'}

__all__ = ['StaticFriction', 'LuGre', 'GMS', 'Joint', 'JointTrajectory', 'friction_model',
           'FRICTION_KINDS', 'PARAMETERS']


__getattr__, __dir__ = lazy_exports(__name__, _HOMES)
