# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The recorder's readiness topic, and a recorder killed with SIGKILL then recovered."""
import os
from pathlib import Path
import signal
import subprocess
import time

import numpy as np
import pytest
import roshelpers
from roshelpers import PYTHON, reliable_qos
import sourcetree

pytestmark = pytest.mark.ros

pytest.importorskip('rclpy')

CLI = [PYTHON, '-m', 'friction_joint']
MCAP_CLI = Path(sourcetree.MCAP_CLI)
_MODEL = Path(sourcetree.ROOT) / 'config' / 'csd25.yaml'


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


def _joint_state(i):
    from sensor_msgs.msg import JointState
    m = JointState()
    m.header.stamp.sec, m.header.stamp.nanosec = 100 + i // 1000, (i % 1000) * 1_000_000
    m.name = ['joint']
    m.position, m.velocity, m.effort = [float(i)], [1000.0], [0.5]    # 1 rad per 1 ms stamp
    return m


def test_killed_recorder_is_recovered(ros_node, spawn, tmp_path):
    from friction_joint.bag import read_recording
    from friction_joint.bag.staging import FLUSH_PERIOD
    from sensor_msgs.msg import JointState

    rate, kill_at = 1000.0, 4000                     # SIGKILL after 4 s at 1 kHz
    out = tmp_path / 'k1'
    rec = spawn(CLI + ['record', out, '--topics', '/joint_states', '/joint_command'])
    assert rec.wait_for('recording /joint_states', 30), rec.describe()
    pub = ros_node.node.create_publisher(JointState, '/joint_states', reliable_qos(None))
    assert rec.wait_for('/joint_states: 1 publisher matched', 15), rec.describe()
    msgs = [_joint_state(i) for i in range(kill_at + 200)]
    t0 = time.perf_counter()
    for i, m in enumerate(msgs):
        if i == kill_at:
            os.killpg(rec.popen.pid, signal.SIGKILL)
        pub.publish(m)
        while time.perf_counter() < t0 + (i + 1) / rate:
            pass
    assert rec.wait(10) == -signal.SIGKILL
    assert not out.exists()
    (staging,) = tmp_path.glob('.k1.*.tmp')
    partial = staging / 'k1' / 'k1.mcap'
    assert partial.stat().st_size > 0

    # reading it names the partial file and the recovery command, in one line (exit 2)
    res = subprocess.run(CLI + ['identify', str(partial), '--model', str(_MODEL), '--out',
                                str(tmp_path / 'g.yaml')], capture_output=True, text=True)
    assert res.returncode == 2, res.stderr
    err = res.stderr.strip()
    assert '\n' not in err and str(partial) in err, err
    assert f'friction_joint recover {os.path.relpath(staging)} {os.path.relpath(out)}' in err

    # a later record to the same OUT names the staging directory left behind
    again = spawn(CLI + ['record', out, '--topics', '/joint_states', '--duration', '0.5'])
    assert again.wait(30) == 0, again.describe()
    assert f'{staging} holds an earlier recording to {out} that did not finish' in \
        again.stderr, again.describe()
    assert f'friction_joint recover {os.path.relpath(staging)} {os.path.relpath(out)}_recovered' \
        in again.stderr, again.describe()

    res = subprocess.run(CLI + ['recover', str(staging), str(tmp_path / 'k1_recovered')],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    got = read_recording(tmp_path / 'k1_recovered')
    n = len(got.joint_states.t)
    print(f'published {kill_at} before SIGKILL, recovered {n}')
    assert f'recovered {n} messages (/joint_states: {n}, /joint_command: 0)' in res.stdout
    # bounded loss: what arrived in the last flush period (plus delivery slack)
    assert kill_at - rate * (FLUSH_PERIOD + 0.5) <= n <= kill_at, n
    np.testing.assert_array_equal(got.joint_states.q, np.arange(n))
    assert not staging.exists()
    if MCAP_CLI.exists():
        doc = subprocess.run([str(MCAP_CLI), 'doctor', '--strict-message-order',
                              str(tmp_path / 'k1_recovered' / 'k1_recovered.mcap')],
                             capture_output=True, text=True)
        assert doc.returncode == 0, doc.stdout + doc.stderr
