# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Reading inputs: the one gate every file the project opens goes through.

A hostile or mistaken path must not hang a command, exhaust the machine or be
misread, so before any byte is read:

* the path must exist and be readable; symlinks are followed, and what they
  point to counts;
* it must be a regular file (or a directory where a directory is expected):
  a FIFO, a socket, a character or block device (``/dev/zero``,
  ``/dev/urandom``) or a directory where a file is expected is refused, since
  opening a FIFO blocks forever and a device never ends;
* its size must be within the limit of its kind (:data:`LIMITS`), and a read
  never returns more than that limit (files whose size the kernel does not
  report, as under ``/proc``, are cut there);
* the file is opened non-blocking and checked again on the open descriptor, so
  a path swapped for a FIFO between the check and the open does not hang.

Errors are one line naming the file and the problem, raised as the caller's
exception class (the caller knows what the file was for).
"""
from __future__ import annotations

from collections.abc import Iterator
import contextlib
import os
import stat
from typing import BinaryIO

from .exceptions import InputFileError

__all__ = ['LIMITS', 'MEMORY_BUDGET', 'check_input', 'check_input_dir', 'open_input',
           'read_input']

_MB = 1 << 20
#: size limit (bytes) of an input file by kind
LIMITS = {
    'gear': 1 * _MB,               # a gear or ROS parameter YAML file
    'mapping': 1 * _MB,            # an import mapping YAML file
    'metadata': 16 * _MB,          # a rosbag2 metadata.yaml
    'recording': 64 * 1024 * _MB,  # an .mcap file (read streaming)
    'table': 64 * 1024 * _MB,      # a CSV/TSV log (read streaming, in chunks)
    'npz': 64 * 1024 * _MB,        # an .npz log (members' declared sizes checked too)
    'report': 64 * _MB,            # a Markdown report or a figure embedded into HTML
    'text': 16 * _MB,              # any other small text file the project reads
}
#: bytes of decoded numbers an input may expand to in memory (arrays of an import,
#: declared members of an .npz); larger inputs are refused or read in chunks
MEMORY_BUDGET = 1024 * _MB

_SPECIAL = ((stat.S_ISFIFO, 'a FIFO (named pipe)'), (stat.S_ISCHR, 'a character device'),
            (stat.S_ISBLK, 'a block device'), (stat.S_ISSOCK, 'a socket'))


def _what(mode):
    """Return a noun phrase for a file mode that is not a regular file or directory."""
    for test, name in _SPECIAL:
        if test(mode):
            return name
    return 'not a regular file'


def _limit_text(limit):
    if limit >= _MB:
        return f'{limit / _MB:g} MiB'
    return f'{limit} bytes'


def _why(exc):
    return exc.strerror or type(exc).__name__


def _kind_limit(kind, limit):
    if limit is not None:
        return int(limit)
    if kind not in LIMITS:
        raise KeyError(f'unknown input kind {kind!r} (kinds: {", ".join(LIMITS)})')
    return LIMITS[kind]


def _check_stat(path, st, what, limit, error):
    if stat.S_ISDIR(st.st_mode):
        raise error(f'{path}: is a directory, expected {what} file')
    if not stat.S_ISREG(st.st_mode):
        raise error(f'{path}: {_what(st.st_mode)}, not a regular file; {what} must be a '
                    'regular file')
    if st.st_size > limit:
        raise error(f'{path}: {st.st_size} bytes, larger than the {_limit_text(limit)} limit '
                    f'of {what} file')


def check_input(path: str | os.PathLike, *, kind: str = 'text', what: str | None = None,
                limit: int | None = None,
                error: type[Exception] = InputFileError) -> os.stat_result:
    """
    Check that ``path`` is a readable regular file within the size limit of its kind.

    Parameters
    ----------
    path : str or os.PathLike
        The input file.
    kind : str
        A key of :data:`LIMITS` (the size limit).
    what : str, optional
        What the file is for, in errors (default: ``'a <kind>'``).
    limit : int, optional
        Size limit (bytes) overriding the kind's.
    error : type
        Exception class raised (one line naming the file).

    Returns
    -------
    os.stat_result
        The status of the file (symlinks followed).

    Raises
    ------
    error
        Missing, unreadable, a directory, a FIFO, device or socket, or too large.

    """
    path = os.fspath(path)
    what = what or f'a {kind}'
    limit = _kind_limit(kind, limit)
    try:
        st = os.stat(path)
    except OSError as exc:
        raise error(f'{path}: cannot read {what} file: {_why(exc)}') from None
    _check_stat(path, st, what, limit, error)
    if not os.access(path, os.R_OK):
        raise error(f'{path}: cannot read {what} file: permission denied')
    return st


def check_input_dir(path: str | os.PathLike, *, what: str = 'a recording',
                    error: type[Exception] = InputFileError) -> os.stat_result:
    """
    Check that ``path`` is a directory that can be listed and entered.

    Parameters
    ----------
    path : str or os.PathLike
        The directory.
    what : str
        What the directory is, in errors.
    error : type
        Exception class raised (one line naming the directory).

    Returns
    -------
    os.stat_result
        The status of the directory.

    Raises
    ------
    error
        Missing, not a directory, or without read and search permission.

    """
    path = os.fspath(path)
    try:
        st = os.stat(path)
    except OSError as exc:
        raise error(f'{path}: cannot read {what}: {_why(exc)}') from None
    if not stat.S_ISDIR(st.st_mode):
        raise error(f'{path}: not a directory, expected {what} directory')
    if not os.access(path, os.R_OK | os.X_OK):
        raise error(f'{path}: cannot read {what} directory: permission denied')
    return st


@contextlib.contextmanager
def open_input(path: str | os.PathLike, *, kind: str = 'text', what: str | None = None,
               limit: int | None = None,
               error: type[Exception] = InputFileError) -> Iterator[BinaryIO]:
    """
    Open an input file for binary reading after :func:`check_input`.

    The file is opened with ``O_NONBLOCK`` (a FIFO swapped in after the check does not
    block) and its descriptor checked again, then switched back to blocking reads.

    Parameters
    ----------
    path : str or os.PathLike
        The input file.
    kind, what, limit, error
        As for :func:`check_input`.

    Yields
    ------
    io.BufferedReader
        The open file.

    Raises
    ------
    error
        As :func:`check_input`, or the open fails.

    """
    path = os.fspath(path)
    what = what or f'a {kind}'
    limit = _kind_limit(kind, limit)
    check_input(path, kind=kind, what=what, limit=limit, error=error)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, 'O_CLOEXEC', 0))
    except OSError as exc:
        raise error(f'{path}: cannot read {what} file: {_why(exc)}') from None
    try:
        _check_stat(path, os.fstat(fd), what, limit, error)
        os.set_blocking(fd, True)
        fh = os.fdopen(fd, 'rb')
    except BaseException:
        os.close(fd)
        raise
    with fh:
        yield fh


def read_input(path: str | os.PathLike, *, kind: str = 'text', what: str | None = None,
               limit: int | None = None, error: type[Exception] = InputFileError) -> bytes:
    """
    Read a whole input file (at most its kind's limit) after :func:`check_input`.

    Parameters
    ----------
    path : str or os.PathLike
        The input file.
    kind, what, limit, error
        As for :func:`check_input`.

    Returns
    -------
    bytes
        The content.

    Raises
    ------
    error
        As :func:`open_input`, a read error, or more bytes than the limit (a file
        whose size the kernel under-reports).

    """
    path = os.fspath(path)
    what = what or f'a {kind}'
    limit = _kind_limit(kind, limit)
    with open_input(path, kind=kind, what=what, limit=limit, error=error) as fh:
        try:
            data = fh.read(limit + 1)
        except OSError as exc:
            raise error(f'{path}: cannot read {what} file: {_why(exc)}') from None
    if len(data) > limit:
        raise error(f'{path}: larger than the {_limit_text(limit)} limit of {what} file')
    return data
