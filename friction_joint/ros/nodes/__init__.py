"""ROS 2 nodes: thin shells over the core (one file per node).

* :mod:`~friction_joint.ros.nodes.joint_sim`  the simulated joint (plant)
* :mod:`~friction_joint.ros.nodes.controller` eq. 17 controller
* :mod:`~friction_joint.ros.nodes.estimator`  eq. 15 external torque estimator
"""
