# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Writing results: rendered in memory, staged next to their destination, swapped in whole.

Every command that writes results declares them in an :class:`OutputSet`
before it starts working, so that a refused output costs nothing:

* an output that exists already -- a file, a symlink (never followed), a FIFO
  or other special file, a non-empty directory -- is an error naming it unless
  ``force=True``; an empty directory counts as absent;
* with ``force`` the old output is replaced as a whole: nothing of it remains
  (no stale figure of an earlier run next to a new report);
* a directory where a file is to be written, a non-directory where a
  directory is to be written, an output that is, contains or lies inside an
  input (or another output of the set), and a directory output that contains
  the current directory are errors even with ``force``.

The new outputs are built in temporary sibling directories
(``.NAME.XXXXXXXX.tmp`` next to each output), then published with renames:
each old output is moved into its staging directory and the new one renamed
into place, in the order declared; if any step fails, the outputs already
swapped are swapped back, so an error leaves either every old output
untouched or every new one complete; SIGINT, SIGTERM and SIGHUP wait until
the set is whole, old or new, and its staging directories are gone.  These
name their owner (``NAME.owner``: host, pid, start time); declaring an output
removes those of dead owners (killed runs; others, e.g. a recorder's, are
left), putting back an old output moved into one (``NAME.old``) if the
output is missing.  Files are written with mode
``0o666`` and directories with ``0o777``, less the umask.  Errors are one-line
``error`` exceptions (default :class:`~friction_joint.exceptions.OutputError`)
naming the path.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
import contextlib
import dataclasses
import os
import re
import stat
import tempfile

from ._output_staging import owner_record, remove_path, signals_held, stale_stage
from .exceptions import OutputError
from .results import ExperimentResult, json_bytes, json_clean, render_png, result_files

__all__ = ['json_clean', 'json_bytes', 'render_png', 'ExperimentResult', 'result_files',
           'OutputSet', 'publish_outputs', 'recording_inputs']

_FILE = 'file'
_DIRECTORY = 'directory'


@dataclasses.dataclass
class _Target:
    """One output of an :class:`OutputSet` and its publishing state."""

    path: str
    abspath: str
    kind: str
    label: str
    stage: str | None = None
    written: list[str] | None = None
    old: str | None = None
    swapped: bool = False
    keep: bool = False

    @property
    def staged(self):
        """Return where the new output is built (inside the staging directory)."""
        return os.path.join(self.stage, os.path.basename(self.abspath))

    def named(self):
        """Return ``label path`` for messages."""
        return f'{self.label} {self.path}'


def _existing(path, error):
    """Return what is at ``path``: None, 'a file', 'a symlink', ..., 'empty', 'directory'."""
    try:
        mode = os.lstat(path).st_mode
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:
        raise error(f'cannot check {path}: {_why(exc)}') from None
    if stat.S_ISLNK(mode):
        return 'a symlink'
    if stat.S_ISDIR(mode):
        try:
            return 'directory' if os.listdir(path) else 'empty'
        except OSError as exc:
            raise error(f'cannot list {path}: {_why(exc)}') from None
    if stat.S_ISREG(mode):
        return 'a file'
    for test, name in _SPECIAL:
        if test(mode):
            return name
    return 'a special file'


#: special files: never replaced by an output, even with ``force`` (``/dev/null`` renamed
#: away would break the machine; a FIFO or socket belongs to another program)
_SPECIAL = ((stat.S_ISFIFO, 'a FIFO'), (stat.S_ISCHR, 'a character device'),
            (stat.S_ISBLK, 'a block device'), (stat.S_ISSOCK, 'a socket'))
_SPECIAL_NAMES = tuple(name for _, name in _SPECIAL) + ('a special file',)


def _relation(a, b):
    """Return how ``a`` relates to ``b``: 'is', 'contains', 'is inside' or None."""
    pairs = [(os.path.abspath(a), os.path.abspath(b))]
    try:
        pairs.append((os.path.realpath(a), os.path.realpath(b)))
    except (OSError, ValueError):            # a NUL byte, a symlink loop: the names only
        pass
    for x, y in pairs:
        if x == y:
            return 'is'
        if y.startswith(x.rstrip(os.sep) + os.sep):
            return 'contains'
        if x.startswith(y.rstrip(os.sep) + os.sep):
            return 'is inside'
    try:
        if os.path.samefile(a, b):
            return 'is'
    except (OSError, ValueError):
        pass
    return None


def _why(exc):
    """Return the reason of an ``OSError`` for a message."""
    return exc.strerror or str(exc)


