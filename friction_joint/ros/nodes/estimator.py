# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``estimator``: the disturbance observer of eq. 4/15 as a ROS 2 node.

    ros2 run friction_joint estimator --ros-args --params-file config/csd25.yaml -p friction:=lugre

Subscribes ``/joint_states`` (effort = applied drive torque, q, qd) and
``/joint_temperature``; publishes ``/external_torque`` (sensor_msgs/JointState,
effort = estimated external torque, same stamp as the state it answers; the
convention of franka_ros2's external joint torques).

Parameters: ``friction`` (none | static | lugre | gms; run-time changeable),
``beta`` (cut-off of Q(s), rad/s), ``gravity`` (subtract the model lever's
gravity; false = estimate it as unknown external load, as in the paper's
Section V-D), ``rate`` (sample rate, default ``simulation.rate``), ``sync``
(pair states with temperatures by stamp; default: ``mode == 'lockstep'``),
``mode`` (``realtime``, the default, or ``lockstep``: the simulator's mode).
Runs unchanged on replayed bags
(``use_sim_time:=true``).

Input gate (see :mod:`~friction_joint.ros.nodes.common`): a state whose
position, velocity or effort is not finite or beyond the plausible limits of
the model gear (:class:`~friction_joint.testbed.plant.InputLimits`, logged at
start), a temperature outside its plausible range, a stamp ahead of the clock
or older than the last state answered is refused, counted and logged
(throttled) and gets no answer; the observer's state is never touched by it.
The count is logged at shutdown.
"""
from collections.abc import Sequence
import sys
from typing import Any

from rclpy.node import Node
from rclpy.publisher import Publisher
from sensor_msgs.msg import JointState, Temperature

from .answers import Answers
from .common import declare_follower_params, Lossless, PairedInput, run_node, StampPairing
from .ranges import (BETA_BOUNDS, between, check_estimator_params, sample_rate,
                     SAMPLE_RATE_BOUNDS, warm_up_temperature)
from ..parameters import declare_gear, describe, parameter_guard
from ..qos import overridable, stream_qos
from ..startup import check_overrides_used
from ...control.observer import DisturbanceObserver
from ...models.friction import FRICTION_KINDS
from ...testbed.plant import InputLimits

__all__ = ['EstimatorNode', 'main']

DEFAULTS = {'friction': 'lugre', 'beta': 60.0, 'gravity': False, 'rate': 0.0,
            'sync': False}
VALIDATORS = {
    'friction': lambda v: (None if v in FRICTION_KINDS
                           else f'must be one of {", ".join(FRICTION_KINDS)}'),
    'beta': lambda v: between(v, BETA_BOUNDS, 'rad/s'),
    'rate': lambda v: between(v, SAMPLE_RATE_BOUNDS, 'Hz', zero='simulation.rate'),
}


DESCRIPTORS = {
    'friction': describe('friction model of the observer: none, static, lugre or gms',
                         read_only=False),
    'beta': describe('cut-off frequency of the observer filter Q(s), rad/s (below the '
                     'Nyquist frequency pi rate)', low=BETA_BOUNDS[0], high=BETA_BOUNDS[1]),
    'gravity': describe("subtract the model lever's gravity (false: estimate it as part of "
                        "the external torque, as in the paper's Section V-D)"),
    'rate': describe("sample rate, Hz (0: the gear's simulation.rate)"),
    'sync': describe('pair each state with the temperature of the same stamp (lockstep)'),
}


class EstimatorNode(Answers, PairedInput, Node):
    """Wires :class:`~friction_joint.control.observer.DisturbanceObserver` to topics."""

    state_fields = ('position', 'velocity', 'effort')

    def __init__(self) -> None:
        super().__init__('estimator')
        self.p = declare_follower_params(self, DEFAULTS, VALIDATORS, DESCRIPTORS)
        self.gear = declare_gear(self, own=list(self.p))
        self.joint = self.gear.joint_name
        check_estimator_params(self.p, self.gear)       # cut-off below Nyquist, first
        self.limits = InputLimits(self.gear)
        self.dt = 1.0 / sample_rate(self.p, self.gear)
        self.observer = self._observer()
        self.observer(0.0, 0.0, 0.0, warm_up_temperature(self.gear))    # compile the kernels
        self.observer = self._observer()
        self.pair = StampPairing(self.p['sync'])
        self.last_ns: int | None = None
        self.last_msg: JointState | None = None
        qos, opts = stream_qos(), overridable()
        self.pub: Publisher | Lossless = self.create_publisher(
            JointState, 'external_torque', stream_qos(lossless=self.p['sync']),
            qos_overriding_options=opts)
        if self.p['sync']:                  # lossless: wait out a killed subscriber
            self.pub = Lossless(self, self.pub)
        self.sub_state = self.create_subscription(JointState, 'joint_states', self.on_state, qos,
                                                  qos_overriding_options=opts)
        self.sub_temp = self.create_subscription(Temperature, 'joint_temperature',
                                                 self.on_temperature, qos,
                                                 qos_overriding_options=opts)
        parameter_guard(self, {'friction': DEFAULTS['friction']}, VALIDATORS, self.apply)
        check_overrides_used(self)                      # a qos_overrides.* naming no entity
        self.get_logger().info(f'external torque observer for {self.joint}: '
                               f'beta {self.p["beta"]:g} '
                               f'rad/s, friction model {self.p["friction"]}; plausible inputs '
                               f'{self.limits.describe()}')

    def _observer(self):
        return DisturbanceObserver(self.gear, beta=self.p['beta'], dt=self.dt,
                                   friction=self.p['friction'],
                                   gravity=self.p['gravity'])

    def apply(self, name: str, value: Any) -> None:
        self.p[name] = value
        est = self.observer.estimate
        self.observer = self._observer()
        self.observer.reset(tau_ext=est)
        self.get_logger().info(f'{name} set to {value!r}')

    def restart(self) -> None:
        """Restart on a new timeline of stamps (a replay that loops): a fresh observer."""
        self.observer = self._observer()
        self.last_ns = self.last_msg = None

    def process(self, ns: int, state: Sequence[float], xi: float) -> None:
        if self.last_ns is not None and ns <= self.last_ns:
            if ns == self.last_ns:
                self.pub.publish(self.last_msg)
            else:
                self._reject('a joint state older than the last one answered',
                             f'stamp {ns * 1e-9:.6f} s < {self.last_ns * 1e-9:.6f} s')
            return
        q, qd, tau = state
        estimate = self.observer(tau, q, qd, xi)      # ValueError: refused (see guarded)
        out = JointState()
        out.header.stamp.sec, out.header.stamp.nanosec = divmod(ns, 1_000_000_000)
        out.name = [self.joint]
        out.effort = [estimate]
        self.last_ns, self.last_msg = ns, out
        self.count_answer()
        self.pub.publish(out)


def main(args: list[str] | None = None) -> int | str:
    return run_node(EstimatorNode, 'estimator', args)


if __name__ == '__main__':
    sys.exit(main())
