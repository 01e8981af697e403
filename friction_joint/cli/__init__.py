"""The ``friction_joint`` command and its subcommands.

Each subcommand lives in its own module, which provides
``register(subparsers)``; the parser it adds sets ``func(args) -> int``.
Errors of this package (bad input) end with a one-line message naming the
problem and exit status 2; nothing half-written is left as a result.
"""
import argparse
import importlib
import sys

from ..exceptions import FrictionJointError

__all__ = ['main']

#: subcommand modules, in the order ``--help`` lists them
SUBCOMMANDS = ('friction_joint.experiments.classic', 'friction_joint.experiments.paper',
               'friction_joint.identification.pipeline', 'friction_joint.demo',
               'friction_joint.ros.record', 'friction_joint.ros.replay', 'friction_joint.ros.bringup',
               'friction_joint.cli.diagnose')


def build_parser():
    parser = argparse.ArgumentParser(
        prog='friction_joint',
        description='Simulated Harmonic Drive joint with thermal- and load-dependent friction.')
    sub = parser.add_subparsers(dest='command', metavar='COMMAND')
    sub.required = True
    for name in SUBCOMMANDS:
        importlib.import_module(name).register(sub)
    return parser


def main(argv=None):
    """Entry point; returns the exit status."""
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


if __name__ == '__main__':
    sys.exit(main())
