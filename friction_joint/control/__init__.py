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
Control and estimation with the friction model.

* :mod:`~friction_joint.control.controller`: the eq. 17 controller (PD with
  friction feed-forward) and its gain design from rise time and overshoot;
* :mod:`~friction_joint.control.gains`: which inertia the gains are designed
  for (presets ``paper`` and ``full-inertia``) and the loop they make on a
  plant;
* :mod:`~friction_joint.control.observer`: the eq. 4/15 disturbance observer
  estimating the external torque.
"""
from .controller import Controller, pd_gains, SineTrajectory, step_metrics
from .gains import gain_design, GAIN_PRESETS, GainDesign, loop_metrics
from .observer import DisturbanceObserver

__all__ = ['Controller', 'SineTrajectory', 'pd_gains', 'step_metrics', 'DisturbanceObserver',
           'GainDesign', 'GAIN_PRESETS', 'gain_design', 'loop_metrics']
