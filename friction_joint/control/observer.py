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
Velocity-based disturbance observer with friction model (seed eq. 4 and 15).

    tau_ext^ = Q(s) [tau + beta J qd - tau_g(q) - tau_rd(qd, xi, tau_L)] - beta J qd,
    Q(s) = beta / (s + beta)                                                    (15)

Without a friction model this is eq. 4 (the estimate then contains the
friction torque).  Q(s) is discretised with scipy (Tustin by default) and
run sample by sample.  As in Section V-D of the paper the gravity of the
lever can be left out (``gravity=False``) so that it is estimated as an
unknown external load; the friction model's load input is then the previous
estimate |tau_ext^|.
"""
import numpy as np
from scipy import signal

from ..exceptions import FrictionJointError
from ..models.friction import friction_model
from ..testbed.sensors import StreamingSOS

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
    gravity : bool
        Subtract the model's lever gravity (True) or estimate it as part of
        tau_ext (False, as in the paper's Section V-D).
    method : str
        ``scipy.signal.cont2discrete`` method for Q(s).

    """

    def __init__(self, gear, beta=60.0, dt=1.0 / 3000.0, friction='lugre', gravity=False,
                 method='bilinear'):
        if not beta > 0:
            raise FrictionJointError(f'observer cut-off beta must be > 0, got {beta}')
        self.J = gear.inertia
        self.mgl = gear.mgl if gravity else 0.0
        self.beta, self.dt = float(beta), float(dt)
        self.kind = friction
        self.friction = friction_model(gear, friction)
        num, den, _ = signal.cont2discrete(([beta], [1.0, beta]), dt, method=method)
        self.q_filter = StreamingSOS(signal.tf2sos(np.ravel(num), den))
        self.estimate = 0.0
        self.tau_friction = 0.0

    def reset(self, tau_ext=0.0, qd=0.0, tau=0.0):
        """Start at a steady state with estimate tau_ext."""
        self.friction.reset()
        self.q_filter.reset(tau_ext + self.beta * self.J * qd)
        self.estimate = tau_ext

    def __call__(self, tau, q, qd, xi):
        """One sample: measured drive torque, position, velocity, temperature -> tau_ext^."""
        tau_g = self.mgl * np.sin(q)
        self.tau_friction = self.friction.step(qd, xi, abs(self.estimate), self.dt, q)
        bjq = self.beta * self.J * qd
        self.estimate = self.q_filter(tau + bjq - tau_g - self.tau_friction) - bjq
        return self.estimate
