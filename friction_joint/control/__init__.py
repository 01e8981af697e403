# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

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
