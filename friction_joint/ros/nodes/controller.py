# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``controller``: the joint controller of eq. 17 as a ROS 2 node.

    ros2 run friction_joint controller --ros-args --params-file config/csd25.yaml \
        -p friction_ff:=lugre -p amplitude:=0.4

Subscribes ``/joint_states`` and ``/joint_temperature``, publishes
``/joint_command`` (effort = commanded torque, position/velocity = q_d, qd_d)
with the stamp of the state it answers.  The reference is
q_d = offset + amplitude sin(omega t), t from the first state's stamp.
Gains come from ``rise_time`` and ``overshoot`` for ``design_inertia`` (0: the gear's inertia)
(a :class:`~friction_joint.control.gains.GainDesign`, whose None is the 0 here).

Run-time parameters (validated; a bad value is rejected with a reason and
the node keeps running): ``friction_ff`` (none | static | lugre | gms),
``ff_velocity`` (measured | desired), ``amplitude``, ``omega``, ``offset``.
``mode`` (``realtime``, the default, or ``lockstep``: the simulator's mode)
decides ``sync`` unless it is set.  ``sync`` (default: ``mode == 'lockstep'``)
pairs each state with the temperature sample of the same stamp (see
:class:`~friction_joint.ros.nodes.common.StampPairing`) and
answers every state (lockstep); with ``sync:=false`` (a real-time plant) the
node answers only the newest queued state, skipping (and counting) stale
ones, so a moment of overload does not turn into a growing delay, and the
friction feed-forward advances by the stamps' time difference.
``rate`` is the control rate (default ``simulation.rate``).

Input gate (see :mod:`~friction_joint.ros.nodes.common`): a state whose
position or velocity is not finite or beyond the plausible limits of the
model gear (:class:`~friction_joint.testbed.plant.InputLimits`, logged at
start), a temperature outside its plausible range, or a stamp ahead of the
clock is refused, counted and logged (throttled) and gets no command; with
``sync:=false`` the newest queued state that passes the gate is answered.
The count is logged at shutdown.
"""
from collections.abc import Sequence
import math
import sys
from typing import Any

from rclpy.node import Node
from sensor_msgs.msg import JointState, Temperature

from .answers import Answers
from .common import (declare_follower_params, Lossless, PairedInput, run_node, StampPairing,
                     take_queued)
from .ranges import (between, check_controller_params, RISE_TIME_BOUNDS, sample_rate,
                     SAMPLE_RATE_BOUNDS, warm_up_temperature)
from ..parameters import declare_gear, describe, parameter_guard
from ..qos import overridable, stream_qos
from ..startup import check_overrides_used
from ...control.controller import Controller, SineTrajectory
from ...control.gains import GainDesign
from ...models.friction import FRICTION_KINDS
from ...testbed.plant import InputLimits

__all__ = ['ControllerNode', 'main']

DEFAULTS = {'friction_ff': 'lugre', 'ff_velocity': 'measured', 'amplitude': 0.4, 'omega': 1.5,
            'offset': 0.0, 'rise_time': GainDesign.rise_time, 'overshoot': GainDesign.overshoot,
            'design_inertia': 0.0,
            'rate': 0.0,
            'sync': False}
RUNTIME = ('friction_ff', 'ff_velocity', 'amplitude', 'omega', 'offset')
VALIDATORS = {
    'friction_ff': lambda v: (None if v in FRICTION_KINDS
                              else f'must be one of {", ".join(FRICTION_KINDS)}'),
    'ff_velocity': lambda v: (None if v in ('measured', 'desired')
                              else "must be 'measured' or 'desired'"),
    'amplitude': lambda v: None if abs(v) <= 3.2 else 'must be within +-3.2 rad',
    'omega': lambda v: None if 0 <= v <= 100 else 'must be in [0, 100] rad/s',
    'offset': lambda v: None if abs(v) <= 3.2 else 'must be within +-3.2 rad',
    'rise_time': lambda v: between(v, RISE_TIME_BOUNDS, 's'),
    'overshoot': lambda v: None if 0 < v < 1 else 'must be in (0, 1)',
    'design_inertia': lambda v: (None if v >= 0 and math.isfinite(v)
                                 else "must be finite and >= 0 (0: the gear's inertia)"),
    'rate': lambda v: between(v, SAMPLE_RATE_BOUNDS, 'Hz', zero='simulation.rate'),
}


DESCRIPTORS = {
    'friction_ff': describe('friction feed-forward model: none, static, lugre or gms',
                            read_only=False),
    'ff_velocity': describe('velocity the feed-forward is evaluated at: measured or desired',
                            read_only=False),
    'amplitude': describe('reference amplitude a of q_d = offset + a sin(omega t), rad',
                          read_only=False, low=-3.2, high=3.2),
    'omega': describe('reference frequency, rad/s', read_only=False, low=0.0, high=100.0),
    'offset': describe('reference offset, rad', read_only=False, low=-3.2, high=3.2),
    'rise_time': describe('rise time the PD gains are designed for, s (at least '
                          '10 samples)', low=RISE_TIME_BOUNDS[0], high=RISE_TIME_BOUNDS[1]),
    'overshoot': describe('overshoot the PD gains are designed for (fraction)', low=0.0,
                          high=1.0),
    'design_inertia': describe("inertia the PD gains are designed for, kg m^2 (0: the gear's "
                               'joint inertia; 0.016: the paper preset, docs/design.md)'),
    'rate': describe("control rate, Hz (0: the gear's simulation.rate)"),
    'sync': describe('pair each state with the temperature of the same stamp and answer every '
                     'state (lockstep); false: answer the newest state (real time)'),
}


class ControllerNode(Answers, PairedInput, Node):
    """Wires :class:`~friction_joint.control.controller.Controller` to topics."""

    def __init__(self):
        super().__init__('controller')
        self.p = declare_follower_params(self, DEFAULTS, VALIDATORS, DESCRIPTORS)
        self.gear = declare_gear(self, own=list(self.p))
        self.joint = self.gear.joint_name
        check_controller_params(self.p, self.gear)      # gains and rate, before any allocation
        self.limits = InputLimits(self.gear)
        rate = sample_rate(self.p, self.gear)
        # design_inertia 0 (a ROS parameter cannot be None): the gear's joint inertia
        self.design = GainDesign(name='node', design_inertia=self.p['design_inertia'] or None,
                                 rise_time=self.p['rise_time'], overshoot=self.p['overshoot'])
        self.kp, self.kd = self.design.gains(self.gear.inertia)
        self.dt = 1.0 / rate
        self.ctrl = self._controller()
        self.ctrl(0.0, 0.0, warm_up_temperature(self.gear), 0.0)    # compile the kernels
        self.ctrl = self._controller()
        self.traj = SineTrajectory(self.p['amplitude'], omega=self.p['omega'],
                                   offset=self.p['offset'])
        self.pair = StampPairing(self.p['sync'])
        self.t0 = None
        self.last_ns = None
        self.last_cmd = None
        qos, opts = stream_qos(), overridable()
        self.pub = self.create_publisher(JointState, 'joint_command',
                                         stream_qos(lossless=self.p['sync']),
                                         qos_overriding_options=opts)
        if self.p['sync']:                  # lossless: wait out a killed subscriber
            self.pub = Lossless(self, self.pub)
        self.sub_state = self.create_subscription(JointState, 'joint_states', self.on_state, qos,
                                                  qos_overriding_options=opts)
        self.stale = 0
        self.sub_temp = self.create_subscription(Temperature, 'joint_temperature',
                                                 self.on_temperature, qos,
                                                 qos_overriding_options=opts)
        parameter_guard(self, {k: DEFAULTS[k] for k in RUNTIME}, VALIDATORS, self.apply)
        check_overrides_used(self)                      # a qos_overrides.* naming no entity
        self.get_logger().info(f'eq. 17 controller for {self.joint}: kp {self.kp:.1f} Nm/rad, '
                               f'kd {self.kd:.2f} Nm s/rad, friction feed-forward '
                               f'{self.p["friction_ff"]}; plausible inputs '
                               f'{self.limits.describe()}')

    def _controller(self):
        return Controller(self.gear, self.kp, self.kd, friction=self.p['friction_ff'],
                          dt=self.dt, ff_velocity=self.p['ff_velocity'])

    def apply(self, name: str, value: Any) -> None:
        self.p[name] = value
        if name in ('friction_ff', 'ff_velocity'):
            self.ctrl = self._controller()
        else:
            self.traj = SineTrajectory(self.p['amplitude'], omega=self.p['omega'],
                                       offset=self.p['offset'])
        self.get_logger().info(f'{name} set to {value!r}')

    def handle_state(self, msg):
        if self.p['sync']:
            super().handle_state(msg)
            return
        # real time: answer the newest state that passes the gate; the older ones are stale.
        # Every one is offered to the stamp order (a new timeline is confirmed by a few states
        # in a row, however many a loaded machine queues at once); only the newest is answered
        states = [s for s in map(self.gate_state, [msg] + take_queued(self.sub_state, JointState))
                  if s is not None]
        if len(states) > 1:
            self.stale += len(states) - 1
            if self._log_due('stale', 5.0):
                self.get_logger().warning(
                    f'skipped {self.stale} stale joint states so far (the loop is behind: '
                    'answering the newest)', throttle_duration_sec=2.5)
        ready = [r for state in states for item in self.pair.state(*state)
                 for r in self.dispatch(*item, answer=False)]
        if ready:
            self.process(*ready[-1])

    def restart(self) -> None:
        """Restart on a new timeline of stamps: the reference and the feed-forward afresh."""
        self.t0 = self.last_ns = self.last_cmd = None
        self.ctrl = self._controller()

    def process(self, ns: int, state: Sequence[float], xi: float) -> None:
        if ns == self.last_ns:                   # the same state again: same answer
            self.pub.publish(self.last_cmd)
            return
        if self.last_ns is not None and ns < self.last_ns:
            self._reject('a joint state older than the last one answered',
                         f'stamp {ns * 1e-9:.6f} s < {self.last_ns * 1e-9:.6f} s')
            return
        if self.t0 is None:
            self.t0 = ns
        q, qd = state
        q_d, qd_d, qdd_d = self.traj((ns - self.t0) * 1e-9)
        dt = None if self.p['sync'] or self.last_ns is None else (ns - self.last_ns) * 1e-9
        tau = self.ctrl(q, qd, xi, q_d, qd_d, qdd_d, dt=dt)
        cmd = JointState()
        cmd.header.stamp.sec, cmd.header.stamp.nanosec = divmod(ns, 1_000_000_000)
        cmd.name = [self.joint]
        cmd.position = [q_d]
        cmd.velocity = [qd_d]
        cmd.effort = [tau]
        self.last_ns, self.last_cmd = ns, cmd
        self.count_answer()
        self.pub.publish(cmd)


def main(args: list[str] | None = None) -> int | str:
    return run_node(ControllerNode, 'controller', args)


if __name__ == '__main__':
    sys.exit(main())
