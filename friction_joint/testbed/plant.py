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
The simulated test bed: joint, lever, thermal model and sensors at a fixed rate.

This is the "hardware" of the experiments: it runs the **truth** gear file.
Controllers and observers only see its :class:`Sample` measurements and run
their own **model** gear file.
"""
import math

import numpy as np

from .sensors import CurrentLoop, Encoder, TemperatureSensor, VelocityEstimator
from .thermal import ThermalModel
from ..exceptions import SimulationError
from ..models.joint import Joint

__all__ = ['Plant', 'Sample']


class Sample:
    """
    One step of the test bed.

    Measured (what a node publishes): ``t``, ``q``, ``qd``, ``effort`` (applied
    drive torque as measured), ``xi`` (housing temperature sensor),
    ``xi_new`` (a new temperature sample was taken), ``tau_link`` (output
    torque sensor, tau_ext).  Truth (for evaluation only): ``q_true``,
    ``qd_true``, ``tau_applied``, ``tau_r``, ``tau_ext``, ``xi_true``.
    """

    __slots__ = ('t', 'q', 'qd', 'effort', 'xi', 'xi_new', 'tau_link',
                 'q_true', 'qd_true', 'tau_applied', 'tau_r', 'tau_ext', 'xi_true')

    def __init__(self, **kw):
        for k, v in kw.items():
            setattr(self, k, v)


class Plant:
    """
    Simulated Harmonic Drive test bed.

    Parameters
    ----------
    gear : GearParams
        The truth gear (friction, inertia, ``lever``, ``thermal``, ``sensors``,
        ``simulation`` sections).
    model : {'static', 'lugre', 'gms'}, optional
        Friction model of the truth; default ``friction.model``.
    xi0 : float, optional
        Initial gear temperature (degC); default ``thermal.initial``/ambient.
    seed : int, optional
        Noise seed; default ``simulation.seed``.
    q0 : float
        Initial position (rad).
    ideal_sensors : bool
        Bypass quantisation, filtering, lags and noise (for tests).

    """

    def __init__(self, gear, model=None, xi0=None, seed=None, q0=0.0, ideal_sensors=False):
        sim = gear.section('simulation')
        sens = gear.section('sensors')
        self.gear = gear
        self.rate = sim['rate']
        self.dt = 1.0 / self.rate
        self.rng = np.random.default_rng(sim['seed'] if seed is None else seed)
        self.joint = Joint(gear, model=model, mgl=gear.mgl)
        self.joint.reset(q=q0)
        self.thermal = ThermalModel.from_gear(gear, initial=xi0)
        self.ideal = ideal_sensors
        self.encoder = Encoder(sens['encoder_bits'])
        self.velocity = VelocityEstimator(sens['velocity_cutoff'], self.rate)
        self.velocity.reset(self.encoder(q0))
        self.current = CurrentLoop(sens['current_bandwidth'], self.rate,
                                   0.0 if ideal_sensors else sens['torque_noise'], self.rng)
        self.effort_noise = sens['effort_noise']
        self.link_noise = sens['link_torque_noise']
        self.temperature = TemperatureSensor(
            sens['temperature_time_constant'], sens['temperature_resolution'],
            sim['temperature_rate'], sens['temperature_noise'], self.rate, rng=self.rng,
            xi0=self.thermal.xi)
        self.t = 0.0
        self.k = 0
        self.last = self._sample(q0, 0.0, 0.0, 0.0, 0.0, 0.0, True)

    @property
    def state(self):
        """Return the true (q, qd, xi)."""
        return float(self.joint.q[0]), float(self.joint.qd[0]), self.thermal.xi

    def _sample(self, q, qd, tau_app, tau_r, tau_ext, effort_noise, xi_new):
        xi = self.thermal.xi
        if self.ideal:
            return Sample(t=self.t, q=q, qd=qd, effort=tau_app, xi=xi, xi_new=True,
                          tau_link=tau_ext, q_true=q, qd_true=qd, tau_applied=tau_app,
                          tau_r=tau_r, tau_ext=tau_ext, xi_true=xi)
        qm = self.encoder(q)
        return Sample(t=self.t, q=qm, qd=self.velocity(qm), effort=tau_app + effort_noise,
                      xi=self.temperature.value, xi_new=xi_new,
                      tau_link=tau_ext + (self.link_noise * self.rng.standard_normal()
                                          if self.link_noise else 0.0),
                      q_true=q, qd_true=qd, tau_applied=tau_app, tau_r=tau_r, tau_ext=tau_ext,
                      xi_true=xi)

    def step(self, tau_cmd, tau_contact=0.0):
        """
        Apply ``tau_cmd`` for one step, plus a contact torque, and measure.

        Returns
        -------
        Sample

        """
        tau_app = self.current(tau_cmd) if not self.ideal else float(tau_cmd)
        q, qd, tau_r, tau_ext = self.joint.step(tau_app, self.dt, self.thermal.xi, tau_contact)
        if not (math.isfinite(q) and math.isfinite(qd)):
            raise SimulationError(
                f'the joint state is no longer finite at t = {self.t + self.dt:.4f} s '
                f'(q = {q}, qd = {qd}, command {tau_cmd} Nm): the closed loop is unstable '
                'or the command ran away')
        self.thermal.step(abs(tau_r * qd), self.dt)
        xi_new = False
        if not self.ideal:
            _, xi_new = self.temperature(self.thermal.xi)
        self.k += 1
        self.t = self.k * self.dt
        noise = (self.effort_noise * self.rng.standard_normal()
                 if (self.effort_noise and not self.ideal) else 0.0)
        self.last = self._sample(q, qd, tau_app, tau_r, tau_ext, noise, xi_new)
        return self.last

    def run(self, tau_cmd, tau_contact=None):
        """Open-loop run over a command sequence; returns a dict of arrays (measured and true)."""
        n = len(tau_cmd)
        contact = np.zeros(n) if tau_contact is None else np.asarray(tau_contact, float)
        names = Sample.__slots__
        out = {k: np.empty(n) for k in names}
        for i in range(n):
            s = self.step(tau_cmd[i], contact[i])
            for k in names:
                out[k][i] = getattr(s, k)
        return out
