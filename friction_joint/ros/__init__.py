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
