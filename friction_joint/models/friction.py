# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
One friction model instance for a sampled-data loop: ``step(qd, xi, tau_l, dt, *, q) -> tau_r``.

Used by the controller feed-forward (eq. 17) and the observer (eq. 15), which
run a *model* gear alongside the plant.  ``kind`` is one of ``'lugre'``,
``'gms'``, ``'static'`` or ``'none'`` (no friction model).  The gear's
``friction.position_ripple`` (a function of q) and ``friction.offset`` are
included, as in the simulated joint.
"""
from __future__ import annotations

import math
from typing import Callable, Protocol, TYPE_CHECKING

from .gms import GMS
from .lugre import LuGre
from .static import StaticFriction
from ..exceptions import GearConfigError

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

    from .params import FrictionParams, GearLike, RippleParams

__all__ = ['FRICTION_KINDS', 'friction_model']

FRICTION_KINDS = ('lugre', 'gms', 'static', 'none')


class _Model(Protocol):
    """A single-gear model that steps (LuGre, GMS, the static curve)."""

    def reset(self) -> None:
        """Relax the state."""

    def step(self, qd: float, xi: float, tau_l: float,
             dt: float) -> float | NDArray[np.float64]:
        """Advance one sample; return the friction torque."""


class _Static:
    def __init__(self, friction: FrictionParams) -> None:
        self.model = StaticFriction(friction)

    def reset(self) -> None:
        pass

    def step(self, qd: float, xi: float, tau_l: float, dt: float) -> float:
        return float(self.model.torque(qd, xi, tau_l)[0])


class _WithRipple:
    """Adds the position ripple sum_n A_n sin(n c q + phi_n) to a model's torque."""

    def __init__(self, model: _Model, ripple: RippleParams | _NoRipple) -> None:
        self.model = model
        self.terms = [(n + 1) * ripple.cycles_per_rev for n in range(len(ripple.amplitude))]
        self.amp = ripple.amplitude
        self.phase = ripple.phase

    def reset(self) -> None:
        self.model.reset()

    def step(self, qd: float, xi: float, tau_l: float, dt: float, *, q: float = 0.0) -> float:
        tau = float(self.model.step(qd, xi, tau_l, dt))     # a float: one gear
        for w, a, p in zip(self.terms, self.amp, self.phase, strict=True):
            tau += a * math.sin(w * q + p)
        return tau


class _NoFriction:
    def reset(self) -> None:
        pass

    def step(self, qd: float, xi: float, tau_l: float, dt: float, *, q: float = 0.0) -> float:
        return 0.0


def friction_model(gear: GearLike, kind: str) -> _WithRipple | _NoFriction:
    """
    Build a stateful single-gear friction model.

    Parameters
    ----------
    gear : GearParams
        The gear whose ``friction`` section parametrizes the model.
    kind : {'lugre', 'gms', 'static', 'none'}
        The friction model.

    Returns
    -------
    object with ``step(qd, xi, tau_l, dt, *, q=0.0) -> float`` and ``reset()``

    """
    if kind not in FRICTION_KINDS:
        raise GearConfigError(f'friction model must be one of {", ".join(FRICTION_KINDS)}; '
                              f'got {kind!r}')
    if kind == 'none':
        return _NoFriction()
    models: dict[str, Callable[[FrictionParams], _Model]] = {'lugre': LuGre, 'gms': GMS,
                                                             'static': _Static}
    model = models[kind](gear.friction)
    return _WithRipple(model, gear.friction.position_ripple or _NO_RIPPLE)


class _NoRipple:
    cycles_per_rev = 0.0
    amplitude: tuple[float, ...] = ()
    phase: tuple[float, ...] = ()


_NO_RIPPLE = _NoRipple()
