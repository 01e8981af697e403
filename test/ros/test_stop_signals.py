# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Signals to the ROS processes: every one stops, none is orphaned, the recording is sealed.

* ``bringup`` killed with SIGKILL (no handler of its runs): its nodes (and the
  composed process) stop by their parent-death signal, the recorder seals;
* the composed node, mid-run, stops on SIGINT / SIGTERM (its loop used to hold it
  until the run's end) with 128 + the signal's number;
* ``joint_sim`` stopped with Ctrl-C after its peers were killed (they never
  acknowledge, until DDS drops them) ends within a bounded time, not after 15 s.

The runs are long (an hour of simulated time): a process that does not stop on
the signal does not end by itself while the test waits.  Waits are for conditions
with generous deadlines; the one duration asserted is far from both sides.
"""
import contextlib
import os
import signal
import sys
import time

from friction_joint.bag import read_recording
import pytest
import roshelpers
from test_bringup_cli import alive, children, MODEL, TRUTH
from test_node_inputs import node_cmd

pytestmark = pytest.mark.ros

PY = sys.executable
LONG = 3600.0                               # s of simulated time: never reached in a test


def subscribe(ros_node, topic='/joint_states'):
    """Return the list the messages of ``topic`` are appended to."""
    from sensor_msgs.msg import JointState
    got = []
    ros_node.node.create_subscription(JointState, topic, got.append, roshelpers.reliable_qos())
    return got


def kill_groups(pids):
    """SIGKILL the process group of each pid still alive (each node has its own session)."""
    for pid in pids:
        if alive(pid):
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(pid, signal.SIGKILL)


@pytest.mark.parametrize('composed', [False, True], ids=['processes', 'composed'])
def test_killed_bringup_takes_its_nodes_with_it_and_seals_the_recording(
        composed, ros_env, ros_node, tmp_path):
    """SIGKILL of bringup: no node outlives it, the recording is finalised and readable."""
    got = subscribe(ros_node)
    out = tmp_path / 'rec'
    proc = roshelpers.Proc([PY, '-m', 'friction_joint', 'bringup', '--model', MODEL,
                            '--truth', TRUTH, '--duration', str(LONG), '--record', str(out)]
                           + (['--composed'] if composed else []), ros_env)
    kids = []
    try:
        assert proc.wait_for('processes up', timeout=240), proc.describe()
        assert ros_node.spin_until(lambda: len(got) > 100, timeout=240), proc.describe()
        kids = children(proc.popen.pid)
        assert len(kids) == (2 if composed else 4), kids
        proc.popen.kill()
        assert proc.wait(timeout=60) == -signal.SIGKILL
        gone = roshelpers.wait_until(lambda: not [k for k in kids if alive(k)],
                                     timeout=2 * roshelpers.DEADLINE)
        assert gone, f'orphaned nodes: {[k for k in kids if alive(k)]}'
    finally:
        proc.stop()
        kill_groups(kids)
    rec = read_recording(str(out))                 # sealed: readable, the loop in it
    assert len(rec.joint_states.t) > 0 and len(rec.joint_command.t) > 0


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM], ids=['INT', 'TERM'])
def test_composed_node_stops_mid_run_on_a_signal(signum, spawn, ros_node, tmp_path):
    """The composed loop sees a signal mid-run: exit 128 + N, the recording sealed."""
    from friction_joint.ros.bringup import composed_command
    got = subscribe(ros_node)
    out = tmp_path / 'rec'
    rec = spawn([PY, '-m', 'friction_joint', 'record', str(out), '--use-sim-time'])
    sim = {'mode': 'lockstep', 'duration': LONG, 'follow': '', 'wait_subscribers': 1,
           'wait_recorder': 'loop', 'start_delay': 0.5}
    params = {'sim': sim, 'controller': {'mode': 'lockstep'}, 'estimator': {'mode': 'lockstep'}}
    node = spawn(composed_command(MODEL, TRUTH, params, str(tmp_path)))
    assert ros_node.spin_until(lambda: len(got) > 300, timeout=240), node.describe()
    node.popen.send_signal(signum)
    try:
        rc = node.wait(timeout=roshelpers.DEADLINE)
    except Exception:                                 # noqa: BLE001 - report, then fail
        pytest.fail('the composed node did not stop on the signal\n' + node.describe())
    assert rc == 128 + signum, node.describe()
    assert rec.stop() == 0, rec.describe()
    bag = read_recording(str(out))
    assert len(bag.joint_states.t) > 300 and len(bag.joint_command.t) > 300


def test_joint_sim_stops_soon_after_ctrl_c_though_its_peers_were_killed(spawn, ros_node):
    """
    Killed controller and estimator never acknowledge: Ctrl-C still ends the simulator soon.

    Before, it waited ``ACK_TIMEOUT`` (15 s) for them; now at most ``STOP_ACK_TIMEOUT``
    (0.5 s) after the signal.  Asserted: under 10 s (a loaded machine adds start-up noise,
    never 15 s).
    """
    commands = subscribe(ros_node, '/joint_command')
    estimates = subscribe(ros_node, '/external_torque')
    ctl = spawn(node_cmd('controller', MODEL))
    est = spawn(node_cmd('estimator', MODEL))
    sim = spawn(node_cmd('joint_sim', TRUTH))
    assert ros_node.spin_until(lambda: len(commands) > 100 and len(estimates) > 100,
                               timeout=240), sim.describe()
    for peer in (ctl, est):
        peer.popen.kill()
        peer.wait(timeout=60)
    ros_node.spin_for(0.5)                             # serve the test's own subscriptions
    t0 = time.monotonic()
    sim.popen.send_signal(signal.SIGINT)
    rc = sim.wait(timeout=roshelpers.DEADLINE)
    took = time.monotonic() - t0
    assert rc == 0, sim.describe()
    assert took < 10.0, f'{took:.1f} s\n' + sim.describe()
