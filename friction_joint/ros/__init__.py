# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ROS 2 layer: the only subpackage that imports rclpy.

* :mod:`~friction_joint.ros.nodes`: ``joint_sim``, ``controller``, ``estimator``;
* :mod:`~friction_joint.ros.record`, :mod:`~friction_joint.ros.replay`:
  recordings from and to live topics;
* :mod:`~friction_joint.ros.bringup`: the nodes as separate processes (what a
  launch file does, for installs without ``ros2 launch``);
* :mod:`~friction_joint.ros.qos`: the QoS profiles, defined once;
* :mod:`~friction_joint.ros.parameters`: the nodes' parameters (gear keys through
  the package's schema, descriptors);
* :mod:`~friction_joint.ros._rclpy`: the rclpy internals relied on, in one place.

Importing this package does not import rclpy; its modules do.
"""
__all__ = []
