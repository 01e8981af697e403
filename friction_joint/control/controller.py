# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Joint controller of eq. 17 and PD gain design from step-response specs.

    tau = J qdd_d + k_p (q_d - q) + k_d (qd_d - qd) + tau_g(q) + psi tau_rd(z, qd, xi, tau_L)  (17)

With the inertia and gravity feed-forward exact, the error obeys
J e'' + k_d e' + k_p e = 0, a second-order system with omega_n^2 = k_p / J and
2 zeta omega_n = k_d / J.  :func:`pd_gains` picks zeta from the maximum
overshoot and omega_n from the 10-90 % rise time of that system's step
response (found numerically, not from an approximation formula).  Its
defaults are the paper's design targets (:data:`PAPER_RISE_TIME`,
:data:`PAPER_OVERSHOOT`), read from :data:`~friction_joint.paper.PAPER`.

:class:`Controller` never holds a non-finite friction feed-forward state: a
sample with a NaN/inf input raises ``InputRejected`` (a ``ValueError``) before anything changes;
a finite sample whose command overflows (e.g. a velocity of 1e306 rad/s in
the friction curve) raises ``InputRejected`` and relaxes the feed-forward state.
Bounding the inputs to plausible values is the caller's job (the
``controller`` node gates them with
:class:`~friction_joint.testbed.plant.InputLimits`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import brentq

from ..exceptions import ArgumentError, InputRejected
from ..models.friction import friction_model
from ..paper import PAPER

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from ..gear import GearParams

__all__ = ['PAPER_RISE_TIME', 'PAPER_OVERSHOOT', 'pd_gains', 'step_metrics', 'SineTrajectory',
           'Controller']


def _number(key: str) -> float:
    """Return the paper's number ``key`` (:data:`~friction_joint.paper.PAPER`), not a range."""
    value = PAPER[key].value
    if isinstance(value, tuple):
        raise TypeError(f'the paper gives a range for {key}, not a number')
    return value


#: the 10-90 % rise time (s) the paper designs the PD gains for (Section V-C)
PAPER_RISE_TIME: float = _number('rise_time')
#: the maximum overshoot the paper designs the PD gains for, as a fraction (the table holds %)
PAPER_OVERSHOOT: float = _number('overshoot') / 100.0


def _zeta_from_overshoot(overshoot: float) -> float:
    lo = math.log(overshoot)
    return -lo / math.sqrt(math.pi ** 2 + lo ** 2)


def _unit_step(tn: float, zeta: float) -> float:
    """Step response of wn^2/(s^2 + 2 zeta wn s + wn^2) at normalised time tn = wn t."""
    wd = math.sqrt(1.0 - zeta ** 2)
    return 1.0 - math.exp(-zeta * tn) * (math.cos(wd * tn) + zeta / wd * math.sin(wd * tn))


def pd_gains(inertia: float, *, rise_time: float = PAPER_RISE_TIME,
             overshoot: float = PAPER_OVERSHOOT) -> tuple[float, float]:
    """
    Return the PD gains of eq. 17 from a 10-90 % rise time and a maximum overshoot.

    Parameters
    ----------
    inertia : float
        J, kg m^2.
    rise_time : float
        10-90 % rise time of the step response, s (default: the paper's,
        :data:`PAPER_RISE_TIME`).
    overshoot : float
        Maximum overshoot as a fraction, 0 < overshoot < 1 (default: the
        paper's, :data:`PAPER_OVERSHOOT`).

    Returns
    -------
    kp, kd : float
        Nm/rad and Nm s/rad.

    """
    if not inertia > 0:
        raise ArgumentError(f'inertia must be > 0, got {inertia}')
    if not rise_time > 0:
        raise ArgumentError(f'rise time must be > 0, got {rise_time}')
    if not 0.0 < overshoot < 1.0:
        raise ArgumentError(f'overshoot must be a fraction in (0, 1), got {overshoot}')
    zeta = _zeta_from_overshoot(overshoot)
    peak = math.pi / math.sqrt(1.0 - zeta ** 2)          # normalised time of the first peak
    t10 = brentq(lambda x: _unit_step(x, zeta) - 0.1, 0.0, peak)
    t90 = brentq(lambda x: _unit_step(x, zeta) - 0.9, 0.0, peak)
    wn = (t90 - t10) / rise_time
    return inertia * wn ** 2, 2.0 * zeta * wn * inertia


def step_metrics(t: ArrayLike, y: ArrayLike, final: float) -> tuple[float, float]:
    """
    Return the 10-90 % rise time and maximum overshoot (fraction) of a step response.

    Parameters
    ----------
    t : array_like (T,)
        Time (s).
    y : array_like (T,)
        The response.
    final : float
        The step's final value.

    Returns
    -------
    rise_time, overshoot : float
        Rise time (s) and overshoot as a fraction of ``final``.

    """
    yn = np.asarray(y) / final
    ta = np.asarray(t)
    t10 = np.interp(0.1, yn[: np.argmax(yn >= 0.9) + 1], ta[: np.argmax(yn >= 0.9) + 1])
    t90 = np.interp(0.9, yn[: np.argmax(yn >= 0.9) + 1], ta[: np.argmax(yn >= 0.9) + 1])
    return t90 - t10, max(0.0, float(np.max(yn)) - 1.0)


