# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Body of the ``record`` / ``replay`` console scripts (``ros2 run friction_joint PROG``)."""
from __future__ import annotations

import argparse
from collections.abc import Callable, Iterator
import contextlib
import logging
import math
import os
import signal
import sys
from types import ModuleType
from typing import NoReturn

from ._parser import Parser
from ..exceptions import ArgumentError, FrictionJointError, RecordingError

__all__ = ['finished', 'interrupts_between_imports', 'console_main', 'progress_printer',
           'check_numbers', 'exit_now', 'os_error_line', 'quiet_cache_warnings']

#: what libraries log when their own on-disk cache cannot be written (a full disk, a
#: read-only home): the cache is theirs and optional; the command's outputs say the rest
_CACHE_NOISE = {'matplotlib': ('created a temporary cache directory', 'mkdir -p failed for path',
                               'is not a writable directory'),
                'matplotlib.font_manager': ('Could not save font_manager cache',)}


def _cache_noise(texts):
    """Return a logging filter dropping the records that hold one of ``texts``."""
    def keep(record):
        try:
            message = record.getMessage()
        except Exception:                   # a malformed record: leave it to logging
            return True
        return not any(t in message for t in texts)
    keep.cache_noise = True
    return keep


def quiet_cache_warnings() -> None:
    """
    Silence the warnings of libraries that could not write their own caches.

    A full disk makes matplotlib print ``Could not save font_manager cache`` before the
    command's own one-line error about the output it could not write; a cache is an
    optimisation of the library, not the command's output.  Idempotent.
    """
    for name, texts in _CACHE_NOISE.items():
        logger = logging.getLogger(name)
        if not any(getattr(f, 'cache_noise', False) for f in logger.filters):
            logger.addFilter(_cache_noise(texts))


def os_error_line(exc: OSError) -> str:
    """
    Return the one-line message of an ``OSError`` no layer below turned into a message.

    ``FILE: reason`` (``FILE -> FILE2: reason`` for a rename), the reason alone when the
    error names no file: a full disk (ENOSPC), a quota (EDQUOT), a read-only file system
    (EROFS), a permission (EACCES) found late.
    """
    where = ''
    if exc.filename is not None:
        where = os.fsdecode(exc.filename)
        if exc.filename2 is not None:
            where += f' -> {os.fsdecode(exc.filename2)}'
        where += ': '
    return f'{where}{exc.strerror or exc}'


def progress_printer(quiet: bool = False) -> Callable[[str], None] | None:
    """Return a ``progress(message)`` callable printing to stderr, or None when ``quiet``."""
    if quiet:
        return None

    def progress(message):
        print(message, file=sys.stderr, flush=True)
    return progress


def console_main(module: ModuleType, argv: list[str] | None = None) -> int:
    """
    Run the subcommand ``module`` as a console script taking ROS arguments.

    ``argv`` is a full command line including the program name, as for
    ``rclpy.init`` (default ``sys.argv``); ROS arguments (``--ros-args ...``)
    are removed before parsing and passed on to rclpy as ``args.ros_args``.
    A :class:`RecordingError` ends with ``PROG: error: ...`` and status 2,
    Ctrl-C with 130.  As the process's entry point, an interrupt after the
    command has ended (while the interpreter shuts down) is ignored.
    """
    if argv is not None:
        return _console_main(module, argv)
    try:
        try:
            with interrupts_between_imports():
                return _console_main(module, argv)
        except KeyboardInterrupt:            # after the command's end, while the guard is
            print(f'{module.NAME}: interrupted', file=sys.stderr)   # taken down: one line
            return exit_now(130)
    finally:
        finished()


#: seconds between checks whether a deferred Ctrl-C can be raised (no import running)
_RECHECK = 0.02


def _importing(frame):
    """Whether ``frame`` or a caller of it is Python's import machinery."""
    while frame is not None:
        if frame.f_code.co_filename.startswith('<frozen importlib'):
            return True
        frame = frame.f_back
    return False


@contextlib.contextmanager
def interrupts_between_imports() -> Iterator[None]:
    """
    Raise Ctrl-C's ``KeyboardInterrupt`` only where no module is being imported.

    An interrupt inside an import run from a C extension's initialisation (numba's)
    is printed there as a traceback before the command sees it.  Inside this context
    SIGINT during an import is held and raised once the import is over (checked every
    :data:`_RECHECK` s with SIGALRM); elsewhere it is raised at once, as usual.  For a
    process's entry point only (it takes SIGALRM).
    """
    def on_sigint(signum, frame):
        if _importing(frame):
            signal.setitimer(signal.ITIMER_REAL, _RECHECK)
            return
        signal.setitimer(signal.ITIMER_REAL, 0)
        current = signal.getsignal(signal.SIGINT)
        if signum == signal.SIGALRM and current is not on_sigint and callable(current):
            # a held interrupt, and the command has installed its own Ctrl-C handling since
            # (the recorder stops and finalises): the interrupt is its to handle
            current(signal.SIGINT, frame)
            return
        raise KeyboardInterrupt

    old = {s: signal.signal(s, on_sigint) for s in (signal.SIGINT, signal.SIGALRM)}
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        for s, handler in old.items():
            signal.signal(s, handler)


def finished() -> None:
    """
    Ignore Ctrl-C from now on: the command has ended and the interpreter shuts down.

    An interrupt while modules run their exit handlers (which may import) would print a
    traceback after the command's own last line.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _console_main(module, argv=None):
    """Run :func:`console_main` (its body: the handlers stay in place around it)."""
    entry = argv is None                     # the process's entry point (a console script)
    try:                                     # Ctrl-C while rclpy imports: one line, 130
        from ..ros._rclpy import ExternalShutdownException
        from ..ros.startup import remove_ros_args
        argv = list(sys.argv if argv is None else argv)
        parser = Parser(prog=module.NAME, description=module.DESCRIPTION)
        module.add_arguments(parser)
        args = parser.parse_args(remove_ros_args(argv)[1:])
        args.ros_args = argv
        check_numbers(args)
    except KeyboardInterrupt:
        print(f'{module.NAME}: interrupted', file=sys.stderr)
        return exit_now(130) if entry else 130
    except FrictionJointError as exc:
        print(f'{module.NAME}: error: {exc}', file=sys.stderr)
        return 2
    try:
        quiet_cache_warnings()
        return module.run(args)
    except RecordingError as exc:
        print(f'{module.NAME}: error: {exc}', file=sys.stderr)
        return 2
    except OSError as exc:                   # a full disk, a read-only target found late, ...
        print(f'{module.NAME}: error: {os_error_line(exc)}', file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f'{module.NAME}: interrupted', file=sys.stderr)
        return exit_now(130) if entry else 130
    except ExternalShutdownException:
        return 130


def exit_now(status: int) -> NoReturn:
    """
    End the process with ``status`` at once, after flushing stdout and stderr.

    A KeyboardInterrupt that passed through code run by ``exec`` of a string (numpy and
    numba do so while they import) marks the interpreter, which then ends itself by
    SIGINT even though the interrupt was handled; the entry points of the command line
    exit this way after Ctrl-C so that the status is the one they report (130).
    """
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(status)


def check_numbers(args: argparse.Namespace) -> None:
    """
    Check that every number option of ``args`` is finite (argparse's ``float`` takes nan, inf).

    Raises
    ------
    ArgumentError
        One line naming the option.

    """
    for dest, value in vars(args).items():
        if isinstance(value, float) and not math.isfinite(value):
            raise ArgumentError(f'--{dest.replace("_", "-")}: must be a finite number, '
                                f'got {value}')
