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
Gear parameter files: load, validate, modify and save (README, Interfaces: gear parameter files).

A gear file is a ROS 2 parameter file; everything sits under ``/**: ros__parameters:``.
The schema below lists every key this package knows.  Unknown keys, wrong types, NaN/inf
and physically impossible values raise :class:`~friction_joint.exceptions.GearConfigError`
naming the key.  A LuGre set that violates the passivity bound only warns
(:class:`~friction_joint.exceptions.GearConfigWarning`).

Keys beyond the contract's base keys (all optional):

``friction.velocity_scale``
    kappa: the friction curve is evaluated at ``kappa * qd``.  Use
    ``gear_ratio`` for coefficients identified against wave-generator speed.
``friction.temperature_range``
    ``[lo, hi]`` degC: xi is clipped to this range before the polynomials are
    evaluated, and the curve is checked for physical values over it.
``friction.offset``
    a constant torque (Nm) added to the friction torque of every model: in
    sliding, friction then differs by direction (the ``asymmetry`` effect).
``friction.position_ripple``
    torque ripple sum_n A_n sin(n c q + phi_n) added to the friction torque.
``friction.lugre.sigma0`` / ``sigma1``
    bristle stiffness (Nm/rad) and micro-damping (Nm s/rad), eq. 10.
``friction.gms.k`` / ``alpha`` / ``c``
    element stiffnesses k_i (Nm/rad), torque fractions alpha_i (sum 1,
    default equal = the paper's mu = 1/N) and attraction C (Nm/s), eq. 11-13.
"""
import copy
import dataclasses
import math
import warnings

import numpy as np
import yaml

from .exceptions import GearConfigError, GearConfigWarning

__all__ = ['GearParams', 'FrictionParams', 'LuGreParams', 'GMSParams', 'RippleParams',
           'load_gear', 'gear_from_dict', 'gear_from_flat', 'save_gear', 'SCHEMA',
           'FRICTION_MODELS', 'passivity_bound', 'Section']

FRICTION_MODELS = ('static', 'lugre', 'gms')
REQUIRED = object()


# ------------------------------------------------------------ key specs ----

class _Spec:
    default = REQUIRED

    def check(self, value, path):  # pragma: no cover - interface
        raise NotImplementedError


class Float(_Spec):
    def __init__(self, default=REQUIRED, positive=False, nonnegative=False, doc=''):
        self.default, self.positive, self.nonnegative, self.doc = (
            default, positive, nonnegative, doc)

    def check(self, value, path):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise GearConfigError(f'{path}: expected a number, got {value!r}')
        value = float(value)
        if not math.isfinite(value):
            raise GearConfigError(f'{path}: must be finite, got {value}')
        if self.positive and value <= 0.0:
            raise GearConfigError(f'{path}: must be > 0, got {value}')
        if self.nonnegative and value < 0.0:
            raise GearConfigError(f'{path}: must be >= 0, got {value}')
        return value


class Int(_Spec):
    def __init__(self, default=REQUIRED, minimum=None, doc=''):
        self.default, self.minimum, self.doc = default, minimum, doc

    def check(self, value, path):
        if isinstance(value, bool) or not isinstance(value, int):
            raise GearConfigError(f'{path}: expected an integer, got {value!r}')
        if self.minimum is not None and value < self.minimum:
            raise GearConfigError(f'{path}: must be >= {self.minimum}, got {value}')
        return value


class Str(_Spec):
    def __init__(self, default=REQUIRED, choices=None, doc=''):
        self.default, self.choices, self.doc = default, choices, doc

    def check(self, value, path):
        if not isinstance(value, str) or not value:
            raise GearConfigError(f'{path}: expected a non-empty string, got {value!r}')
        if self.choices and value not in self.choices:
            raise GearConfigError(f'{path}: must be one of {", ".join(self.choices)}; '
                                  f'got {value!r}')
        return value


class FloatList(_Spec):
    def __init__(self, default=REQUIRED, min_len=0, length=None, positive=False, doc=''):
        self.default, self.min_len, self.length, self.positive, self.doc = (
            default, min_len, length, positive, doc)

    def check(self, value, path):
        if not isinstance(value, (list, tuple)):
            raise GearConfigError(f'{path}: expected a list of numbers, got {value!r}')
        out = []
        for i, v in enumerate(value):
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise GearConfigError(f'{path}[{i}]: expected a number, got {v!r}')
            v = float(v)
            if not math.isfinite(v):
                raise GearConfigError(f'{path}[{i}]: must be finite, got {v}')
            if self.positive and v <= 0.0:
                raise GearConfigError(f'{path}[{i}]: must be > 0, got {v}')
            out.append(v)
        if self.length is not None and len(out) != self.length:
            raise GearConfigError(f'{path}: expected {self.length} numbers, got {len(out)}')
        if len(out) < self.min_len:
            raise GearConfigError(f'{path}: needs at least {self.min_len} coefficient(s), '
                                  f'got {len(out)}')
        return out


class Section(_Spec):
    def __init__(self, fields, optional=True, doc=''):
        self.fields, self.doc = fields, doc
        self.default = None if optional else REQUIRED

    def check(self, value, path):
        if not isinstance(value, dict):
            raise GearConfigError(f'{path}: expected a mapping of keys, got {value!r}')
        return _validate(self.fields, value, path)


def _validate(fields, data, path):
    prefix = path + '.' if path else ''
    unknown = sorted(set(data) - set(fields))
    if unknown:
        raise GearConfigError(f'unknown key {prefix}{unknown[0]}'
                              + (f' (and {len(unknown) - 1} more)' if len(unknown) > 1 else '')
                              + f'; known keys here: {", ".join(sorted(fields))}')
    out = {}
    for key, spec in fields.items():
        if key in data and data[key] is not None:
            out[key] = spec.check(data[key], prefix + key)
        elif spec.default is REQUIRED:
            raise GearConfigError(f'missing required key {prefix}{key}')
        else:
            out[key] = copy.deepcopy(spec.default)
    return out


def _coef(doc, required=False):
    return FloatList(REQUIRED if required else None, min_len=1, doc=doc)


def _load(doc):
    return FloatList([], doc=doc)


FRICTION_SCHEMA = {
    'model': Str('static', choices=FRICTION_MODELS, doc='friction model used by default'),
    'fc': _coef('F_c temperature coefficients, powers 0..n (Nm)', required=True),
    'fv': _coef('F_v temperature coefficients (Nm / (rad/s)^delta_v)', required=True),
    'fs': _coef('F_s temperature coefficients (Nm); absent = no Stribeck effect'),
    'vs': _coef('v_s temperature coefficients (rad/s); required with fs'),
    'delta_v': FloatList([1.0], min_len=1, doc='delta_v temperature coefficients'),
    'delta_s': Float(2.0, positive=True, doc='Stribeck exponent'),
    'fc_load': _load('F_c load coefficients, powers 1..m'),
    'fv_load': _load('F_v load coefficients'),
    'fs_load': _load('F_s load coefficients'),
    'vs_load': _load('v_s load coefficients'),
    'delta_v_load': _load('delta_v load coefficients'),
    'velocity_scale': Float(1.0, positive=True, doc='curve evaluated at velocity_scale * qd'),
    'temperature_range': FloatList([0.0, 100.0], length=2,
                                   doc='validity range of the polynomials, degC'),
    'lugre': Section({
        'sigma0': Float(positive=True, doc='bristle stiffness, Nm/rad'),
        'sigma1': Float(0.0, nonnegative=True, doc='micro-damping, Nm s/rad'),
    }, doc='LuGre pre-sliding parameters (eq. 10)'),
    'gms': Section({
        'k': FloatList(REQUIRED, min_len=1, positive=True, doc='element stiffnesses, Nm/rad'),
        'alpha': FloatList(None, min_len=1, positive=True, doc='element torque fractions, sum 1'),
        'c': Float(positive=True, doc='attraction parameter C, Nm/s'),
    }, doc='GMS parameters (eq. 11-13)'),
    'offset': Float(0.0, doc='constant torque added to the friction torque, Nm'),
    'position_ripple': Section({
        'cycles_per_rev': Float(REQUIRED, positive=True,
                                doc='fundamental, cycles per output revolution'),
        'amplitude': FloatList(REQUIRED, min_len=1, doc='Nm, one per harmonic 1..n'),
        'phase': FloatList(None, min_len=1, doc='rad, one per harmonic (default 0)'),
    }, doc='torque ripple periodic in q, added to the friction torque'),
}

#: The full schema of the ``ros__parameters`` mapping of a gear file.
SCHEMA = {
    'joint_name': Str('joint', doc='joint name in JointState messages'),
    'gear_ratio': Float(positive=True, doc='gear ratio N'),
    'inertia': Float(positive=True, doc='output-side inertia J, kg m^2'),
    'friction': Section(FRICTION_SCHEMA, optional=False, doc='friction model'),
    'lever': Section({
        'mass': Float(0.0, nonnegative=True, doc='kg'),
        'length': Float(0.0, nonnegative=True, doc='distance of the mass from the axis, m'),
        'gravity': Float(9.81, positive=True, doc='m/s^2'),
    }, doc='lever whose gravity m g l sin(q) loads the joint (q = 0 hanging down)'),
    'thermal': Section({
        'capacity': Float(450.0, positive=True, doc='heat capacity of gear and housing, J/K'),
        'resistance': Float(1.2, positive=True, doc='thermal resistance housing-ambient, K/W'),
        'ambient': Float(25.0, doc='ambient temperature, degC'),
        'initial': Float(None, doc='initial housing temperature, degC (default ambient)'),
    }, doc='lumped thermal model heated by the friction losses'),
    'sensors': Section({
        'encoder_bits': Int(25, minimum=1, doc='output encoder resolution, bits/rev'),
        'velocity_cutoff': Float(250.0, positive=True, doc='velocity filter cut-off, Hz'),
        'current_bandwidth': Float(800.0, positive=True, doc='current loop bandwidth, Hz'),
        'torque_noise': Float(0.01, nonnegative=True, doc='applied-torque noise std, Nm'),
        'effort_noise': Float(0.005, nonnegative=True, doc='measured-effort noise std, Nm'),
        'temperature_resolution': Float(0.0625, positive=True, doc='degC'),
        'temperature_time_constant': Float(4.0, positive=True, doc='sensor lag, s'),
        'temperature_noise': Float(0.0, nonnegative=True, doc='std, degC'),
        'link_torque_noise': Float(0.03, nonnegative=True,
                                   doc='output torque sensor noise std, Nm'),
    }, doc='sensor models of the simulated test bed'),
    'simulation': Section({
        'rate': Float(3000.0, positive=True, doc='simulation and control rate, Hz'),
        'temperature_rate': Float(4.0, positive=True, doc='temperature sample rate, Hz'),
        'seed': Int(0, minimum=0, doc='noise seed'),
    }, doc='simulator rates'),
}

#: sections whose defaults apply when they are absent from a file
DEFAULT_SECTIONS = ('lever', 'thermal', 'sensors', 'simulation')


# ------------------------------------------------------------ parameters ---

@dataclasses.dataclass(frozen=True)
class LuGreParams:
    sigma0: float
    sigma1: float = 0.0


@dataclasses.dataclass(frozen=True)
class GMSParams:
    k: tuple
    alpha: tuple
    c: float


@dataclasses.dataclass(frozen=True)
class RippleParams:
    cycles_per_rev: float
    amplitude: tuple
    phase: tuple


@dataclasses.dataclass(frozen=True)
class FrictionParams:
    """Friction parameters of one gear (seed eq. 1, 5-13)."""

    model: str
    fc: tuple
    fv: tuple
    fs: tuple = None
    vs: tuple = None
    delta_v: tuple = (1.0,)
    delta_s: float = 2.0
    fc_load: tuple = ()
    fv_load: tuple = ()
    fs_load: tuple = ()
    vs_load: tuple = ()
    delta_v_load: tuple = ()
    velocity_scale: float = 1.0
    temperature_range: tuple = (0.0, 100.0)
    lugre: LuGreParams = None
    gms: GMSParams = None
    position_ripple: RippleParams = None
    offset: float = 0.0


@dataclasses.dataclass(frozen=True)
class GearParams:
    """
    A validated gear parameter set.

    ``data`` is the validated ``ros__parameters`` mapping (defaults filled
    in); the other attributes are typed views of it.
    """

    joint_name: str
    gear_ratio: float
    inertia: float
    friction: FrictionParams
    data: dict = dataclasses.field(repr=False, compare=False)
    source: str = None
    given: frozenset = dataclasses.field(default=frozenset(), repr=False, compare=False)

    def section(self, name):
        """Return a validated simulator section with defaults (``'lever'``, ``'thermal'``, ...)."""
        sec = self.data.get(name)
        if sec is None and name in DEFAULT_SECTIONS:
            sec = _validate(SCHEMA[name].fields, {}, name)
        return copy.deepcopy(sec)

    @property
    def mgl(self):
        """Lever gravity amplitude m g l, in Nm."""
        lever = self.section('lever')
        return lever['mass'] * lever['gravity'] * lever['length']

    def replace(self, changes):
        """Return a new GearParams with ``changes`` (a nested dict) merged in and validated."""
        data = copy.deepcopy(self.data)
        _merge(data, changes)
        return gear_from_dict(data, source=self.source, given=self.given | _given_keys(changes))

    def to_dict(self):
        """
        Return the gear file's content: ``{'/**': {'ros__parameters': ...}}``.

        Keys the source did not give and that still hold their default are
        left out, so writing a gear does not change its model structure
        (e.g. an absent ``delta_v`` stays absent, meaning linear viscous).
        """
        return {'/**': {'ros__parameters': _prune(copy.deepcopy(self.data), SCHEMA, self.given)}}


def _merge(dst, src):
    for key, val in src.items():
        if isinstance(val, dict) and isinstance(dst.get(key), dict):
            _merge(dst[key], val)
        else:
            dst[key] = val


def _given_keys(d, prefix=''):
    out = set()
    for k, v in d.items():
        name = prefix + str(k)
        out.add(name)
        if isinstance(v, dict):
            out |= _given_keys(v, name + '.')
    return frozenset(out)


def _prune(d, fields, given, prefix=''):
    """Drop absent optional keys, and defaults that were not given, for writing."""
    out = {}
    for k, v in d.items():
        name = prefix + k
        spec = fields.get(k)
        if v is None:
            continue
        if isinstance(v, dict) and isinstance(spec, Section):
            out[k] = _prune(v, spec.fields, given, name + '.')
        elif name in given or spec is None or spec.default is REQUIRED or v != spec.default:
            out[k] = v
    return out


def _tup(x):
    return None if x is None else tuple(x)


def gear_from_dict(params, source=None, given=None):
    """
    Validate a ``ros__parameters`` mapping and return :class:`GearParams`.

    Parameters
    ----------
    params : dict
        The nested mapping under ``ros__parameters`` (not the whole file).
    source : str, optional
        Where it came from, used in error messages.
    given : set of str, optional
        Dotted keys given explicitly (default: those present in ``params``).

    Raises
    ------
    GearConfigError
        Unknown key, wrong type, NaN or a physically impossible value.

    """
    where = f'{source}: ' if source else ''
    try:
        data = _validate(SCHEMA, params, '')
        fr = data['friction']
        friction = _friction_from(fr)
        _check_physics(friction)
    except GearConfigError as exc:
        raise GearConfigError(where + str(exc)) from None
    gear = GearParams(data['joint_name'], data['gear_ratio'], data['inertia'],
                      friction, data, source,
                      _given_keys(params) if given is None else frozenset(given))
    _warn_passivity(gear, where)
    return gear


def _friction_from(fr):
    if fr['fs'] is not None and fr['vs'] is None:
        raise GearConfigError('friction.fs is given but friction.vs is missing: '
                              'the Stribeck term needs both')
    if fr['vs'] is not None and fr['fs'] is None:
        raise GearConfigError('friction.vs is given but friction.fs is missing: '
                              'the Stribeck term needs both')
    if fr['fs'] is None and (fr['fs_load'] or fr['vs_load']):
        raise GearConfigError('friction.fs_load/vs_load need friction.fs and friction.vs')
    lo, hi = fr['temperature_range']
    if not lo < hi:
        raise GearConfigError(f'friction.temperature_range: need lo < hi, got [{lo}, {hi}]')
    lugre = gms = None
    if fr['lugre'] is not None:
        lugre = LuGreParams(fr['lugre']['sigma0'], fr['lugre']['sigma1'])
    if fr['gms'] is not None:
        g = fr['gms']
        k = tuple(g['k'])
        alpha = tuple(g['alpha']) if g['alpha'] is not None else tuple([1.0 / len(k)] * len(k))
        if len(alpha) != len(k):
            raise GearConfigError(f'friction.gms.alpha: {len(alpha)} fractions for '
                                  f'{len(k)} elements')
        if abs(sum(alpha) - 1.0) > 1e-9:
            raise GearConfigError('friction.gms.alpha: fractions must sum to 1, '
                                  f'got {sum(alpha):.12g}')
        gms = GMSParams(k, alpha, g['c'])
    ripple = None
    if fr['position_ripple'] is not None:
        r = fr['position_ripple']
        phase = r['phase'] if r['phase'] is not None else [0.0] * len(r['amplitude'])
        if len(phase) != len(r['amplitude']):
            raise GearConfigError(f'friction.position_ripple.phase: {len(phase)} phases for '
                                  f'{len(r["amplitude"])} amplitudes')
        ripple = RippleParams(r['cycles_per_rev'], tuple(r['amplitude']), tuple(phase))
    if fr['model'] == 'lugre' and lugre is None:
        raise GearConfigError('friction.model is lugre but friction.lugre (sigma0, sigma1) '
                              'is missing')
    if fr['model'] == 'gms' and gms is None:
        raise GearConfigError('friction.model is gms but friction.gms (k, c) is missing')
    return FrictionParams(
        model=fr['model'], fc=_tup(fr['fc']), fv=_tup(fr['fv']), fs=_tup(fr['fs']),
        vs=_tup(fr['vs']), delta_v=_tup(fr['delta_v']), delta_s=fr['delta_s'],
        fc_load=_tup(fr['fc_load']), fv_load=_tup(fr['fv_load']), fs_load=_tup(fr['fs_load']),
        vs_load=_tup(fr['vs_load']), delta_v_load=_tup(fr['delta_v_load']),
        velocity_scale=fr['velocity_scale'], temperature_range=(lo, hi), lugre=lugre, gms=gms,
        position_ripple=ripple, offset=fr['offset'])


def _raw_curve(friction, xi):
    """Unclipped polynomial values over temperatures xi at zero load."""
    def poly(c):
        return np.polynomial.polynomial.polyval(xi, c)
    out = {'fc': poly(friction.fc), 'fv': poly(friction.fv), 'delta_v': poly(friction.delta_v)}
    if friction.fs is not None:
        out['fs'] = poly(friction.fs)
        out['vs'] = poly(friction.vs)
    return out


def _check_physics(friction):
    lo, hi = friction.temperature_range
    xi = np.linspace(lo, hi, 41)
    for name, vals in _raw_curve(friction, xi).items():
        strict = name in ('vs', 'delta_v')
        bad = vals <= 0.0 if strict else vals < 0.0
        if np.any(bad):
            i = int(np.argmax(bad))
            raise GearConfigError(
                f'friction.{name}: evaluates to {vals[i]:.4g} '
                f'(must be {"> 0" if strict else ">= 0"}) '
                f'at xi = {xi[i]:.1f} degC inside friction.temperature_range [{lo}, {hi}]; '
                'narrow the range to where the polynomial was identified or fix the coefficients')


def passivity_bound(friction, xi):
    """
    Upper bound on sigma1 for a passive LuGre model (Astrom & Canudas de Wit 2008).

    sigma1 < sigma2 F_c / (F_s - F_c), with sigma2 the viscous slope.  For the nonlinear viscous
    term (eq. 5) sigma2 is taken as ds/dqd at qd = v_s/kappa, the velocity where the Stribeck dip
    happens; for delta_v = 1 this is the exact linear coefficient.  Returns inf where F_s <= F_c.
    """
    from .models.static import StaticFriction
    p = StaticFriction(friction).parameters(np.atleast_1d(xi))
    kappa = friction.velocity_scale
    v = p['vs'] / kappa
    sigma2 = p['fv'] * p['delta_v'] * kappa * np.abs(kappa * v) ** (p['delta_v'] - 1.0)
    dif = p['fs'] - p['fc']
    with np.errstate(divide='ignore'):
        return np.where(dif > 0, sigma2 * p['fc'] / np.where(dif > 0, dif, 1.0), np.inf)


def _warn_passivity(gear, where):
    f = gear.friction
    if f.lugre is None or f.fs is None:
        return
    xi = np.linspace(*f.temperature_range, 21)
    bound = passivity_bound(f, xi)
    i = int(np.argmin(bound))
    if f.lugre.sigma1 >= bound[i]:
        warnings.warn(
            f'{where}friction.lugre.sigma1 = {f.lugre.sigma1:g} violates the passivity bound '
            f'sigma1 < sigma2*Fc/(Fs-Fc) = {bound[i]:.4g} at xi = {xi[i]:.1f} degC '
            '(Astrom & Canudas de Wit 2008): the model may be non-passive near velocity reversal',
            GearConfigWarning, stacklevel=3)


# ------------------------------------------------------------------ files --

def _expand_dotted(params):
    out = {}
    for key, val in params.items():
        parts = str(key).split('.')
        d = out
        for p in parts[:-1]:
            d = d.setdefault(p, {})
            if not isinstance(d, dict):
                raise GearConfigError(f'key {key}: {p} is both a value and a section')
        if isinstance(val, dict):
            val = _expand_dotted(val)
            if isinstance(d.get(parts[-1]), dict):
                _merge(d[parts[-1]], val)
                continue
        d[parts[-1]] = val
    return out


def gear_from_flat(params, source=None):
    """Build GearParams from ROS-style dotted names (``friction.fc`` ...)."""
    return gear_from_dict(_expand_dotted(params), source=source)


def load_gear(path):
    """
    Load and validate a gear parameter file.

    Parameters
    ----------
    path : str or os.PathLike
        The gear parameter file.

    Returns
    -------
    GearParams

    Raises
    ------
    GearConfigError
        The file is missing, not YAML, not a ROS 2 parameter file, or invalid.

    """
    path = str(path)
    try:
        with open(path, encoding='utf-8') as fh:
            doc = yaml.safe_load(fh)
    except OSError as exc:
        raise GearConfigError(f'{path}: cannot read gear file: {exc.strerror}') from None
    except yaml.YAMLError as exc:
        raise GearConfigError(f'{path}: not valid YAML: {exc}') from None
    if not isinstance(doc, dict) or '/**' not in doc:
        raise GearConfigError(f'{path}: not a gear parameter file: expected a top-level '
                              '"/**:" key with "ros__parameters:" below it')
    extra = sorted(set(doc) - {'/**'})
    if extra:
        raise GearConfigError(f'{path}: unexpected top-level key {extra[0]!r}; '
                              'put every parameter under "/**: ros__parameters:"')
    node = doc['/**']
    if not isinstance(node, dict) or set(node) != {'ros__parameters'} or not isinstance(
            node['ros__parameters'], dict):
        raise GearConfigError(f'{path}: "/**" must contain exactly one mapping "ros__parameters"')
    return gear_from_dict(_expand_dotted(node['ros__parameters']), source=path)


def save_gear(gear, path, header=None):
    """Write ``gear`` as a ROS 2 parameter file (atomically), with optional comment header."""
    import os
    import tempfile
    text = yaml.safe_dump(gear.to_dict(), sort_keys=False, default_flow_style=None)
    if header:
        text = ''.join(f'# {line}\n' if line else '#\n' for line in header.splitlines()) + text
    path = str(path)
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=d, prefix='.gear-', suffix='.yaml')
    with os.fdopen(fd, 'w', encoding='utf-8') as fh:
        fh.write(text)
    os.replace(tmp, path)
