# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The simulated test bed: joint, lever, thermal model and sensors at a fixed rate.

This is the "hardware" of the experiments: it runs the **truth** gear file.
Controllers and observers only see its :class:`Sample` measurements and run
their own **model** gear file.

:class:`InputLimits` says which values of a joint's signals are physically
plausible for a gear (derived from its gear file); the nodes refuse inputs
beyond them.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from .sensors import CurrentLoop, Encoder, TemperatureSensor, VelocityEstimator
from .thermal import ThermalModel
from ..exceptions import SimulationError
from ..gear.schema import ABSOLUTE_ZERO
from ..models.joint import Joint
from ..models.static import StaticFriction

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['Plant', 'Sample', 'InputLimits', 'PLAUSIBILITY_FACTOR', 'MAX_INPUT_SPEED',
           'ACCELERATION_TIME']

#: multiple of the plausible speed and torque scales beyond which an input is refused
PLAUSIBILITY_FACTOR = 10.0
#: top wave-generator (motor) speed assumed for any gear: 10 000 rpm, in rad/s
MAX_INPUT_SPEED = 10_000.0 * 2.0 * math.pi / 60.0
#: time in which the drive is assumed able to bring the joint from rest to its speed scale, s
ACCELERATION_TIME = 0.1
#: absolute zero, degC
_UNITS = {'position': 'rad', 'velocity': 'rad/s', 'torque': 'Nm', 'temperature': 'degC'}


class InputLimits:
    """
    Plausible magnitudes of a joint's signals, derived from its gear file alone.

    The rule (no gear keys of its own):

    * speed scale V = max(``MAX_INPUT_SPEED`` / ``gear_ratio``, sqrt(4 m g l / J)):
      the motor at 10 000 rpm through the gear, or the lever falling from
      upright to hanging, whichever is faster;
    * torque scale T = m g l + F + J V / ``ACCELERATION_TIME``: the lever's
      gravity; F, the largest friction torque of the gear's static curve at any
      speed up to V, any temperature of ``friction.temperature_range`` and a
      load from 0 to m g l (with ``friction.offset``), plus the amplitudes of
      ``friction.position_ripple``; and the inertia torque that brings the
      joint from rest to V in ``ACCELERATION_TIME``;
    * ``velocity`` = factor V and ``torque`` = factor T (rad/s, Nm; drive
      effort, torque command and contact torque alike);
    * ``position``: the largest |q| at which a double still resolves one count
      of the encoder (``sensors.encoder_bits``), no multiple;
    * ``temperature``: ``friction.temperature_range`` widened by factor times its
      width (at least 1 K) on both sides, and not below absolute zero (degC).

    For the CSD-25 model (config/csd25.yaml) this gives 141 rad/s and 607 Nm.

    Parameters
    ----------
    gear : GearParams
        The gear whose signals are bounded.
    factor : float
        Multiple of the speed and torque scales (default ``PLAUSIBILITY_FACTOR``).

    """

    def __init__(self, gear: GearParams, *, factor: float = PLAUSIBILITY_FACTOR) -> None:
        if not (math.isfinite(factor) and factor >= 1.0):
            raise ValueError(f'plausibility factor must be >= 1, got {factor}')
        mgl, inertia = gear.mgl, gear.inertia
        self.factor = float(factor)
        self.speed = max(MAX_INPUT_SPEED / gear.gear_ratio, math.sqrt(4.0 * mgl / inertia))
        self.friction = self._peak_friction(gear, self.speed)
        self.torque_scale = mgl + self.friction + inertia * self.speed / ACCELERATION_TIME
        self.velocity = self.factor * self.speed
        self.torque = self.factor * self.torque_scale
        sensors = gear.section('sensors')
        assert sensors is not None  # a section with defaults
        bits = sensors['encoder_bits']
        self.position = 2.0 * math.pi / 2.0 ** bits / np.finfo(float).eps
        lo, hi = gear.friction.temperature_range
        width = max(hi - lo, 1.0)
        self.temperature = (max(ABSOLUTE_ZERO, lo - self.factor * width),
                            hi + self.factor * width)

    @staticmethod
    def _peak_friction(gear, speed):
        lo, hi = gear.friction.temperature_range
        v = speed * np.geomspace(1e-6, 1.0, 61)
        vv, xx = np.meshgrid(np.concatenate([v, -v]), np.linspace(lo, hi, 9))
        model = StaticFriction(gear.friction)
        peak = max(float(np.max(np.abs(model.torque(vv.ravel(), xx.ravel(), load))))
                   for load in (0.0, gear.mgl))
        ripple = gear.friction.position_ripple
        return peak + (sum(abs(a) for a in ripple.amplitude) if ripple else 0.0)

    def check(self, quantity: str, value: float) -> str | None:
        """
        Return why ``value`` is not plausible for ``quantity``, or None if it is.

        Parameters
        ----------
        quantity : {'position', 'velocity', 'torque', 'temperature'}
            What ``value`` is.
        value : float
            The value (rad, rad/s, Nm or degC).

        Returns
        -------
        str or None
            The reason, one line, or None for a plausible value.

        """
        unit = _UNITS[quantity]
        if not math.isfinite(value):
            return f'{quantity} {value:g} {unit} is not finite'
        if quantity == 'temperature':
            lo, hi = self.temperature
            if lo <= value <= hi:
                return None
            return (f'{quantity} {value:g} {unit} is outside the plausible '
                    f'[{lo:.4g}, {hi:.4g}] {unit} of this gear')
        bound = getattr(self, quantity)
        if abs(value) <= bound:
            return None
        return (f'{quantity} {value:g} {unit} is beyond the plausible +-{bound:.4g} {unit} '
                'of this gear')

    def describe(self) -> str:
        """Return the limits as one line of text."""
        lo, hi = self.temperature
        return (f'|q| <= {self.position:.3g} rad, |qd| <= {self.velocity:.4g} rad/s, '
                f'|torque| <= {self.torque:.4g} Nm, temperature in [{lo:.4g}, {hi:.4g}] degC')


