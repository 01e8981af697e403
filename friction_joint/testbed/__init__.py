# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The simulated hardware: plant, sensors and the lumped thermal model of the test bed.

* :mod:`~friction_joint.testbed.plant`: :class:`Plant`, the joint with lever,
  current loop, encoder, velocity filter and temperature sensor at 3 kHz;
* :mod:`~friction_joint.testbed.sensors`: sensor models;
* :mod:`~friction_joint.testbed.thermal`: ``C dξ/dt = |τ_r q̇| − (ξ − ξ_amb)/R``;
* :mod:`~friction_joint.testbed.watchdog`: the drive's command watchdog;
* :mod:`~friction_joint.testbed.pacing`: realtime pacing behind a lagging controller.
"""
from .pacing import Pacing
from .plant import InputLimits, Plant, Sample
from .sensors import CurrentLoop, Encoder, StreamingSOS, TemperatureSensor, VelocityEstimator
from .thermal import ThermalModel
from .watchdog import CommandWatchdog

__all__ = ['Plant', 'Sample', 'InputLimits', 'ThermalModel', 'StreamingSOS', 'Encoder',
           'VelocityEstimator', 'CurrentLoop', 'TemperatureSensor', 'CommandWatchdog', 'Pacing']
