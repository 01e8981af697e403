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
Foreign logs (CSV/TSV/NPZ) -> the topics of a recording (``friction_joint import``).

Each input file is one run.  Its columns are picked by a mapping
(:data:`QUANTITIES` -> ``COL[:unit]``, ``COL`` a header name or a 0-based
index) and converted to SI and the joint convention of the README
(*Interfaces*):

* **Units** (:data:`UNITS`): time s/ms/us; position rad/deg/rev or, for a
  linear device, m/mm/um; velocity rad/s, deg/s, rev/s, m/s, mm/s, um/s;
  torques Nm/Nmm or forces N/mN/uN; temperature degC/K.  Without a unit the
  one in brackets of the header name (``Position [mm]``) is taken, else SI.
* **Linear devices** map to the joint with a radius ``r`` (default 1 m):
  ``q [rad] = x [m] / r``, ``qd [rad/s] = v [m/s] / r`` and
  ``tau [Nm] = F [N] * r``.  The mapping used is returned (and written into the
  recording's ``metadata.yaml`` by the command).
* **Time**: stamps must increase (else an error naming the file and row).  A
  run is split into pieces where a step exceeds :data:`SPLIT` median sample
  intervals; each piece is resampled onto a uniform grid of the file's median
  interval by linear interpolation (stamps already on the grid are kept), so
  nothing is interpolated across a gap.
* **Pieces**: the first file starts at t = 0; every further file starts
  :func:`file_gap` (at least :data:`GAP` = 10 s) after the previous one ends,
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
* ``temperature`` becomes ``/joint_temperature`` (optional), ``load`` the
  measured τ_ext on ``/link_torque``.
"""
import json
import math
import os
import re

import numpy as np

from .tables import read_table
from ..exceptions import RecordingError

__all__ = ['QUANTITIES', 'UNITS', 'GAP', 'SPLIT', 'ImportedLog', 'parse_column',
           'load_mapping', 'file_gap', 'import_logs']

#: the mapping keys, in the order they are reported
QUANTITIES = ('time', 'position', 'velocity', 'torque', 'friction', 'load', 'temperature')

_TORQUE = {'Nm': (1.0, False), 'Nmm': (1e-3, False), 'N': (1.0, True), 'mN': (1e-3, True),
           'uN': (1e-6, True)}
#: quantity -> unit -> (factor to SI, linear: scaled by the radius)
UNITS = {
    'time': {'s': (1.0, False), 'ms': (1e-3, False), 'us': (1e-6, False)},
    'position': {'rad': (1.0, False), 'deg': (math.pi / 180.0, False),
                 'rev': (2.0 * math.pi, False), 'm': (1.0, True), 'mm': (1e-3, True),
                 'um': (1e-6, True)},
    'velocity': {'rad/s': (1.0, False), 'deg/s': (math.pi / 180.0, False),
                 'rev/s': (2.0 * math.pi, False), 'm/s': (1.0, True), 'mm/s': (1e-3, True),
                 'um/s': (1e-6, True)},
    'torque': _TORQUE, 'friction': _TORQUE, 'load': _TORQUE,
    'temperature': {'degC': (1.0, False), 'K': (1.0, False)},
}
_SI = {'time': 's', 'position': 'rad', 'velocity': 'rad/s', 'torque': 'Nm', 'friction': 'Nm',
       'load': 'Nm', 'temperature': 'degC'}
_ALIASES = {'N m': 'Nm', 'N*m': 'Nm', 'N.m': 'Nm', 'N mm': 'Nmm',
            '°C': 'degC', 'C': 'degC', 'sec': 's', 'rad/sec': 'rad/s'}

#: smallest time gap (s) between the runs of two files
GAP = 10.0
#: a step of the stamps longer than this many median intervals splits a run into pieces
SPLIT = 5.0
#: stamps within this fraction of an interval of the uniform grid are kept as they are
_ON_GRID = 1e-3
#: a friction column opposing the velocity on more than this fraction of the sliding
#: samples gets the --flip-friction warning
_OPPOSED = 0.6
_OPTIONS = ('radius', 'unwrap', 'flip_friction', 'skip_rows')


def _unit_name(text):
    text = str(text).strip().replace('µ', 'u').replace('μ', 'u')
    return _ALIASES.get(text, text)


def _unit(quantity, unit, where):
    unit = _unit_name(unit)
    if unit not in UNITS[quantity]:
        raise RecordingError(f'{where}: unknown {quantity} unit {unit!r} (known: '
                             f'{", ".join(UNITS[quantity])})')
    return unit


def parse_column(quantity, text, where):
    """
    Parse a column spec ``COL[:unit]`` of one quantity.

    Parameters
    ----------
    quantity : str
        One of :data:`QUANTITIES`.
    text : str or int
        A header name or a 0-based index, optionally followed by ``:unit`` (the part
        after the last colon is the unit: a header name with a colon in it needs one).
    where : str
        The option or file the spec came from (start of error messages).

    Returns
    -------
    tuple
        ``(column, unit)``: column an int (index) or str (name); unit a key of
        ``UNITS[quantity]`` or None (from the header, else SI).

    Raises
    ------
    RecordingError
        Empty column or unknown unit.

    """
    if quantity not in UNITS:
        raise RecordingError(f'{where}: unknown quantity {quantity!r} (known: '
                             f'{", ".join(QUANTITIES)})')
    if isinstance(text, bool) or not isinstance(text, (str, int)):
        raise RecordingError(f'{where}: {quantity}: expected COL[:unit], got {text!r}')
    text = str(text)
    col, unit = text, None
    if ':' in text:                                 # the part after the last colon is a unit
        col, tail = text.rsplit(':', 1)
        unit = _unit(quantity, tail, f'{where}: {quantity}')
    col = col.strip()
    if not col:
        raise RecordingError(f'{where}: {quantity}: no column given')
    return (int(col) if re.fullmatch(r'\d+', col) else col), unit


def load_mapping(path):
    """
    Read a mapping file: YAML with the keys of :data:`QUANTITIES` (``COL[:unit]``).

    Optional keys: ``radius`` (m), ``unwrap``, ``flip_friction`` (bools),
    ``skip_rows`` (int).

    Returns
    -------
    tuple
        ``(columns, options)``: quantity -> ``(column, unit)``, and the options given.

    Raises
    ------
    RecordingError
        Unreadable, not a mapping, an unknown key or a bad value (naming the file).

    """
    import yaml
    path = os.fspath(path)
    try:
        with open(path, 'rb') as fh:
            data = fh.read(1 << 20)
        doc = yaml.safe_load(data.decode('utf-8'))
    except OSError as exc:
        raise RecordingError(f'{path}: cannot read mapping file: {exc.strerror or exc}') from None
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        why = str(exc).splitlines()[0]
        raise RecordingError(f'{path}: not a YAML mapping file ({why})') from None
    if not isinstance(doc, dict):
        raise RecordingError(f'{path}: a mapping file is a YAML mapping of '
                             f'{", ".join(QUANTITIES)} to COL[:unit]')
    unknown = [str(k) for k in doc if k not in QUANTITIES + _OPTIONS]
    if unknown:
        raise RecordingError(f'{path}: unknown key(s) {", ".join(unknown)} (keys: '
                             f'{", ".join(QUANTITIES + _OPTIONS)})')
    columns = {k: parse_column(k, v, path) for k, v in doc.items() if k in QUANTITIES}
    options = {k: doc[k] for k in _OPTIONS if k in doc}
    for key in ('unwrap', 'flip_friction'):
        if key in options and not isinstance(options[key], bool):
            raise RecordingError(f'{path}: {key} must be true or false')
    if 'skip_rows' in options and (isinstance(options['skip_rows'], bool)
                                   or not isinstance(options['skip_rows'], int)
                                   or options['skip_rows'] < 0):
        raise RecordingError(f'{path}: skip_rows must be a whole number >= 0')
    if 'radius' in options:
        r = options['radius']
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not 0 < r < math.inf:
            raise RecordingError(f'{path}: radius must be a positive number (m)')
        options['radius'] = float(r)
    return columns, options


def _header_unit(quantity, name):
    m = re.search(r'[\[(]([^\])]+)[\])]\s*$', name or '')
    if m and _unit_name(m.group(1)) in UNITS[quantity]:
        return _unit_name(m.group(1))
    return None


def _pick(path, header, data, quantity, spec):
    """Return the column of ``spec`` as an array, its display name and unit."""
    col, unit = spec
    if isinstance(col, int):
        if not 0 <= col < data.shape[1]:
            raise RecordingError(f'{path}: no column {col} for {quantity} (the file has '
                                 f'{data.shape[1]} columns, 0-based)')
        name = header[col] if header else f'column {col}'
        idx = col
    else:
        if not header or col not in header:
            have = ', '.join(repr(h) for h in header) if header else 'no header line'
            raise RecordingError(f'{path}: no column {col!r} for {quantity} (columns: {have})')
        idx, name = header.index(col), col
    unit = unit or _header_unit(quantity, name) or _SI[quantity]
    return data[:, idx], name, unit


# ------------------------------------------------------------------------- conversion ---

def _convert(quantity, x, unit, radius):
    factor, linear = UNITS[quantity][unit]
    if quantity == 'temperature':
        return x - 273.15 if unit == 'K' else x
    x = x * factor
    if linear and quantity in ('position', 'velocity'):
        return x / radius
    if linear:
        return x * radius
    return x


def _mapping_text(quantity, name, unit, radius):
    """Return how a column became its SI joint quantity, e.g. ``q [rad] := x [mm] * 1e-3 / r``."""
    factor, linear = UNITS[quantity][unit]
    target = {'time': 't [s]', 'position': 'q [rad]', 'velocity': 'qd [rad/s]',
              'torque': 'tau [Nm]', 'friction': 'tau_r [Nm]', 'load': 'tau_ext [Nm]',
              'temperature': 'xi [degC]'}[quantity]
    src = f'{name!r} [{unit}]'
    if quantity == 'temperature':
        return f'{target} := {src}' + (' - 273.15' if unit == 'K' else '')
    scale = '' if factor == 1.0 else f' * {factor:.9g}'
    if linear and quantity in ('position', 'velocity'):
        return f'{target} := {src}{scale} / radius {radius:g} m'
    if linear:
        return f'{target} := {src}{scale} * radius {radius:g} m'
    return f'{target} := {src}{scale}'


def _check_time(path, t, rows):
    if not np.all(np.isfinite(t)):
        i = int(np.flatnonzero(~np.isfinite(t))[0])
        raise RecordingError(f'{path}: row {rows[i]}: time is not finite')
    bad = np.flatnonzero(np.diff(t) <= 0)
    if len(bad):
        i = int(bad[0]) + 1
        raise RecordingError(f'{path}: row {rows[i]}: time {t[i]:.9g} s does not increase '
                             f'(previous row {t[i - 1]:.9g} s); time stamps must increase')


def _pieces(t):
    """Index ranges split where a step exceeds SPLIT median intervals; the median."""
    d = np.diff(t)
    dt = float(np.median(d))
    cuts = np.flatnonzero(d > SPLIT * dt) + 1
    bounds = np.concatenate(([0], cuts, [len(t)]))
    return [(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])], dt


def _resample(t, cols, dt):
    """Columns on the uniform grid of ``dt`` from t[0]; unchanged if already on it."""
    m = int(np.floor((t[-1] - t[0]) / dt * (1 + 1e-9) + 1e-9)) + 1
    grid = t[0] + np.arange(m) * dt
    if m == len(t) and np.max(np.abs(t - grid)) <= _ON_GRID * dt:
        return t, cols, False
    return grid, {k: np.interp(grid, t, v) for k, v in cols.items()}, True


def file_gap(dts):
    """Return the time gap (s) put between two files: max(GAP, 10 x the largest interval)."""
    return max(GAP, 10.0 * max(dts, default=0.0))


class ImportedLog:
    """
    The result of :func:`import_logs`.

    Attributes
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

    def __init__(self, topics, mapping, notes, warnings):
        self.topics = topics
        self.mapping = mapping
        self.notes = notes
        self.warnings = warnings

    def metadata(self):
        """Return the mapping as ``{key: str}``, the custom data of ``metadata.yaml``."""
        return {'friction_joint.import': json.dumps(self.mapping, sort_keys=True)}


def _check_columns(columns, radius):
    for need in ('time', 'position'):
        if need not in columns:
            raise RecordingError(f'no {need} column given (--{need} COL[:unit])')
    if 'torque' not in columns and 'friction' not in columns:
        raise RecordingError('give the drive torque (--torque COL[:unit]) or the friction '
                             '(--friction COL[:unit])')
    if 'torque' in columns and 'friction' in columns:
        raise RecordingError('give either --torque (drive torque) or --friction (friction '
                             'logged directly), not both')
    if not (isinstance(radius, (int, float)) and 0 < radius < math.inf):
        raise RecordingError(f'--radius must be a positive length in m, got {radius!r}')


def _one_file(path, columns, options):
    """Read and convert one file; returns the list of pieces and what was done."""
    header, data, rows = read_table(path, options['skip_rows'])
    radius = options['radius']
    picked, mapping = {}, {}
    for q in QUANTITIES:
        if q in columns:
            x, name, unit = _pick(path, header, data, q, columns[q])
            bad = np.flatnonzero(~np.isfinite(x))
            if len(bad):
                raise RecordingError(f'{path}: row {rows[bad[0]]}: {q} ({name}) is not finite')
            picked[q] = _convert(q, x, unit, radius)
            mapping[q] = {'column': name, 'unit': unit,
                          'conversion': _mapping_text(q, name, unit, radius)}
    if len(picked['time']) < 3:
        raise RecordingError(f'{path}: {len(picked["time"])} rows, at least 3 are needed')
    t = picked.pop('time')
    _check_time(path, t, rows)
    if options['unwrap']:
        if UNITS['position'][mapping['position']['unit']][1]:
            raise RecordingError(f'{path}: --unwrap applies to angles, the position is in '
                                 f'{mapping["position"]["unit"]}')
        picked['position'] = np.unwrap(picked['position'])
    ranges, dt = _pieces(t)
    pieces, resampled = [], 0
    for a, b in ranges:
        if b - a < 3:
            raise RecordingError(f'{path}: rows {rows[a]}-{rows[b - 1]}: a piece of {b - a} '
                                 f'sample(s) between gaps (> {SPLIT:g} x the median interval '
                                 f'{dt:.6g} s); at least 3 are needed')
        tt, cols, moved = _resample(t[a:b], {k: v[a:b] for k, v in picked.items()}, dt)
        resampled += bool(moved)
        if 'velocity' not in cols:
            cols['velocity'] = np.gradient(cols['position'], tt)
        pieces.append((tt, cols))
    return pieces, dt, mapping, resampled


def _effort(cols, flip):
    if 'torque' in cols:
        return cols['torque']
    sign = -1.0 if flip else 1.0
    return sign * cols['friction'] + cols.get('load', 0.0)


def _opposed_fraction(qd, friction):
    """Fraction of the sliding samples where ``friction`` opposes ``qd`` (None: no sliding)."""
    aq = np.abs(qd)
    moving = aq > 0.1 * np.percentile(aq, 99) if len(aq) else aq > 0
    moving &= friction != 0
    if not np.any(moving):
        return None
    return float(np.mean(np.sign(friction[moving]) != np.sign(qd[moving])))


def import_logs(paths, columns, *, radius=1.0, unwrap=False, flip_friction=False, skip_rows=0,
                joint_name='joint'):
    """
    Convert logs (one run per file) into the topics of one recording.

    Parameters
    ----------
    paths : sequence of str or os.PathLike
        CSV/TSV/whitespace-delimited text files or ``.npz`` files, one run each.
    columns : dict
        Quantity (:data:`QUANTITIES`) -> ``(column, unit)`` from :func:`parse_column`;
        ``time``, ``position`` and one of ``torque`` / ``friction`` are required.
    radius : float
        Radius (m) mapping a linear device to the joint (q = x / r, τ = F r).
    unwrap : bool
        Unwrap an angle logged modulo a turn (wrapped encoder).
    flip_friction : bool
        Negate the ``friction`` column (a log of the force acting on the moving body).
    skip_rows : int
        Lines skipped at the top of each text file before its header.
    joint_name : str
        Joint name written into the JointState messages.

    Returns
    -------
    ImportedLog

    Raises
    ------
    RecordingError
        One line naming the problem and the file (and row): unreadable file, unknown
        column or unit, a value that is not a number, time stamps that do not
        increase, a piece too short, an inconsistent mapping.

    """
    _check_columns(columns, radius)
    if not paths:
        raise RecordingError('no input files given')
    options = {'radius': float(radius), 'unwrap': bool(unwrap), 'skip_rows': int(skip_rows)}
    friction_mode = 'friction' in columns
    out = {k: [] for k in ('t', 'q', 'qd', 'effort', 'tau', 'xi')}
    files, notes, warnings, mapping = [], [], [], {}
    start, dts, prev = 0.0, [], []
    for path in map(os.fspath, paths):
        pieces, dt, mapping, resampled = _one_file(path, columns, options)
        if files:
            start = prev[-1] + file_gap(dts + [dt])
        offset = start - pieces[0][0][0]
        dts.append(dt)
        for tt, cols in pieces:
            out['t'].append(tt + offset)
            out['q'].append(cols['position'])
            out['qd'].append(cols['velocity'])
            out['effort'].append(_effort(cols, flip_friction))
            out['tau'].append(cols.get('load', np.zeros(len(tt))))
            if 'temperature' in cols:
                out['xi'].append(cols['temperature'])
        prev = [float(out['t'][-1][-1])]
        files.append({'path': path, 'offset_s': offset, 'sample_interval_s': dt,
                      'samples': int(sum(len(p[0]) for p in pieces)),
                      'pieces': [[float(p[0][0] + offset), float(p[0][-1] + offset)]
                                 for p in pieces],
                      'resampled_pieces': resampled})
        if friction_mode:
            frac = _opposed_fraction(np.concatenate([c['velocity'] for _, c in pieces]),
                                     np.concatenate([_effort(c, flip_friction) - c.get('load', 0.0)
                                                     for _, c in pieces]))
            if frac is not None and frac > _OPPOSED:
                flag = 'without' if flip_friction else 'with'
                warnings.append(
                    f'{path}: the friction as written opposes the velocity on {100 * frac:.0f} % '
                    'of the sliding samples: the convention is tau_r of eq. 2 (the sign of the '
                    f'velocity while sliding); the column looks sign-flipped, import {flag} '
                    '--flip-friction')
    cat = {k: np.concatenate(v) for k, v in out.items() if v}
    topics = {'/joint_states': {'t': cat['t'], 'q': cat['q'], 'qd': cat['qd'],
                                'effort': cat['effort'], 'name': joint_name}}
    if friction_mode or 'load' in columns:
        topics['/link_torque'] = {'t': cat['t'], 'tau': cat['tau']}
    if 'temperature' in columns:
        topics['/joint_temperature'] = {'t': cat['t'], 'xi': cat['xi']}
    linear = any(UNITS[q][m['unit']][1] for q, m in mapping.items())
    info = {'columns': mapping, 'radius_m': options['radius'] if linear else None,
            'unwrap': options['unwrap'], 'files': files, 'gap_s': file_gap(dts),
            'mode': 'friction' if friction_mode else 'drive_torque',
            'velocity': 'logged' if 'velocity' in columns else 'centred difference per piece'}
    for q, m in mapping.items():
        notes.append(f'{q}: {m["conversion"]}')
    if linear:
        notes.append(f'linear device: q [rad] := x [m] / {options["radius"]:g} m, '
                     f'tau [Nm] := F [N] * {options["radius"]:g} m (--radius)')
    if 'velocity' not in columns:
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
