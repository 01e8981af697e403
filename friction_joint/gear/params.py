# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Validated gear parameters: the typed views, the consistency and physical checks.

:func:`gear_from_dict` (a nested ``ros__parameters`` mapping) and
:func:`gear_from_flat` (ROS-style dotted names, as the nodes get them from
rcl) both end in the same schema (:mod:`.schema`) and checks, so a gear read
by the command line and by a node is the same :class:`GearParams`.
"""
from __future__ import annotations

import copy
import dataclasses
import os
from typing import Any, overload
import warnings

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .polynomial import polynomial_violation
from .schema import (DEFAULT_SECTIONS, MIN_CUTOFF_FRACTION, REQUIRED, SCHEMA, Section,
                     validate_fields)
from ..exceptions import GearConfigError, GearConfigWarning
from ..models.params import FrictionParams, GMSParams, LuGreParams, RippleParams

__all__ = ['LuGreParams', 'GMSParams', 'RippleParams', 'FrictionParams', 'GearParams',
           'gear_from_dict', 'gear_from_flat', 'expand_dotted', 'passivity_bound']


@dataclasses.dataclass(frozen=True)
class GearParams:
    """
    A validated gear parameter set.

    ``data`` is the validated ``ros__parameters`` mapping (defaults filled
    in); the other attributes are typed views of it.

    Attributes
    ----------
    joint_name : str
        The joint's name in recordings.
    gear_ratio : float
        Gear ratio.
    inertia : float
        Joint inertia (kg m^2).
    friction : FrictionParams
        The ``friction`` section.
    data : dict
        The validated ``ros__parameters`` mapping.
    source : str or None
        Where it came from, used in error messages.
    given : frozenset of str
        Dotted names of the keys the source gave (the others hold defaults).

    """

    joint_name: str
    gear_ratio: float
    inertia: float
    friction: FrictionParams
    data: dict[str, Any] = dataclasses.field(repr=False, compare=False)
    source: str | None = None
    given: frozenset[str] = dataclasses.field(default=frozenset(), repr=False, compare=False)

    def section(self, name: str) -> dict[str, Any] | None:
        """
        Return a validated simulator section with defaults (``'lever'``, ``'thermal'``, ...).

        Parameters
        ----------
        name : str
            The section's key.

        Returns
        -------
        dict or None
            A copy of the section; None for an absent section without defaults.

        """
        sec = self.data.get(name)
        if sec is None and name in DEFAULT_SECTIONS:
            sec = _defaults(name)
        return copy.deepcopy(sec)

    @property
    def mgl(self) -> float:
        """Lever gravity amplitude m g l, in Nm."""
        lever = _section(self.data, 'lever')
        return float(lever['mass'] * lever['gravity'] * lever['length'])

    @property
    def lever_offset(self) -> float:
        """Angle (rad) at which the lever hangs down: gravity is m g l sin(q - offset)."""
        return float(_section(self.data, 'lever')['angle_offset'])

    def lever_torque(self, q: ArrayLike) -> float | NDArray[np.float64]:
        """
        Return the lever's torque m g l sin(q - angle_offset) (+ its pose torque) at ``q``.

        ``lever.pose_torque`` (Nm per power of rad, default none) adds the polynomial
        ``sum_k c_k (q - lever.pose_center)^k``: a pose-dependent load a diagnosis
        found over a stroke too short to tell a lever's sine (the simulated plant and
        the controller's feed-forward use the lever's sine only).

        Parameters
        ----------
        q : float or array_like
            Output position(s), rad.

        Returns
        -------
        float or numpy.ndarray
            Torque (Nm), a float for a scalar ``q``, else an array of ``q``'s shape.

        """
        lever = _section(self.data, 'lever')
        mgl = lever['mass'] * lever['gravity'] * lever['length']
        qa = np.asarray(q, float)
        out: NDArray[np.float64] = mgl * np.sin(qa - lever['angle_offset'])
        pose = lever.get('pose_torque') or []
        if len(pose):
            out = out + np.polynomial.polynomial.polyval(qa - lever['pose_center'], pose)
        return float(out) if out.ndim == 0 else out

    def replace(self, changes: dict[str, Any]) -> GearParams:
        """
        Return a new GearParams with ``changes`` merged in and validated.

        Parameters
        ----------
        changes : dict
            A nested ``ros__parameters`` mapping of the keys to change.

        Returns
        -------
        GearParams

        """
        data = copy.deepcopy(self.data)
        _merge(data, changes)
        return gear_from_dict(data, source=self.source, given=self.given | _given_keys(changes))

    def to_dict(self) -> dict[str, Any]:
        """
        Return the gear file's content: ``{'/**': {'ros__parameters': ...}}``.

        Keys the source did not give and that still hold their default are
        left out, so writing a gear does not change its model structure
        (e.g. an absent ``delta_v`` stays absent, meaning linear viscous).
        """
        return {'/**': {'ros__parameters': _prune(copy.deepcopy(self.data), SCHEMA, self.given)}}


def _merge(dst: dict[Any, Any], src: dict[Any, Any]) -> None:
    for key, val in src.items():
        if isinstance(val, dict) and isinstance(dst.get(key), dict):
            _merge(dst[key], val)
        else:
            dst[key] = val


def _given_keys(d: dict[Any, Any], prefix: str = '') -> frozenset[str]:
    out: set[str] = set()
    for k, v in d.items():
        name = prefix + str(k)
        out.add(name)
        if isinstance(v, dict):
            out |= _given_keys(v, name + '.')
    return frozenset(out)


def _prune(d: dict[str, Any], fields: dict[str, Any], given: frozenset[str],
           prefix: str = '') -> dict[str, Any]:
    """Drop absent optional keys, and defaults that were not given, for writing."""
    out: dict[str, Any] = {}
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


@overload
def _tup(x: None) -> None: ...


@overload
def _tup(x: list[float]) -> tuple[float, ...]: ...


def _tup(x: list[float] | None) -> tuple[float, ...] | None:
    return None if x is None else tuple(x)


def gear_from_dict(params: dict[str, Any], *, source: str | os.PathLike[str] | None = None,
                   given: frozenset[str] | None = None) -> GearParams:
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
        Unknown key, wrong type, NaN, a list longer than its limit or a
        physically impossible value.

    """
    where = f'{source}: ' if source else ''
    try:
        if not isinstance(params, dict):
            raise GearConfigError(f'expected a mapping of gear keys, got {type(params).__name__}')
        data = validate_fields(SCHEMA, params, '')
        _check_sections(data)
        friction = _friction_from(data['friction'])
        _check_physics(friction)
    except GearConfigError as exc:
        raise GearConfigError(where + str(exc)) from None
    gear = GearParams(data['joint_name'], data['gear_ratio'], data['inertia'],
                      friction, data, None if source is None else os.fspath(source),
                      _given_keys(params) if given is None else frozenset(given))
    _warn_passivity(gear, where)
    return gear


def _defaults(name: str) -> dict[str, Any]:
    spec = SCHEMA[name]
    assert isinstance(spec, Section)                   # a simulator section
    return validate_fields(spec.fields, {}, name)


def _section(data: dict[str, Any], name: str) -> dict[str, Any]:
    sec: dict[str, Any] | None = data.get(name)
    return _defaults(name) if sec is None else sec


def _check_sections(data: dict[str, Any]) -> None:
    """
    Check the values of the simulator sections against each other (defaults filled in).

    The velocity filter's cut-off must be below the Nyquist frequency of the
    simulation rate, and not below :data:`~.schema.MIN_CUTOFF_FRACTION` of it (a
    2nd-order low-pass at a smaller fraction loses its unit gain in double
    precision); the temperature is sampled at most at the simulation rate; the
    lever's gravity torque m g l is finite.
    """
    sens, sim, lever = (_section(data, n) for n in ('sensors', 'simulation', 'lever'))
    rate, cutoff = sim['rate'], sens['velocity_cutoff']
    if not cutoff < rate / 2.0:
        raise GearConfigError(f'sensors.velocity_cutoff: {cutoff:g} Hz must be below the '
                              f'Nyquist frequency {rate / 2.0:g} Hz of simulation.rate '
                              f'{rate:g} Hz')
    if cutoff < MIN_CUTOFF_FRACTION * rate:
        raise GearConfigError(f'sensors.velocity_cutoff: {cutoff:g} Hz is below '
                              f'{MIN_CUTOFF_FRACTION:g} of simulation.rate {rate:g} Hz (the '
                              'velocity filter loses its unit gain in double precision)')
    if sim['temperature_rate'] > rate:
        raise GearConfigError(f'simulation.temperature_rate: {sim["temperature_rate"]:g} Hz '
                              f'is above simulation.rate {rate:g} Hz')
    mgl = lever['mass'] * lever['gravity'] * lever['length']
    if not np.isfinite(mgl):
        raise GearConfigError('lever: the gravity torque mass * gravity * length overflows '
                              f'({lever["mass"]:g} * {lever["gravity"]:g} * '
                              f'{lever["length"]:g})')


def _friction_from(fr: dict[str, Any]) -> FrictionParams:
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
    lugre: LuGreParams | None = None
    gms: GMSParams | None = None
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


def _temperature_polynomials(friction: FrictionParams) -> dict[str, tuple[float, ...]]:
    """Coefficients of the temperature polynomials the curve is made of (at zero load)."""
    out = {'fc': friction.fc, 'fv': friction.fv, 'delta_v': friction.delta_v}
    if friction.fs is not None and friction.vs is not None:    # both or none (_friction_from)
        out['fs'] = friction.fs
        out['vs'] = friction.vs
    return out


def _check_physics(friction: FrictionParams) -> None:
    """
    Check F_c, F_v, F_s >= 0 and v_s, delta_v > 0 on the whole temperature range, at zero load.

    Exact on the interval (:func:`~.polynomial.polynomial_violation`: end points
    and critical points), so a polynomial dipping below zero between two
    temperatures is found.  The load terms are not part of the check: the gear
    file has no load range (contact torques are unbounded), and the models clip
    the evaluated parameters to their physical bounds at run time.
    """
    lo, hi = friction.temperature_range
    for name, coef in _temperature_polynomials(friction).items():
        strict = name in ('vs', 'delta_v')
        bad = polynomial_violation(coef, lo, hi, strict=strict)
        if bad is not None:
            value, xi = bad
            raise GearConfigError(
                f'friction.{name}: evaluates to {value:.4g} '
                f'(must be {"> 0" if strict else ">= 0"}) '
                f'at xi = {xi:.1f} degC inside friction.temperature_range [{lo}, {hi}]; '
                'narrow the range to where the polynomial was identified or fix the coefficients')


def passivity_bound(friction: FrictionParams, xi: ArrayLike) -> NDArray[np.float64]:
    """
    Return the upper bound on sigma1 for a passive LuGre model (Astrom & Canudas de Wit 2008).

    sigma1 < sigma2 F_c / (F_s - F_c), with sigma2 the viscous slope.  For the nonlinear viscous
    term (eq. 5) sigma2 is taken as ds/dqd at qd = v_s/kappa, the velocity where the Stribeck dip
    happens; for delta_v = 1 this is the exact linear coefficient.

    Parameters
    ----------
    friction : FrictionParams
        The friction section.
    xi : array_like
        Temperatures (degC).

    Returns
    -------
    ndarray
        The bound (Nm s/rad) at each temperature; inf where F_s <= F_c.

    """
    from ..models.static import StaticFriction
    p = StaticFriction(friction).parameters(np.atleast_1d(xi))
    kappa = friction.velocity_scale
    v = p['vs'] / kappa
    sigma2 = p['fv'] * p['delta_v'] * kappa * np.abs(kappa * v) ** (p['delta_v'] - 1.0)
    dif = p['fs'] - p['fc']
    with np.errstate(divide='ignore'):
        return np.where(dif > 0, sigma2 * p['fc'] / np.where(dif > 0, dif, 1.0), np.inf)


def _warn_passivity(gear: GearParams, where: str) -> None:
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


def _combine(dst: dict[str, Any], src: dict[str, Any], prefix: str) -> None:
    """Merge ``src`` into ``dst``; a key given by both is an error (dotted and nested)."""
    for key, val in src.items():
        if key not in dst:
            dst[key] = val
        elif isinstance(dst[key], dict) and isinstance(val, dict):
            _combine(dst[key], val, f'{prefix}{key}.')
        elif isinstance(dst[key], dict) or isinstance(val, dict):
            raise GearConfigError(f'key {prefix}{key} is both a value and a section')
        else:
            raise GearConfigError(f'key {prefix}{key} is given twice (as a dotted name and '
                                  'within its section)')


def expand_dotted(params: dict[Any, Any], prefix: str = '') -> dict[str, Any]:
    """
    Return ``params`` with dotted names (``friction.fc``) turned into nested sections.

    Parameters
    ----------
    params : dict
        A ``ros__parameters`` mapping, nested, dotted or both.
    prefix : str
        Dotted name of ``params`` itself, for error messages.

    Raises
    ------
    GearConfigError
        A key is given twice (``friction.fc`` and ``friction: {fc: ...}``), or
        is both a value and a section.

    """
    out: dict[str, Any] = {}
    for key, val in params.items():
        parts = str(key).split('.')
        if isinstance(val, dict):
            val = expand_dotted(val, f'{prefix}{key}.')
        for part in reversed(parts[1:]):
            val = {part: val}
        _combine(out, {parts[0]: val}, prefix)
    return out


def gear_from_flat(params: dict[str, Any], *, source: str | None = None) -> GearParams:
    """
    Build GearParams from ROS-style dotted names (``friction.fc`` ...).

    Parameters
    ----------
    params : dict
        A ``ros__parameters`` mapping, dotted, nested or both.
    source : str, optional
        Where it came from, used in error messages.

    Returns
    -------
    GearParams

    """
    where = f'{source}: ' if source else ''
    try:
        nested = expand_dotted(params)
    except GearConfigError as exc:
        raise GearConfigError(where + str(exc)) from None
    return gear_from_dict(nested, source=source)
