# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A recorder's staging directory: marked, locked, flushed; found again when the recorder was killed.

``friction_joint record OUT`` writes into a hidden staging directory beside
``OUT`` (``.OUT.rec-XXXXXXXX.tmp/OUT/OUT.mcap``; ``rec-``: not one of the
staging directories of :class:`~friction_joint.output.OutputSet`, which
removes those of dead owners), marked by ``recorder.json``
(:class:`RecorderStaging`: what is recorded, the recorder's pid, the offered
QoS seen so far) and locked (``flock``) while the recorder runs, and renamed
to ``OUT`` when finished.  The recorder closes its MCAP chunk and flushes it to
disk (``fsync``) every second (:func:`flush_chunks`), so a recorder killed
without a chance to finish leaves a truncated MCAP file (no summary, no
footer) holding everything but the last second or so.

* :func:`~friction_joint.bag.recover.recover_recording` (``friction_joint
  recover PATH OUT``) turns such a file into a recording;
* :func:`partial_recording_error` is the reader's one-line error for a
  truncated file or a staging directory, naming the recovery command;
* :func:`killed_recordings` lists the staging directories that earlier,
  killed recordings to ``OUT`` left behind (``record`` names them);
* :func:`missing_recording_error` is every reader's one-line error for a
  recording that does not exist: when a recorder's staging directory for it
  is there, it says so and names the ``recover`` command with its arguments.
"""
from __future__ import annotations

import fcntl
import glob
import json
import os
import time

from ..exceptions import RecordingError
from ..inputs import check_input, read_input

__all__ = ['RecorderStaging', 'flush_chunks', 'killed_recordings', 'partial_recording_error',
           'missing_recording_error', 'recovery_command', 'staging_directory', 'staging_state',
           'read_marker', 'MARKER', 'FLUSH_PERIOD', 'STAGING_TAG']

#: file that marks a recorder's staging directory (JSON)
MARKER = 'recorder.json'
#: after ``.OUT.`` in the name of a recorder's staging directory (``.OUT.rec-XXXXXXXX.tmp``)
STAGING_TAG = 'rec-'
#: seconds between two chunk flushes (+ fsync) of the recorder: the most a SIGKILL loses
FLUSH_PERIOD = 1.0

_MAGIC = b'\x89MCAP0\r\n'


def flush_chunks(writer, *, sync=True):
    """
    Close the open chunk of a rosbags MCAP ``Writer`` and push the file to disk.

    rosbags (0.11) keeps messages in an in-memory chunk until it exceeds 1 MiB and
    writes the file header through a buffered file, so a recorder killed before
    that leaves an empty file.  This closes the chunk (if it holds a message),
    flushes the file and, with ``sync``, ``fsync``s it.  A writer without these
    internals (another storage plugin) is left alone.
    """
    storage = getattr(writer, 'storage', None)
    chunk = getattr(storage, 'chunk', None)
    bio = getattr(storage, 'bio', None)
    if chunk is None or bio is None or bio.closed:
        return
    if getattr(chunk, 'msgs', None):
        storage.close_chunk()
    bio.flush()
    if sync:
        os.fsync(bio.fileno())


class RecorderStaging:
    """
    The marker and lock of a recorder's staging directory.

    Parameters
    ----------
    directory : str
        The staging directory (created by the recorder, holds the bag directory).
    out : str
        Where the recording goes when finished.
    topics : list of (str, str)
        ``(topic, msgtype)`` recorded.
    sim_time : bool
        Log times from ``/clock``.

    Notes
    -----
    The directory is locked with ``flock`` as long as the object lives (the lock
    goes with the process, also on SIGKILL), so :func:`killed_recordings` tells a
    running recorder from a killed one.

    """

    def __init__(self, directory, out, topics, *, sim_time=False):
        self.directory = os.fspath(directory)
        self._fd = os.open(self.directory, os.O_RDONLY)
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(self._fd)
            raise
        self.info = {'out': os.path.abspath(out), 'pid': os.getpid(),
                     'started': time.strftime('%Y-%m-%dT%H:%M:%S%z'),
                     'topics': dict(topics), 'use_sim_time': bool(sim_time), 'offered_qos': {}}
        self._write()

    def _write(self):
        path = os.path.join(self.directory, MARKER)
        tmp = path + '.tmp'
        with open(tmp, 'w', encoding='utf8') as fh:
            json.dump(self.info, fh, indent=1)
        os.replace(tmp, path)

    def update(self, offered_qos):
        """Store the offered QoS profiles (topic -> list of dicts) seen so far."""
        qos = {t: list(p) for t, p in offered_qos.items()}
        if qos != self.info['offered_qos']:
            self.info['offered_qos'] = qos
            try:
                self._write()
            except OSError:
                pass                              # only metadata for a recovery

    def close(self):
        """Release the lock."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None


