# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Processes seen from /proc: a process's children and descendants, and whether it runs."""
import contextlib
import os

__all__ = ['parents', 'children', 'descendants', 'alive']


def parents():
    """Return ``{pid: parent pid}`` of every process (from /proc)."""
    parent = {}
    for entry in os.listdir('/proc'):
        if entry.isdigit():
            with contextlib.suppress(OSError, IndexError, ValueError):
                with open(f'/proc/{entry}/stat') as fh:
                    parent[int(entry)] = int(fh.read().rsplit(')', 1)[1].split()[1])
    return parent


def children(pid):
    """Return the pids whose parent is ``pid``."""
    return [k for k, p in parents().items() if p == pid]


def descendants(pid):
    """Return the pids of the processes below ``pid``."""
    parent = parents()
    found, todo = [], [pid]
    while todo:
        p = todo.pop()
        kids = [k for k, pp in parent.items() if pp == p]
        found += kids
        todo += kids
    return found


def alive(pid):
    """Whether ``pid`` is a process that has not ended (a zombie has)."""
    try:
        with open(f'/proc/{pid}/stat') as fh:
            return fh.read().rsplit(')', 1)[1].split()[0] != 'Z'
    except OSError:
        return False
