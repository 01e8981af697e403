# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``composed``: ``joint_sim``, ``controller`` and ``estimator`` in one process (lockstep).

    python -m friction_joint.ros.nodes.composed --ros-args --params-file composed.yaml

The three nodes of the closed loop, unchanged, in one process with one
executor: the lockstep loop between them is wired by direct calls instead of
DDS round trips, so a step costs the three nodes' computation and the
publishing of their messages, not two cross-process deliveries and five
takes.  Every node still publishes every message on its topics
(``/joint_states``, ``/joint_temperature``, ``/link_torque``, ``/clock``,
``/joint_command``, ``/external_torque``), so a recorder or any other
subscriber sees exactly what the separate processes publish, and the loop
computes exactly what they compute (the offline equivalence holds).

Parameters come from one params file with a section per node name
(``joint_sim:``, ``controller:``, ``estimator:``), each a whole gear plus the
node's own parameters (``friction_joint bringup --composed`` writes it: the
truth gear for the simulator, the model gear for the others).  The nodes run
in ``mode`` lockstep; the simulator's flow control (``follow``) is not needed
(nothing lags in one process) and the followers' input subscriptions are
removed (their input comes by call).  The simulator keeps its
``/contact_torque`` subscription, taken every ``EXECUTOR_EVERY`` s, and its
start conditions (``wait_subscribers``, ``wait_recorder``).
"""
import collections
import sys
import time

from geometry_msgs.msg import WrenchStamped
from rclpy.executors import Executor
from sensor_msgs.msg import JointState

from .common import EXECUTOR_EVERY, run_node, take_queued
from .controller import ControllerNode
from .estimator import EstimatorNode
from .joint_sim import JointSimNode
from ...exceptions import GearConfigError

__all__ = ['Composition', 'main']


class _Relay:
    """A publisher that also hands every message to an in-process consumer."""

    def __init__(self, publisher, consume):
        self.publisher = publisher
        self.consume = consume

    def publish(self, msg):
        self.publisher.publish(msg)
        self.consume(msg)

    def __getattr__(self, name):
        return getattr(self.publisher, name)


class Composition:
    """
    The lockstep loop of three nodes in one process, wired by calls.

    The simulator's state and temperature go to the estimator and the
    controller (temperature first, as :class:`StampPairing` expects in no
    particular order); the controller's command is queued and handed to the
    simulator by :meth:`spin_step`, which advances it (no recursion).
    """

    def __init__(self):
        self.sim = JointSimNode()
        self.controller = ControllerNode()
        self.estimator = EstimatorNode()
        self.nodes = (self.sim, self.controller, self.estimator)
        for node in self.nodes:
            if node.p['mode'] != 'lockstep':
                raise GearConfigError(f'{node.get_name()}: the composed loop runs in lockstep '
                                      f"only (mode is {node.p['mode']!r})")
        if self.sim.followers:
            raise GearConfigError('joint_sim: follow is not used in the composed loop '
                                  '(nothing lags in one process); leave it empty')
        self.followers = (self.estimator, self.controller)
        for node in self.followers:
            node.destroy_subscription(node.sub_state)
            node.destroy_subscription(node.sub_temp)
        self.sim.destroy_subscription(self.sim.sub_command)
        self.temps = []
        self.commands = collections.deque()
        self.sim.pub_temp = _Relay(self.sim.pub_temp, self.temps.append)
        self.sim.pub_state = _Relay(self.sim.pub_state, self.deliver)
        self.controller.pub = _Relay(self.controller.pub, self.commands.append)
        self.next_turn = 0.0

    def deliver(self, state: JointState) -> None:
        """Hand a published state (and the temperatures before it) to the followers."""
        temps, self.temps[:] = list(self.temps), []
        for node in self.followers:
            for msg in temps:
                node.on_temperature(msg)
            node.on_state(state)

    def spin_step(self, executor: Executor) -> None:
        """
        One turn: hand the queued commands to the simulator, or turn the executor.

        Returns after each executor turn (every ``EXECUTOR_EVERY`` s), so that ``run_node``
        sees a signal: each step queues the next command, the loop never runs dry by itself.
        """
        sim = self.sim
        if not self.commands or sim.done:
            executor.spin_once(timeout_sec=0.05 if not sim.started or sim.done else 0.0)
            return
        while self.commands and not sim.done:
            sim.on_command(self.commands.popleft())
            now = time.monotonic()
            if now >= self.next_turn:
                self.next_turn = now + EXECUTOR_EVERY
                for msg in take_queued(sim.sub_contact, WrenchStamped):
                    sim.on_contact(msg)
                executor.spin_once(timeout_sec=0.0)
                return

    def interrupted(self) -> bool:
        """Whether the simulated run has not reached its ``duration`` (see ``run_node``)."""
        return self.sim.interrupted()


def main(args: list[str] | None = None) -> int | str:
    return run_node(Composition, 'composed', args, drain=False)


if __name__ == '__main__':
    sys.exit(main())
