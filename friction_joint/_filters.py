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

"""Shared signal processing: zero-phase filtered derivatives of sampled positions."""
import numpy as np
from scipy import signal

from .exceptions import PreslidingDataError

__all__ = ['zero_phase_derivatives']


def zero_phase_derivatives(q, dt, cutoff=100.0, order=2):
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