class Sample:
    """
    One step of the test bed.

    Measured (what a node publishes): ``t``, ``q``, ``qd``, ``effort`` (applied
    drive torque as measured), ``xi`` (housing temperature sensor),
    ``xi_new`` (a new temperature sample was taken), ``tau_link`` (output
    torque sensor, tau_ext).  Truth (for evaluation only): ``q_true``,
    ``qd_true``, ``tau_applied``, ``tau_r``, ``tau_ext``, ``xi_true``.

    Parameters
    ----------
    **kw : float or bool
        The values, by the names above.

    """

    __slots__ = ('t', 'q', 'qd', 'effort', 'xi', 'xi_new', 'tau_link',
                 'q_true', 'qd_true', 'tau_applied', 'tau_r', 'tau_ext', 'xi_true')
    t: float
    q: float
    qd: float
    effort: float
    xi: float
    xi_new: bool
    tau_link: float
    q_true: float
    qd_true: float
    tau_applied: float
    tau_r: float
    tau_ext: float
    xi_true: float

    def __init__(self, **kw: float | bool) -> None:
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

    def __init__(self, gear: GearParams, *, model: str | None = None, xi0: float | None = None,
                 seed: int | None = None, q0: float = 0.0, ideal_sensors: bool = False) -> None:
        sim = gear.section('simulation')
        sens = gear.section('sensors')
        assert sim is not None and sens is not None  # a section with defaults
        self.gear = gear
        self.rate = sim['rate']
        self.dt = 1.0 / self.rate
        self.rng = np.random.default_rng(sim['seed'] if seed is None else seed)
        self.joint = Joint(gear, model=model, mgl=gear.mgl, lever_offset=gear.lever_offset)
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

    def step(self, tau_cmd: float, *, tau_contact: float = 0.0) -> Sample:
        """
        Apply ``tau_cmd`` for one step, plus a contact torque, and measure.

        A NaN/inf command or contact torque raises
        :class:`~friction_joint.exceptions.SimulationError` before anything
        changes (the plant can go on).  A finite input that drives the state
        out of the finite range (an unstable loop, a runaway command) raises it
        too, naming the time, command and contact torque; the plant is then
        spent.

        Parameters
        ----------
        tau_cmd : float
            Torque command (Nm).
        tau_contact : float
            Contact torque on the link (Nm), part of tau_ext.

        Returns
        -------
        Sample

        """
        for name, value in (('command', tau_cmd), ('contact torque', tau_contact)):
            if not math.isfinite(value):
                raise SimulationError(f'{name} {value} Nm at t = {self.t:.4f} s is not finite: '
                                      'step refused, nothing applied')
        tau_app = self.current(tau_cmd) if not self.ideal else float(tau_cmd)
        q, qd, tau_r, tau_ext = self.joint.step(tau_app, self.dt, xi=self.thermal.xi,
                                                tau_ext=tau_contact)
        power = abs(float(tau_r) * float(qd))    # Python floats: inf, no overflow warning
        if not (math.isfinite(q) and math.isfinite(qd) and math.isfinite(power)):
            raise SimulationError(
                f'the joint state is no longer finite at t = {self.t + self.dt:.4f} s '
                f'(q = {q}, qd = {qd}, command {tau_cmd} Nm, contact torque {tau_contact} '
                'Nm): the closed loop is unstable or the command ran away')
        self.thermal.step(power, self.dt)
        xi_new = False
        if not self.ideal:
            _, xi_new = self.temperature(self.thermal.xi)
        self.k += 1
        self.t = self.k * self.dt
        noise = (self.effort_noise * self.rng.standard_normal()
                 if (self.effort_noise and not self.ideal) else 0.0)
        self.last = self._sample(q, qd, tau_app, tau_r, tau_ext, noise, xi_new)
        return self.last

    def run(self, tau_cmd: ArrayLike, *,
            tau_contact: ArrayLike | None = None) -> dict[str, np.ndarray]:
        """
        Run open loop over a command sequence.

        Parameters
        ----------
        tau_cmd : array_like (T,)
            Torque command of each step (Nm).
        tau_contact : array_like (T,), optional
            Contact torque of each step (Nm); default none.

        Returns
        -------
        dict of str to ndarray
            Each field of :class:`Sample` (measured and true) over the steps.

        """
        tau_cmd = np.asarray(tau_cmd, dtype=float)
        n = len(tau_cmd)
        contact = np.zeros(n) if tau_contact is None else np.asarray(tau_contact, float)
        names = Sample.__slots__
        out = {k: np.empty(n) for k in names}
        for i in range(n):
            s = self.step(tau_cmd[i], tau_contact=contact[i])
            for k in names:
                out[k][i] = getattr(s, k)
        return out
