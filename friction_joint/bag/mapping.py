# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The mapping of ``friction_joint import``: the mapping file, the column checks, motor current.

A log of the motor current (``current``, A or mA; UR RTDE, Kinova, Franka
logs) becomes the drive torque at the joint::

    tau [Nm] := I [A] * K [N m/A] * N

with the motor's torque constant ``K`` (``torque_constant``, motor side) and
the gear ratio ``N`` (``gear_ratio``, default 1), both finite and positive.  A
current column excludes a torque or friction column.  The conversion is printed
by the command and written into the recording's ``metadata.yaml``
(``custom_data`` ``friction_joint.import``, key ``torque_from_current``), from
where :func:`torque_from_current` tells ``diagnose`` and ``identify`` that their
torque came from a current.
"""
from __future__ import annotations

from collections.abc import Sequence
import json
import math
import os
from typing import Any

import numpy as np

from .units import check_radius, parse_column, QUANTITIES, UNITS
from ..exceptions import RecordingError
from ..inputs import read_input

__all__ = ['OPTIONS', 'load_mapping', 'check_motor', 'check_columns', 'current_torque',
           'torque_from_current']

#: the option keys of a mapping file (besides :data:`QUANTITIES`)
OPTIONS = ('radius', 'unwrap', 'flip_friction', 'skip_rows', 'velocity_from_position',
           'torque_constant', 'gear_ratio')
_MOTOR = {'torque_constant': ('--torque-constant', 'a torque constant in N m/A'),
          'gear_ratio': ('--gear-ratio', 'a gear ratio')}


def load_mapping(path: str | os.PathLike) -> tuple[dict[str, tuple[int | str, str | None]],
                                                   dict[str, Any]]:
    """
    Read a mapping file: YAML with the keys of :data:`QUANTITIES` (``COL[:unit]``).

    Optional keys: ``radius`` (m), ``unwrap``, ``flip_friction``,
    ``velocity_from_position`` (bools), ``skip_rows`` (int), ``torque_constant``
    (N m/A) and ``gear_ratio`` (with a ``current`` column).

    Parameters
    ----------
    path : str or os.PathLike
        The mapping file.

    Returns
    -------
    tuple
        ``(columns, options)``: quantity -> ``(column, unit)``, and the options given.

    Raises
    ------
    RecordingError
        Not a readable regular file, not a mapping, an unknown key or a bad value
        (naming the file).

    """
    import yaml
    path = os.fspath(path)
    data = read_input(path, kind='mapping', what='a mapping', error=RecordingError)
    try:
        doc = yaml.safe_load(data.decode('utf-8'))
    except (UnicodeDecodeError, yaml.YAMLError) as exc:
        why = str(exc).splitlines()[0]
        raise RecordingError(f'{path}: not a YAML mapping file ({why})') from None
    except RecursionError:
        raise RecordingError(f'{path}: not a mapping file: nested too deeply') from None
    if not isinstance(doc, dict):
        raise RecordingError(f'{path}: a mapping file is a YAML mapping of '
                             f'{", ".join(QUANTITIES)} to COL[:unit]')
    unknown = [str(k) for k in doc if k not in QUANTITIES + OPTIONS]
    if unknown:
        raise RecordingError(f'{path}: unknown key(s) {", ".join(unknown)} (keys: '
                             f'{", ".join(QUANTITIES + OPTIONS)})')
    columns = {k: parse_column(k, v, path) for k, v in doc.items() if k in QUANTITIES}
    options = {k: doc[k] for k in OPTIONS if k in doc}
    for key in ('unwrap', 'flip_friction', 'velocity_from_position'):
        if key in options and not isinstance(options[key], bool):
            raise RecordingError(f'{path}: {key} must be true or false')
    if 'skip_rows' in options and (isinstance(options['skip_rows'], bool)
                                   or not isinstance(options['skip_rows'], int)
                                   or options['skip_rows'] < 0):
        raise RecordingError(f'{path}: skip_rows must be a whole number >= 0')
    if 'radius' in options:
        options['radius'] = check_radius(options['radius'], f'{path}: radius')
    for key in _MOTOR:
        if key in options:
            options[key] = check_motor(key, options[key], where=f'{path}: {key}')
    return columns, options


def check_motor(key: str, value: object, *, where: str | None = None) -> float:
    """
    Return ``value`` of ``torque_constant`` or ``gear_ratio`` as a float.

    Parameters
    ----------
    key : str
        ``torque_constant`` or ``gear_ratio``.
    value : object
        The value given.
    where : str, optional
        Start of the error message (default: the option, ``--torque-constant``).

    Returns
    -------
    float
        The value.

    Raises
    ------
    RecordingError
        Not a finite positive number (naming the option or file).

    """
    option, what = _MOTOR[key]
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)) or \
            not math.isfinite(float(value)) or float(value) <= 0:
        raise RecordingError(f'{where or option} must be {what}, finite and > 0, got '
                             f'{value!r}')
    return float(value)


def check_columns(columns: dict[str, tuple[int | str, str | None]], *, radius: float,
                  joint_name: str, torque_constant: float | None,
                  gear_ratio: float | None) -> None:
    """
    Check the columns and options of an import before any file is read.

    Parameters
    ----------
    columns : dict
        Quantity -> ``(column, unit)``.
    radius : float
        Radius (m) of a linear device.
    joint_name : str
        The joint name of the recording.
    torque_constant, gear_ratio : float or None
        K (N m/A) and N of a ``current`` column (None: not given).

    Raises
    ------
    RecordingError
        A required column missing, two torque sources, a current without its torque
        constant (or motor options without a current), a bad radius, K, N or joint name.

    """
    for need in ('time', 'position'):
        if need not in columns:
            raise RecordingError(f'no {need} column given (--{need} COL[:unit])')
    given = [k for k in ('torque', 'friction', 'current') if k in columns]
    if not given:
        raise RecordingError('give the drive torque (--torque COL[:unit]), the friction '
                             '(--friction COL[:unit]) or the motor current (--current '
                             'COL[:A|mA] with --torque-constant)')
    if 'current' in given and len(given) > 1:
        raise RecordingError(f'give either --current (motor current, converted to the torque) '
                             f'or --{given[0]} (a torque column), not both')
    if len(given) > 1:
        raise RecordingError('give either --torque (drive torque) or --friction (friction '
                             'logged directly), not both')
    if 'current' in columns and torque_constant is None:
        raise RecordingError('--current needs --torque-constant K (N m/A, motor side) to give '
                             'the torque')
    for key, value in (('torque_constant', torque_constant), ('gear_ratio', gear_ratio)):
        if value is not None:
            check_motor(key, value)
            if 'current' not in columns:
                raise RecordingError(f'{_MOTOR[key][0]} applies to a --current column, none '
                                     'given')
    check_radius(radius)
    if (not isinstance(joint_name, str) or not joint_name.strip()
            or joint_name != joint_name.strip() or not joint_name.isprintable()):
        raise RecordingError(f'--joint: a joint name must be a non-empty printable name '
                             f'without surrounding spaces, got {joint_name!r}')


def current_torque(x: np.ndarray, name: str, unit: str, torque_constant: float,
                   gear_ratio: float, *, path: str, rows: Sequence[int] | np.ndarray) -> dict:
    """
    Turn a current column (A, converted) into the joint torque (Nm), in place.

    Parameters
    ----------
    x : numpy.ndarray
        The current in A (overwritten by the torque in Nm).
    name, unit : str
        The column and its unit as logged.
    torque_constant : float
        K, N m/A on the motor side.
    gear_ratio : float
        N, motor turns per joint turn.
    path : str
        The file (errors).
    rows : sequence
        The file line of each value (errors).

    Returns
    -------
    dict
        What was done (JSON-able): column, unit, torque constant, gear ratio and the
        conversion as text.

    Raises
    ------
    RecordingError
        A torque that is not finite (an overflow), naming the row.

    """
    with np.errstate(over='ignore'):
        x *= torque_constant
        x *= gear_ratio
    if not np.isfinite(x).all():
        i = int(np.flatnonzero(~np.isfinite(x))[0])
        raise RecordingError(f'{path}: row {rows[i]}: the torque from the current ({name}) is '
                             'not finite')
    factor = UNITS['current'][unit][0]
    scale = '' if factor == 1.0 else f' * {factor:.9g}'
    return {'column': name, 'unit': unit, 'torque_constant_Nm_per_A': torque_constant,
            'gear_ratio': gear_ratio,
            'conversion': f'tau [Nm] := {name!r} [{unit}]{scale} * torque constant '
                          f'{torque_constant:.9g} N m/A * gear ratio {gear_ratio:.9g}'}


def torque_from_current(custom_data: dict[str, str]) -> dict | None:
    """
    Return how a recording's torque came from a motor current, from its custom data.

    Parameters
    ----------
    custom_data : dict
        The recording's ``metadata.yaml`` custom data
        (:func:`~friction_joint.bag.reader.recording_custom_data`).

    Returns
    -------
    dict or None
        None for a recording whose torque was not converted from a current; else
        ``torque_constant_Nm_per_A``, ``gear_ratio``, ``column``, ``unit``,
        ``conversion`` and ``text`` (the line for reports, e.g. ``friction torque from
        motor current x 0.12 N m/A x 100 (import)``).

    """
    try:
        info = json.loads(custom_data.get('friction_joint.import', 'null'))
        src = info.get('torque_from_current') if isinstance(info, dict) else None
        if src is None:
            raise TypeError     # no record of a conversion
        k, n = src['torque_constant_Nm_per_A'], src['gear_ratio']
        text = f'friction torque from motor current x {k:.6g} N m/A x {n:.6g} (import)'
    except (TypeError, ValueError, KeyError, AttributeError):
        return None
    return {**src, 'text': text}
