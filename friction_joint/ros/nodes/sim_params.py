# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The parameters of ``joint_sim``: defaults, validators, descriptors and the checks against the gear.

Every parameter is bounded to a physical range before anything is allocated:
the static bounds (:data:`VALIDATORS`, also the ranges ``ros2 param describe``
shows) and, once the gear is known, :func:`check_sim_params` (``publish_rate``
at most ``simulation.rate``, ``command_timeout`` at least one step and longer than
``max_lead``, ``xi0``
and ``q0`` within the plausible temperature and position of the gear).
"""
from __future__ import annotations

from collections.abc import Mapping
import math
from typing import Any, TYPE_CHECKING

from .ranges import (between, DURATION_BOUNDS, PUBLISH_RATE_BOUNDS, RESEND_BOUNDS,
                     topics_problem, WAIT_BOUNDS)
from ..parameters import describe
from ...exceptions import GearConfigError
from ...gear.schema import INT64_RANGE
from ...testbed.watchdog import REACTIONS

if TYPE_CHECKING:
    from ...gear import GearParams
    from ...testbed import InputLimits

__all__ = ['DEFAULTS', 'VALIDATORS', 'DESCRIPTORS', 'check_sim_params']

DEFAULTS = {'mode': 'realtime', 'publish_rate': 1000.0, 'duration': 0.0, 'xi0': float('nan'),
            'q0': 0.0, 'seed': -1, 'friction_model': '', 'resend_period': 0.2,
            'wait_subscribers': 1, 'start_delay': 0.5, 'follow': '', 'window': 300,
            'wait_recorder': '', 'command_timeout': 0.05, 'timeout_reaction': 'zero',
            'max_lead': 0.02, 'lead_wait': 0.5}
VALIDATORS = {
    'mode': lambda v: (None if v in ('realtime', 'lockstep')
                       else "must be 'realtime' or 'lockstep'"),
    'publish_rate': lambda v: between(v, PUBLISH_RATE_BOUNDS, 'Hz'),
    'duration': lambda v: between(v, DURATION_BOUNDS, 's', zero='run forever'),
    'seed': lambda v: (None if v == -1 or 0 <= v <= INT64_RANGE[1]
                       else "must be -1 (the gear's simulation.seed) or >= 0"),
    'friction_model': lambda v: (None if v in ('', 'static', 'lugre', 'gms')
                                 else 'must be static, lugre or gms'),
    'resend_period': lambda v: between(v, RESEND_BOUNDS, 's'),
    'wait_subscribers': lambda v: between(v, (0, 1000, 'peers on one topic'), ''),
    'start_delay': lambda v: between(v, WAIT_BOUNDS, 's'),
    'follow': topics_problem,
    'window': lambda v: between(v, (1, 10_000_000, 'states held by a follower'), ''),
    'wait_recorder': lambda v: topics_problem(v, allow=('loop',)),
    'command_timeout': lambda v: between(v, WAIT_BOUNDS, 's', zero='no watchdog'),
    'timeout_reaction': lambda v: (None if v in REACTIONS
                                   else f'must be {" or ".join(REACTIONS)}'),
    'max_lead': lambda v: between(v, WAIT_BOUNDS, 's', zero='never wait for the controller'),
    'lead_wait': lambda v: between(v, WAIT_BOUNDS, 's', zero='never wait for the controller'),
}


DESCRIPTORS = {
    'mode': describe('realtime (own tick loop at publish_rate) or lockstep (advance when the '
                     'command of the last state arrives; publishes /clock)'),
    'publish_rate': describe('realtime: state publish rate, Hz (at most simulation.rate)',
                             low=PUBLISH_RATE_BOUNDS[0], high=PUBLISH_RATE_BOUNDS[1]),
    'duration': describe('simulated seconds after which the node ends (0: run forever)',
                         low=0.0, high=DURATION_BOUNDS[1]),
    'xi0': describe('initial gear temperature, degC (NaN: thermal.initial of the gear)'),
    'q0': describe('initial joint position, rad'),
    'seed': describe('sensor noise seed (-1: simulation.seed of the gear)', low=-1,
                     high=INT64_RANGE[1], integer=True),
    'friction_model': describe('friction model of the plant: static, lugre or gms (empty: '
                               'friction.model of the gear)'),
    'resend_period': describe('lockstep: resend the last state after this many seconds '
                              'without a command, s', low=RESEND_BOUNDS[0],
                              high=RESEND_BOUNDS[1]),
    'wait_subscribers': describe('start when this many subscribers of joint_states have '
                                 'matched', low=0, high=1000, integer=True),
    'start_delay': describe('seconds to wait after the subscribers have matched, s',
                            low=0.0, high=WAIT_BOUNDS[1]),
    'follow': describe('lockstep: comma-separated topics on which followers echo the state '
                       'stamps they processed (e.g. external_torque); the simulation waits '
                       'for them'),
    'window': describe('lockstep: steps a follower may lag behind before the simulation waits',
                       low=1, high=10_000_000, integer=True),
    'wait_recorder': describe("comma-separated topics (or 'loop': the closed loop's) a recorder "
                              'must announce on recorder_ready before the first state'),
    'command_timeout': describe('simulated seconds without a valid joint_command after which '
                                'the drive takes timeout_reaction (0: no watchdog; else at '
                                'least one simulation step), s', low=0.0, high=WAIT_BOUNDS[1]),
    'timeout_reaction': describe('the drive on a command timeout: zero (torque off, the joint '
                                 'coasts) or brake (a damping torque that stops the joint)'),
    'max_lead': describe('realtime: simulated seconds the joint may run ahead of the newest '
                         'state a valid command answered; beyond it the simulation waits '
                         'for the controller (its clock slows; 0: never waits, as hardware)',
                         low=0.0, high=WAIT_BOUNDS[1]),
    'lead_wait': describe('realtime: wall seconds the simulation waits for a lagging '
                          'controller before it runs on without it (the watchdog decides)',
                          low=0.0, high=WAIT_BOUNDS[1]),
}


def check_sim_params(p: Mapping[str, Any], xi0: float, gear: GearParams,
                     limits: InputLimits) -> None:
    """
    Check the simulator's parameters ``p`` (and ``xi0``) against the gear.

    Raises
    ------
    GearConfigError
        ``parameter NAME: problem`` (one line).

    """
    sim = gear.section('simulation')
    assert sim is not None  # a section with defaults
    rate = sim['rate']
    if p['publish_rate'] > rate:
        raise GearConfigError(f"parameter publish_rate: {p['publish_rate']:g} Hz is faster than "
                              f'the simulation (simulation.rate {rate:g} Hz of the gear)')
    if 0 < p['command_timeout'] < 1.0 / rate:
        raise GearConfigError(f"parameter command_timeout: {p['command_timeout']:g} s is shorter "
                              f'than one simulation step ({1.0 / rate:g} s); 0 turns the '
                              'watchdog off')
    timeout, lead = p['command_timeout'], p['max_lead']
    if p['mode'] == 'realtime' and 0 < timeout <= lead:
        raise GearConfigError(f'parameter max_lead: {lead:g} s is not shorter than '
                              f'command_timeout ({timeout:g} s): every command answering the '
                              'newest state the simulation may hold would be stale')
    if p['mode'] == 'realtime' and 0 < lead < 1.0 / p['publish_rate']:
        raise GearConfigError(f'parameter max_lead: {lead:g} s is shorter than one tick '
                              f"(1 / publish_rate = {1.0 / p['publish_rate']:g} s); 0 turns "
                              'the pacing off')
    if not math.isnan(xi0):
        why = limits.check('temperature', xi0)
        if why:
            raise GearConfigError(f'parameter xi0: {why}')
    why = limits.check('position', p['q0'])
    if why:
        raise GearConfigError(f'parameter q0: {why}')
