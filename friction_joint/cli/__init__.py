# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The command line: ``friction_joint COMMAND`` and the ``record``/``replay`` console scripts.

Only this subpackage parses arguments.  Each subcommand is one module with
``NAME``, ``HELP``, ``DESCRIPTION``, ``add_arguments(parser)`` and
``run(args) -> int``; :func:`main` builds the parser from :data:`SUBCOMMANDS`.
The modules import the library lazily inside ``run`` where it needs ROS, so
``friction_joint --help`` and the ROS-free commands work without rclpy.

Errors of this package (bad input) end with a one-line message naming the
problem and exit status 2; nothing half-written is left as a result.

SIGTERM and SIGHUP stop a command as Ctrl-C (SIGINT) does: :func:`main` has
them raise :class:`KeyboardInterrupt` where the command is (unless a signal
was ignored when it started, as under ``nohup``), so the same clean-up runs:
staged outputs are removed and the old ones left untouched; a signal that
comes while the outputs are being swapped takes effect once the swap is
complete (:class:`~friction_joint.output.OutputSet`).  The exit status is
128 + the signal number, as a shell reports a process killed by it: 130 for
SIGINT, 143 for SIGTERM, 129 for SIGHUP.  ``record`` and ``replay`` install
their own handlers for the time they run.  Before :func:`main` runs, while the
package itself loads, Ctrl-C is one line and 130 as well (:mod:`friction_joint._entry`).
"""
import importlib
import signal
import sys
import threading
import warnings

from ._console import (check_numbers, exit_now, finished, interrupts_between_imports,
                       os_error_line, quiet_cache_warnings)
from ._parser import Parser
from ..exceptions import FrictionJointError

__all__ = ['main', 'build_parser', 'SUBCOMMANDS']

#: subcommand modules of this package, in the order ``--help`` lists them
SUBCOMMANDS = ('classic', 'experiment', 'identify', 'demo', 'record', 'replay', 'bringup',
               'diagnose', 'import_', 'recover', 'fleet')


def build_parser() -> Parser:
    """Return the ``friction_joint`` argument parser with every subcommand."""
    parser = Parser(
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


class _Stopped(KeyboardInterrupt):
    """SIGTERM or SIGHUP, raised where the command is, as SIGINT raises ``KeyboardInterrupt``."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _stop(signum, frame):
    raise _Stopped(signum)


def _stop_on_signals():
    """Let SIGTERM and SIGHUP stop the command like SIGINT; return the handlers replaced."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    return {s: signal.signal(s, _stop) for s in (signal.SIGTERM, signal.SIGHUP)
            if signal.getsignal(s) == signal.SIG_DFL}


def main(argv: list[str] | None = None) -> int:
    """
    Run the ``friction_joint`` command line (the console script's entry point).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; default ``sys.argv[1:]`` (the process's
        own command line, with its warnings printed as one line each).

    Returns
    -------
    int
        The exit status: 0, 2 for bad input, 128 + N after signal N.

    """
    replaced = _stop_on_signals()
    prog = ['friction_joint']
    shown = warnings.showwarning
    if argv is None:                         # the process's entry: warnings as one line each
        warnings.showwarning = (lambda message, category, *rest:
                                print(f'{prog[0]}: warning: {message}', file=sys.stderr))
    try:
        if argv is not None:
            return _main(argv, prog)
        try:
            with interrupts_between_imports():
                return _main(argv, prog)
        except KeyboardInterrupt as exc:     # after the command's own handling, while its
            return _interrupted(exc, prog, argv)  # handlers are put back: the same line
    finally:
        warnings.showwarning = shown
        _put_back(replaced)
        if argv is None:                     # the command has ended: no traceback from an
            finished()                       # interrupt while the interpreter shuts down


def _main(argv, prog):
    """Run the command of ``argv``; ``prog[0]`` becomes its name for messages."""
    try:
        args = build_parser().parse_args(argv)
        prog[0] = f'friction_joint {args.command}'
        check_numbers(args)
        quiet_cache_warnings()
        return int(args.func(args) or 0)
    except FrictionJointError as exc:
        print(f'{prog[0]}: error: {exc}', file=sys.stderr)
        return 2
    except OSError as exc:                   # a full disk, a read-only target found late, ...
        print(f'{prog[0]}: error: {os_error_line(exc)}', file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        return _interrupted(exc, prog, argv)


def _interrupted(exc, prog, argv):
    """Print the one line for Ctrl-C, SIGTERM or SIGHUP ``exc``; return (or exit with) 128+N."""
    signum = getattr(exc, 'signum', signal.SIGINT)
    what = ('interrupted' if signum == signal.SIGINT else
            f'stopped by {signal.Signals(signum).name}')
    print(f'{prog[0]}: {what}', file=sys.stderr)
    if argv is None:
        exit_now(128 + signum)
    return 128 + signum


def _put_back(replaced):
    """
    Restore the SIGTERM and SIGHUP handlers ``replaced`` by :func:`_stop_on_signals`.

    A stop arriving while they are restored (the command has ended) is delivered again
    once the original handlers are in place: by default the process ends by it.
    """
    late = None
    while True:
        try:
            for s, handler in replaced.items():
                signal.signal(s, handler)
            break
        except _Stopped as exc:
            late = exc.signum
    if late is not None:
        signal.raise_signal(late)
