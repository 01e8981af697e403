# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Ctrl-C from the first instant of a friction_joint program: one line and exit 130.

The package's ``__init__`` calls :func:`guard` first.  A program of the package
(``python -m friction_joint ...``, ``python -m friction_joint.ros.nodes.NODE``, a
console script such as ``friction_joint``) imports the package before its own
handlers exist (``main()`` of the command line, ``run_node``): an interrupt then
raised ``KeyboardInterrupt`` inside an import, a traceback.  Until they take over,
SIGINT prints ``PROG: interrupted`` and ends the process with status 130 (nothing
has been written yet).  Only in such a program, and only when SIGINT has Python's
default handler (a process started with SIGINT ignored keeps ignoring it); a library
user importing the package keeps its handlers.  What happens before the package is
imported at all (Python's start-up, ``site``) is the interpreter's.
"""
import os
import signal
import sys

__all__ = ['guard', 'PROGRAMS', 'GUARDED']

#: the console scripts of the package (setup.py)
PROGRAMS = ('friction_joint', 'joint_sim', 'controller', 'estimator', 'record', 'replay')


def _program():
    """Return the name of the friction_joint program this process runs, or None."""
    argv0 = sys.argv[0] if sys.argv else ''
    if argv0 == '-m':            # python -m MODULE: the package of MODULE is being imported
        argv = list(getattr(sys, 'orig_argv', []))
        module = argv[argv.index('-m') + 1] if '-m' in argv[:-1] else 'friction_joint'
        return module.rpartition('.')[2] if module.startswith('friction_joint') else None
    name = os.path.basename(argv0)
    return name if name in PROGRAMS else None


def guard():
    """
    Have SIGINT end a friction_joint program in one line (status 130) until it takes over.

    Returns whether the handler was installed.
    """
    name = _program()
    if name is None or signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        return False

    def interrupted(signum, frame):
        os.write(2, f'{name}: interrupted\n'.encode())
        os._exit(130)

    try:
        signal.signal(signal.SIGINT, interrupted)
    except ValueError:           # not the main thread: leave SIGINT as it is
        return False
    return True


#: whether this process's SIGINT is guarded (done once, as the package is imported)
GUARDED = guard()
