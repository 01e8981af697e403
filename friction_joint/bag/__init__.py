"""Recordings (rosbag2 / MCAP) as numpy arrays, without ROS.

* :mod:`~friction_joint.bag.types`: the contract topics and their array classes
  (:class:`Recording`, :class:`JointStates`, ...);
* :mod:`~friction_joint.bag.reader`: :func:`read_recording`, :func:`iter_messages`;
* :mod:`~friction_joint.bag.writer`: :func:`write_recording`.
"""
from .reader import iter_messages, read_recording, recording_topics
from .types import (CONTRACT_TYPES, REQUIRED_TOPICS, ExternalTorque, JointCommand, JointStates,
                    LinkTorque, Recording, Temperature, zero_order_hold)
from .writer import write_recording

__all__ = ['CONTRACT_TYPES', 'REQUIRED_TOPICS', 'JointStates', 'Temperature', 'LinkTorque',
           'JointCommand', 'ExternalTorque', 'Recording', 'read_recording', 'write_recording',
           'zero_order_hold', 'recording_topics', 'iter_messages']