class SineTrajectory:
    """
    Desired trajectory q_d(t) = a sin(w t) + offset, with its first two derivatives.

    Parameters
    ----------
    amplitude : float
        a (rad).
    omega : float
        w (rad/s); the paper's is 1.5.
    offset : float
        Offset (rad).

    """

    def __init__(self, amplitude: float, *, omega: float = 1.5, offset: float = 0.0) -> None:
        self.a, self.w, self.offset = float(amplitude), float(omega), float(offset)

    def __call__(self, t: float) -> tuple[float, float, float]:
        s, c = math.sin(self.w * t), math.cos(self.w * t)
        return (self.offset + self.a * s, self.a * self.w * c, -self.a * self.w ** 2 * s)


class Controller:
    """
    PD + inertia/gravity feed-forward + friction feed-forward (eq. 17).

    Parameters
    ----------
    gear : GearParams
        The *model* gear (inertia, lever, friction).
    kp, kd : float
        Gains, e.g. from :func:`pd_gains`.
    friction : {'lugre', 'gms', 'static', 'none'}
        Model used for the friction feed-forward; ``'none'`` is psi = 0.
    dt : float
        Control period (s).
    ff_velocity : {'measured', 'desired'}
        Velocity fed to the friction model: the measured qd as in eq. 17
        (default), or the desired qd_d (a common, noise-free variant).

    """

    def __init__(self, gear: GearParams, kp: float, kd: float, *, friction: str = 'lugre',
                 dt: float = 1.0 / 3000.0, ff_velocity: str = 'measured') -> None:
        if ff_velocity not in ('measured', 'desired'):
            raise ArgumentError("ff_velocity must be 'measured' or 'desired', "
                                f'got {ff_velocity!r}')
        self.gear = gear
        self.J = gear.inertia
        self.mgl = gear.mgl
        self.lever_offset = gear.lever_offset
        self.kp, self.kd, self.dt = float(kp), float(kd), float(dt)
        self.kind = friction
        self.ff_velocity = ff_velocity
        self.friction = friction_model(gear, friction)
        self.last: dict[str, float] = {}

    def reset(self) -> None:
        """Relax the friction feed-forward state."""
        self.friction.reset()

    def gravity(self, q: float) -> float:
        """
        Return tau_g(q) = m g l sin(q - angle_offset) of the model's lever.

        Parameters
        ----------
        q : float
            Joint position (rad).

        Returns
        -------
        float
            The gravity torque (Nm).

        """
        return self.mgl * math.sin(q - self.lever_offset)

    def __call__(self, q: float, qd: float, xi: float, q_d: float, qd_d: float = 0.0,
                 qdd_d: float = 0.0, *, dt: float | None = None) -> float:
        """
        Torque command for one sample; components are kept in ``self.last``.

        ``dt`` is the time since the previous sample when it differs from the
        control period (a real-time loop that skipped stale samples); it
        advances the dynamic friction model's state.  Raises ``InputRejected``
        for a sample that cannot give a finite command (see the module
        docstring).
        """
        h = self.dt if dt is None else dt
        for name, value in (('position', q), ('velocity', qd), ('temperature', xi),
                            ('desired position', q_d), ('desired velocity', qd_d),
                            ('desired acceleration', qdd_d)):
            if not math.isfinite(value):
                raise InputRejected(f'controller input {name} is {value}: sample refused')
        if not (math.isfinite(h) and h > 0):
            raise ArgumentError(f'controller time step must be finite and > 0, got {h}')
        tau_g = self.gravity(q)
        tau_pd = self.kp * (q_d - q) + self.kd * (qd_d - qd)
        if not math.isfinite(self.J * qdd_d + tau_pd):
            raise InputRejected(f'controller command overflows (position {q} rad, velocity {qd} '
                                'rad/s): sample refused')
        v = qd if self.ff_velocity == 'measured' else qd_d
        tau_f = self.friction.step(v, xi, abs(tau_g), h, q=q)
        tau = self.J * qdd_d + tau_pd + tau_g + tau_f
        if not math.isfinite(tau):
            self.reset()
            raise InputRejected(f'controller command overflows ({tau} Nm at position {q} rad, '
                                f'velocity {qd} rad/s): sample refused, friction feed-forward '
                                'relaxed')
        self.last = {'pd': tau_pd, 'gravity': tau_g, 'friction': tau_f, 'inertia': self.J * qdd_d}
        return tau
