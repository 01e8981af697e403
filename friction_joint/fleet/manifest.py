# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The fleet manifest: which recording belongs to which joint, and when (docs/fleet.md).

A CSV file (UTF-8, comma-separated, a header line) with the columns

``recording``
    path of the recording (rosbag2 directory or ``.mcap`` file), relative to the
    manifest's directory (or absolute);
``joint``
    the joint's id in the fleet (any non-empty text without control
    characters, e.g. ``robot07/j3``);
``time``
    when the recording was made, ISO 8601 (``2026-03-02T14:05:00+00:00``; a time
    without a zone is taken as UTC), within :data:`TIME_RANGE`;

and optionally ``travel``: the joint's odometer at the recording (rad of
output travel since a fixed start, non-decreasing per joint), as a robot
controller counts it: a plain decimal number (ASCII digits, no ``_``
separators).  Further columns are kept as metadata.  No field holds a NUL
byte, and a recording path or joint id no other control character and no
invisible formatting character (a bidirectional override that shows ``j01`` for
``j10``, a zero-width space that makes two ids look the same).  A
recording is listed once, also through a symlink or another spelling of its
path; at most :data:`MAX_ROWS` are listed, in a file of at most
:data:`MANIFEST_LIMIT` bytes.  A manifest that breaks a rule is a one-line
:class:`~friction_joint.exceptions.InputFileError` naming the file and the
row (header = row 1); the recordings themselves are not opened here (a
missing or broken recording is reported per recording by the run, which goes
on).
"""
from __future__ import annotations

import csv
import dataclasses
import datetime
import io
import math
import os
import re
from typing import Any

from ..exceptions import InputFileError
from ..inputs import open_input

__all__ = ['REQUIRED_COLUMNS', 'TIME_RANGE', 'MAX_ROWS', 'MANIFEST_LIMIT', 'ManifestEntry',
           'read_manifest']

REQUIRED_COLUMNS = ('recording', 'joint', 'time')
#: the times a recording may have (UTC): from the Unix epoch to the year 2200
TIME_RANGE = (datetime.datetime(1970, 1, 1, tzinfo=datetime.timezone.utc),
              datetime.datetime(2200, 1, 1, tzinfo=datetime.timezone.utc))
_DECIMAL = re.compile(r'[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?', re.ASCII)
_CONTROL = re.compile(r'[\x00-\x1f\x7f-\x9f]')
#: invisible formatting: zero-width characters, bidirectional marks, overrides
#: and isolates, the word joiner, the byte order mark
_INVISIBLE = re.compile('[\u200b-\u200f\u202a-\u202e\u2060-\u2069\ufeff]')
#: characters of a manifest's text an error message shows (a field may hold 128 KiB)
_SHOWN = 60
#: most recordings a manifest may list: a run holds every one's result in memory (a few kB
#: each), so a larger fleet is split into several manifests (refused before any work)
MAX_ROWS = 250000
#: largest manifest file read (bytes)
MANIFEST_LIMIT = 256 << 20


@dataclasses.dataclass(frozen=True)
class ManifestEntry:
    """
    One row of the manifest.

    Attributes
    ----------
    row : int
        Row number in the file (header = 1).
    recording : str
        As written in the manifest.
    path : str
        The recording's absolute path.
    joint : str
        The joint's id.
    time : datetime.datetime
        Timezone-aware (UTC when the manifest gives no zone).
    travel : float or None
        The ``travel`` column (rad), if the manifest has one.
    metadata : dict
        The further columns (name -> text).

    """

    row: int
    recording: str
    path: str
    joint: str
    time: datetime.datetime
    travel: float | None = None
    metadata: dict = dataclasses.field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """Return plain JSON types."""
        return {'row': self.row, 'recording': self.recording, 'path': self.path,
                'joint': self.joint, 'time': self.time.isoformat(), 'travel': self.travel,
                'metadata': dict(self.metadata)}


def _shown(text: str) -> str:
    """Return ``repr(text)``, clipped to :data:`_SHOWN` characters with the full length."""
    if len(text) <= _SHOWN:
        return repr(text)
    return f'{text[:_SHOWN]!r}... ({len(text)} characters)'


def _parse_time(text):
    text = text.strip()
    if not text.isascii():
        raise ValueError(text)
    t = datetime.datetime.fromisoformat(text.replace('Z', '+00:00'))
    if t.tzinfo is None:
        t = t.replace(tzinfo=datetime.timezone.utc)
    return t


def _rows(reader, path):
    """Yield the CSV records after the header; a CSV error is one line naming the file."""
    while True:
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:
            raise InputFileError(f'{path}: not a CSV file: {exc}') from None
        yield row


def read_manifest(path: str | os.PathLike[str]) -> list[ManifestEntry]:
    """
    Read and check a fleet manifest.

    Parameters
    ----------
    path : str or os.PathLike
        The manifest (CSV).

    Returns
    -------
    list of ManifestEntry
        In the file's order.

    Raises
    ------
    InputFileError
        Unreadable, not CSV with the required header, an empty field, a bad time or
        travel, a travel that decreases for a joint, a recording listed twice, no rows.

    """
    path = os.fspath(path)
    with open_input(path, kind='table', what='a fleet manifest', limit=MANIFEST_LIMIT) as fh:
        raw = fh.read(MANIFEST_LIMIT + 1)
    if len(raw) > MANIFEST_LIMIT:
        raise InputFileError(f'{path}: larger than the {MANIFEST_LIMIT >> 20} MiB limit of a '
                             'fleet manifest')
    try:
        text = raw.decode('utf-8-sig')
    except UnicodeDecodeError as exc:
        raise InputFileError(f'{path}: the fleet manifest is not UTF-8 text ({exc.reason} at '
                             f'byte {exc.start})') from None
    reader = csv.reader(io.StringIO(text, newline=''))
    try:
        first = next(reader, None)
    except csv.Error as exc:
        raise InputFileError(f'{path}: not a CSV file: {exc}') from None
    if first is None:
        raise InputFileError(f'{path}: the fleet manifest is empty: it needs a header with the '
                             f'columns {", ".join(REQUIRED_COLUMNS)}')
    header = [h.strip() for h in first]
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise InputFileError(f'{path}: row 1 (header): no column {", ".join(missing)} '
                             f'(a fleet manifest needs {", ".join(REQUIRED_COLUMNS)}; found '
                             f'{_shown(", ".join(header)) if header else "nothing"})')
    dup = sorted({h for h in header if header.count(h) > 1})
    if dup:
        raise InputFileError(f'{path}: row 1 (header): column '
                             f'{_shown(", ".join(dup))} appears twice')
    base = os.path.dirname(os.path.abspath(path))
    entries: list[ManifestEntry] = []
    seen: dict[str, int] = {}
    last_travel: dict[str, tuple[float, int]] = {}
    for k, row in enumerate(_rows(reader, path), start=2):
        if not any(cell.strip() for cell in row):
            continue                                          # blank line
        if len(entries) >= MAX_ROWS:
            raise InputFileError(f'{path}: row {k}: more than {MAX_ROWS} recordings (a run '
                                 'keeps every result in memory); split the fleet into several '
                                 'manifests')
        if len(row) != len(header):
            raise InputFileError(f'{path}: row {k}: {len(row)} fields, the header has '
                                 f'{len(header)}')
        rec = dict(zip(header, (c.strip() for c in row), strict=True))
        for col, value in rec.items():
            if '\0' in value:
                raise InputFileError(f'{path}: row {k}: column {_shown(col)} holds a '
                                     'NUL byte (not text)')
        for col in REQUIRED_COLUMNS:
            if not rec[col]:
                raise InputFileError(f'{path}: row {k}: empty {col}')
        for col in ('recording', 'joint'):
            if _CONTROL.search(rec[col]):
                raise InputFileError(f'{path}: row {k}: {col} {_shown(rec[col])} holds a '
                                     'control character (a tab, a line break, an escape)')
            hidden = _INVISIBLE.search(rec[col])
            if hidden:
                raise InputFileError(f'{path}: row {k}: {col} {_shown(rec[col])} holds an '
                                     'invisible formatting character '
                                     f'(U+{ord(hidden.group()):04X}: a bidirectional override '
                                     'or a zero-width character)')
        try:
            when = _parse_time(rec['time'])
        except (ValueError, OverflowError):
            raise InputFileError(f'{path}: row {k}: time {_shown(rec["time"])} is not '
                                 'an ISO 8601 date and time (e.g. '
                                 '2026-03-02T14:05:00+00:00)') from None
        try:
            inside = TIME_RANGE[0] <= when < TIME_RANGE[1]
        except OverflowError:                     # a zone that pushes it out of datetime's
            inside = False
        if not inside:
            raise InputFileError(f'{path}: row {k}: time {_shown(rec["time"])} is outside '
                                 f'{TIME_RANGE[0].year}..{TIME_RANGE[1].year - 1} (UTC)')
        travel: float | None = None
        if 'travel' in rec:
            text = rec['travel']
            travel = float(text) if _DECIMAL.fullmatch(text) else math.nan
            if not math.isfinite(travel) or travel < 0:
                raise InputFileError(f'{path}: row {k}: travel {_shown(text)} is not a finite '
                                     'decimal number >= 0 (rad; ASCII digits, no separators)')
        full = os.path.normpath(os.path.join(base, rec['recording']))
        same = os.path.realpath(full)
        if full in seen or same in seen:
            earlier = seen.get(full, seen.get(same))
            how = '' if full in seen else ' (the same file through a symlink)'
            raise InputFileError(f'{path}: row {k}: recording {rec["recording"]} is '
                                 f'already listed in row {earlier}{how}')
        seen[full] = seen[same] = k
        meta = {h: v for h, v in rec.items() if h not in REQUIRED_COLUMNS + ('travel',)}
        entries.append(ManifestEntry(k, rec['recording'], full, rec['joint'], when, travel,
                                     meta))
    if not entries:
        raise InputFileError(f'{path}: the fleet manifest has a header but no recordings')
    if any(e.travel is not None for e in entries):
        for e in sorted(entries, key=lambda e: (e.joint, e.time)):
            prev = last_travel.get(e.joint)
            if e.travel is None:            # the travel column is in every row or in none
                continue
            if prev is not None and e.travel < prev[0]:
                raise InputFileError(f'{path}: row {e.row}: travel {e.travel:g} rad of joint '
                                     f'{e.joint} is less than {prev[0]:g} rad at an earlier '
                                     f'time (row {prev[1]}): the odometer never decreases')
            last_travel[e.joint] = (e.travel, e.row)
    return entries
