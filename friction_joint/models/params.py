# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The parameters of the friction models: plain, frozen values, the models' own input.

:mod:`friction_joint.gear` reads them from gear files, validates them and
re-exports them (``friction_joint.gear.FrictionParams`` is this class); the
models take them (a friction section) or anything with a ``friction`` section
and an ``inertia`` (:class:`GearLike`, e.g. :class:`~friction_joint.gear.GearParams`).
This module imports nothing of the package, so the gear files' layer can import
it without loading the models (and numba).
"""
from __future__ import annotations

import dataclasses
from typing import Protocol

__all__ = ['LuGreParams', 'GMSParams', 'RippleParams', 'FrictionParams', 'GearLike']


@dataclasses.dataclass(frozen=True)
class LuGreParams:
    """
    LuGre pre-sliding parameters (seed eq. 10), ``friction.lugre``.

    Attributes
    ----------
    sigma0 : float
        Bristle stiffness (Nm/rad).
    sigma1 : float
        Micro-damping (Nm s/rad).

    """

    sigma0: float
    sigma1: float = 0.0


@dataclasses.dataclass(frozen=True)
class GMSParams:
    """
    GMS parameters (seed eq. 11-13), ``friction.gms``.

    Attributes
    ----------
    k : tuple of float
        Element stiffnesses k_i (Nm/rad).
    alpha : tuple of float
        Torque fractions alpha_i (sum 1).
    c : float
        Attraction C (Nm/s).

    """

    k: tuple[float, ...]
    alpha: tuple[float, ...]
    c: float


@dataclasses.dataclass(frozen=True)
class RippleParams:
    """
    Position ripple sum_n A_n sin(n c q + phi_n), ``friction.position_ripple``.

    Attributes
    ----------
    cycles_per_rev : float
        c, the fundamental's cycles per output revolution.
    amplitude : tuple of float
        A_n (Nm).
    phase : tuple of float
        phi_n (rad).

    """

    cycles_per_rev: float
    amplitude: tuple[float, ...]
    phase: tuple[float, ...]


@dataclasses.dataclass(frozen=True)
class FrictionParams:
    """
    Friction parameters of one gear (seed eq. 1, 5-13), the ``friction`` section.

    Attributes
    ----------
    model : {'static', 'lugre', 'gms'}
        The friction model.
    fc, fv : tuple of float
        Temperature polynomials (powers 0..n) of F_c and F_v (eq. 7).
    fs, vs : tuple of float or None
        Those of F_s and v_s; None: no Stribeck effect.
    delta_v : tuple of float
        That of the viscous exponent (eq. 5).
    delta_s : float
        Stribeck exponent (eq. 1).
    fc_load, fv_load, fs_load, vs_load, delta_v_load : tuple of float
        Load polynomials (powers 1..m) of the same parameters.
    velocity_scale : float
        kappa: the curve is evaluated at ``kappa * qd``.
    temperature_range : tuple of float
        ``(lo, hi)`` degC: xi is clipped to it.
    lugre : LuGreParams or None
        ``friction.lugre``.
    gms : GMSParams or None
        ``friction.gms``.
    position_ripple : RippleParams or None
        ``friction.position_ripple``.
    offset : float
        Constant torque added to the friction torque (Nm).

    """

    model: str
    fc: tuple[float, ...]
    fv: tuple[float, ...]
    fs: tuple[float, ...] | None = None
    vs: tuple[float, ...] | None = None
    delta_v: tuple[float, ...] = (1.0,)
    delta_s: float = 2.0
    fc_load: tuple[float, ...] = ()
    fv_load: tuple[float, ...] = ()
    fs_load: tuple[float, ...] = ()
    vs_load: tuple[float, ...] = ()
    delta_v_load: tuple[float, ...] = ()
    velocity_scale: float = 1.0
    temperature_range: tuple[float, float] = (0.0, 100.0)
    lugre: LuGreParams | None = None
    gms: GMSParams | None = None
    position_ripple: RippleParams | None = None
    offset: float = 0.0


class GearLike(Protocol):
    """What a model reads of a gear: its friction section and inertia (a ``GearParams``)."""

    @property
    def friction(self) -> FrictionParams:
        """Return the ``friction`` section."""

    @property
    def inertia(self) -> float:
        """Return the joint's moment of inertia, in kg m^2."""
