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
Friction models and the joint they act in (seed eq. 1, 5-7, 10-13).

Sign convention: docs/interfaces.md.

* :mod:`~friction_joint.models.static`: static Stribeck curve with nonlinear
  viscous friction, temperature and load polynomials (eq. 1, 5-7);
* :mod:`~friction_joint.models.lugre`: modified LuGre model (eq. 10);
* :mod:`~friction_joint.models.gms`: modified GMS model (eq. 11-13);
* :mod:`~friction_joint.models.friction`: a model by name (``static``,
  ``lugre``, ``gms``, ``none``);
* :mod:`~friction_joint.models.joint`: the joint ``J q̈ = τ − τ_r − τ_ext``
  integrated together with its friction state.

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
from .friction import FRICTION_KINDS, friction_model
from .gms import GMS
from .joint import Joint, JointTrajectory
from .lugre import LuGre
from .static import PARAMETERS, StaticFriction

__all__ = ['StaticFriction', 'LuGre', 'GMS', 'Joint', 'JointTrajectory', 'friction_model',
           'FRICTION_KINDS', 'PARAMETERS']
