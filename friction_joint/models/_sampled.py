# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Shared driver of the batched, sampled-velocity friction models (LuGre, GMS)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .static import broadcast_batch, pack_static

if TYPE_CHECKING:
    from .params import FrictionParams

__all__ = ['SampledFrictionModel']


class SampledFrictionModel:
    """
    Batch bookkeeping, input broadcasting and the low-overhead single step.

    Subclasses implement ``_run(qd, xi, tau_l, dt, out)`` on (B, T) arrays
    (advancing their state in place) and ``reset()``; ``friction.offset`` is
    added here.
    """

    def _init_batch(self, frictions: FrictionParams | list[FrictionParams]
                    | tuple[FrictionParams, ...]) -> list[FrictionParams]:
        self.single = not isinstance(frictions, (list, tuple))
        flist = list(frictions) if isinstance(frictions, (list, tuple)) else [frictions]
        self.packed = pack_static(flist)
        self._buf = np.zeros((4, 1, 1))
        self._offset = float(self.packed.offset[0])
        return flist

    @property
    def batch(self) -> int:
        return self.packed.batch

    def _run(self, qd: NDArray[np.float64], xi: NDArray[np.float64], tl: NDArray[np.float64],
             dt: float, out: NDArray[np.float64]) -> None:
        raise NotImplementedError          # the subclass's kernel

    def _simulate(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike,
                  dt: float) -> NDArray[np.float64]:
        qd2, xi2, tl = broadcast_batch(self.batch, qd, xi, tau_l)
        tau = np.empty_like(qd2)
        self._run(qd2, xi2, np.abs(tl), float(dt), tau)
        tau += self.packed.offset[:, None]
        return tau[0] if self.single else tau

    def step(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike,
             dt: float) -> float | NDArray[np.float64]:
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
            return self._simulate(col[0], col[1], col[2], dt)[:, 0]
        buf = self._buf
        buf[0, 0, 0] = qd
        buf[1, 0, 0] = xi
        buf[2, 0, 0] = np.abs(tau_l)
        self._run(buf[0], buf[1], buf[2], float(dt), buf[3])
        return float(buf[3, 0, 0]) + self._offset