def recording_inputs(paths: Iterable[str | os.PathLike], *,
                     label: str = 'recording') -> list[tuple[str, str]]:
    """
    Return the inputs a command that reads ``paths`` (recordings) registers with its outputs.

    Each recording, and for a file that lies in a rosbag2 directory (a
    ``metadata.yaml`` beside it) that directory too: the recording is the
    whole directory, so no output may be written into it, even when the
    command was given its ``.mcap`` file only.

    Parameters
    ----------
    paths : iterable of str or os.PathLike
        The recordings (rosbag2 directories or ``.mcap`` files).
    label : str
        How the inputs are named in error messages.

    Returns
    -------
    list of tuple
        ``(label, path)`` pairs for :class:`OutputSet`'s ``inputs``.

    """
    pairs = []
    for path in paths:
        path = os.fspath(path)
        pairs.append((label, path))
        parent = os.path.dirname(os.path.abspath(path))
        try:
            is_file = os.path.isfile(path)
            in_bag = is_file and os.path.isfile(os.path.join(parent, 'metadata.yaml'))
        except (OSError, ValueError):        # a NUL in the path: not a file of a bag
            in_bag = False
        if in_bag:
            pairs.append((f'{label} {path} is part of the rosbag2 directory', parent))
    return pairs


class OutputSet:
    """
    The outputs of one command, checked up front and published together or not at all.

    Use it as a context manager (an error, or leaving the block unpublished,
    removes everything staged)::

        with OutputSet(force=force, inputs=[('--model', model)]) as outputs:
            outputs.add_directory(report_dir, label='--report')
            outputs.add_file(gear_path, label='--out')
            outputs.check()                  # before the work: refusals cost nothing
            ...                              # compute
            outputs.write_directory(report_dir, [('report.json', data), ...])
            outputs.write_file(gear_path, text)
            written = outputs.publish()

    Parameters
    ----------
    force : bool
        Replace existing outputs (as a whole) instead of refusing them.
    inputs : iterable
        The command's inputs: paths, or ``(label, path)`` pairs (``None`` paths are
        ignored).  No output may be, contain or lie inside one of them.
    error : type
        Exception class raised (one-line message naming the path).

    """

    def __init__(self, *, force: bool = False,
                 inputs: Iterable[str | os.PathLike | tuple[str, str | os.PathLike | None]] = (),
                 error: type[Exception] = OutputError) -> None:
        self.force = bool(force)
        self.error = error
        self.inputs = []
        for item in inputs:
            label, path = item if isinstance(item, tuple) else ('input', item)
            if path is not None:
                self.inputs.append((label, os.fspath(path)))
        self._targets: list[_Target] = []
        self._made: list[str] = []
        self._published = False

    def __enter__(self):
        """Return the set."""
        return self

    def __exit__(self, *exc_info):
        """Remove whatever was staged and not published."""
        self.discard()
        return False

    # ---------------------------------------------------------------- declare ---

    def add_file(self, path: str | os.PathLike, *, label: str = '--out') -> str:
        """
        Declare a file output; returns its absolute path.

        Parameters
        ----------
        path : str or os.PathLike
            The output.
        label : str
            Its option in error messages.

        Returns
        -------
        str

        """
        return self._add(path, _FILE, label)

    def add_directory(self, path: str | os.PathLike, *, label: str = '--out') -> str:
        """
        Declare a directory output (replaced as a whole); returns its absolute path.

        Parameters
        ----------
        path : str or os.PathLike
            The output.
        label : str
            Its option in error messages.

        Returns
        -------
        str

        """
        return self._add(path, _DIRECTORY, label)

    def _add(self, path, kind, label):
        if self._published:
            raise self.error('outputs already published')
        path = os.fspath(path)
        target = _Target(path, os.path.abspath(path), kind, label)
        if os.path.basename(target.abspath) in ('', '.', '..'):
            raise self.error(f'{label} {path} cannot be an output')
        if kind == _FILE and (path.endswith(os.sep) or (os.altsep and path.endswith(os.altsep))
                              or os.path.basename(path) in ('.', '..')):
            raise self.error(f'{label} {path} ends with a directory separator; give the name '
                             'of the file to write')
        if kind == _DIRECTORY and path.rstrip(os.sep + (os.altsep or '')).endswith('.mcap') \
                and not path.endswith('.mcap'):         # x.mcap/: never a rosbag2 directory
            raise self.error(f'{label} {path} ends with a directory separator; a .mcap '
                             'recording is a file: give it without the separator')
        self._sweep(target)
        self._targets.append(target)
        return target.abspath

    def _target(self, path):
        full = os.path.abspath(os.fspath(path))
        for t in self._targets:
            if t.abspath == full:
                return t
        raise self.error(f'{path} is not a declared output')

    def check(self) -> None:
        """
        Check every declared output; raise ``error`` naming the problem.

        Refuses (even with ``force``) a wrong kind, an overlap with an input or
        another output, a directory containing the current directory, an
        existing non-directory above an output; refuses existing outputs
        unless ``force`` (all of them named in one message).
        """
        existing = []
        for i, t in enumerate(self._targets):
            for label, path in self.inputs:
                rel = _relation(t.abspath, path)
                if rel:
                    raise self.error(f'{t.named()} {rel} {"an" if rel == "is" else "the"} '
                                     f'input ({label} {path}); choose another path')
            for other in self._targets[:i]:
                if _relation(t.abspath, other.abspath):
                    raise self.error(f'{t.named()} and {other.named()} overlap; choose '
                                     'separate paths')
            found = _existing(t.abspath, self.error)
            if t.kind == _DIRECTORY and _relation(t.abspath, os.getcwd()) in ('is', 'contains'):
                raise self.error(f'{t.named()} contains the current directory; it cannot be '
                                 'replaced')
            if t.kind == _FILE and found in ('empty', 'directory'):
                raise self.error(f'{t.named()} is a directory; give the file to write')
            if found in _SPECIAL_NAMES:
                raise self.error(f'{t.named()} is {found}, not a regular file or directory; '
                                 'it is never replaced by an output, even with --force')
            if t.kind == _DIRECTORY and found == 'a file':
                raise self.error(f'{t.named()} exists and is not a directory ({found[2:]})')
            if found is not None and found != 'empty':
                existing.append((t, 'a non-empty directory' if found == 'directory' else found))
            self._check_parent(t)
        if existing and not self.force:
            names = ', '.join(f'{t.named()} ({what})' for t, what in existing)
            it = 'it' if len(existing) == 1 else 'them'
            raise self.error(f'{names} exist{"s" if len(existing) == 1 else ""} already; give '
                             f'--force to replace {it}')

    def _check_parent(self, target):
        parent = os.path.dirname(target.abspath)
        probe = parent
        while not os.path.lexists(probe):
            probe = os.path.dirname(probe)
        if not os.path.isdir(probe):
            raise self.error(f'cannot create output directory {parent}: {probe} is not a '
                             'directory')

    def _sweep(self, target):            # staging directories of killed runs, old data back
        parent, name = os.path.split(target.abspath)
        pattern = re.compile(re.escape(f'.{name}.') + r'[a-z0-9_]{8}\.tmp')
        try:
            entries = os.listdir(parent)
        except OSError:
            return
        for entry in entries:
            stage = os.path.join(parent, entry)
            if not pattern.fullmatch(entry) or not stale_stage(stage, name):
                continue
            old = os.path.join(stage, f'{name}.old')
            if os.path.lexists(old) and _existing(target.abspath, self.error) in (None, 'empty'):
                try:
                    os.rename(old, target.abspath)
                except OSError:
                    continue                 # data: leave it where it is
            remove_path(stage)

    # ------------------------------------------------------------------ stage ---

    def _stage(self, target):
        if target.stage is None:
            parent = os.path.dirname(target.abspath)
            missing = []
            probe = parent
            while not os.path.lexists(probe):
                missing.append(probe)
                probe = os.path.dirname(probe)
            try:
                os.makedirs(parent, exist_ok=True)
            except OSError as exc:
                raise self.error(f'cannot create output directory {parent}: '
                                 f'{_why(exc)}') from None
            self._made.extend(missing)
            name = os.path.basename(target.abspath)
            with signals_held():            # never a staging directory without its owner
                try:
                    target.stage = tempfile.mkdtemp('.tmp', f'.{name}.', parent)
                except OSError as exc:
                    raise self.error(f'cannot write to {parent}: {_why(exc)}') from None
                self._write(os.path.join(target.stage, f'{name}.owner'),
                            owner_record(os.getpid()).encode('utf-8'), target.path)
        return target

    def staging_path(self, path: str | os.PathLike) -> str:
        """
        Return where to build output ``path``: a path in its staging directory, not yet existing.

        For commands that produce an output on disk themselves (a recording, a
        whole result tree); :meth:`publish` moves it into place.

        Parameters
        ----------
        path : str or os.PathLike
            A declared output.

        Returns
        -------
        str

        """
        return self._stage(self._target(path)).staged

    def final_path(self, path: str | os.PathLike) -> str:
        """
        Return where ``path`` (inside a staged output) will be once published; else ``path``.

        Parameters
        ----------
        path : str or os.PathLike
            A path.

        Returns
        -------
        str

        """
        full = os.path.abspath(os.fspath(path))
        for t in self._targets:
            if t.stage is not None and (full == t.staged or full.startswith(t.staged + os.sep)):
                return t.abspath + full[len(t.staged):]
        return os.fspath(path)

    def _write(self, path, data, shown):
        try:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            with os.fdopen(fd, 'wb') as fh:
                fh.write(data)
        except OSError as exc:
            raise self.error(f'cannot write {shown}: {_why(exc)}') from None

    def write_file(self, path: str | os.PathLike, data: bytes | str) -> None:
        """
        Stage the content of file output ``path``.

        Parameters
        ----------
        path : str or os.PathLike
            A declared file output.
        data : bytes or str
            The content (str: written as UTF-8).

        """
        t = self._stage(self._target(path))
        if t.kind != _FILE:
            raise self.error(f'{t.named()} is a directory output, not a file')
        self._write(t.staged, data.encode('utf-8') if isinstance(data, str) else data, t.path)

    def write_directory(self, path: str | os.PathLike, files: Iterable[tuple[str, bytes]]) -> None:
        """
        Stage directory output ``path`` with its files.

        Parameters
        ----------
        path : str or os.PathLike
            A declared directory output.
        files : iterable of tuple
            ``(file name, bytes)`` pairs.

        """
        t = self._stage(self._target(path))
        if t.kind != _DIRECTORY:
            raise self.error(f'{t.named()} is a file output, not a directory')
        try:
            os.mkdir(t.staged)
        except OSError as exc:
            raise self.error(f'cannot write {t.path}: {_why(exc)}') from None
        t.written = []
        for name, data in files:
            if not name or name != os.path.basename(name) or name in ('.', '..'):
                raise self.error(f'bad file name {name!r} for {t.named()}')
            self._write(os.path.join(t.staged, name), data, os.path.join(t.path, name))
            t.written.append(os.path.join(t.path, name))

    # ---------------------------------------------------------------- publish ---

    def publish(self) -> list[str]:
        """
        Move every staged output into place (old ones replaced), all or nothing.

        Returns
        -------
        list of str
            The paths written, as given: a file output's path; the files of a
            directory written with :meth:`write_directory`, else its path.

        """
        self.check()
        for t in self._targets:
            if t.stage is None or not os.path.lexists(t.staged):
                raise self.error(f'nothing was written for {t.named()}')
        with signals_held():                # signals: after the set is whole, old or new
            try:
                for t in self._targets:
                    current = t
                    if os.path.lexists(t.abspath):
                        os.rename(t.abspath, t.staged + '.old')
                        t.old = t.staged + '.old'     # only once moved: else none to restore
                    os.rename(t.staged, t.abspath)
                    t.swapped = True
                self._published = True
            except BaseException as exc:     # an interrupt too: never half swapped
                kept = self._rollback()
                if not isinstance(exc, OSError):
                    raise
                note = (f'; the old output is kept in {", ".join(kept)}' if kept else
                        '; nothing was changed')
                raise self.error(f'cannot write {current.named()}: {_why(exc)}{note}') from None
            finally:
                self.discard()
        return [p for t in self._targets
                for p in (t.written if t.written is not None else [t.path])]

    def _rollback(self):
        """Swap published outputs back; return where old outputs are kept if that failed."""
        kept = []
        for t in reversed(self._targets):
            try:
                if t.swapped:
                    os.rename(t.abspath, t.staged)
                    t.swapped = False
                if t.old is not None:
                    os.rename(t.old, t.abspath)
                    t.old = None
            except OSError:
                t.keep = True
                kept.append(t.old or t.abspath)
        return kept

    def discard(self) -> None:
        """Remove the staging directories (old outputs replaced by publishing with them)."""
        with signals_held():
            for t in self._targets:
                if t.stage is not None and not t.keep:
                    remove_path(t.stage)
                    t.stage = None
            for d in self._made if not self._published else ():     # deepest first
                with contextlib.suppress(OSError):
                    os.rmdir(d)
            self._made = []


def publish_outputs(targets: Sequence[tuple[str | os.PathLike, bytes | str | list]], *,
                    force: bool = False,
                    inputs: Iterable[str | os.PathLike
                                     | tuple[str, str | os.PathLike | None]] = (),
                    error: type[Exception] = OutputError) -> list[str]:
    """
    Write a set of outputs together or not at all (see :class:`OutputSet`).

    Parameters
    ----------
    targets : sequence
        ``(path, bytes)`` for a file, ``(path, [(file name, bytes), ...])`` for a
        directory (replaced as a whole).
    force : bool
        Replace existing outputs.
    inputs : iterable
        Paths or ``(label, path)`` pairs no output may overlap.
    error : type
        Exception class raised on a refused or failed output.

    Returns
    -------
    list of str
        The paths written (:meth:`OutputSet.publish`).

    """
    with OutputSet(force=force, inputs=inputs, error=error) as outputs:
        for path, content in targets:
            if isinstance(content, (bytes, bytearray, str)):
                outputs.add_file(path)
            else:
                outputs.add_directory(path)
        outputs.check()
        for path, content in targets:
            if isinstance(content, (bytes, bytearray, str)):
                outputs.write_file(path, content)
            else:
                outputs.write_directory(path, content)
        return outputs.publish()