def read_marker(directory):
    """Return the marker of a recorder staging directory, {} if unreadable, None if absent."""
    path = os.path.join(directory, MARKER)
    if not os.path.isfile(path):
        return None
    try:
        info = json.loads(read_input(path, kind='text', error=RecordingError))
        return info if isinstance(info, dict) else {}
    except (OSError, ValueError, RecordingError):
        return {}


def staging_state(directory):
    """
    Return the state of a recorder staging directory.

    ``'running'`` (locked by its recorder), ``'killed'`` (marked, lock free),
    ``'unknown'`` (no marker, the layout of one: an older recorder's) or None (not a
    recorder's staging directory).
    """
    name = os.path.basename(os.path.normpath(directory))
    if not (name.startswith('.') and name.endswith('.tmp') and os.path.isdir(directory)):
        return None
    if read_marker(directory) is None:
        base = name[1:].rsplit('.', 2)[0]
        inner = os.path.join(directory, base, f'{base}.mcap')
        return 'unknown' if os.path.isfile(inner) else None
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return 'unknown'
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError:
        return 'running'
    finally:
        os.close(fd)
    return 'killed'


def staging_directory(path):
    """Return the recorder staging directory that ``path`` is or lies in (two levels), or None."""
    p = os.path.abspath(path)
    for _ in range(3):
        if staging_state(p):
            return p
        p = os.path.dirname(p)
    return None


def _suggest_out(staging, path, avoid):
    """Return a recovery target: the recording's own OUT if free, else ``OUT_recovered``."""
    info = (read_marker(staging) or {}) if staging else {}
    if info.get('out'):
        out = os.path.relpath(info['out'])
    elif staging:
        out = os.path.relpath(os.path.join(os.path.dirname(staging),
                                           os.path.basename(staging)[1:].rsplit('.', 2)[0]))
    else:
        out = os.path.splitext(os.path.normpath(path))[0]
    taken = {os.path.abspath(p) for p in (path, avoid) if p}
    candidate, n = out, 1
    while os.path.lexists(candidate) or os.path.abspath(candidate) in taken:
        candidate = f'{out}_recovered' + (str(n) if n > 1 else '')
        n += 1
    return candidate


def recovery_command(path, *, avoid=None):
    """
    Return ``friction_joint recover SRC OUT`` for a partial file or staging directory.

    SRC is the staging directory ``path`` lies in, if any, else ``path``; OUT the
    recording's own destination if free (and not ``avoid``), else ``OUT_recovered``.
    """
    staging = staging_directory(path)
    src = os.path.relpath(staging) if staging else os.fspath(path)
    return f'friction_joint recover {src} {_suggest_out(staging, src, avoid)}'


def _stagings(out):
    """Return ``[(directory, state)]``: the staging directories of ``out``, oldest first."""
    parent = os.path.dirname(os.path.abspath(out))
    base = os.path.basename(os.path.normpath(out))
    found = []
    for d in glob.glob(os.path.join(glob.escape(parent), f'.{glob.escape(base)}.*.tmp')):
        state = staging_state(d)
        if state:
            try:
                found.append((os.path.getmtime(d), d, state))
            except OSError:
                continue
    return [(d, state) for _, d, state in sorted(found)]


def killed_recordings(out):
    """
    Staging directories that earlier recordings to ``out`` left behind.

    Returns
    -------
    list of (str, str)
        ``(directory, state)``: state ``'killed'`` (its recorder is gone) or
        ``'unknown'`` (an older recorder's directory without a marker: killed, unless
        that recorder still runs).  Directories of running recorders are left out.

    """
    return sorted((d, state) for d, state in _stagings(out) if state in ('killed', 'unknown'))


