# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The friction effects a model may lack: one registry for diagnosis, experiments and reports.

Each :class:`Effect` says what it is, which measured variable shows it, when
a recording can test it, whether a gear file can hold it, and whether the
hidden-effect experiments can put it into a simulated truth.  The diagnosis
(:mod:`friction_joint.diagnosis`) tests the effects of :data:`EFFECTS` in this
order, the hidden-effect experiments (:mod:`friction_joint.experiments.hidden`)
hide those of :data:`HIDEABLE`, and docs/interfaces.md lists them under
``diagnose`` outputs.
"""
from dataclasses import dataclass

from .exceptions import ArgumentError

__all__ = ['Effect', 'REGISTRY', 'EFFECTS', 'HIDEABLE', 'UNREPRESENTABLE', 'effect']


@dataclass(frozen=True)
class Effect:
    """
    One friction effect.

    Attributes
    ----------
    name : str
        The exact string of ``--effects``, ``report.json`` and the hidden-effect
        experiments.
    description : str
        What it is, in one line.
    variable : str
        The measured variable the residual depends on when the effect is missing.
    testable_when : str
        What a recording needs for the effect to be tested (the rule's scale-free
        thresholds are in docs/diagnosis.md).
    representable : bool
        Whether a gear file has keys for it (else ``diagnose`` names and measures
        it, but ``extended.yaml`` leaves it out: :attr:`reason`).
    hideable : bool
        Whether the hidden-effect experiments can put it into a simulated truth
        (only what a gear file can hold can be simulated).
    reason : str
        Why it is not representable (empty when it is).

    """

    name: str
    description: str
    variable: str
    testable_when: str
    representable: bool = True
    hideable: bool = True
    reason: str = ''


_DRIFT_REASON = ('not representable in the gear file (it has no key for friction that changes '
                 'with accumulated travel): extended.yaml has the Coulomb level averaged over '
                 'the data')

#: every effect, in the order diagnosis tests and reports them
REGISTRY = {e.name: e for e in (
    Effect('thermal', 'friction parameters depend on the gear temperature',
           'temperature', 'a temperature signal that spans enough'),
    Effect('load', 'friction depends on the transmitted load |tau_ext|',
           'load', 'a load that varies by a fraction of the friction level'),
    Effect('position_ripple', 'a torque periodic in the position (tooth engagement)',
           'position', 'travel over several ripple periods, every part of a period visited'),
    Effect('nonlinear_viscous', 'viscous friction not linear in the speed (delta_v != 1)',
           'velocity', 'sliding speeds spanning a factor of several'),
    Effect('stribeck', 'static friction above Coulomb friction near zero speed',
           'velocity', 'sliding speeds spanning a factor of several'),
    Effect('presliding', 'reversals need a friction state (LuGre or GMS), not sign(qd)',
           'reversals', 'several reversals while the joint moves'),
    Effect('inertia', 'the configured inertia is wrong',
           'acceleration', 'accelerations large against the friction level'),
    Effect('asymmetry', 'friction differs by direction of motion (a constant offset)',
           'direction', 'sliding in both directions'),
    Effect('drift', 'friction changes with accumulated travel beyond temperature (run-in, '
                    'wear)',
           'accumulated travel', 'travel of several strokes', representable=False,
           hideable=False, reason=_DRIFT_REASON),
    Effect('gravity', 'a position-dependent torque m g l sin(q - q0) missing or wrong',
           'position', 'a stroke long enough to tell sin q from a constant and a slope'),
)}
#: the effect names, in the order they are tested and reported
EFFECTS = tuple(REGISTRY)
#: the effects the hidden-effect experiments can put into a simulated truth
HIDEABLE = tuple(name for name, e in REGISTRY.items() if e.hideable)
#: effect name -> why a gear file cannot hold it
UNREPRESENTABLE = {name: e.reason for name, e in REGISTRY.items() if not e.representable}


def effect(name: str) -> Effect:
    """
    Return the :class:`Effect` called ``name``.

    Parameters
    ----------
    name : str
        A name of :data:`REGISTRY`.

    Returns
    -------
    Effect

    Raises
    ------
    ArgumentError
        For an unknown name, listing the known ones.

    """
    try:
        return REGISTRY[name]
    except (KeyError, TypeError):
        raise ArgumentError(f'unknown effect {name!r}; effects: {", ".join(EFFECTS)}') from None
