# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint record OUT``: topics recorded into a rosbag2 directory.

Also the ``record`` console script; see :func:`friction_joint.ros.record.record`.
"""
import argparse
import sys

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run', 'main']

NAME = 'record'
HELP = 'record topics into a rosbag2 recording (MCAP)'
DESCRIPTION = ('Record topics into a rosbag2 directory (version 9, MCAP, CDR) until Ctrl-C, '
               'SIGTERM or --duration; every message received is written.')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``record`` arguments to ``parser``."""
    from ..bag import CONTRACT_TYPES         # here: a Ctrl-C while loading it is handled
    parser.add_argument('out', metavar='OUT', help='rosbag2 directory to create (must not exist)')
    parser.add_argument('--topics', nargs='+', metavar='TOPIC',
                        help='topics to record, TOPIC or TOPIC:pkg/msg/Type for non-contract '
                             f'topics (default: {" ".join(CONTRACT_TYPES)})')
    parser.add_argument('--duration', type=float, metavar='S',
                        help='stop after S seconds (default: until Ctrl-C / SIGTERM)')
    parser.add_argument('--use-sim-time', action='store_true',
                        help='log times from /clock (as ros2 bag record --use-sim-time): each '
                             'message at the /clock time current when it was sent, so a '
                             'lockstep recording spans (and replays in) its simulated time; '
                             'default: receive (wall) time')
    return parser


def run(args: argparse.Namespace) -> int:
    """Record; prints the message counts."""
    from ..ros.record import format_counts, record
    counts = record(args.out, topics=args.topics, duration=args.duration,
                    args=getattr(args, 'ros_args', None),
                    use_sim_time=getattr(args, 'use_sim_time', False))
    print(f'recorded {format_counts(counts)} to {args.out}', flush=True)
    return 0


def main(args: list[str] | None = None) -> int:
    """Console script ``record`` (``ros2 run friction_joint record OUT ...``)."""
    from ._console import console_main
    return console_main(sys.modules[__name__], args)