def missing_recording_error(path: str | os.PathLike) -> RecordingError:
    """
    Return the readers' error for a recording ``path`` that does not exist.

    A recorder writes ``OUT`` into a hidden staging directory beside it and renames it
    at the end, so a recorder killed (or still running) leaves ``OUT`` missing and
    its messages in ``.OUT.rec-XXXXXXXX.tmp``: then the one-line message says so and
    names the command that recovers them (``friction_joint recover STAGING OUT``, the
    newest such directory, the others counted); a running recorder is named by its
    pid.  ``path`` may also be the ``.mcap`` file inside a missing ``OUT``.

    Parameters
    ----------
    path : str or os.PathLike
        The recording asked for (a rosbag2 directory or a ``.mcap`` file).

    Returns
    -------
    RecordingError
        The error to raise.

    """
    path = os.fspath(path)
    targets = [path]
    parent = os.path.dirname(os.path.normpath(path))
    if path.endswith('.mcap') and parent and not os.path.lexists(parent):
        targets.append(parent)                   # OUT/OUT.mcap of a recording never renamed
    for out in targets:
        found = _stagings(out)
        if not found:
            continue
        running = [d for d, state in found if state == 'running']
        if running:
            pid = (read_marker(running[-1]) or {}).get('pid', '?')
            return RecordingError(f'recording {path} does not exist yet: a recorder (pid {pid}) '
                                  f'is still writing it in {os.path.relpath(running[-1])}; '
                                  'stop it (Ctrl-C) to finish it')
        staging, state = found[-1]
        older = (f' ({len(found) - 1} older staging director'
                 f'{"y" if len(found) == 2 else "ies"} of it beside)' if len(found) > 1 else '')
        how = 'was killed' if state == 'killed' else 'was killed (or still runs)'
        return RecordingError(f'recording {path} does not exist: its recorder {how} before it '
                              f'finished, leaving what it had written in '
                              f'{os.path.relpath(staging)}{older}; recover it with: '
                              f'{recovery_command(staging)}')
    return RecordingError(f'recording {path} does not exist')


def _truncated_mcap(path):
    """Return a description if ``path`` is an MCAP file cut short (or empty), else None."""
    if os.path.lexists(path):                     # a FIFO or device: refused, never opened
        check_input(path, kind='recording', what='a recording storage', error=RecordingError)
    try:
        size = os.path.getsize(path)
        with open(path, 'rb') as fh:
            head = fh.read(len(_MAGIC))
            fh.seek(max(0, size - len(_MAGIC)))
            tail = fh.read(len(_MAGIC))
    except OSError:
        return None
    if size == 0:
        return 'is empty'
    if head == _MAGIC[:len(head)] and (size < 2 * len(_MAGIC) or tail != _MAGIC):
        return f'ends without the MCAP footer after {size} bytes'
    return None


def partial_recording_error(path: str | os.PathLike) -> RecordingError | None:
    """
    Return the reader's error for a cut-short recording at ``path``, or None.

    The one-line message names the file and the recovery command.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.mcap`` file, a rosbag2 directory or a recorder's staging directory.

    Returns
    -------
    RecordingError or None
        The error to raise; None when the recording is not cut short.

    """
    path = os.fspath(path)
    staging = staging_directory(path)
    if staging and staging_state(staging) == 'running':
        return RecordingError(f'{path}: a recorder is still writing this recording (its '
                              'staging directory is locked); stop it (Ctrl-C) to finish it')
    if os.path.isdir(path):
        files = sorted(glob.glob(os.path.join(glob.escape(path), '*.mcap')) +
                       glob.glob(os.path.join(glob.escape(path), '*', '*.mcap')))
        files = [f for f in files if not os.path.basename(f).startswith('.')]
    else:
        files = [path] if path.endswith('.mcap') else []
    for f in files:
        what = _truncated_mcap(f)
        if what == 'is empty':
            return RecordingError(f'{path}: truncated or corrupt recording: {f} is empty (a '
                                  'recorder killed before it wrote anything?); nothing to '
                                  'recover')
        if what:
            return RecordingError(
                f'{path}: truncated or corrupt recording: {f} {what} (a recorder killed before '
                f'it finished?); recover the messages it holds with: {recovery_command(path)}')
    if staging and os.path.isdir(path) and not os.path.isfile(os.path.join(path,
                                                                           'metadata.yaml')):
        return RecordingError(f'{path}: staging directory of a recording that did not finish; '
                              f'recover it with: {recovery_command(path)}')
    return None
