# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The gear file schema: every key, its type, default, bounds and length limits.

Limits on list lengths (checked before a list's elements are looked at):

``MAX_POLYNOMIAL_ORDER`` = 8
    Temperature polynomials (``fc``, ``fv``, ``fs``, ``vs``, ``delta_v``: at
    most 9 coefficients, powers 0..8) and load polynomials (``*_load``: at most
    8 coefficients, powers 1..8).  The paper uses order 2; ``identify``'s
    automatic order selection goes up to 2 and ``diagnose`` raises an order by
    one.  In the monomial basis the coefficients of order 8 are at the end of
    double precision: the Vandermonde matrix of 50 temperatures over 0-100 degC
    has condition number 1.7e16 at order 8 (1.3e19 over the CSD-25's 22-37
    degC), so a higher order cannot be identified or evaluated meaningfully; it
    only costs (a 1001-coefficient polynomial ran ``diagnose`` for > 300 s).
``MAX_GMS_ELEMENTS`` = 100
    GMS elements (``gms.k``, ``gms.alpha``).  Published GMS models use 3-10
    elements; every element is a state updated at each step of every
    simulation (3 kHz, batched in identification), so the cost grows linearly.
``MAX_RIPPLE_HARMONICS`` = 100
    Position-ripple harmonics (``amplitude``, ``phase``).  Harmonic n of a
    c cycles/rev ripple at q' rad/s has n c q' / 2 pi Hz; for the CSD-25's
    c = 160 at 3.5 rad/s, harmonic 100 is already ~9 kHz, above the Nyquist
    frequency of the 3 kHz simulation, so more harmonics cannot be simulated.

Integers are ROS 2 parameter integers (64-bit); larger ones are rejected.
"""
from __future__ import annotations

import copy
import math
import reprlib
from typing import Any

from ..exceptions import GearConfigError

__all__ = ['REQUIRED', 'FRICTION_MODELS', 'MAX_POLYNOMIAL_ORDER', 'MAX_GMS_ELEMENTS',
           'MAX_RIPPLE_HARMONICS', 'INT64_RANGE', 'ABSOLUTE_ZERO', 'TEMPERATURE_BOUNDS',
           'RATE_BOUNDS', 'ENCODER_BITS_BOUNDS', 'RIPPLE_CYCLES_BOUNDS', 'MIN_CUTOFF_FRACTION',
           'TEMPERATURE_RESOLUTION_BOUNDS', 'VELOCITY_SCALE_BOUNDS', 'STRIBECK_EXPONENT_BOUNDS',
           'ANGLE_OFFSET_BOUNDS',
           'Float', 'Int', 'Str', 'FloatList', 'Section',
           'FRICTION_SCHEMA', 'SCHEMA', 'DEFAULT_SECTIONS', 'validate_fields', 'key_specs',
           'required_keys']

FRICTION_MODELS = ('static', 'lugre', 'gms')
REQUIRED = object()
MAX_POLYNOMIAL_ORDER = 8
MAX_GMS_ELEMENTS = 100
MAX_RIPPLE_HARMONICS = 100
#: the range of a ROS 2 integer parameter
INT64_RANGE = (-2 ** 63, 2 ** 63 - 1)

# Physical ranges (lo, hi, why) of the values that reach an exponent, a division or the
# size of an allocation; derived from physics and double precision, not from one gear.
#: absolute zero, degC
ABSOLUTE_ZERO = -273.15
#: a temperature of the gear, its housing or its surroundings, degC
TEMPERATURE_BOUNDS = (ABSOLUTE_ZERO, 1000.0, "above absolute zero; a gear's lubricant and "
                      'seals are destroyed far below 1000 degC')
#: simulation and control rate, Hz
RATE_BOUNDS = (1.0, 1.0e6, 'a step longer than 1 s resolves no motion of a joint; a step '
               'shorter than 1 us is within 3 digits of the 1 ns resolution of ROS stamps, '
               'and every simulated second allocates its samples')
#: output encoder resolution, bits per revolution
ENCODER_BITS_BOUNDS = (1, 52, 'a count of 2 pi / 2**52 rad is the resolution of a double '
                       'at one revolution; finer counts cannot be represented')
#: position ripple fundamental, cycles per revolution
RIPPLE_CYCLES_BOUNDS = (None, 2.0 ** 52, 'a cycle shorter than 2 pi / 2**52 rad is below the '
                        'resolution of a double at one revolution')
#: smallest velocity filter cut-off as a fraction of the rate
MIN_CUTOFF_FRACTION = 1.0e-6
#: temperature sensor resolution, degC
TEMPERATURE_RESOLUTION_BOUNDS = (1.0e-6, 100.0, 'from 1 uK, beyond any thermometer, to '
                                 '100 K, coarser than any temperature effect')
#: friction curve velocity scale (dimensionless)
VELOCITY_SCALE_BOUNDS = (1.0e-6, 1.0e6, 'it maps the output velocity to the one the curve '
                         'is written in, e.g. by a gear ratio; gear ratios are 1 to 1e4')
#: Stribeck exponent (dimensionless)
STRIBECK_EXPONENT_BOUNDS = (0.01, 100.0, 'Stribeck exponents of gears are 0.5-2; outside '
                            '[0.01, 100] the Stribeck curve is flat or a step in double '
                            'precision')
#: lever angle offset, rad: refused beyond one turn either way, never reduced (a value
#: beyond 2 pi is almost always in degrees, which reducing it would hide)
ANGLE_OFFSET_BOUNDS = (-2.0 * math.pi, 2.0 * math.pi, 'an angle of the lever within one '
                       'turn either way, in rad; a larger one is most likely in degrees '
                       '(90 deg = 1.5708 rad)')

_REPR = reprlib.Repr()
_REPR.maxstring = 60
_REPR.maxother = 60
_REPR.maxlist = _REPR.maxtuple = _REPR.maxdict = 6


def _short(value: object) -> str:
    """repr() cut to a readable length: error messages stay one short line."""
    return _REPR.repr(value)


#: ``(lo, hi, why)`` of a value's physical range (``lo``, ``hi`` may be None)
_Bounds = tuple[float | None, float | None, str]


class _Spec:
    default: object = REQUIRED

    def check(self, value: object, path: str) -> Any:  # pragma: no cover - interface
        raise NotImplementedError


class Float(_Spec):
    """
    A finite number (an integer is accepted and becomes a float), optionally bounded.

    ``bounds`` is ``(lo, hi, why)``: the physical range ``lo <= value <= hi`` (either
    may be None) and the reason, named in the error.
    """

    def __init__(self, default: object = REQUIRED, positive: bool = False,
                 nonnegative: bool = False, doc: str = '', *,
                 bounds: _Bounds | None = None) -> None:
        self.default, self.positive, self.nonnegative, self.doc = (
            default, positive, nonnegative, doc)
        self.bounds = bounds

    def check(self, value: object, path: str) -> float:
        """Return ``value`` as a float or raise GearConfigError naming ``path``."""
        value = _number(value, path, self.positive, self.nonnegative)
        _check_bounds(value, path, self.bounds)
        return value


def _check_bounds(value: float, path: str, bounds: _Bounds | None) -> None:
    """Raise GearConfigError naming ``path`` if ``value`` is outside ``bounds`` (lo, hi, why)."""
    if bounds is None:
        return
    lo, hi, why = bounds
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        rng = ('>= ' + format(lo, 'g') if hi is None else '<= ' + format(hi, 'g')
               if lo is None else f'in [{lo:g}, {hi:g}]')
        got = value if isinstance(value, int) else format(value, 'g')
        raise GearConfigError(f'{path}: must be {rng} ({why}), got {got}')


def _number(value: object, path: str, positive: bool = False,
            nonnegative: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise GearConfigError(f'{path}: expected a number, got {_short(value)}')
    try:
        value = float(value)
    except OverflowError:
        raise GearConfigError(f'{path}: must be finite, got an integer of '
                              f'{int(value).bit_length()} bits') from None
    if not math.isfinite(value):
        raise GearConfigError(f'{path}: must be finite, got {value}')
    if positive and value <= 0.0:
        raise GearConfigError(f'{path}: must be > 0, got {value}')
    if nonnegative and value < 0.0:
        raise GearConfigError(f'{path}: must be >= 0, got {value}')
    return value


class Int(_Spec):
    """An integer in the ROS 2 (64-bit) range."""

    def __init__(self, default: object = REQUIRED, minimum: int | None = None, doc: str = '',
                 *, bounds: _Bounds | None = None) -> None:
        self.default, self.minimum, self.doc = default, minimum, doc
        self.bounds = bounds

    def check(self, value: object, path: str) -> int:
        """Return ``value`` or raise GearConfigError naming ``path``."""
        if isinstance(value, bool) or not isinstance(value, int):
            raise GearConfigError(f'{path}: expected an integer, got {_short(value)}')
        if not INT64_RANGE[0] <= value <= INT64_RANGE[1]:
            raise GearConfigError(f'{path}: outside the 64-bit integer range of ROS 2 '
                                  'parameters')
        if self.minimum is not None and value < self.minimum:
            raise GearConfigError(f'{path}: must be >= {self.minimum}, got {value}')
        _check_bounds(value, path, self.bounds)
        return value


class Str(_Spec):
    """A non-empty string, optionally one of ``choices``."""

    def __init__(self, default: object = REQUIRED, choices: tuple[str, ...] | None = None,
                 doc: str = '') -> None:
        self.default, self.choices, self.doc = default, choices, doc

    def check(self, value: object, path: str) -> str:
        """Return ``value`` or raise GearConfigError naming ``path``."""
        if not isinstance(value, str) or not value:
            raise GearConfigError(f'{path}: expected a non-empty string, got {_short(value)}')
        if self.choices and value not in self.choices:
            raise GearConfigError(f'{path}: must be one of {", ".join(self.choices)}; '
                                  f'got {_short(value)}')
        return value


class FloatList(_Spec):
    """A list of finite numbers (integers become floats), its length bounded."""

    def __init__(self, default: object = REQUIRED, min_len: int = 0, length: int | None = None,
                 positive: bool = False, doc: str = '', *, max_len: int | None = None,
                 limit: str = '', bounds: _Bounds | None = None) -> None:
        self.default, self.min_len, self.length, self.positive, self.doc = (
            default, min_len, length, positive, doc)
        self.max_len = length if max_len is None else max_len
        self.limit = limit
        self.bounds = bounds

    def check(self, value: object, path: str) -> list[float]:
        """Return ``value`` as a list of floats or raise GearConfigError naming ``path``."""
        if not isinstance(value, (list, tuple)):
            raise GearConfigError(f'{path}: expected a list of numbers, got {_short(value)}')
        if self.length is not None and len(value) != self.length:
            raise GearConfigError(f'{path}: expected {self.length} numbers, got {len(value)}')
        if self.max_len is not None and len(value) > self.max_len:
            why = f' ({self.limit})' if self.limit else ''
            raise GearConfigError(f'{path}: at most {self.max_len} numbers{why}, '
                                  f'got {len(value)}')
        if len(value) < self.min_len:
            raise GearConfigError(f'{path}: needs at least {self.min_len} coefficient(s), '
                                  f'got {len(value)}')
        out = [_number(v, f'{path}[{i}]', self.positive) for i, v in enumerate(value)]
        for i, v in enumerate(out):
            _check_bounds(v, f'{path}[{i}]', self.bounds)
        return out


class Section(_Spec):
    """
    A mapping of keys with their own specs.

    Parameters
    ----------
    fields : dict
        Each key's spec (``Float``, ``Int``, ``Str``, ``FloatList`` or a ``Section``).
    optional : bool
        Whether the section may be absent.
    doc : str
        What the section is, for documentation.

    """

    def __init__(self, fields: dict[str, _Spec], *, optional: bool = True, doc: str = '') -> None:
        self.fields, self.doc = fields, doc
        self.default = None if optional else REQUIRED

    def check(self, value: object, path: str) -> dict[str, Any]:
        """
        Return the validated mapping (defaults filled in) or raise GearConfigError.

        Parameters
        ----------
        value : object
            The section's value as read.
        path : str
            Its dotted name, for error messages.

        Returns
        -------
        dict

        """
        if not isinstance(value, dict):
            raise GearConfigError(f'{path}: expected a mapping of keys, got {_short(value)}')
        return validate_fields(self.fields, value, path)


def validate_fields(fields: dict[str, _Spec], data: dict[Any, Any],
                    path: str) -> dict[str, Any]:
    """
    Validate mapping ``data`` against ``fields`` (key -> spec); return it with defaults.

    Parameters
    ----------
    fields : dict
        Key -> spec (:class:`Float`, :class:`Section`, ...).
    data : dict
        The mapping to check.
    path : str
        Dotted name of the mapping ('' at the top), used in error messages.

    Returns
    -------
    dict
        Every key of ``fields``: the checked value, or its default.

    Raises
    ------
    GearConfigError
        Unknown or missing key, or a value its spec rejects.

    """
    prefix = path + '.' if path else ''
    unknown = sorted(str(k) for k in set(data) - set(fields))
    if unknown:
        raise GearConfigError(f'unknown key {prefix}{_short(unknown[0])[1:-1]}'
                              + (f' (and {len(unknown) - 1} more)' if len(unknown) > 1 else '')
                              + f'; known keys here: {", ".join(sorted(fields))}')
    out: dict[str, Any] = {}
    for key, spec in fields.items():
        if key in data and data[key] is not None:
            out[key] = spec.check(data[key], prefix + key)
        elif spec.default is REQUIRED:
            raise GearConfigError(f'missing required key {prefix}{key}')
        else:
            out[key] = copy.deepcopy(spec.default)
    return out


def _temperature(doc: str, required: bool = False) -> FloatList:
    return FloatList(REQUIRED if required else None, min_len=1, doc=doc,
                     max_len=MAX_POLYNOMIAL_ORDER + 1,
                     limit=f'temperature polynomial order <= {MAX_POLYNOMIAL_ORDER}')


def _load(doc: str) -> FloatList:
    return FloatList([], doc=doc, max_len=MAX_POLYNOMIAL_ORDER,
                     limit=f'load polynomial order <= {MAX_POLYNOMIAL_ORDER}')


def _elements(default: object, doc: str, positive: bool = True) -> FloatList:
    return FloatList(default, min_len=1, positive=positive, doc=doc, max_len=MAX_GMS_ELEMENTS,
                     limit=f'GMS elements <= {MAX_GMS_ELEMENTS}')


def _harmonics(default: object, doc: str) -> FloatList:
    return FloatList(default, min_len=1, doc=doc, max_len=MAX_RIPPLE_HARMONICS,
                     limit=f'ripple harmonics <= {MAX_RIPPLE_HARMONICS}')


FRICTION_SCHEMA: dict[str, _Spec] = {
    'model': Str('static', choices=FRICTION_MODELS, doc='friction model used by default'),
    'fc': _temperature('F_c temperature coefficients, powers 0..n (Nm)', required=True),
    'fv': _temperature('F_v temperature coefficients (Nm / (rad/s)^delta_v)', required=True),
    'fs': _temperature('F_s temperature coefficients (Nm); absent = no Stribeck effect'),
    'vs': _temperature('v_s temperature coefficients (rad/s); required with fs'),
    'delta_v': FloatList([1.0], min_len=1, doc='delta_v temperature coefficients',
                         max_len=MAX_POLYNOMIAL_ORDER + 1,
                         limit=f'temperature polynomial order <= {MAX_POLYNOMIAL_ORDER}'),
    'delta_s': Float(2.0, positive=True, doc='Stribeck exponent',
                     bounds=STRIBECK_EXPONENT_BOUNDS),
    'fc_load': _load('F_c load coefficients, powers 1..m'),
    'fv_load': _load('F_v load coefficients'),
    'fs_load': _load('F_s load coefficients'),
    'vs_load': _load('v_s load coefficients'),
    'delta_v_load': _load('delta_v load coefficients'),
    'velocity_scale': Float(1.0, positive=True, doc='curve evaluated at velocity_scale * qd',
                            bounds=VELOCITY_SCALE_BOUNDS),
    'temperature_range': FloatList([0.0, 100.0], length=2,
                                   doc='validity range of the polynomials, degC',
                                   bounds=TEMPERATURE_BOUNDS),
    'lugre': Section({
        'sigma0': Float(positive=True, doc='bristle stiffness, Nm/rad'),
        'sigma1': Float(0.0, nonnegative=True, doc='micro-damping, Nm s/rad'),
    }, doc='LuGre pre-sliding parameters (eq. 10)'),
    'gms': Section({
        'k': _elements(REQUIRED, 'element stiffnesses, Nm/rad'),
        'alpha': _elements(None, 'element torque fractions, sum 1'),
        'c': Float(positive=True, doc='attraction parameter C, Nm/s'),
    }, doc='GMS parameters (eq. 11-13)'),
    'offset': Float(0.0, doc='constant torque added to the friction torque, Nm'),
    'position_ripple': Section({
        'cycles_per_rev': Float(REQUIRED, positive=True,
                                doc='fundamental, cycles per output revolution',
                                bounds=RIPPLE_CYCLES_BOUNDS),
        'amplitude': _harmonics(REQUIRED, 'Nm, one per harmonic 1..n'),
        'phase': _harmonics(None, 'rad, one per harmonic (default 0)'),
    }, doc='torque ripple periodic in q, added to the friction torque'),
}

#: The full schema of the ``ros__parameters`` mapping of a gear file.
SCHEMA: dict[str, _Spec] = {
    'joint_name': Str('joint', doc='joint name in JointState messages'),
    'gear_ratio': Float(positive=True, doc='gear ratio N'),
    'inertia': Float(positive=True, doc='output-side inertia J, kg m^2'),
    'friction': Section(FRICTION_SCHEMA, optional=False, doc='friction model'),
    'lever': Section({
        'mass': Float(0.0, nonnegative=True, doc='kg'),
        'length': Float(0.0, nonnegative=True, doc='distance of the mass from the axis, m'),
        'gravity': Float(9.81, positive=True, doc='m/s^2'),
        'angle_offset': Float(0.0, doc='rad: the gravity torque is m g l sin(q - angle_offset), '
                              'q = angle_offset hangs down', bounds=ANGLE_OFFSET_BOUNDS),
        'pose_center': Float(0.0, doc='rad: the position pose_torque is a polynomial about'),
        'pose_torque': FloatList([], doc='Nm, Nm/rad, Nm/rad^2: a direction-independent torque '
                                 'sum_k c_k (q - pose_center)^k added to the lever torque (a '
                                 'pose-dependent load error found over a short stroke: '
                                 'gravity, payload, cable; [] none)',
                                 max_len=MAX_POLYNOMIAL_ORDER + 1,
                                 limit=f'pose polynomial order <= {MAX_POLYNOMIAL_ORDER}'),
    }, doc='lever whose gravity m g l sin(q - angle_offset) (plus pose_torque) loads the '
           'joint (q = angle_offset hanging down)'),
    'thermal': Section({
        'capacity': Float(450.0, positive=True, doc='heat capacity of gear and housing, J/K'),
        'resistance': Float(1.2, positive=True, doc='thermal resistance housing-ambient, K/W'),
        'ambient': Float(25.0, doc='ambient temperature, degC', bounds=TEMPERATURE_BOUNDS),
        'initial': Float(None, doc='initial housing temperature, degC (default ambient)',
                         bounds=TEMPERATURE_BOUNDS),
    }, doc='lumped thermal model heated by the friction losses'),
    'sensors': Section({
        'encoder_bits': Int(25, minimum=1, doc='output encoder resolution, bits/rev',
                            bounds=ENCODER_BITS_BOUNDS),
        'velocity_cutoff': Float(250.0, positive=True, doc='velocity filter cut-off, Hz (below '
                                 'the Nyquist frequency of simulation.rate)'),
        'current_bandwidth': Float(800.0, positive=True, doc='current loop bandwidth, Hz'),
        'torque_noise': Float(0.01, nonnegative=True, doc='applied-torque noise std, Nm'),
        'effort_noise': Float(0.005, nonnegative=True, doc='measured-effort noise std, Nm'),
        'temperature_resolution': Float(0.0625, positive=True, doc='degC',
                                        bounds=TEMPERATURE_RESOLUTION_BOUNDS),
        'temperature_time_constant': Float(4.0, positive=True, doc='sensor lag, s'),
        'temperature_noise': Float(0.0, nonnegative=True, doc='std, degC'),
        'link_torque_noise': Float(0.03, nonnegative=True,
                                   doc='output torque sensor noise std, Nm'),
    }, doc='sensor models of the simulated test bed'),
    'simulation': Section({
        'rate': Float(3000.0, positive=True, doc='simulation and control rate, Hz',
                      bounds=RATE_BOUNDS),
        'temperature_rate': Float(4.0, positive=True, doc='temperature sample rate, Hz (at most '
                                  'simulation.rate)'),
        'seed': Int(0, minimum=0, doc='noise seed'),
    }, doc='simulator rates'),
}

#: sections whose defaults apply when they are absent from a file
DEFAULT_SECTIONS = ('lever', 'thermal', 'sensors', 'simulation')


def key_specs(schema: dict[str, _Spec] | None = None, prefix: str = '') -> dict[str, _Spec]:
    """Return {dotted name: spec} of every key and section of ``schema`` (:data:`SCHEMA`)."""
    out: dict[str, _Spec] = {}
    for key, spec in (SCHEMA if schema is None else schema).items():
        out[prefix + key] = spec
        if isinstance(spec, Section):
            out.update(key_specs(spec.fields, prefix + key + '.'))
    return out


def required_keys(schema: dict[str, _Spec] | None = None, prefix: str = '') -> list[str]:
    """Return the dotted names of the keys every gear must give (``gear_ratio``, ...)."""
    out: list[str] = []
    for key, spec in (SCHEMA if schema is None else schema).items():
        if spec.default is not REQUIRED:
            continue
        if isinstance(spec, Section):
            out += required_keys(spec.fields, prefix + key + '.')
        else:
            out.append(prefix + key)
    return out
