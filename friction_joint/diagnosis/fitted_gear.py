# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Gear files of fitted diagnosis structures: for simulation and the validated ``extended.yaml``.

:func:`sim_gear` builds an unvalidated gear of a fold's fit (for the open-loop
velocity simulation); :func:`extended_gear` the validated gear file of a
structure fitted on all data, its temperature polynomials limited to the
range the data cover (:func:`~friction_joint.diagnosis.structures.fit_range`);
:func:`extended_model` walks back from the last added effect to the first
structure that fits physically, so an extension that cannot be fitted
physically is reported as such and never aborts the report.
"""
from __future__ import annotations

import dataclasses
from typing import Any, TYPE_CHECKING, TypedDict
import warnings

import numpy as np

from . import structures as dm
from .crossval import fit_all
from .gravity import corrected_lever, pose_lever
from ..exceptions import GearConfigError, GearConfigWarning
from ..gear import gear_from_dict, GMSParams, LuGreParams, passivity_bound, RippleParams

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from ..gear import GearParams

__all__ = ['sim_gear', 'extended_gear', 'extended_model', 'PASSIVITY_MARGIN', 'ExtendedFit']


class ExtendedFit(TypedDict):
    """The extended model of :func:`extended_model` (its keys are documented there)."""

    gear: GearParams
    structure: dm.CandidateStructure
    coef: dict[str, Any]
    kept: int
    reason: str | None


def sim_gear(base: GearParams, s: dm.CandidateStructure, coef: dict[str, Any]) -> GearParams:
    """Return an unvalidated GearParams for simulation (coefficients as fitted)."""
    f = base.friction
    kw: dict[str, Any]
    kw = {'fc': tuple(coef['fc']), 'fv': tuple(coef['fv']), 'fc_load': tuple(coef['fc_load']),
          'fv_load': tuple(coef['fv_load']), 'fs': None, 'vs': None, 'fs_load': ()}
    if s.nfs:
        kw.update(fs=tuple(coef['fs']), vs=tuple(coef['vs']), fs_load=tuple(coef['fs_load']))
    kw['delta_v'] = tuple(coef['delta_v']) if 'delta_v' in coef else (1.0,)
    if s.ripple:
        r = coef['position_ripple']
        kw['position_ripple'] = RippleParams(r['cycles_per_rev'], tuple(r['amplitude']),
                                             tuple(r['phase']))
    else:
        kw['position_ripple'] = None
    if s.presliding:
        model, stiff = s.ps
        kw['model'] = model
        if model == 'lugre':
            kw['lugre'] = LuGreParams(stiff, f.lugre.sigma1 if f.lugre else 0.0)
        else:
            kw['gms'] = GMSParams(tuple(float(v) for v in stiff * _ctx_ratios(base)),
                                  tuple(_ctx_alpha(base)), f.gms.c if f.gms else 400.0)
    else:
        kw['model'] = 'static'
    if hasattr(f, 'offset'):
        kw['offset'] = 0.0            # applied through the drive torque in simulation
    fr = dataclasses.replace(f, **kw)
    return dataclasses.replace(base, friction=fr,
                               inertia=base.inertia + coef.get('d_inertia', 0.0))


def _ctx_ratios(base: GearParams) -> NDArray[np.float64]:
    g = base.friction.gms
    r: NDArray[np.float64] = np.asarray(g.k, float) if g is not None else dm.GMS_RATIOS
    return r / float(r.sum())


def _ctx_alpha(base: GearParams) -> list[float]:
    g = base.friction.gms
    if g is not None:
        return list(g.alpha)
    return [1.0 / len(dm.GMS_RATIOS)] * len(dm.GMS_RATIOS)


def extended_gear(base: GearParams, s: dm.CandidateStructure, coef: dict[str, Any],
                  ctx: dm.Context) -> GearParams:
    """
    Return the validated gear file of the extended model (base sections kept).

    Raises
    ------
    GearConfigError
        The fitted model is not physical (e.g. a polynomial below zero in its range).

    """
    fr: dict[str, Any]
    fr = {'fc': coef['fc'], 'fv': coef['fv'], 'fc_load': coef['fc_load'],
          'fv_load': coef['fv_load']}
    if s.nfs:
        fr.update(fs=coef['fs'], vs=coef['vs'], fs_load=coef['fs_load'])
    if 'delta_v' in coef:
        fr['delta_v'] = coef['delta_v']
    if s.ripple:
        fr['position_ripple'] = coef['position_ripple']
    if s.offset:
        fr['offset'] = coef['offset']
    changes: dict[str, Any] = {'friction': fr}
    if s.gravity and 'pose' in coef['gravity']:
        changes['lever'], coef['gravity']['pose'] = pose_lever(base, coef['gravity']['pose'])
    elif s.gravity:
        changes['lever'], coef['gravity']['lever'] = corrected_lever(base, coef['gravity'])
    if s.inertia:
        changes['inertia'] = base.inertia + coef['d_inertia']
    if s.presliding:
        model, stiff = s.ps
        fr['model'] = model
        if model == 'lugre':
            fr['lugre'] = {'sigma0': float(stiff),
                           'sigma1': base.friction.lugre.sigma1 if base.friction.lugre else 0.0}
        else:
            g = base.friction.gms
            fr['gms'] = {'k': [float(v) for v in stiff * _ctx_ratios(base)],
                         'alpha': [float(a) for a in _ctx_alpha(base)],
                         'c': g.c if g is not None else 400.0}
    if max(s.nfc, s.nfv, s.nfs) > 1:
        fr['temperature_range'] = [float(v) for v in ctx.range]
    gear = _validated(base, changes, quiet=True)
    f = gear.friction
    if f.lugre is not None and f.fs is not None:
        # a Stribeck dip added to a LuGre base can make the base's sigma1 non-passive
        # (Astrom & Canudas de Wit 2008): keep sigma1 below the bound with a margin
        bound = float(np.min(passivity_bound(f, np.linspace(*f.temperature_range, 21))))
        if f.lugre.sigma1 >= bound:
            sigma1 = float(f'{PASSIVITY_MARGIN * bound:.4g}')
            fr['lugre'] = {'sigma0': f.lugre.sigma0, 'sigma1': sigma1}
            coef['sigma1_passivity'] = {'from': f.lugre.sigma1, 'to': sigma1, 'bound': bound}
            gear = _validated(base, changes)
    return gear


#: sigma1 of an extended LuGre model is set to this fraction of the passivity bound
#: when the base's value exceeds it
PASSIVITY_MARGIN = 0.9


def _validated(base: GearParams, changes: dict[str, Any], quiet: bool = False) -> GearParams:
    new = base.replace(changes)
    data_d = new.to_dict()['/**']['ros__parameters']
    with warnings.catch_warnings():
        if quiet:
            warnings.simplefilter('ignore', GearConfigWarning)
        return gear_from_dict(data_d, source='extended model', given=new.given)


def extended_model(base: GearParams, structures: list[dm.CandidateStructure], ctx: dm.Context,
                   y: NDArray[np.float64]) -> ExtendedFit:
    """
    Fit the last physical structure of a greedy sequence on all data; never raises.

    Parameters
    ----------
    base : GearParams
        The base gear.
    structures : list of CandidateStructure
        The base structure and the structure after every added effect, in order.
    ctx : Context
        The design context.
    y : ndarray
        Measured friction torque per bin.

    Returns
    -------
    ExtendedFit
        ``gear`` (validated GearParams), ``structure``, ``coef``, ``kept`` (how
        many additions the gear has: ``len(structures) - 1`` unless the last
        extensions cannot be fitted physically) and ``reason`` (None, or why the
        first left-out extension is not physical).  When not even the base
        structure fits physically, ``gear`` is ``base`` as given and ``kept`` -1.

    """
    reason = None
    for j in range(len(structures) - 1, -1, -1):
        s, beta, names, _ = fit_all([structures[j]], ctx, y)
        coef = dm.coefficients(s, beta, names, ctx)
        try:
            gear = extended_gear(base, s, coef, ctx)
        except GearConfigError as exc:
            reason = reason or f'no physical fit on all data: {exc}'
            continue
        return {'gear': gear, 'structure': s, 'coef': coef, 'kept': j, 'reason': reason}
    s, beta, names, _ = fit_all([structures[0]], ctx, y)
    return {'gear': base, 'structure': structures[0],
            'coef': dm.coefficients(s, beta, names, ctx), 'kept': -1, 'reason': reason}
