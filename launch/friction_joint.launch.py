# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Closed loop of one simulated joint: simulator, controller and estimator.

    ros2 launch friction_joint friction_joint.launch.py
    ros2 launch friction_joint friction_joint.launch.py mode:=realtime friction:=gms
    ros2 launch friction_joint friction_joint.launch.py duration:=10.0 namespace:=joint1

The same three nodes with the same parameters as ``friction_joint bringup``
(which is the launcher where ``ros2 launch`` is not installed): ``joint_sim`` on
the truth gear file, ``controller`` and ``estimator`` on the model gear file.
The recorder is not started here: start ``ros2 run friction_joint record BAG``
before the launch (so it has discovered the topics when the loop starts), or
use ``friction_joint bringup --record``.

``mode`` defaults to ``lockstep`` as in ``bringup``: simulated time, the
simulator advances only when the controller has answered, so the loop is
deterministic whatever the machine load.  ``duration`` (simulated seconds in
lockstep, wall seconds in realtime) makes the simulator end itself; it is
``0.0`` here, i.e. run until Ctrl-C, since a launch has no fixed length.  With
a duration, the end of the simulator shuts the whole launch down, as
``bringup`` stops the other processes.

``namespace`` puts the three nodes, and with them their topics, into a
namespace: the nodes use relative topic names, so in the root namespace (the
default) they are ``/joint_states`` ... and in ``namespace:=joint1`` they are
``/joint1/joint_states`` and so on.  ``/clock`` stays global.
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, Shutdown
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution, PythonExpression
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare

PACKAGE = 'friction_joint'


def generate_launch_description():
    """Declare the arguments and the three nodes of ``friction_joint bringup``."""
    share = FindPackageShare(PACKAGE)
    model = LaunchConfiguration('model')
    truth = LaunchConfiguration('truth')
    mode = LaunchConfiguration('mode')
    friction = LaunchConfiguration('friction')
    namespace = LaunchConfiguration('namespace')
    # bringup gives controller and estimator rate 1000.0 in realtime only; 0.0 (their
    # default) means the gear file's simulation.rate, which is what lockstep runs at
    rate = PythonExpression(["1000.0 if '", mode, "' == 'realtime' else 0.0"])
    # lockstep flow control: the simulator waits when the estimator's echo lags 300 steps
    follow = PythonExpression(["'external_torque' if '", mode, "' == 'lockstep' else ''"])

    arguments = [
        DeclareLaunchArgument(
            'model', default_value=PathJoinSubstitution([share, 'config', 'csd25.yaml']),
            description='gear file of controller and estimator (the identified model)'),
        DeclareLaunchArgument(
            'truth', default_value=PathJoinSubstitution([share, 'config', 'csd25_truth.yaml']),
            description='gear file of the simulated joint (the "hardware")'),
        DeclareLaunchArgument(
            'mode', default_value='lockstep', choices=['lockstep', 'realtime'],
            description='lockstep: simulated time, deterministic; realtime: 1 kHz wall clock'),
        DeclareLaunchArgument(
            'friction', default_value='lugre', choices=['none', 'static', 'lugre', 'gms'],
            description='friction model of controller feed-forward and estimator'),
        DeclareLaunchArgument(
            'duration', default_value='0.0',
            description='seconds after which the simulator ends the launch (0.0: run until '
                        'stopped)'),
        DeclareLaunchArgument(
            'amplitude', default_value='0.4', description='reference amplitude, rad'),
        DeclareLaunchArgument(
            'omega', default_value='1.5', description='reference frequency, rad/s'),
        DeclareLaunchArgument(
            'namespace', default_value='',
            description='namespace of the nodes and of their topics (/clock stays global)'),
    ]
    estimator = Node(
        package=PACKAGE, executable='estimator', namespace=namespace, output='screen',
        parameters=[model, {'friction': friction, 'mode': mode, 'rate': rate}])
    controller = Node(
        package=PACKAGE, executable='controller', namespace=namespace, output='screen',
        parameters=[model, {'friction_ff': friction,
                            'amplitude': LaunchConfiguration('amplitude'),
                            'omega': LaunchConfiguration('omega'),
                            'mode': mode, 'rate': rate}])
    # waits for the two subscribers (controller, estimator) before the loop starts
    joint_sim = Node(
        package=PACKAGE, executable='joint_sim', namespace=namespace, output='screen',
        parameters=[truth, {'mode': mode, 'duration': LaunchConfiguration('duration'),
                            'wait_subscribers': 2, 'start_delay': 2.0,
                            'follow': follow, 'window': 300}],
        on_exit=Shutdown(reason='the simulator has finished'))
    return LaunchDescription(arguments + [estimator, controller, joint_sim])
