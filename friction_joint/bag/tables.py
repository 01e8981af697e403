# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Reading logs as tables: delimited text (tab, semicolon, comma, whitespace) or ``.npz``.

Used by :mod:`~friction_joint.bag.importer`; errors name the file and the row.

Text is read through the input gate (:mod:`friction_joint.inputs`: regular
files only) and **streamed**: whole lines in chunks of :data:`CHUNK` bytes, each
parsed at once by numpy; only the columns asked for are kept, in arrays
allocated once from a first pass that counts the lines, after checking the
memory they need against a budget (the caller's, by default
:data:`~friction_joint.inputs.MEMORY_BUDGET`).  Chunks are small: a chunk of
text being parsed costs several times its size in transient buffers.
A number is plain ASCII decimal or scientific notation (``-1.5``, ``2e-3``,
``.5``), or ``nan``/``inf`` (refused later where a column is used); Python's
other spellings (``1_000``, ``0x10``, non-ASCII digits) are errors naming the
row and the value, never misread.  ``.npz`` logs: :mod:`~friction_joint.bag.npzlog`.
"""
from array import array
import io
import os
import re

import numpy as np

from .npzlog import read_npz
from ..exceptions import RecordingError
from ..inputs import MEMORY_BUDGET, open_input

__all__ = ['CHUNK', 'MAX_LINE', 'RowLines', 'read_table']

#: bytes read and parsed at a time
CHUNK = 2 << 20
#: longest line (bytes) accepted
MAX_LINE = 1 << 20
_NUMBER = re.compile(r'[+-]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?'
                     r'|nan|inf|infinity)', re.ASCII | re.IGNORECASE)
# bytes a data chunk made of such numbers (and delimiters) may hold: anything else is
# looked at field by field (and refused with its row)
_NUMERIC_BYTES = b'0123456789+-.eE \t\r\n,;naifNAIFtyTY'
_BLANK = re.compile(r'\n[ \t\r\f\v]*(?=\n)')


class RowLines:
    """
    The 1-based file line of each row of a table, without an array of them.

    Rows run on line by line, except after skipped (blank) lines: ``starts[j]`` is the
    first row of stretch ``j`` and ``lines[j]`` its file line.
    """

    def __init__(self, starts, lines, n):
        self._starts = np.asarray(starts, dtype=np.int64)
        self._lines = np.asarray(lines, dtype=np.int64)
        self._n = int(n)

    def __len__(self):
        """Return the number of rows."""
        return self._n

    def __getitem__(self, i):
        """Return the file line of row ``i``."""
        i = int(i)
        if i < 0:
            i += self._n
        j = int(np.searchsorted(self._starts, i, side='right')) - 1
        return int(self._lines[j] + (i - self._starts[j]))


def _is_number(token):
    return _NUMBER.fullmatch(token.strip()) is not None


def _delimiter(lines, first):
    """
    Return the delimiter of the data lines: tab, semicolon, comma or None (whitespace).

    Without one all lines agree on, the first of them in the ``first`` (header) line
    (so that a ragged row is named as such).
    """
    for delim in ('\t', ';', ','):
        counts = {ln.count(delim) for ln in lines}
        if len(counts) == 1 and counts.pop() > 0:
            return delim
    return next((d for d in ('\t', ';', ',') if d in first), None)


def _split(line, delim):
    return [x.strip() for x in (line.split(delim) if delim else line.split())]


def _mib(n):
    return f'{n / (1 << 20):.1f} MiB'


def _decode(path, data, line, first):
    try:
        return data.decode('utf-8-sig' if first else 'utf-8')
    except UnicodeDecodeError as exc:
        row = line + data.count(b'\n', 0, exc.start) + 1
        raise RecordingError(f'{path}: row {row}: not UTF-8 text (byte {data[exc.start]:#04x}); '
                             'a log is a text file (CSV/TSV) or .npz') from None


def _chunks(fh, path):
    """Yield ``(text, first line index)`` of whole lines, :data:`CHUNK` bytes at a time."""
    rest, line, first = b'', 0, True
    while True:
        try:
            data = fh.read(CHUNK)
        except OSError as exc:
            raise RecordingError(f'{path}: cannot read: {exc.strerror or exc}') from None
        if not data:
            if rest.strip():
                yield _decode(path, rest + b'\n', line, first), line
            return
        buf = rest + data if rest else data
        cut = buf.rfind(b'\n')
        if cut < 0:
            if len(buf) > MAX_LINE:
                raise RecordingError(f'{path}: row {line + 1}: a line longer than '
                                     f'{_mib(MAX_LINE)}; not a log')
            rest = buf
            continue
        rest = buf[cut + 1:]
        text = _decode(path, buf[:cut + 1], line, first)
        first = False
        yield text, line
        line += text.count('\n')


def _count_lines(fh, path):
    n, last = 0, b'\n'
    while True:
        try:
            data = fh.read(CHUNK)
        except OSError as exc:
            raise RecordingError(f'{path}: cannot read: {exc.strerror or exc}') from None
        if not data:
            return n + (last != b'\n')
        n += data.count(b'\n')
        last = data[-1:]


def _head(path, chunks, skip_rows):
    """Skip ``skip_rows`` lines; return the next (22 non-blank or all) and their first line."""
    parts, start = [], None
    for text, line in chunks:
        if start is None:
            n = text.count('\n')
            if line + n <= skip_rows:
                continue
            cut = 0
            for _ in range(skip_rows - line):
                cut = text.index('\n', cut) + 1
            text, line = text[cut:], max(line, skip_rows)
            start = line
        parts.append(text)
        head = ''.join(parts)
        if sum(1 for ln in head.splitlines() if ln.strip()) >= 22:
            return head, start
    return ''.join(parts), start


def _check_fields(path, text, line, delim, width):
    """Raise on the first row of ``text`` that is ragged or holds a field not a number."""
    for k, ln in enumerate(text.split('\n')):
        if not ln.strip():
            continue
        row = _split(ln, delim)
        if len(row) != width:
            raise RecordingError(f'{path}: row {line + k + 1}: {len(row)} fields, expected '
                                 f'{width}')
        for x in row:
            if not _is_number(x):
                raise RecordingError(f'{path}: row {line + k + 1}: {x!r} is not a number '
                                     '(plain decimal or scientific notation, e.g. -1.5e-3)')


class _Text:
    """The state of reading the data rows of one text file."""

    def __init__(self, path, delim, width, usecols, capacity):
        self.path, self.delim, self.width, self.usecols = path, delim, width, usecols
        self.cols = [np.empty(capacity) for _ in usecols]
        self.capacity = capacity
        self.n = 0
        self.starts, self.lines = array('q'), array('q')   # 8 bytes a stretch

    def _stretch(self, line):
        """Rows from now on start at (0-based) file line ``line``."""
        if not self.starts or self.lines[-1] + (self.n - self.starts[-1]) != line + 1:
            self.starts.append(self.n)
            self.lines.append(line + 1)

    def add(self, text, line):
        """Parse ``text`` (whole lines starting at 0-based file line ``line``)."""
        if _BLANK.search('\n' + text):             # blank lines: parse what lies between
            self._with_blanks(text, line)
            return
        self._stretch(line)
        self._parse(text, line)

    def _with_blanks(self, text, line):
        k0, part = 0, []
        for k, ln in enumerate(text.split('\n')[:-1]):
            if ln.strip():
                if not part:
                    k0 = k
                part.append(ln)
            elif part:
                self._stretch(line + k0)
                self._parse('\n'.join(part) + '\n', line + k0)
                part = []
        if part:
            self._stretch(line + k0)
            self._parse('\n'.join(part) + '\n', line + k0)

    def _parse(self, text, line):
        if text.encode('ascii', 'replace').translate(None, _NUMERIC_BYTES):
            _check_fields(self.path, text, line, self.delim, self.width)
        try:
            block = np.loadtxt(io.StringIO(text), delimiter=self.delim, comments=None,
                               ndmin=2, dtype=float)
        except ValueError:
            block = None
        if block is None or block.shape[1] != self.width:
            _check_fields(self.path, text, line, self.delim, self.width)
            raise RecordingError(f'{self.path}: rows {line + 1}...: cannot be read as numbers')
        m = len(block)
        if self.n + m > self.capacity:
            raise RecordingError(f'{self.path}: grew while being read')
        for out, c in zip(self.cols, self.usecols, strict=True):
            out[self.n:self.n + m] = block[:, c]
        self.n += m


def _read_text(path, skip_rows, pick, row_bytes, budget):
    with open_input(path, kind='table', what='a log', error=RecordingError) as fh:
        chunks = _chunks(fh, path)
        head, start = _head(path, chunks, skip_rows)
        lines = [(k, ln) for k, ln in enumerate(head.split('\n')[:-1]) if ln.strip()]
        if not lines:
            raise RecordingError(f'{path}: no data rows (after {skip_rows} skipped rows)')
        delim = _delimiter([ln for _, ln in lines[1:21]] or [lines[0][1]], lines[0][1])
        first = _split(lines[0][1], delim)
        header = None
        if not all(_is_number(x) for x in first):
            header = [h.strip('"\'') for h in first]
            if len(lines) == 1:
                raise RecordingError(f'{path}: a header line and no data rows')
        width = len(header) if header else len(first)
        usecols = [int(c) for c in pick(header, width)]
        fh.seek(0)
        capacity = _count_lines(fh, path) - skip_rows - (header is not None)
        need = max(capacity, 0) * (row_bytes or 8 * len(usecols))
        if need > budget:
            raise RecordingError(
                f'{path}: {capacity} rows need about {_mib(need)} of memory to import, more '
                f'than the memory budget ({_mib(budget)} left); import a shorter stretch')
        reader = _Text(path, delim, width, usecols, max(capacity, 0))
        fh.seek(0)
        chunks = _chunks(fh, path)
        skip = start + (lines[0][0] + 1 if header else lines[0][0])
        for text, line in chunks:
            if line + text.count('\n') <= skip:
                continue
            if line < skip:
                cut = 0
                for _ in range(skip - line):
                    cut = text.index('\n', cut) + 1
                text, line = text[cut:], skip
            reader.add(text, line)
    if reader.n == 0:
        raise RecordingError(f'{path}: a header line and no data rows' if header else
                             f'{path}: no data rows (after {skip_rows} skipped rows)')
    cols = [c[:reader.n] for c in reader.cols]
    return header, cols, RowLines(reader.starts, reader.lines, reader.n)


def read_table(path, skip_rows=0, *, pick=None, row_bytes=None, budget=MEMORY_BUDGET):
    """
    Read some columns of a log: delimited text (tab, semicolon, comma or whitespace) or ``.npz``.

    Parameters
    ----------
    path : str or os.PathLike
        The file.  Text: ``skip_rows`` lines skipped, then one optional header line
        (taken as a header when it is not all numbers), then one row per sample.
        ``.npz``: one 1-D array per column (named by its key) or a single 2-D array.
    skip_rows : int
        Lines skipped at the top of a text file.
    pick : callable, optional
        ``pick(header, width)`` -> the 0-based indices of the columns to read
        (``header`` a list of names or None); default all.
    row_bytes : int, optional
        Bytes of memory the caller needs per row (default 8 per column read): the
        rows times this must be within ``budget``, else the file is refused before
        being decoded.
    budget : int
        Memory budget (bytes).

    Returns
    -------
    tuple
        ``(header, columns, rows)``: column names (None without a header), a float64
        array per index picked, and the 1-based file line of each row (:class:`RowLines`;
        for ``.npz`` the 1-based index).

    Raises
    ------
    RecordingError
        A file that is not a regular readable file, not text nor ``.npz``, too large
        for the budget, ragged rows, a field that is not a number (naming file and row).

    """
    path = os.fspath(path)
    pick = pick or (lambda header, width: range(width))
    if path.endswith('.npz'):
        header, cols, n = read_npz(path, pick=pick, row_bytes=row_bytes, budget=budget)
        return header, cols, RowLines([0], [1], n)
    return _read_text(path, int(skip_rows), pick, row_bytes, budget)
