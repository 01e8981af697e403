# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint replay BAG``: a recording published again, with ``/clock``.

Also the ``replay`` console script; see :func:`friction_joint.ros.replay.replay`.
"""
import argparse
import sys

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run', 'main']

NAME = 'replay'
HELP = 'publish a recording again, with /clock'
DESCRIPTION = ('Publish the messages of a recording (rosbag2 directory or .mcap) with their '
               'original timing scaled by --rate, and /clock from their header stamps so '
               'nodes with use_sim_time run on recorded data.')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``replay`` arguments to ``parser``."""
    parser.add_argument('bag', metavar='BAG', help='rosbag2 directory or .mcap file')
    parser.add_argument('--rate', default='1', metavar='R',
                        help="time scale > 0 (2 = twice as fast), or 'max': as fast as possible, "
                             'in order (default 1)')
    parser.add_argument('--topics', nargs='+', metavar='TOPIC',
                        help='topics to replay (default: all in the bag)')
    parser.add_argument('--no-clock', dest='clock', action='store_false',
                        help="do not publish /clock from the header stamps (the bag's own "
                             '/clock, if any, is then replayed)')
    parser.add_argument('--loop', action='store_true', help='start over at the end until stopped')
    parser.add_argument('--wait', type=float, default=2.0, metavar='S',
                        help='wait up to S seconds for a subscriber on every topic before '
                             'playing (default 2)')
    parser.add_argument('--settle', type=float, default=0.5, metavar='S',
                        help='then wait S seconds more so that every subscriber has matched '
                             'from its side too (default 0.5)')
    return parser


def run(args: argparse.Namespace) -> int:
    """Replay; prints the message counts."""
    from ..ros.record import format_counts
    from ..ros.replay import parse_rate, replay
    counts = replay(args.bag, rate=parse_rate(args.rate), topics=args.topics, clock=args.clock,
                    loop=args.loop, wait=args.wait, settle=args.settle,
                    args=getattr(args, 'ros_args', None))
    print(f'replayed {format_counts(counts)} from {args.bag}', flush=True)
    return 0


def main(args: list[str] | None = None) -> int:
    """Console script ``replay`` (``ros2 run friction_joint replay BAG ...``)."""
    from ._console import console_main
    return console_main(sys.modules[__name__], args)
