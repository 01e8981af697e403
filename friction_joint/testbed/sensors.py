# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Sensor models of the simulated test bed.

* output encoder: quantisation to 2 pi / 2^bits (25 bit as in the paper);
* velocity: backward difference of the encoder position, low-pass filtered
  by a 2nd-order Butterworth filter (what a drive does), designed with scipy;
* applied torque: commanded torque through the current loop (first-order lag
  at its bandwidth) plus current ripple noise; the measured effort adds
  current-measurement noise;
* housing temperature: first-order sensor lag, sampled at its own rate,
  quantised to 0.0625 degC (MCP9808);
* output torque sensor: true link torque plus noise.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy import signal

__all__ = ['StreamingSOS', 'Encoder', 'VelocityEstimator', 'CurrentLoop',
           'TemperatureSensor', 'quantize']


def quantize(x, step):
    """Round to the nearest multiple of ``step``."""
    return np.round(np.asarray(x) / step) * step


class StreamingSOS:
    """
    Apply a scipy second-order-sections filter one sample at a time.

    Same result as ``scipy.signal.sosfilt`` (transposed direct form II), at a
    per-sample cost small enough for a 3 kHz loop.  The state never holds a
    non-finite value: a sample that is not finite, or that would overflow the
    state, raises ``ValueError`` and leaves the filter as it was.

    Parameters
    ----------
    sos : array_like, (n_sections, 6)
        Second-order sections as ``scipy.signal`` designs them.

    """

    def __init__(self, sos: ArrayLike) -> None:
        self.sos = np.asarray(sos, dtype=float)
        self._coef = [tuple(float(c) for c in row) for row in self.sos]
        self.reset()

    def reset(self, *, x0: float = 0.0) -> None:
        """
        Start in the steady state of a constant input x0 (finite).

        Parameters
        ----------
        x0 : float
            The constant input.

        """
        if not math.isfinite(x0):
            raise ValueError(f'filter reset to a non-finite value {x0}')
        zi = signal.sosfilt_zi(self.sos) * x0
        self._z = [[float(a), float(b)] for a, b in zi]

    @property
    def state(self):
        """Return the section states, a list of (z0, z1)."""
        return [tuple(z) for z in self._z]

    def __call__(self, x):
        """Filter one sample; refuses (``ValueError``) what would leave the state non-finite."""
        x_in = x
        new = []
        for (b0, b1, b2, _, a1, a2), (z0, z1) in zip(self._coef, self._z, strict=True):
            y = b0 * x + z0
            new.append((b1 * x - a1 * y + z1, b2 * x - a2 * y))
            x = y
        if not (math.isfinite(x) and all(math.isfinite(a) and math.isfinite(b)
                                         for a, b in new)):
            raise ValueError(f'filter input {x_in} gives a non-finite filter state; '
                             'sample refused, state kept')
        for z, (a, b) in zip(self._z, new, strict=True):
            z[0] = a
            z[1] = b
        return x


class Encoder:
    """
    Absolute encoder with 2^bits counts per revolution.

    Parameters
    ----------
    bits : int
        Resolution in bits.

    """

    def __init__(self, bits: int) -> None:
        self.resolution = 2.0 * math.pi / 2 ** int(bits)

    def __call__(self, q):
        return round(q / self.resolution) * self.resolution


class VelocityEstimator:
    """
    Backward difference of the encoder position, 2nd-order Butterworth low-pass.

    Parameters
    ----------
    cutoff_hz : float
        Cut-off of the low-pass (Hz), below Nyquist.
    rate_hz : float
        Sample rate (Hz).

    """

    def __init__(self, cutoff_hz: float, rate_hz: float) -> None:
        if not 0 < cutoff_hz < rate_hz / 2:
            raise ValueError(f'velocity cut-off {cutoff_hz} Hz must be below Nyquist '
                             f'({rate_hz / 2} Hz)')
        self.filter = StreamingSOS(signal.butter(2, cutoff_hz, fs=rate_hz, output='sos'))
        self.rate = float(rate_hz)
        self.q_prev: float | None = None

    def reset(self, q: float, *, qd: float = 0.0) -> None:
        """
        Start at position q with the filter at the steady state of velocity qd.

        Parameters
        ----------
        q : float
            Measured position (rad).
        qd : float
            Velocity (rad/s).

        """
        self.q_prev = q
        self.filter.reset(x0=qd)

    def __call__(self, q_meas):
        if self.q_prev is None:
            self.reset(q_meas)
        v = (q_meas - self.q_prev) * self.rate
        self.q_prev = q_meas
        return self.filter(v)


class CurrentLoop:
    """
    Torque actually applied: first-order lag of the command plus noise.

    Parameters
    ----------
    bandwidth_hz : float
        Bandwidth of the current loop (Hz).
    rate_hz : float
        Sample rate (Hz).
    noise : float
        Standard deviation of the current ripple (Nm).
    rng : numpy.random.Generator
        Source of the noise.

    """

    def __init__(self, bandwidth_hz: float, rate_hz: float, noise: float,
                 rng: np.random.Generator) -> None:
        self.a = math.exp(-2.0 * math.pi * bandwidth_hz / rate_hz)
        self.noise = float(noise)
        self.rng = rng
        self.tau = 0.0

    def __call__(self, tau_cmd):
        self.tau = self.a * self.tau + (1.0 - self.a) * tau_cmd
        return self.tau + (self.noise * self.rng.standard_normal() if self.noise else 0.0)


class TemperatureSensor:
    """
    Housing temperature sensor: lag, sample-and-hold at its rate, quantisation.

    Parameters
    ----------
    time_constant : float
        Sensor lag (s).
    resolution : float
        Quantisation step (degC).
    rate_hz : float
        Sample rate of the sensor (Hz).
    noise : float
        Standard deviation of the noise (degC).
    sim_rate_hz : float
        Rate at which it is advanced (Hz).
    rng : numpy.random.Generator
        Source of the noise.
    xi0 : float
        Initial temperature (degC).

    """

    def __init__(self, time_constant: float, resolution: float, rate_hz: float, noise: float,
                 sim_rate_hz: float, *, rng: np.random.Generator, xi0: float) -> None:
        self.a = math.exp(-1.0 / (time_constant * sim_rate_hz))
        self.resolution = resolution
        self.every = max(1, int(round(sim_rate_hz / rate_hz)))
        self.noise = noise
        self.rng = rng
        self.state = xi0
        self.count = 0
        self.value = self._sample()

    def _sample(self):
        x = self.state + (self.noise * self.rng.standard_normal() if self.noise else 0.0)
        return round(x / self.resolution) * self.resolution

    def __call__(self, xi):
        """Advance one simulation step; returns (value, new_sample_taken)."""
        self.state = self.a * self.state + (1.0 - self.a) * xi
        self.count += 1
        if self.count >= self.every:
            self.count = 0
            self.value = self._sample()
            return self.value, True
        return self.value, False
