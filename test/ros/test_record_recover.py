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

"""The recorder's readiness topic, and a recorder killed with SIGKILL then recovered."""
import pytest
import roshelpers
from roshelpers import PYTHON, reliable_qos

pytestmark = pytest.mark.ros

pytest.importorskip('rclpy')

CLI = [PYTHON, '-m', 'friction_joint']


def _ready_subscription(node, got):
    from friction_joint.ros.record import READY_QOS, READY_TOPIC
    from std_msgs.msg import String
    return node.create_subscription(String, READY_TOPIC, lambda m: got.append(m.data), READY_QOS)


def test_recorder_announces_matched_topics(ros_node, spawn, ros_env, tmp_path):
    from friction_joint.ros.record import READY_QOS, READY_TOPIC
    from rclpy.qos import DurabilityPolicy, ReliabilityPolicy
    from sensor_msgs.msg import JointState

    assert READY_TOPIC == 'recorder_ready'
    assert READY_QOS.depth == 1
    assert READY_QOS.reliability == ReliabilityPolicy.RELIABLE
    assert READY_QOS.durability == DurabilityPolicy.TRANSIENT_LOCAL

    early = []
    _ready_subscription(ros_node.node, early)
    rec = spawn(CLI + ['record', tmp_path / 'rec', '--topics', '/joint_command',
                       '/joint_states'])
    assert rec.wait_for('recording /joint_command', 30), rec.describe()
    # at start: nothing matched yet, announced as the empty string
    assert ros_node.spin_until(lambda: early, 15), rec.describe()
    assert early[0] == ''

    pub = ros_node.node.create_publisher(JointState, '/joint_command', reliable_qos())
    assert rec.wait_for('/joint_command: 1 publisher matched', 15), rec.describe()
    assert ros_node.spin_until(lambda: early[-1:] == ['/joint_command'], 10), (early,
                                                                               rec.describe())
    # a node joining later gets the current set at once (transient local)
    with roshelpers.ros_node('late_node', ros_env['ROS_DOMAIN_ID']) as late:
        got = []
        _ready_subscription(late.node, got)
        assert late.spin_until(lambda: got, 15), rec.describe()
        assert got == ['/joint_command']
    # the set changes again when the publisher goes
    ros_node.node.destroy_publisher(pub)
    assert ros_node.spin_until(lambda: early[-1] == '', 15), early
    assert rec.stop() == 0, rec.describe()
    assert '/joint_command: 1 publisher matched' in rec.stderr
