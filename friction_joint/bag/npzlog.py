# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Reading ``.npz`` logs: one 1-D array per column (named by its key) or a single 2-D array.

Before anything is decompressed, the file goes through the input gate
(:mod:`friction_joint.inputs`), must be a zip archive (a ``.npy`` file, a text
file or anything else under that name is named as what it is), and every
member's header is read: its dtype must be numbers (bool, integers, floats;
``datetime64``/``timedelta64`` for the time), never objects (pickles), strings,
complex or structured records, and the sizes the zip directory and the
headers declare must fit the memory budget, so a zip bomb is refused at once.

``datetime64`` and ``timedelta64`` arrays are converted exactly to seconds (a
datetime relative to its first sample, so float64 keeps the resolution) and
flagged as such; NaT is refused.
"""
import zipfile

import numpy as np

from ..exceptions import RecordingError
from ..inputs import open_input

__all__ = ['TIME_KINDS', 'read_npz']

#: dtype kinds read as time (converted to seconds)
TIME_KINDS = ('M', 'm')
_KINDS = {'b': 'bool', 'i': 'integer', 'u': 'unsigned integer', 'f': 'float'}
_REFUSED = {'O': 'objects (pickled data)', 'c': 'complex numbers', 'U': 'strings',
            'S': 'bytes strings', 'V': 'structured records'}
_NPY = b'\x93NUMPY'
_ZIP = (b'PK\x03\x04', b'PK\x05\x06')
# seconds per datetime64/timedelta64 unit
_SECONDS = {'W': 604800.0, 'D': 86400.0, 'h': 3600.0, 'm': 60.0, 's': 1.0, 'ms': 1e-3,
            'us': 1e-6, 'ns': 1e-9, 'ps': 1e-12, 'fs': 1e-15, 'as': 1e-18}


def _mib(n):
    return f'{n / (1 << 20):.1f} MiB'


def _what_instead(head):
    """Return what a file that is not a zip archive looks like, from its first bytes."""
    if head.startswith(_NPY):
        return 'a single .npy array, not an .npz archive (save the log with numpy.savez)'
    if head.startswith(_ZIP[0]):
        return 'not a valid zip archive although it starts like one'
    try:
        text = head.decode('utf-8')
    except UnicodeDecodeError:
        return 'not an .npz archive (a zip of .npy arrays)'
    if text.strip() and all(ch.isprintable() or ch in '\t\r\n' for ch in text):
        return ('a text file, not an .npz archive (a zip of .npy arrays); give a text log a '
                '.csv, .tsv or .txt name')
    return 'not an .npz archive (a zip of .npy arrays)'


def _member_header(zf, info, path):
    """Return ``(shape, dtype)`` from the .npy header of member ``info``, before its data."""
    key = info.filename[:-4]
    try:
        with zf.open(info) as fp:
            version = np.lib.format.read_magic(fp)
            if version == (1, 0):
                shape, _, dtype = np.lib.format.read_array_header_1_0(fp)
            else:
                shape, _, dtype = np.lib.format.read_array_header_2_0(fp)
    except (ValueError, OSError, EOFError, zipfile.BadZipFile, RuntimeError,
            NotImplementedError) as exc:
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise RecordingError(f'{path}: array {key!r} is not a readable .npy array ({why})') \
            from None
    if dtype.hasobject or dtype.kind in _REFUSED:
        what = _REFUSED.get(dtype.kind, 'objects (pickled data)')
        raise RecordingError(f'{path}: array {key!r} holds {what} ({dtype}), not numbers; '
                             'a log holds numbers (time also as datetime64/timedelta64)')
    if dtype.kind not in _KINDS and dtype.kind not in TIME_KINDS:
        raise RecordingError(f'{path}: array {key!r} has dtype {dtype}, not numbers')
    return tuple(int(n) for n in shape), dtype


def _as_seconds(path, key, x):
    """Return a datetime64/timedelta64 array in float seconds (a datetime from its start)."""
    unit, count = np.datetime_data(x.dtype)
    if unit not in _SECONDS:
        raise RecordingError(f'{path}: array {key!r}: unsupported time unit {x.dtype}')
    ints = x.view(np.int64)
    nat = np.flatnonzero(ints == np.iinfo(np.int64).min)
    if len(nat):
        raise RecordingError(f'{path}: row {int(nat[0]) + 1}: array {key!r} is NaT (not a '
                             'time)')
    if x.dtype.kind == 'M':
        ints = ints - ints[0] if len(ints) else ints
    return ints * (_SECONDS[unit] * count)


def _load(zf, info, path):
    key = info.filename[:-4]
    try:
        with zf.open(info) as fp:
            x = np.lib.format.read_array(fp, allow_pickle=False)
    except (ValueError, OSError, EOFError, zipfile.BadZipFile, RuntimeError) as exc:
        why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise RecordingError(f'{path}: array {key!r} cannot be read ({why})') from None
    return x


def _column(path, key, x):
    if x.dtype.kind in TIME_KINDS:
        return _as_seconds(path, key, x)
    return np.ascontiguousarray(x, dtype=float)


def read_npz(path, *, pick, row_bytes=None, budget):
    """
    Read the columns ``pick(header, width)`` of an ``.npz`` log.

    Parameters
    ----------
    path : str
        The file.
    pick : callable
        ``pick(header, width)`` -> 0-based column indices (``header``: the keys, or None
        for a single 2-D array).
    row_bytes : int, optional
        Bytes of memory the caller needs per row (default 8 per column read).
    budget : int
        Memory budget (bytes) for the decoded arrays and ``row_bytes`` per row.

    Returns
    -------
    tuple
        ``(header, columns, n)``: the keys (or None), a float64 array per index picked
        (datetime64/timedelta64 converted to seconds), the number of rows.  The keys
        carry, as attribute ``times``, index -> dtype of the columns that were times.

    Raises
    ------
    RecordingError
        One line naming the file and the problem.

    """
    with open_input(path, kind='npz', what='an .npz log', error=RecordingError) as fh:
        head = fh.read(64)
        if not head.startswith(_ZIP):
            raise RecordingError(f'{path}: {_what_instead(head)}')
        fh.seek(0)
        try:
            zf = zipfile.ZipFile(fh)
        except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
            raise RecordingError(f'{path}: not a valid zip archive ({exc}); an .npz log is '
                                 'a zip of .npy arrays') from None
        with zf:
            return _read_members(zf, path, pick, row_bytes, budget)


def _read_members(zf, path, pick, row_bytes, budget):
    infos = zf.infolist()
    if not infos:
        raise RecordingError(f'{path}: an empty .npz archive')
    bad = [i.filename for i in infos if not i.filename.endswith('.npy')]
    if bad:
        raise RecordingError(f'{path}: member {bad[0]!r} is not a .npy array; an .npz log '
                             'holds only arrays')
    declared = sum(i.file_size for i in infos)
    if declared > budget:
        raise RecordingError(f'{path}: its arrays declare {declared} bytes ({_mib(declared)}) '
                             f'uncompressed, more than the memory budget ({_mib(budget)} left)')
    heads = [(_member_header(zf, i, path), i) for i in infos]
    if len(heads) == 1 and len(heads[0][0][0]) == 2:
        (shape, dtype), info = heads[0]
        header, width, n = None, shape[1], shape[0]
    else:
        bad = [(i.filename[:-4], s) for (s, _), i in heads if len(s) != 1]
        lengths = {s[0] for (s, _), _i in heads if len(s) == 1}
        if bad or len(lengths) != 1:
            why = (f'array {bad[0][0]!r} has shape {bad[0][1]}' if bad else
                   f'the arrays have lengths {sorted(lengths)}')
            raise RecordingError(f'{path}: {why}; an .npz log holds 1-D arrays of one length '
                                 '(one per column) or a single 2-D array')
        header, width, n = [i.filename[:-4] for i in infos], len(infos), lengths.pop()
    usecols = [int(c) for c in pick(header, width)]
    need = n * (row_bytes or 8 * len(usecols))
    if header is None:
        need += n * width * 8                       # the whole 2-D array is decoded
    if need > budget:
        raise RecordingError(f'{path}: {n} rows need about {_mib(need)} of memory to import, '
                             f'more than the memory budget ({_mib(budget)} left); import a '
                             'shorter stretch')
    if header is None:
        (shape, dtype), info = heads[0]
        x = _load(zf, info, path)
        if dtype.kind in TIME_KINDS:
            raise RecordingError(f'{path}: a single 2-D array of {dtype}; time columns go in '
                                 'their own 1-D array')
        return None, [np.array(x[:, c], dtype=float) for c in usecols], n
    cols = [_column(path, header[c], _load(zf, infos[c], path)) for c in usecols]
    kinds = {c: heads[c][0][1] for c in usecols if heads[c][0][1].kind in TIME_KINDS}
    return _Keys(header, kinds), cols, n


class _Keys(list):
    """The keys of an ``.npz`` log, with the dtypes of its time-kind columns (``times``)."""

    def __init__(self, keys, times):
        super().__init__(keys)
        self.times = times
