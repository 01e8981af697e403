# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Gear parameter files: load, validate, modify and save (docs/interfaces.md, gear parameter files).

Modules: :mod:`.schema` (every key, limits), :mod:`.params` (the validated
parameters and their checks), :mod:`.polynomial` (exact bounds of the
polynomials), :mod:`.strict_yaml` (the YAML reader) and :mod:`.files` (gear
files and the nodes' ``--params-file``).

A gear file is a ROS 2 parameter file; everything sits under ``/**: ros__parameters:``.
The schema (:mod:`.schema`) lists every key this package knows.  Unknown keys, wrong types, NaN/inf
and physically impossible values raise :class:`~friction_joint.exceptions.GearConfigError`
naming the key; so do lists longer than their limit (polynomial order <= 8,
at most 100 GMS elements or ripple harmonics, see :mod:`.schema`).  Files
are read by a strict YAML 1.2 reader (:mod:`.strict_yaml`): ``2e4`` is a
number, a key given twice, an alias, a file over 1 MB or not UTF-8 text is an
error naming the file.  A LuGre set that violates the passivity bound only warns
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
from .files import format_gear, load_gear, parse_gear, save_gear
from .params import (FrictionParams, gear_from_dict, gear_from_flat, GearParams, GMSParams,
                     LuGreParams, passivity_bound, RippleParams)
from .schema import FRICTION_MODELS, SCHEMA, Section

__all__ = ['GearParams', 'FrictionParams', 'LuGreParams', 'GMSParams', 'RippleParams',
           'load_gear', 'parse_gear', 'format_gear', 'gear_from_dict', 'gear_from_flat',
           'save_gear', 'SCHEMA',
           'FRICTION_MODELS', 'passivity_bound', 'Section']
