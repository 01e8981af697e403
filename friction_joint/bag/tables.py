# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
Reading logs as tables: delimited text (tab, semicolon, comma, whitespace) or ``.npz``.

Used by :mod:`~friction_joint.bag.importer`; errors name the file and the row.
"""
import os

import numpy as np

from ..exceptions import RecordingError

__all__ = ['read_table']


def _is_number(token):
    try:
        float(token)
    except ValueError:
        return False
    return True


def _delimiter(lines):
    """Return the delimiter of the data lines: tab, semicolon, comma or None (whitespace)."""
    for delim in ('\t', ';', ','):
        counts = {ln.count(delim) for ln in lines}
        if len(counts) == 1 and counts.pop() > 0:
            return delim
    return None


def _split(line, delim):
    return [x.strip() for x in (line.split(delim) if delim else line.split())]


def _read_text(path, skip_rows):
    try:
        with open(path, encoding='utf-8-sig') as fh:
            lines = fh.read().splitlines()
    except OSError as exc:
        raise RecordingError(f'{path}: cannot read: {exc.strerror or exc}') from None
    except UnicodeDecodeError:
        raise RecordingError(f'{path}: not a text file (CSV/TSV) nor .npz') from None
    first = skip_rows                               # index of the header or first data line
    body = [(i, ln) for i, ln in enumerate(lines) if i >= first and ln.strip()]
    if not body:
        raise RecordingError(f'{path}: no data rows (after {skip_rows} skipped rows)')
    delim = _delimiter([ln for _, ln in body[1:21]] or [body[0][1]])
    head = _split(body[0][1], delim)
    header = None
    if not all(_is_number(x) for x in head):
        header, body = [h.strip('"\'') for h in head], body[1:]
    if not body:
        raise RecordingError(f'{path}: a header line and no data rows')
    width = len(header) if header else len(_split(body[0][1], delim))
    data = np.empty((len(body), width))
    for k, (i, ln) in enumerate(body):
        row = _split(ln, delim)
        if len(row) != width:
            raise RecordingError(f'{path}: row {i + 1}: {len(row)} fields, expected {width}')
        try:
            data[k] = [float(x) for x in row]
        except ValueError:
            bad = next(x for x in row if not _is_number(x))
            raise RecordingError(f'{path}: row {i + 1}: {bad!r} is not a number') from None
    rows = np.asarray([i + 1 for i, _ in body])
    return header, data, rows


def _read_npz(path):
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {k: np.asarray(z[k]) for k in z.files}
    except (OSError, ValueError) as exc:
        raise RecordingError(f'{path}: cannot read .npz file ({exc})') from None
    if len(arrays) == 1 and next(iter(arrays.values())).ndim == 2:
        data = next(iter(arrays.values())).astype(float)
        return None, data, np.arange(1, len(data) + 1)
    bad = [k for k, v in arrays.items() if v.ndim != 1]
    lengths = {len(v) for v in arrays.values() if v.ndim == 1}
    if bad or len(lengths) != 1:
        raise RecordingError(f'{path}: an .npz log holds 1-D arrays of one length (one per '
                             'column) or a single 2-D array')
    try:
        data = np.column_stack([v.astype(float) for v in arrays.values()])
    except (TypeError, ValueError):
        raise RecordingError(f'{path}: .npz arrays must be numbers') from None
    return list(arrays), data, np.arange(1, len(data) + 1)


def read_table(path, skip_rows=0):
    """
    Read a log: delimited text (tab, semicolon, comma or whitespace) or ``.npz``.

    Parameters
    ----------
    path : str or os.PathLike
        The file.  Text: ``skip_rows`` lines skipped, then one optional header line
        (taken as a header when it is not all numbers), then one row per sample.
        ``.npz``: one 1-D array per column (named by its key) or a single 2-D array.
    skip_rows : int
        Lines skipped at the top of a text file.

    Returns
    -------
    tuple
        ``(header, data, rows)``: column names (None without a header), an ``(n, k)``
        float array and the 1-based file line of each row.

    Raises
    ------
    RecordingError
        Unreadable file, ragged rows, a field that is not a number (naming file and row).

    """
    path = os.fspath(path)
    if path.endswith('.npz'):
        return _read_npz(path)
    return _read_text(path, int(skip_rows))
