# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Shared signal processing: zero-phase filtered derivatives of sampled positions."""
import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import signal

from .exceptions import PreslidingDataError

__all__ = ['zero_phase_derivatives']


def zero_phase_derivatives(q: ArrayLike, dt: float, cutoff: float = 100.0, order: int = 2
                           ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """
    Velocity and acceleration from a sampled position without phase lag.

    Forward-backward Butterworth low-pass (``scipy.signal.filtfilt``) of the
    position, then central differences.  Offline only (non-causal).

    Parameters
    ----------
    q : array_like, (T,)
        Position (rad), e.g. the encoder reading.
    dt : float
        Sample time (s).
    cutoff : float
        Low-pass cut-off (Hz), below the Nyquist frequency.
    order : int
        Butterworth order (applied twice).

    Returns
    -------
    qd, qdd : ndarray, (T,)

    """
    q = np.asarray(q, dtype=float)
    rate = 1.0 / float(dt)
    if not 0.0 < cutoff < 0.5 * rate:
        raise PreslidingDataError(f'cut-off {cutoff} Hz must be between 0 and the Nyquist '
                                  f'frequency {0.5 * rate:g} Hz')
    b, a = signal.butter(order, cutoff, fs=rate)
    if q.size <= 3 * max(len(a), len(b)):
        raise PreslidingDataError(f'position signal of {q.size} samples is too short to filter')
    qf = signal.filtfilt(b, a, q)
    qd = np.gradient(qf, dt)
    return qd, np.gradient(qd, dt)
