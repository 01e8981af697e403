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

"""
``friction_joint record OUT`` (also the ``record`` console script).

Records topics into a rosbag2 directory; see :func:`friction_joint.ros.record.record`.
"""
import sys

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run', 'main']

NAME = 'record'
HELP = 'record topics into a rosbag2 recording (MCAP)'
DESCRIPTION = ('Record topics into a rosbag2 directory (version 9, MCAP, CDR) until Ctrl-C, '
               'SIGTERM or --duration; every message received is written.')


def add_arguments(parser):
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


def run(args):
    """Record; prints the message counts."""
    from ..ros.record import format_counts, record
    counts = record(args.out, topics=args.topics, duration=args.duration,
                    args=getattr(args, 'ros_args', None),
                    use_sim_time=getattr(args, 'use_sim_time', False))
    print(f'recorded {format_counts(counts)} to {args.out}', flush=True)
    return 0


def main(args=None):
    """Console script ``record`` (``ros2 run friction_joint record OUT ...``)."""
    from ._console import console_main
    return console_main(sys.modules[__name__], args)
