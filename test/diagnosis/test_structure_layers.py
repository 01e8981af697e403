# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The diagnosis's model structure is the identification's static structure plus its own terms.

For every shipped gear file, gear -> :class:`StaticStructure` ->
:class:`CandidateStructure` (:func:`base_structure`) gives the structure the
gear's lists gave directly (the reference below reads them as the diagnosis
did), and a structure's static part reads back as the same
:class:`StaticStructure`.
"""
from pathlib import Path

from friction_joint import load_gear
from friction_joint.diagnosis import base_structure, CandidateStructure, extend
from friction_joint.identification import StaticStructure
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
GEARS = sorted((ROOT / 'config').glob('*.yaml'))
STATIC_FIELDS = ('nfc', 'nfv', 'nfs', 'nfc_load', 'nfv_load', 'nfs_load', 'dv_free')


def _from_lists(gear):
    """Read the base structure from the gear's coefficient lists directly."""
    f = gear.friction
    s = CandidateStructure(nfc=len(f.fc), nfv=len(f.fv), nfc_load=len(f.fc_load),
                           nfv_load=len(f.fv_load))
    if f.fs is not None:
        vs0 = float(np.polynomial.polynomial.polyval(np.mean(f.temperature_range), f.vs))
        s = s.with_(nfs=len(f.fs), nfs_load=len(f.fs_load), vs=max(vs0, 1e-6) / f.velocity_scale)
    if len(f.delta_v) > 1 or f.delta_v[0] != 1.0:
        s = s.with_(dv_free=True, dv=float(np.polynomial.polynomial.polyval(
            np.mean(f.temperature_range), f.delta_v)))
    if f.position_ripple is not None:
        s = s.with_(ripple=len(f.position_ripple.amplitude), cyc=f.position_ripple.cycles_per_rev)
    if f.offset:
        s = s.with_(offset=True)
    if f.model == 'lugre':
        s = s.with_(presliding=True, ps=('lugre', f.lugre.sigma0))
    elif f.model == 'gms':
        s = s.with_(presliding=True, ps=('gms', float(sum(f.gms.k))))
    return s


def _terms(s):
    """Return the fields of ``s`` the diagnosis adds to the static structure."""
    return {k: v for k, v in vars(s).items() if k not in STATIC_FIELDS}


def test_the_shipped_gears_are_varied():
    """The gear files cover the branches: Stribeck or not, free delta_v or not, load terms."""
    structures = [base_structure(load_gear(p)) for p in GEARS]
    assert len(GEARS) >= 4
    assert {s.nfs > 0 for s in structures} == {True, False}
    assert {s.dv_free for s in structures} == {True, False}
    assert any(s.nfc > 1 and s.nfc_load for s in structures)
    assert {s.ps[0] for s in structures if s.presliding} == {'lugre', 'gms'}


@pytest.mark.parametrize('path', GEARS, ids=[p.name for p in GEARS])
def test_gear_to_static_to_candidate(path):
    gear = load_gear(path)
    s = base_structure(gear)
    assert s == _from_lists(gear)
    linear = tuple(gear.friction.delta_v) == (1.0,)
    static = StaticStructure.from_gear(gear, fixed=('delta_v',) if linear else ())
    # the static part reads back as the gear's structure, the rest as the diagnosis's terms
    assert s.static(base=static) == static
    assert CandidateStructure.from_static(static, **_terms(s)) == s
    assert CandidateStructure.from_static(s.static(), **_terms(s)) == s
    # an extension keeps its layers: thermal and load change the static part only
    for effect in ('thermal', 'load', 'stribeck', 'nonlinear_viscous'):
        ext = extend(s, effect)
        if ext is not None:
            e = ext[0]
            assert CandidateStructure.from_static(e.static(base=static), **_terms(e)) == e


def test_static_part_of_an_extension():
    base = load_gear(ROOT / 'config' / 'csd25_base.yaml')
    static = StaticStructure.from_gear(base, fixed=('delta_v',))
    s = extend(extend(base_structure(base), 'thermal')[0], 'nonlinear_viscous')[0]
    got = s.static(base=static)
    assert got.orders == {'fc': 1, 'fv': 1, 'delta_v': 0}
    assert got.fixed == {} and not got.stribeck
    assert got.describe().startswith('fc linear in temperature, fv linear in temperature')


def test_from_static_rejects_what_the_diagnosis_cannot_keep():
    gear = load_gear(ROOT / 'config' / 'csd25.yaml')
    static = StaticStructure.from_gear(gear)
    with pytest.raises(ValueError, match='nfc'):
        CandidateStructure.from_static(static, nfc=3)
    with pytest.raises(ValueError, match='fc'):
        CandidateStructure.from_static(StaticStructure.from_gear(gear, fixed=('fc',)))
    with pytest.raises(ValueError, match='delta_v'):
        CandidateStructure.from_static(StaticStructure.from_gear(gear, fixed=('delta_v',)))
