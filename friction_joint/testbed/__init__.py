"""The simulated hardware: plant, sensors and the lumped thermal model of the test bed.

* :mod:`~friction_joint.testbed.plant`: :class:`Plant`, the joint with lever,
  current loop, encoder, velocity filter and temperature sensor at 3 kHz;
* :mod:`~friction_joint.testbed.sensors`: sensor models;
* :mod:`~friction_joint.testbed.thermal`: ``C dξ/dt = |τ_r q̇| − (ξ − ξ_amb)/R``.
"""
from .plant import Plant, Sample
from .sensors import CurrentLoop, Encoder, StreamingSOS, TemperatureSensor, VelocityEstimator
from .thermal import ThermalModel

__all__ = ['Plant', 'Sample', 'ThermalModel', 'StreamingSOS', 'Encoder', 'VelocityEstimator',
           'CurrentLoop', 'TemperatureSensor']
