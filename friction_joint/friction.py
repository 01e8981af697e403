"""One friction model instance for a sampled-data loop: ``step(qd, xi, tau_l, dt) -> tau_r``.

Used by the controller feed-forward (eq. 17) and the observer (eq. 15), which
run a *model* gear alongside the plant.  ``kind`` is one of ``'lugre'``,
``'gms'``, ``'static'`` or ``'none'`` (no friction model).
"""
from .exceptions import GearConfigError
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


class _NoFriction:
    def reset(self):
        pass

    def step(self, qd, xi, tau_l, dt):
        return 0.0


def friction_model(gear, kind):
    """Build a stateful single-gear friction model.

    Parameters
    ----------
    gear : GearParams
    kind : {'lugre', 'gms', 'static', 'none'}

    Returns
    -------
    object with ``step(qd, xi, tau_l, dt) -> float`` and ``reset()``
    """
    if kind not in FRICTION_KINDS:
        raise GearConfigError(f'friction model must be one of {", ".join(FRICTION_KINDS)}; got {kind!r}')
    if kind == 'lugre':
        return LuGre(gear.friction)
    if kind == 'gms':
        return GMS(gear.friction)
    if kind == 'static':
        return _Static(gear.friction)
    return _NoFriction()
