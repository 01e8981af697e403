# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The diagnosis's model structure of a gear file, and its extension by one candidate effect.

:func:`base_structure` layers a gear's
:class:`~friction_joint.identification.StaticStructure` (the paper's static
structure, read by :meth:`~friction_joint.identification.StaticStructure.from_gear`)
with the terms the diagnosis adds, into a
:class:`~friction_joint.diagnosis.structures.CandidateStructure`;
:func:`extend` adds one effect of :data:`~friction_joint.effects.EFFECTS` to a structure.
"""
from __future__ import annotations

from typing import Any, TYPE_CHECKING

import numpy as np

from . import structures as dm
from ..effects import effect as _effect
from ..identification import StaticStructure

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['base_structure', 'extend']


def base_structure(gear: GearParams) -> dm.CandidateStructure:
    """
    Return a gear file's :class:`~friction_joint.diagnosis.structures.CandidateStructure`.

    Parameters
    ----------
    gear : GearParams
        The gear.

    Returns
    -------
    CandidateStructure
        The gear's static structure (:meth:`StaticStructure.from_gear`, delta_v
        fixed when the viscous law is linear) plus its ripple, offset and
        pre-sliding model, the nonlinear values at the middle of its temperature range.

    """
    f = gear.friction
    mid = np.mean(f.temperature_range)
    linear = tuple(f.delta_v) == (1.0,)
    static = StaticStructure.from_gear(gear, fixed=('delta_v',) if linear else ())
    terms: dict[str, Any] = {}
    if f.fs is not None and f.vs is not None:      # given together (the gear file check)
        vs0 = float(np.polynomial.polynomial.polyval(mid, f.vs))
        terms['vs'] = max(vs0, 1e-6) / f.velocity_scale
    if 'delta_v' in static.orders:
        terms['dv'] = float(np.polynomial.polynomial.polyval(mid, f.delta_v))
    if f.position_ripple is not None:
        terms.update(ripple=len(f.position_ripple.amplitude), cyc=f.position_ripple.cycles_per_rev)
    if getattr(f, 'offset', None):
        terms['offset'] = True
    # a pre-sliding model has its section (the gear file check)
    if f.model == 'lugre' and f.lugre is not None:
        terms.update(presliding=True, ps=('lugre', f.lugre.sigma0))
    elif f.model == 'gms' and f.gms is not None:
        terms.update(presliding=True, ps=('gms', float(sum(f.gms.k))))
    return dm.CandidateStructure.from_static(static, **terms)


def extend(s: dm.CandidateStructure,
           effect: str) -> tuple[dm.CandidateStructure, str | None] | None:
    """
    Return ``(structure, nonlinear parameter to grid)`` of ``s`` extended by ``effect``.

    Parameters
    ----------
    s : CandidateStructure
        The structure.
    effect : str
        A name of :data:`EFFECTS`.

    Returns
    -------
    tuple or None
        None if the structure has the effect already.

    """
    if effect == 'thermal':
        return s.with_(nfc=s.nfc + 1, nfv=s.nfv + 1, nfs=s.nfs + 1 if s.nfs else 0), None
    if effect == 'load':
        return s.with_(nfc_load=s.nfc_load + 1, nfv_load=s.nfv_load + 1,
                       nfs_load=s.nfs_load + 1 if s.nfs else 0), None
    if effect == 'position_ripple':
        return (None if s.ripple else (s.with_(ripple=dm.RIPPLE_HARMONICS), 'cyc'))
    if effect == 'nonlinear_viscous':
        return None if s.dv_free else (s.with_(dv_free=True), 'dv')
    if effect == 'stribeck':
        return None if s.nfs else (s.with_(nfs=s.nfc, nfs_load=s.nfc_load), 'vs')
    if effect == 'presliding':
        return None if s.presliding else (s.with_(presliding=True), 'ps')
    if effect == 'inertia':
        return None if s.inertia else (s.with_(inertia=True), None)
    if effect == 'asymmetry':
        return None if s.offset else (s.with_(offset=True), None)
    if effect == 'drift':
        return None if s.drift else (s.with_(drift=dm.DRIFT_ORDER), None)
    if effect == 'gravity':
        return None if s.gravity else (s.with_(gravity=True), None)
    _effect(effect)                     # an unknown name: ArgumentError naming the known ones
    raise AssertionError(f'effect {effect!r} of the registry has no extension')
