"""One friction model instance for a sampled-data loop: ``step(qd, xi, tau_l, dt, q) -> tau_r``.

Used by the controller feed-forward (eq. 17) and the observer (eq. 15), which
run a *model* gear alongside the plant.  ``kind`` is one of ``'lugre'``,
``'gms'``, ``'static'`` or ``'none'`` (no friction model).  The gear's
``friction.position_ripple`` (a function of q) and ``friction.offset`` are
included, as in the simulated joint.
"""
import math

from ..exceptions import GearConfigError
from .gms import GMS
from .lugre import LuGre
from .static import StaticFriction

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

    def step(self, qd, xi, tau_l, dt, q=0.0):
        tau = self.model.step(qd, xi, tau_l, dt)
        for w, a, p in zip(self.terms, self.amp, self.phase):
            tau += a * math.sin(w * q + p)
        return tau


class _NoFriction:
    def reset(self):
        pass

    def step(self, qd, xi, tau_l, dt, q=0.0):
        return 0.0


def friction_model(gear, kind):
    """Build a stateful single-gear friction model.

    Parameters
    ----------
    gear : GearParams
    kind : {'lugre', 'gms', 'static', 'none'}

    Returns
    -------
    object with ``step(qd, xi, tau_l, dt, q=0.0) -> float`` and ``reset()``
    """
    if kind not in FRICTION_KINDS:
        raise GearConfigError(f'friction model must be one of {", ".join(FRICTION_KINDS)}; got {kind!r}')
    if kind == 'none':
        return _NoFriction()
    model = {'lugre': LuGre, 'gms': GMS, 'static': _Static}[kind](gear.friction)
    return _WithRipple(model, gear.friction.position_ripple or _NO_RIPPLE)


class _NoRipple:
    cycles_per_rev = 0.0
    amplitude = ()
    phase = ()


_NO_RIPPLE = _NoRipple()
