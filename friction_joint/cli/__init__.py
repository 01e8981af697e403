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
The command line: ``friction_joint COMMAND`` and the ``record``/``replay`` console scripts.

Only this subpackage parses arguments.  Each subcommand is one module with
``NAME``, ``HELP``, ``DESCRIPTION``, ``add_arguments(parser)`` and
``run(args) -> int``; :func:`main` builds the parser from :data:`SUBCOMMANDS`.
The modules import the library lazily inside ``run`` where it needs ROS, so
``friction_joint --help`` and the ROS-free commands work without rclpy.

Errors of this package (bad input) end with a one-line message naming the
problem and exit status 2; nothing half-written is left as a result.
"""
import argparse
import importlib
import sys

from ..exceptions import FrictionJointError

__all__ = ['main', 'build_parser', 'SUBCOMMANDS']

#: subcommand modules of this package, in the order ``--help`` lists them
SUBCOMMANDS = ('classic', 'experiment', 'identify', 'demo', 'record', 'replay', 'bringup',
               'diagnose', 'import_')


def build_parser():
    """Return the ``friction_joint`` argument parser with every subcommand."""
    parser = argparse.ArgumentParser(
        prog='friction_joint',
        description='Simulated Harmonic Drive joint with thermal- and load-dependent friction.')
    sub = parser.add_subparsers(dest='command', metavar='COMMAND')
    sub.required = True
    for name in SUBCOMMANDS:
        module = importlib.import_module(f'{__name__}.{name}')
        p = sub.add_parser(module.NAME, help=module.HELP, description=module.DESCRIPTION)
        module.add_arguments(p)
        p.set_defaults(func=module.run)
    return parser


def main(argv=None):
    """Entry point of ``friction_joint``; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except FrictionJointError as exc:
        print(f'friction_joint {args.command}: error: {exc}', file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f'friction_joint {args.command}: interrupted', file=sys.stderr)
        return 130
