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
The simulated hardware: plant, sensors and the lumped thermal model of the test bed.

* :mod:`~friction_joint.testbed.plant`: :class:`Plant`, the joint with lever,
  current loop, encoder, velocity filter and temperature sensor at 3 kHz;
* :mod:`~friction_joint.testbed.sensors`: sensor models;
* :mod:`~friction_joint.testbed.thermal`: ``C dξ/dt = |τ_r q̇| − (ξ − ξ_amb)/R``;
* :mod:`~friction_joint.testbed.watchdog`: the drive's command watchdog.
"""
from .plant import InputLimits, Plant, Sample
from .sensors import CurrentLoop, Encoder, StreamingSOS, TemperatureSensor, VelocityEstimator
from .thermal import ThermalModel
from .watchdog import CommandWatchdog

__all__ = ['Plant', 'Sample', 'InputLimits', 'ThermalModel', 'StreamingSOS', 'Encoder',
           'VelocityEstimator', 'CurrentLoop', 'TemperatureSensor', 'CommandWatchdog']
