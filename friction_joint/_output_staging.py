# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Staging directories of the output sets (:mod:`friction_joint.output`): owners, held signals.

Not a recorder's staging directory: that is :mod:`friction_joint.bag.staging`.
"""
import contextlib
import os
import shutil
import signal
import socket
import stat
import threading
import time

__all__ = ['remove_path', 'signals_held', 'owner_record', 'stale_stage']


def remove_path(path):
    """Remove a file, symlink or directory tree; errors are ignored."""
    try:
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path, ignore_errors=True)
        else:
            os.unlink(path)
    except OSError:
        pass


@contextlib.contextmanager
def signals_held():
    """Hold SIGINT, SIGTERM and SIGHUP back inside the block, deliver them after it."""
    held, saved = [], {}
    try:
        if threading.current_thread() is threading.main_thread():   # else no signals here
            for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
                if signal.getsignal(s) not in (None, signal.SIG_IGN):   # None: set in C
                    saved[s] = signal.signal(s, lambda signum, frame: held.append(signum))
        yield
    finally:
        for s, handler in saved.items():
            signal.signal(s, handler)
        for s in dict.fromkeys(held):
            signal.raise_signal(s)


def owner_record(pid):
    """Return the owner record of process ``pid``: host, pid, start time (from /proc)."""
    try:
        with open(f'/proc/{pid}/stat', 'rb') as fh:
            started = fh.read().rsplit(b')', 1)[1].split()[19].decode()
    except (OSError, IndexError, UnicodeDecodeError):
        started = '-'
    return f'{socket.gethostname()} {pid} {started}'


def stale_stage(stage, name):
    """Whether staging directory ``stage`` of output ``name`` belongs to no live process."""
    age = 0.0
    try:
        st = os.lstat(stage)
        if not stat.S_ISDIR(st.st_mode):
            return False
        age = time.time() - st.st_mtime
        with open(os.path.join(stage, f'{name}.owner'), encoding='utf-8') as fh:
            host, pid, started = fh.read().split()
        pid = int(pid)
    except FileNotFoundError:                # no record: ours (before records) if it holds
        return age > 3600.0 and os.path.lexists(os.path.join(stage, f'{name}.old'))  # .old
    except (OSError, ValueError):
        return False
    if host != socket.gethostname() or pid <= 0:
        return False                         # another machine's: not ours to judge
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except OSError:                          # exists, another user's
        return False
    return started != '-' and owner_record(pid).split()[2] not in ('-', started)    # pid reused
