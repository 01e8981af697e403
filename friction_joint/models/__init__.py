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
"""
from .friction import FRICTION_KINDS, friction_model
from .gms import GMS
from .joint import Joint, JointTrajectory
from .lugre import LuGre
from .static import PARAMETERS, StaticFriction

__all__ = ['StaticFriction', 'LuGre', 'GMS', 'Joint', 'JointTrajectory', 'friction_model',
           'FRICTION_KINDS', 'PARAMETERS']
