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

"""Shared driver of the batched, sampled-velocity friction models (LuGre, GMS)."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .static import broadcast_batch, pack_static

__all__ = ['SampledFrictionModel']


class SampledFrictionModel:
    """
    Batch bookkeeping, input broadcasting and the low-overhead single step.

    Subclasses implement ``_run(qd, xi, tau_l, dt, out)`` on (B, T) arrays
    (advancing their state in place) and ``reset()``; ``friction.offset`` is
    added here.
    """

    def _init_batch(self, frictions):
        self.single = not isinstance(frictions, (list, tuple))
        flist = [frictions] if self.single else list(frictions)
        self.packed = pack_static(flist)
        self._buf = np.zeros((4, 1, 1))
        self._offset = float(self.packed.offset[0])
        return flist

    @property
    def batch(self):
        return self.packed.batch

    def _simulate(self, qd, xi, tau_l, dt):
        qd, xi, tl = broadcast_batch(self.batch, qd, xi, tau_l)
        tau = np.empty_like(qd)
        self._run(qd, xi, np.abs(tl), float(dt), tau)
        tau += self.packed.offset[:, None]
        return tau[0] if self.single else tau

    def step(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike,
             dt: float) -> float | np.ndarray:
        """
        Advance one sample.

        Parameters
        ----------
        qd, xi, tau_l : float or array_like (B,)
            Velocity (rad/s), temperature (degC), load (Nm), held over the step.
        dt : float
            Step (s).

        Returns
        -------
        float or ndarray (B,)
            The friction torque (Nm) at the end of the step.

        """
        if not self.single:
            col = [np.reshape(a, (-1, 1)) if np.ndim(a) else a for a in (qd, xi, tau_l)]
            return self._simulate(*col, dt)[:, 0]
        buf = self._buf
        buf[0, 0, 0] = qd
        buf[1, 0, 0] = xi
        buf[2, 0, 0] = abs(tau_l)
        self._run(buf[0], buf[1], buf[2], float(dt), buf[3])
        return float(buf[3, 0, 0]) + self._offset
