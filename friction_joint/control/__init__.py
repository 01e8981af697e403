"""Control and estimation with the friction model.

* :mod:`~friction_joint.control.controller`: the eq. 17 controller (PD with
  friction feed-forward) and its gain design from rise time and overshoot;
* :mod:`~friction_joint.control.observer`: the eq. 4/15 disturbance observer
  estimating the external torque.
"""
from .controller import Controller, SineTrajectory, pd_gains, step_metrics
from .observer import DisturbanceObserver

__all__ = ['Controller', 'SineTrajectory', 'pd_gains', 'step_metrics', 'DisturbanceObserver']
