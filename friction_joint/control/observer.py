# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Velocity-based disturbance observer with friction model (seed eq. 4 and 15).

    tau_ext^ = Q(s) [tau + beta J qd - tau_g(q) - tau_rd(qd, xi, tau_L)] - beta J qd,
    Q(s) = beta / (s + beta)                                                    (15)

Without a friction model this is eq. 4 (the estimate then contains the
friction torque).  Q(s) is discretised with scipy (Tustin by default) and
run sample by sample.  As in Section V-D of the paper the gravity of the
lever can be left out (``gravity=False``) so that it is estimated as an
unknown external load; the friction model's load input is then the previous
estimate |tau_ext^|.

The observer's states (the Q(s) sections, the LuGre/GMS friction state, the
estimate) never hold a non-finite value.  A sample with a NaN/inf input, or
whose ``tau + beta J qd`` overflows, raises ``InputRejected`` before anything
changes, so the outputs afterwards are those of an observer that never saw
it.  A finite sample that still overflows further in (e.g. a velocity of
1e306 rad/s in the friction curve) raises ``InputRejected`` too and resets the
observer to the steady state of the last finite estimate and velocity, with
a relaxed friction state; the estimate then converges back at the rate beta.
Bounding the inputs to plausible values is the caller's job (the
``estimator`` node gates them with
:class:`~friction_joint.testbed.plant.InputLimits`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from scipy import signal

from ..exceptions import ArgumentError, InputRejected
from ..models.friction import friction_model
from ..testbed.sensors import StreamingSOS

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['DisturbanceObserver']


class DisturbanceObserver:
    """
    External torque estimator of eq. 15.

    Parameters
    ----------
    gear : GearParams
        The *model* gear.
    beta : float
        Cut-off of Q(s), rad/s.
    dt : float
        Sample time, s.
    friction : {'lugre', 'gms', 'static', 'none'}
        The friction model subtracted (eq. 15); ``'none'`` gives eq. 4.
    gravity : bool
        Subtract the model's lever gravity (True) or estimate it as part of
        tau_ext (False, as in the paper's Section V-D).
    method : str
        ``scipy.signal.cont2discrete`` method for Q(s).

    """

    def __init__(self, gear: GearParams, *, beta: float = 60.0, dt: float = 1.0 / 3000.0,
                 friction: str = 'lugre', gravity: bool = False,
                 method: str = 'bilinear') -> None:
        if not beta > 0:
            raise ArgumentError(f'observer cut-off beta must be > 0, got {beta}')
        self.J = gear.inertia
        self.mgl = gear.mgl if gravity else 0.0
        self.lever_offset = gear.lever_offset
        self.beta, self.dt = float(beta), float(dt)
        self.kind = friction
        self.friction = friction_model(gear, friction)
        num, den, _ = signal.cont2discrete(([beta], [1.0, beta]), dt, method=method)
        self.q_filter = StreamingSOS(signal.tf2sos(np.ravel(num), den))
        self.estimate = 0.0
        self.tau_friction = 0.0
        self._qd = 0.0

    def reset(self, *, tau_ext: float = 0.0, qd: float = 0.0, tau: float = 0.0) -> None:
        """
        Start at a steady state with estimate tau_ext (finite) at velocity qd.

        Parameters
        ----------
        tau_ext : float
            The estimate (Nm).
        qd : float
            Velocity (rad/s).
        tau : float
            Drive torque (Nm); not used (the steady state does not depend on it).

        """
        if not (math.isfinite(tau_ext) and math.isfinite(qd)):
            raise InputRejected(f'observer reset to a non-finite state (tau_ext {tau_ext}, '
                                f'qd {qd})')
        self.friction.reset()
        self.q_filter.reset(x0=tau_ext + self.beta * self.J * qd)
        self.estimate = tau_ext
        self.tau_friction = 0.0
        self._qd = qd

    def __call__(self, tau: float, q: float, qd: float, xi: float) -> float:
        """
        Return tau_ext^ for one sample of drive torque, position, velocity and temperature.

        Raises ``InputRejected`` (a ``ValueError``) for a sample it cannot turn into a finite
        estimate (see the module docstring); the state stays finite.
        """
        for name, value in (('drive torque', tau), ('position', q), ('velocity', qd),
                            ('temperature', xi)):
            if not math.isfinite(value):
                raise InputRejected(f'observer input {name} is {value}: sample refused')
        tau_g = self.mgl * math.sin(q - self.lever_offset)
        bjq = self.beta * self.J * qd
        u = tau + bjq - tau_g
        if not math.isfinite(u):
            raise InputRejected(f'observer input overflows (drive torque {tau} Nm, velocity '
                                f'{qd} rad/s): sample refused')
        tau_f = self.friction.step(qd, xi, abs(self.estimate), self.dt, q=q)
        try:
            if not math.isfinite(tau_f):
                raise InputRejected(f'the friction model gives {tau_f} Nm')
            estimate: float = self.q_filter(u - tau_f) - bjq
            if not math.isfinite(estimate):
                raise InputRejected(f'the estimate overflows ({estimate} Nm)')
        except ValueError as exc:
            self.reset(tau_ext=self.estimate, qd=self._qd)
            raise InputRejected(f'observer sample (drive torque {tau} Nm, velocity {qd} '
                                f'rad/s) refused: {exc}; observer reset to '
                                f'{self.estimate:.6g} Nm') from None
        self.tau_friction = tau_f
        self.estimate = estimate
        self._qd = qd
        return estimate
