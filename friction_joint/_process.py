# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Child processes that end with their parent: the Linux parent-death signal.

A process killed with SIGKILL runs no handler and cannot stop its children:
``prctl(PR_SET_PDEATHSIG, SIG)`` has the kernel send SIG to a child when the
thread that started it ends.  :func:`end_with_parent` sets it in the child
(and sends SIG at once when the parent has already gone);
:func:`parent_death_preexec` is the ``preexec_fn`` of a ``subprocess.Popen``
doing so.  Elsewhere than on Linux both do nothing.
"""
import ctypes
import os
from typing import Any, Callable

__all__ = ['end_with_parent', 'parent_death_preexec']

_PR_SET_PDEATHSIG = 1                    # linux/prctl.h
_prctl: Callable[..., Any] | None
try:                                     # looked up before any fork: a child only calls it
    _prctl = ctypes.CDLL(None, use_errno=True).prctl
except (OSError, AttributeError):        # not Linux (or no libc symbol): nothing to set
    _prctl = None


def end_with_parent(signum, parent=None):
    """
    Have this process get ``signum`` when its parent ends; returns whether it was set.

    ``parent`` is the pid the parent had when it started this process (default: the
    current parent): if the process has been re-parented since, it gets ``signum`` now.
    """
    if _prctl is None:
        return False
    parent = os.getppid() if parent is None else parent
    if _prctl(_PR_SET_PDEATHSIG, int(signum), 0, 0, 0) != 0:
        return False
    if os.getppid() != parent:
        os.kill(os.getpid(), signum)
    return True


def parent_death_preexec(signum):
    """Return a ``preexec_fn``: the child gets ``signum`` when this process ends."""
    parent = os.getpid()

    def preexec():
        end_with_parent(signum, parent)
    return preexec
