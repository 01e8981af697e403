# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Units of imported log columns (``friction_joint import``): names, conversion to SI, checks.

A column's unit is the one given after its name (``COL:unit``), else the one
in brackets at the end of its header name (``Position [mm]``, ``Torque (Nm)``),
else SI (a file without a header).  Brackets at the end of a header that do not
hold a known unit of the quantity (``Temp [°R]``, ``Sensor (left)``) are an
error naming the column and the known units: a unit is never guessed.  Every
converted value must be finite (an overflow is an error naming the column and
row), and the radius of a linear device lies in :data:`RADIUS_RANGE`.
"""
import math
import re

import numpy as np

from ..exceptions import RecordingError

__all__ = ['QUANTITIES', 'UNITS', 'SI', 'RADIUS_RANGE', 'parse_column', 'header_unit',
           'check_radius', 'convert', 'mapping_text']

#: the mapping keys, in the order they are reported
QUANTITIES = ('time', 'position', 'velocity', 'torque', 'current', 'friction', 'load',
              'temperature')

_TORQUE = {'Nm': (1.0, False), 'Nmm': (1e-3, False), 'mNm': (1e-3, False),
           'kNm': (1e3, False), 'N': (1.0, True), 'kN': (1e3, True), 'mN': (1e-3, True),
           'uN': (1e-6, True)}
#: quantity -> unit -> (factor to SI, linear: scaled by the radius); temperatures are
#: offset too (K: - 273.15, degF: (x - 32) * 5 / 9)
UNITS = {
    'time': {'s': (1.0, False), 'ms': (1e-3, False), 'us': (1e-6, False),
             'ns': (1e-9, False), 'min': (60.0, False), 'h': (3600.0, False)},
    'position': {'rad': (1.0, False), 'deg': (math.pi / 180.0, False),
                 'rev': (2.0 * math.pi, False), 'm': (1.0, True), 'cm': (1e-2, True),
                 'mm': (1e-3, True), 'um': (1e-6, True)},
    'velocity': {'rad/s': (1.0, False), 'deg/s': (math.pi / 180.0, False),
                 'rev/s': (2.0 * math.pi, False), 'rpm': (2.0 * math.pi / 60.0, False),
                 'm/s': (1.0, True), 'mm/s': (1e-3, True), 'um/s': (1e-6, True)},
    'torque': _TORQUE, 'friction': _TORQUE, 'load': _TORQUE,
    'current': {'A': (1.0, False), 'mA': (1e-3, False)},
    'temperature': {'degC': (1.0, False), 'K': (1.0, False), 'degF': (5.0 / 9.0, False)},
}
#: the SI unit of each quantity (a column without a unit and header brackets)
SI = {'time': 's', 'position': 'rad', 'velocity': 'rad/s', 'torque': 'Nm', 'friction': 'Nm',
      'load': 'Nm', 'temperature': 'degC', 'current': 'A'}
#: radius (m) of a linear device: a normal float within this range
RADIUS_RANGE = (1e-9, 1e9)
_ALIASES = {'N m': 'Nm', 'N*m': 'Nm', 'N.m': 'Nm', 'N·m': 'Nm', 'N mm': 'Nmm', 'kN m': 'kNm',
            'kN*m': 'kNm', 'kN.m': 'kNm', 'mN m': 'mNm', '°': 'deg', 'degree': 'deg',
            'degrees': 'deg', '°/s': 'deg/s', 'deg/sec': 'deg/s', 'rad/sec': 'rad/s',
            'rev/min': 'rpm', '°C': 'degC', 'C': 'degC', '°F': 'degF', 'sec': 's',
            'msec': 'ms', 'amp': 'A', 'amps': 'A'}
_BRACKETS = re.compile(r'[\[(]([^\[\]()]*)[\])]\s*$')


def _unit_name(text):
    text = str(text).strip().replace('µ', 'u').replace('μ', 'u')
    return _ALIASES.get(text, text)


def _known(quantity):
    return ', '.join(UNITS[quantity])


def _unit(quantity, unit, where):
    name = _unit_name(unit)
    if name not in UNITS[quantity]:
        raise RecordingError(f'{where}: unknown {quantity} unit {str(unit).strip()!r} (known: '
                             f'{_known(quantity)})')
    return name


def parse_column(quantity: str, text: str | int, where: str) -> tuple[int | str, str | None]:
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
    return (int(col) if re.fullmatch(r'[0-9]+', col) else col), unit


def header_unit(quantity, name, where):
    """
    Return the unit in brackets at the end of header ``name`` (None without brackets).

    Raises
    ------
    RecordingError
        The brackets hold something that is not a unit of ``quantity`` (naming the
        column, the known units and how to give the unit instead).

    """
    m = _BRACKETS.search(name or '')
    if not m:
        return None
    unit = _unit_name(m.group(1))
    if unit not in UNITS[quantity]:
        raise RecordingError(
            f'{where}: column {name!r} ({quantity}): {m.group(1).strip()!r} at the end of its '
            f'header is not a known {quantity} unit (known: {_known(quantity)}); give the unit '
            f'after the column ("{name}:UNIT", in the option or the mapping), which overrides '
            'the header')
    return unit


def check_radius(radius, where='--radius'):
    """Return ``radius`` (m) as a float; raise unless a normal float in :data:`RADIUS_RANGE`."""
    lo, hi = RADIUS_RANGE
    if (isinstance(radius, bool) or not isinstance(radius, (int, float, np.floating))
            or not lo <= float(radius) <= hi):
        raise RecordingError(f'{where} must be a length in m from {lo:g} to {hi:g}, got '
                             f'{radius!r}')
    return float(radius)


def convert(quantity, x, unit, radius, *, path, name, rows):
    """
    Convert column ``x`` (float64, converted in place) of ``quantity`` from ``unit`` to SI.

    Parameters
    ----------
    quantity, unit : str
        The quantity and a key of ``UNITS[quantity]``.
    x : numpy.ndarray
        The values (overwritten).
    radius : float
        Radius (m) of a linear device.
    path, name : str
        The file and the column (errors).
    rows : sequence
        The file line of each value (errors).

    Returns
    -------
    numpy.ndarray
        ``x``, converted.

    Raises
    ------
    RecordingError
        A value that is not finite before or after the conversion (naming the row).

    """
    _finite(x, rows, path, f'{quantity} ({name}) is not finite')
    factor, linear = UNITS[quantity][unit]
    with np.errstate(over='ignore', under='ignore', invalid='ignore'):
        if quantity == 'temperature':
            if unit == 'K':
                x -= 273.15
            elif unit == 'degF':
                x -= 32.0
                x *= factor
        else:
            if factor != 1.0:
                x *= factor
            if linear and quantity in ('position', 'velocity'):
                x /= radius
            elif linear:
                x *= radius
    _finite(x, rows, path, f'{quantity} ({name}) is not finite once converted from {unit} to '
            'SI' + (f' with radius {radius:g} m' if linear else ''))
    return x


def _finite(x, rows, path, what):
    if not np.isfinite(x).all():
        i = int(np.flatnonzero(~np.isfinite(x))[0])
        raise RecordingError(f'{path}: row {rows[i]}: {what}')


def mapping_text(quantity, name, unit, radius):
    """Return how a column became its SI joint quantity, e.g. ``q [rad] := x [mm] * 1e-3 / r``."""
    factor, linear = UNITS[quantity][unit]
    target = {'time': 't [s]', 'position': 'q [rad]', 'velocity': 'qd [rad/s]',
              'torque': 'tau [Nm]', 'friction': 'tau_r [Nm]', 'load': 'tau_ext [Nm]',
              'temperature': 'xi [degC]', 'current': 'I [A]'}[quantity]
    src = f'{name!r} [{unit}]'
    if quantity == 'temperature':
        return f'{target} := ' + {'K': f'{src} - 273.15', 'degF': f'({src} - 32) * 5 / 9'}.get(
            unit, src)
    scale = '' if factor == 1.0 else f' * {factor:.9g}'
    if linear and quantity in ('position', 'velocity'):
        return f'{target} := {src}{scale} / radius {radius:g} m'
    if linear:
        return f'{target} := {src}{scale} * radius {radius:g} m'
    return f'{target} := {src}{scale}'
