# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint bringup``: simulator, controller, estimator (and recorder) as processes.

See :func:`friction_joint.ros.bringup.bringup`.
"""
import argparse

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'bringup'
HELP = 'start sim, controller, estimator (and recorder) as processes'
DESCRIPTION = ('Start joint_sim on the truth gear, controller and estimator on the model gear '
               '(and a recorder) as separate processes, wait, stop them cleanly and print a '
               "closing summary: each node's achieved rate and answered states, its warnings, "
               'the recording path and its message count per topic.')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``bringup`` arguments to ``parser``."""
    parser.add_argument('--model', required=True, help='gear file of controller and estimator')
    parser.add_argument('--truth', required=True, help='gear file of the simulated joint')
    parser.add_argument('--duration', type=float, required=True, help='seconds to run')
    parser.add_argument('--record', help='record the contract topics into this new bag directory')
    parser.add_argument('--mode', default='lockstep', choices=('lockstep', 'realtime'),
                        help='lockstep (default: the simulator waits for every command; '
                             'deterministic, slower than real time) or realtime (1 kHz on the '
                             'wall clock; on a busy machine the simulator waits for the '
                             "controller, see docs/ros.md 'Realtime pacing')")
    parser.add_argument('--friction', default='lugre', choices=('none', 'static', 'lugre', 'gms'))
    parser.add_argument('--amplitude', type=float, default=0.4, help='reference amplitude, rad')
    parser.add_argument('--omega', type=float, default=1.5, help='reference frequency, rad/s')
    parser.add_argument('--xi0', type=float,
                        help='initial gear temperature of the simulator, degC')
    parser.add_argument('--log-dir', help='write each process log here')
    parser.add_argument('--composed', action='store_true',
                        help='lockstep: simulator, controller and estimator in one process')
    return parser


def run(args: argparse.Namespace) -> int:
    """Bring the nodes up for ``--duration`` and stop them."""
    from ..ros.bringup import bringup
    bringup(args.model, args.truth, args.duration, record=args.record, mode=args.mode,
            friction=args.friction, amplitude=args.amplitude, omega=args.omega, xi0=args.xi0,
            log_dir=args.log_dir, composed=args.composed)
    return 0
