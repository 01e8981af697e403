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
One friction model instance for a sampled-data loop: ``step(qd, xi, tau_l, dt, *, q) -> tau_r``.

Used by the controller feed-forward (eq. 17) and the observer (eq. 15), which
run a *model* gear alongside the plant.  ``kind`` is one of ``'lugre'``,
``'gms'``, ``'static'`` or ``'none'`` (no friction model).  The gear's
``friction.position_ripple`` (a function of q) and ``friction.offset`` are
included, as in the simulated joint.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .gms import GMS
from .lugre import LuGre
from .static import StaticFriction
from ..exceptions import GearConfigError

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['FRICTION_KINDS', 'friction_model']

FRICTION_KINDS = ('lugre', 'gms', 'static', 'none')


class _Static:
    def __init__(self, friction):
        self.model = StaticFriction(friction)

    def reset(self):
        pass

    def step(self, qd, xi, tau_l, dt):
        return float(self.model.torque(qd, xi, tau_l)[0])


class _WithRipple:
    """Adds the position ripple sum_n A_n sin(n c q + phi_n) to a model's torque."""

    def __init__(self, model, ripple):
        self.model = model
        self.terms = [(n + 1) * ripple.cycles_per_rev for n in range(len(ripple.amplitude))]
        self.amp = ripple.amplitude
        self.phase = ripple.phase

    def reset(self):
        self.model.reset()

    def step(self, qd, xi, tau_l, dt, *, q=0.0):
        tau = self.model.step(qd, xi, tau_l, dt)
        for w, a, p in zip(self.terms, self.amp, self.phase):
            tau += a * math.sin(w * q + p)
        return tau


class _NoFriction:
    def reset(self):
        pass

    def step(self, qd, xi, tau_l, dt, *, q=0.0):
        return 0.0


def friction_model(gear: GearParams, kind: str) -> _WithRipple | _NoFriction:
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
    model = {'lugre': LuGre, 'gms': GMS, 'static': _Static}[kind](gear.friction)
    return _WithRipple(model, gear.friction.position_ripple or _NO_RIPPLE)


class _NoRipple:
    cycles_per_rev = 0.0
    amplitude = ()
    phase = ()


_NO_RIPPLE = _NoRipple()
