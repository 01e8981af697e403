# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Foreign logs (CSV/TSV/NPZ) -> the topics of a recording (``friction_joint import``).

Each input file is one run.  Its columns are picked by a mapping
(:data:`QUANTITIES` -> ``COL[:unit]``, ``COL`` a header name or a 0-based
index) and converted to SI and the joint convention of docs/interfaces.md
(*Interfaces*):

* **Units** (:data:`UNITS`, :mod:`~friction_joint.bag.units`): time
  s/ms/us/ns/min/h; position rad/deg/rev or, for a linear device,
  m/cm/mm/um; velocity rad/s, deg/s, rev/s, rpm, m/s, mm/s, um/s; torques
  Nm/Nmm/mNm/kNm or forces N/kN/mN/uN; current A/mA; temperature degC/K/degF.  Without a
  unit the one in brackets of the header name (``Position [mm]``) is taken
  (brackets holding anything else are an error), else SI.  A value that is
  not finite once converted is an error naming the column and row.
* **Linear devices** map to the joint with a radius ``r`` (default 1 m):
  ``q [rad] = x [m] / r``, ``qd [rad/s] = v [m/s] / r`` and
  ``tau [Nm] = F [N] * r``.  The mapping used is returned (and written into the
  recording's ``metadata.yaml`` by the command).
* **Time**: stamps must increase by at least 1 ns (the recording's
  resolution) and fit its int64 nanosecond stamps (else an error naming the
  file and row).  A
  run is split into pieces where a step exceeds :data:`SPLIT` median sample
  intervals; each piece is resampled onto a uniform grid of the file's median
  interval by linear interpolation (stamps already on the grid are kept), so
  nothing is interpolated across a gap.
* **Pieces**: the first file starts at t = 0; every further file starts
  :func:`file_gap` (at least :data:`FILE_GAP` = 10 s) after the previous one ends,
  so no derivative or fit of a reader bridges two runs.
* **Velocity**: when not logged, the centred difference of the position within
  each piece (one-sided at its ends; ``/joint_states`` must carry a velocity).
* **Drive torque or friction**: ``torque`` is the drive torque τ (effort).  A
  log of the friction itself (``friction``, no ``torque``) is written as the
  effort with τ = τ_r (+ τ_ext when a ``load`` is logged): the friction torque
  τ_r of eq. 2, which is subtracted from the drive torque, so it has the sign of
  the velocity while sliding (the drive torque that overcomes it).  A logged
  force *on the moving body* opposes motion and needs ``flip_friction``; a
  column that, as given, mostly opposes the velocity gets a warning naming the
  option (never flipped silently).  In friction mode inertia is negligible (the
  base gear file should have a tiny inertia, e.g. 1e-9 kg m², as gear files need
  one > 0) and ``/link_torque`` carries the logged load, or 0 when there is none.
* **Motor current** (``current``, with ``torque_constant`` K and ``gear_ratio`` N,
  :mod:`~friction_joint.bag.mapping`): the drive torque τ := I K N, recorded as
  ``torque_from_current``.
* ``temperature`` becomes ``/joint_temperature`` (optional, at least
  −273.15 °C), ``load`` the measured τ_ext on ``/link_torque``.
* **Memory**: the files are read in chunks (:mod:`~friction_joint.bag.tables`),
  only the columns mapped are kept, every step works on them in place or a
  block at a time (:mod:`~friction_joint.bag.blockwise`), and logs whose import
  and writing need more than :data:`IMPORT_BUDGET` (per row :data:`ROW_BYTES`
  plus 8 per column kept plus :data:`WRITE_BYTES` per topic written, all files
  together) are refused before they are decoded, with one line naming the size.
"""
from __future__ import annotations

import json
import os
from typing import Any

import numpy as np

from .blockwise import (first_where, gradient, grid, increasing_ns, interp, off_grid,
                        opposed_fraction, spans, unwrap)
from .consistency import check_signals
from .mapping import check_columns, current_torque, load_mapping
from .tables import read_table
from .topics import NS
from .units import convert, header_unit, mapping_text, parse_column, QUANTITIES, SI, UNITS
from ..exceptions import RecordingError

__all__ = ['QUANTITIES', 'UNITS', 'FILE_GAP', 'SPLIT', 'IMPORT_BUDGET', 'ROW_BYTES', 'WRITE_BYTES',
           'ImportedLog',
           'parse_column', 'load_mapping', 'file_gap', 'import_logs']

#: smallest time gap (s) between the runs of two files
FILE_GAP = 10.0
#: a step of the stamps longer than this many median intervals splits a run into pieces
SPLIT = 5.0
#: memory (bytes) the rows of the logs of one import may take (:data:`ROW_BYTES` and the
#: columns a row), besides the fixed cost of the process (about 0.3 GB: the modules, a chunk
#: of text being parsed, the writer's blocks), so that a 1 GB CSV of four columns (23 M rows)
#: is imported in under 2 GB (``benchmarks/bench_import_memory.py``)
IMPORT_BUDGET = 3 << 29
#: bytes of memory an import needs per row of a log besides 8 per column it keeps (the time,
#: the columns mapped, the velocity when not logged, a zero load): the scratch of resampling
#: (the new time and one new column at a time, 16), of checking (one column, in place) and of
#: joining the files (one column at a time), plus a margin; every other temporary is a
#: block of :data:`~friction_joint.bag.blockwise.BLOCK` rows
ROW_BYTES = 24
#: bytes of memory writing a recording takes per message beyond the arrays written (the
#: streaming :func:`~friction_joint.bag.write_recording` works a block at a time; stamps
#: out of order would take 16 a message, which an import never writes)
WRITE_BYTES = 0
#: stamps within this fraction of an interval of the uniform grid are kept as they are
_ON_GRID = 1e-3
#: a friction column opposing the velocity on more than this fraction of the sliding
#: samples gets the --flip-friction warning
_OPPOSED = 0.6
#: largest |time| (s) the recording's int64 nanosecond stamps hold, and its longest span
_TIME_LIMIT = (2**63 - 1) / NS
_SPAN_LIMIT = 2.0**31
_ZERO_C = -273.15


def _resolve(path, header, width, quantity, spec):
    """Return the 0-based index, display name and unit (None: not given) of ``spec``."""
    col, unit = spec
    if isinstance(col, int):
        if not 0 <= col < width:
            raise RecordingError(f'{path}: no column {col} for {quantity} (the file has '
                                 f'{width} columns, 0-based)')
        return col, (header[col] if header else f'column {col}'), unit
    if not header or col not in header:
        have = ', '.join(repr(h) for h in header) if header else 'no header line'
        raise RecordingError(f'{path}: no column {col!r} for {quantity} (columns: {have})')
    where = [i for i, h in enumerate(header) if h == col]
    if len(where) > 1:
        raise RecordingError(f'{path}: the header names {len(where)} columns {col!r} (0-based '
                             f'columns {", ".join(map(str, where))}) for {quantity}; give the '
                             'column by its index or rename it')
    return where[0], col, unit


# ------------------------------------------------------------------------- conversion ---

def _check_time(path, t, rows):
    n = len(t)
    big = first_where(n, lambda a, b: np.abs(t[a:b]) > _TIME_LIMIT)
    if big is not None:
        raise RecordingError(f'{path}: row {rows[big]}: time {t[big]:.9g} s does not fit the '
                             "recording's int64 nanosecond stamps "
                             f'(|t| <= {_TIME_LIMIT:.3g} s); a wrong time unit?')
    i = first_where(n, lambda a, b: np.diff(t[a:b + 1]) <= 0, overlap=1)
    if i is not None:
        i += 1
        raise RecordingError(f'{path}: row {rows[i]}: time {t[i]:.9g} s does not increase '
                             f'(previous row {t[i - 1]:.9g} s); time stamps must increase')
    i = first_where(n, lambda a, b: np.diff(t[a:b + 1]) < 1.0 / NS, overlap=1)
    if i is not None:
        i += 1
        raise RecordingError(f'{path}: row {rows[i]}: time step {t[i] - t[i - 1]:.3g} s from '
                             "the previous row, below 1 ns, the recording's resolution; a "
                             'wrong time unit?')
    if t[-1] - t[0] >= _SPAN_LIMIT:
        raise RecordingError(f'{path}: the time spans {t[-1] - t[0]:.6g} s, more than a '
                             f'recording holds ({_SPAN_LIMIT:.0f} s); a wrong time unit?')


def _pieces(t):
    """Index ranges split where a step exceeds SPLIT median intervals; the median."""
    d = np.diff(t)
    dt = float(np.median(d, overwrite_input=True))
    del d
    cuts = [np.flatnonzero(np.diff(t[a:b + 1]) > SPLIT * dt) + (a + 1)
            for a, b in spans(len(t), 1)]
    bounds = np.concatenate([[0]] + cuts + [[len(t)]])
    return [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:], strict=True)], dt


def _grid_size(t, dt):
    """Return the size of the uniform grid of ``dt`` over ``t`` (None: ``t`` is on it)."""
    m = int(np.floor((t[-1] - t[0]) / dt * (1 + 1e-9) + 1e-9)) + 1
    if m == len(t) and off_grid(t, dt) <= _ON_GRID * dt:
        return None
    return m


def _resample(path, rows, t, picked, ranges, dt):
    """
    Put the pieces on the uniform grid of ``dt`` (each from its first stamp), in place.

    Stamps already on the grid are kept.  Returns the new time, the pieces' new index
    ranges and how many were resampled; ``picked``'s columns are replaced one at a time
    (memory: the new time and one new column besides the old ones).
    """
    sizes = [_grid_size(t[a:b], dt) for a, b in ranges]
    moved = [m is not None for m in sizes]
    if not any(moved):
        return t, ranges, 0
    sizes = [b - a if m is None else m for (a, b), m in zip(ranges, sizes, strict=True)]
    if min(sizes) < 2:
        a, b = ranges[sizes.index(min(sizes))]
        raise RecordingError(f'{path}: rows {rows[a]}-{rows[b - 1]}: a piece shorter than the '
                             f'median interval {dt:.6g} s; at least 2 intervals are needed')
    offsets = np.cumsum([0] + sizes)
    out = [(int(o), int(o) + m) for o, m in zip(offsets[:-1], sizes, strict=True)]
    new_t = np.empty(int(offsets[-1]))
    for (a, b), (c, d), m in zip(ranges, out, moved, strict=True):
        if m:
            for u, w in spans(d - c):
                new_t[c + u:c + w] = grid(u, w, dt, t[a])
        else:
            new_t[c:d] = t[a:b]
    for k in list(picked):
        col = np.empty(len(new_t))
        for (a, b), (c, d), m in zip(ranges, out, moved, strict=True):
            if m:
                interp(col[c:d], new_t[c:d], t[a:b], picked[k][a:b])
            else:
                col[c:d] = picked[k][a:b]
        picked[k] = col                             # the old column is freed
    return new_t, out, sum(moved)


def file_gap(dts):
    """Return the time gap (s) put between two files: max(FILE_GAP, 10 x the largest interval)."""
    return max(FILE_GAP, 10.0 * max(dts, default=0.0))


class ImportedLog:
    """
    The result of :func:`import_logs`.

    Parameters
    ----------
    topics : dict
        Topic -> dict of arrays, the input of :func:`~friction_joint.bag.write_recording`.
    mapping : dict
        What was done, JSON-able: per quantity the column, unit and conversion, the
        radius, the mode, the files with their pieces and time offsets.
    notes : list of str
        Lines for the user (conversions, resampling, velocity, inertia).
    warnings : list of str
        Lines for the user that point at a likely mistake (sign of the friction column).

    """

    def __init__(self, topics: dict[str, dict[str, np.ndarray]], mapping: dict, notes: list[str],
                 warnings: list[str]) -> None:
        self.topics = topics
        self.mapping = mapping
        self.notes = notes
        self.warnings = warnings

    def metadata(self) -> dict[str, str]:
        """Return the mapping as ``{key: str}``, the custom data of ``metadata.yaml``."""
        return {'friction_joint.import': json.dumps(self.mapping, sort_keys=True)}


def _row_bytes(columns):
    """Return the memory (bytes) an import of ``columns`` needs per row (the estimate)."""
    topics = 1 + ('friction' in columns or 'load' in columns) + ('temperature' in columns)
    kept = len(columns) + ('velocity' not in columns) + ('friction' in columns
                                                         and 'load' not in columns)
    return ROW_BYTES + 8 * kept + WRITE_BYTES * topics


def _read(path, columns, options, budget):
    """Read the columns of one file; return ``{quantity: (array, name, unit)}``, rows, bytes."""
    found = {}

    def pick(header, width):
        for q in QUANTITIES:
            if q in columns:
                found[q] = _resolve(path, header, width, q, columns[q])
        return sorted({idx for idx, _, _ in found.values()})

    row_bytes = _row_bytes(columns)
    header, cols, rows = read_table(path, options['skip_rows'], pick=pick, row_bytes=row_bytes,
                                    budget=budget)
    by_index = dict(zip(sorted({idx for idx, _, _ in found.values()}), cols, strict=True))
    times = getattr(header, 'times', {})
    picked, used = {}, set()
    for q, (idx, name, unit) in found.items():
        x = by_index[idx]
        if idx in used:
            x = x.copy()                            # converted in place: one array each
        used.add(idx)
        if idx in times:
            if q != 'time' or unit not in (None, 's'):
                raise RecordingError(
                    f'{path}: column {name!r} is {times[idx]}, a time in its own unit'
                    + ('' if q == 'time' else f', not a {q}')
                    + ('; give it without a unit' if q == 'time' else ''))
            unit = 's'
        if unit is None and header is not None:
            unit = header_unit(q, name, path)
        picked[q] = (x, name, unit or SI[q])
    return picked, rows, len(rows) * row_bytes


def _one_file(path, columns, options):
    """Read and convert one file; returns the list of pieces and what was done."""
    raw, rows, used = _read(path, columns, options, IMPORT_BUDGET - options['used'])
    options['used'] += used
    radius = options['radius']
    picked, mapping = {}, {}
    for q in QUANTITIES:
        if q in raw:
            x, name, unit = raw.pop(q)
            picked[q] = convert(q, x, unit, radius, path=path, name=name, rows=rows)
            mapping[q] = {'column': name, 'unit': unit,
                          'conversion': mapping_text(q, name, unit, radius)}
    if 'current' in picked:                         # tau := I K N (docs: bag.mapping)
        mapping['current'] = current_torque(picked['current'], mapping['current']['column'],
                                            mapping['current']['unit'], *options['motor'],
                                            path=path, rows=rows)
        picked['torque'] = picked.pop('current')
    if len(picked['time']) < 3:
        raise RecordingError(f'{path}: {len(picked["time"])} rows, at least 3 are needed')
    if 'temperature' in picked:
        cold = np.flatnonzero(picked['temperature'] < _ZERO_C)
        if len(cold):
            i = int(cold[0])
            raise RecordingError(f'{path}: row {rows[i]}: temperature '
                                 f'({mapping["temperature"]["column"]}) '
                                 f'{picked["temperature"][i]:.6g} degC is below absolute zero')
    t = picked.pop('time')
    _check_time(path, t, rows)
    if options['unwrap']:
        if UNITS['position'][mapping['position']['unit']][1]:
            raise RecordingError(f'{path}: --unwrap applies to angles, the position is in '
                                 f'{mapping["position"]["unit"]}')
        unwrap(picked['position'])
    ranges, dt = _pieces(t)
    for a, b in ranges:
        if b - a < 3:
            raise RecordingError(f'{path}: rows {rows[a]}-{rows[b - 1]}: a piece of {b - a} '
                                 f'sample(s) between gaps (> {SPLIT:g} x the median interval '
                                 f'{dt:.6g} s); at least 3 are needed')
    t, ranges, resampled = _resample(path, rows, t, picked, ranges, dt)
    if 'velocity' not in picked:
        qd = np.empty(len(t))
        with np.errstate(all='ignore'):             # an overflow is refused by _file_checks
            for a, b in ranges:
                gradient(picked['position'][a:b], t[a:b], qd[a:b])
        picked['velocity'] = qd
    return t, picked, ranges, dt, mapping, resampled


def _effort(cols, flip, friction_mode):
    """
    Return the effort column and the friction sign warning's fraction (friction mode).

    In friction mode the friction column becomes the effort in place (negated with
    ``flip``, plus the load): the fraction is found before.
    """
    if 'torque' in cols:
        return cols.pop('torque'), None
    x = cols.pop('friction')
    if flip:
        x = np.negative(x, out=x)
    frac = opposed_fraction(cols['velocity'], x) if friction_mode else None
    if 'load' in cols:
        with np.errstate(all='ignore'):             # an overflow is refused by _file_checks
            for a, b in spans(len(x)):
                x[a:b] += cols['load'][a:b]
    return x, frac


def _check_stamps(path, t):
    """Raise unless ``t`` (s, from 0) gives strictly increasing int64 ns stamps."""
    if t[-1] >= _SPAN_LIMIT:
        raise RecordingError(f'{path}: the files end at {t[-1]:.6g} s of the recording, more '
                             f'than it holds ({_SPAN_LIMIT:.0f} s)')
    if not increasing_ns(t, NS):
        raise RecordingError(f'{path}: two samples fall on the same nanosecond of the '
                             "recording's stamps; a sample interval of at least 1 ns is needed")


def _concat(parts):
    return parts[0] if len(parts) == 1 else np.concatenate(parts)


def _file_checks(path, t, cols, flip_friction, frac, joint_name):
    """Per file: what a reader would refuse; the friction sign warning."""
    fields = {k: cols[f] for k, f in (('q', 'position'), ('qd', 'velocity'),
                                      ('effort', 'effort'), ('xi', 'temperature'),
                                      ('tau', 'load')) if f in cols}
    for k, x in fields.items():                     # a derivative or sum that overflowed
        i = first_where(len(x), lambda a, b, x=x: ~np.isfinite(x[a:b]))
        if i is not None:
            raise RecordingError(f'{path}: the {k} at t = {t[i] - t[0]:.9g} s of the file is not '
                                 'finite (an overflow of the values logged)')
    check_signals(path, joint_name, t, (fields['q'], fields['qd'], fields['effort']),
                  xi=fields.get('xi'), tau=fields.get('tau'))
    if frac is None or frac <= _OPPOSED:
        return None
    flag = 'without' if flip_friction else 'with'
    return (f'{path}: the friction as written opposes the velocity on {100 * frac:.0f} % '
            'of the sliding samples: the convention is tau_r of eq. 2 (the sign of the '
            f'velocity while sliding); the column looks sign-flipped, import {flag} '
            '--flip-friction')


def import_logs(paths: list[str | os.PathLike],
                columns: dict[str, tuple[int | str, str | None]], *, radius: float = 1.0,
                unwrap: bool = False, flip_friction: bool = False, skip_rows: int = 0,
                joint_name: str = 'joint', velocity_from_position: bool = False,
                torque_constant: float | None = None, gear_ratio: float | None = None
                ) -> ImportedLog:
    """
    Convert logs (one run per file) into the topics of one recording.

    Parameters
    ----------
    paths : sequence of str or os.PathLike
        CSV/TSV/whitespace-delimited text files or ``.npz`` files, one run each.
    columns : dict
        Quantity (:data:`QUANTITIES`) -> ``(column, unit)`` from :func:`parse_column`;
        ``time``, ``position`` and one of ``torque`` / ``friction`` / ``current`` are
        required.
    radius : float
        Radius (m) mapping a linear device to the joint (q = x / r, τ = F r).
    unwrap : bool
        Unwrap an angle logged modulo a turn (wrapped encoder).
    flip_friction : bool
        Negate the ``friction`` column (a log of the force acting on the moving body).
    skip_rows : int
        Lines skipped at the top of each text file before its header.
    joint_name : str
        Joint name written into the JointState messages (non-empty).
    velocity_from_position : bool
        Write the centred difference of the position as the velocity, also when a
        ``velocity`` column is mapped (which is then not read): for a velocity that
        disagrees with its position (other units, another sign).
    torque_constant : float, optional
        K (N m/A, motor side) of a ``current`` column: τ = I K N (needed with one).
    gear_ratio : float, optional
        N of a ``current`` column (default 1): the torque at the joint.

    Returns
    -------
    ImportedLog

    Raises
    ------
    RecordingError
        One line naming the problem and the file (and row): unreadable file, unknown
        column or unit, a value that is not a number or not finite once converted,
        time stamps that do not increase by at least 1 ns, a piece too short, a log
        too large for the memory budget, an inconsistent mapping, and whatever a reader
        of the recording would refuse (:func:`~friction_joint.bag.consistency.check_contents`:
        absurd samples, a velocity that is not the position's derivative, a temperature
        outside physical bounds), per file and for the files joined.

    """
    check_columns(columns, radius=radius, joint_name=joint_name,
                  torque_constant=torque_constant, gear_ratio=gear_ratio)
    ignored = columns.get('velocity') if velocity_from_position else None
    if ignored is not None:
        columns = {k: v for k, v in columns.items() if k != 'velocity'}
    if not paths:
        raise RecordingError('no input files given')
    options = {'radius': float(radius), 'unwrap': bool(unwrap), 'skip_rows': int(skip_rows),
               'used': 0, 'motor': (torque_constant, 1.0 if gear_ratio is None else gear_ratio)}
    friction_mode = 'friction' in columns
    out: dict[str, list[np.ndarray]] = {k: [] for k in ('t', 'q', 'qd', 'effort', 'tau', 'xi')}
    files: list[dict[str, Any]] = []
    notes: list[str] = []
    warnings: list[str] = []
    mapping: dict[str, Any] = {}
    dts: list[float] = []
    start, end = 0.0, None
    for path in (os.fspath(p) for p in paths):
        t, cols, ranges, dt, mapping, resampled = _one_file(path, columns, options)
        if files:
            start = end + file_gap(dts + [dt])
        offset = start - t[0]
        dts.append(dt)
        cols['effort'], frac = _effort(cols, flip_friction, friction_mode)
        warning = _file_checks(path, t, cols, flip_friction, frac, joint_name)
        if warning:
            warnings.append(warning)
        spans_ = [[float(t[a] + offset), float(t[b - 1] + offset)] for a, b in ranges]
        t += offset                                 # the file's own array
        for a, b in ranges:
            _check_stamps(path, t[a:b])
        out['t'].append(t)
        out['q'].append(cols.pop('position'))
        out['qd'].append(cols.pop('velocity'))
        out['effort'].append(cols.pop('effort'))
        if friction_mode or 'load' in columns:
            out['tau'].append(cols.pop('load') if 'load' in cols else np.zeros(len(t)))
        if 'temperature' in cols:
            out['xi'].append(cols.pop('temperature'))
        end = float(t[-1])
        files.append({'path': path, 'offset_s': offset, 'sample_interval_s': dt,
                      'samples': len(t), 'pieces': spans_, 'resampled_pieces': resampled})
        del t, cols
    cat = {}
    for k in list(out):
        if out[k]:
            cat[k] = _concat(out.pop(k))            # one file: its arrays, not a copy
    topics = {'/joint_states': {'t': cat['t'], 'q': cat['q'], 'qd': cat['qd'],
                                'effort': cat['effort'], 'name': joint_name}}
    if friction_mode or 'load' in columns:
        topics['/link_torque'] = {'t': cat['t'], 'tau': cat['tau']}
    if 'temperature' in columns:
        topics['/joint_temperature'] = {'t': cat['t'], 'xi': cat['xi']}
    if len(files) > 1:                              # the files joined, as a reader sees them
        check_signals(' + '.join(f['path'] for f in files), joint_name, cat['t'],
                      (cat['q'], cat['qd'], cat['effort']), xi=cat.get('xi'), tau=cat.get('tau'))
    linear = any(UNITS[q][m['unit']][1] for q, m in mapping.items())
    info = {'columns': mapping, 'radius_m': options['radius'] if linear else None,
            'unwrap': options['unwrap'], 'files': files, 'gap_s': file_gap(dts),
            'mode': 'friction' if friction_mode else 'drive_torque',
            'velocity': 'logged' if 'velocity' in columns else 'centred difference per piece',
            'velocity_from_position': bool(velocity_from_position)}
    if 'current' in mapping:
        info['torque_from_current'] = mapping['current']
    if ignored is not None:
        info['velocity'] += (f' (--velocity-from-position: the velocity column '
                             f'{ignored[0]!r} not used)')
    for q, m in mapping.items():
        notes.append(f'{q}: {m["conversion"]}')
    if linear:
        notes.append(f'linear device: q [rad] := x [m] / {options["radius"]:g} m, '
                     f'tau [Nm] := F [N] * {options["radius"]:g} m (--radius)')
    if ignored is not None:
        notes.append(f'velocity: --velocity-from-position: the column {ignored[0]!r} is not '
                     'used; centred difference of the position within each piece')
    elif 'velocity' not in columns:
        notes.append('velocity: not logged, centred difference of the position within each '
                     'piece (no piece bridged)')
    if friction_mode:
        info['friction_sign'] = 'flipped' if flip_friction else 'as logged'
        info['inertia'] = 'negligible'
        notes.append(f'friction mode: effort := {"-" if flip_friction else "+"}friction'
                     + (' + load' if 'load' in columns else '') + ' (tau_r of eq. 2, sign '
                     'of the velocity while sliding); inertia negligible: give the base gear '
                     'file a tiny inertia (e.g. 1e-9 kg m^2); /link_torque = '
                     + ('the load' if 'load' in columns else '0'))
    npieces = sum(len(f['pieces']) for f in files)
    nres = sum(f['resampled_pieces'] for f in files)
    notes.append(f'{len(files)} file(s), {npieces} piece(s) (split at steps > {SPLIT:g} x the '
                 f'median interval), {nres} resampled onto a uniform grid; files '
                 f'{file_gap(dts):g} s apart')
    return ImportedLog(topics, info, notes, warnings)
