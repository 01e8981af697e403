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
Static friction curve with temperature and load dependency (seed eq. 1, 5-7).

The steady-state (gross-sliding) friction torque is

    tau_rs(qd, xi, tau_L) = g(qd, xi, tau_L) + s(qd, xi, tau_L)                (6)
    g = sign(qd) (F_c + (F_s - F_c) exp(-|kappa qd / v_s|^delta_s))             (1)
    s = F_v sign(qd) |kappa qd|^delta_v                                        (5)

where each of F_c, F_s, F_v, v_s, delta_v is a polynomial in the housing
temperature xi (powers 0..n) plus a polynomial in the load tau_L (powers
1..m), eq. 7.  ``kappa`` is ``friction.velocity_scale`` (1 by default): the
velocity unit the coefficients were identified in, e.g. ``gear_ratio`` when
they refer to wave-generator (motor-side) speed as the paper's Table I does.

Evaluation rules (documented in docs/interfaces.md):

* xi is clipped to ``friction.temperature_range`` before the polynomials are
  evaluated: identified polynomials are not extrapolated.
* evaluated parameters are clipped to physical bounds: F_c, F_s, F_v >= 0,
  v_s >= 1e-9, delta_v >= 0.05.

Everything here works on a *batch* of parameter sets: coefficient arrays have
a leading batch dimension so identification can evaluate hundreds of
candidate models at once.  The scalar kernels are numba-compiled when numba
is available and are shared by the LuGre, GMS and joint kernels.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from .._jit import njit

if TYPE_CHECKING:
    from collections.abc import Sequence

    from ..gear import FrictionParams

__all__ = ['PARAMETERS', 'PackedStatic', 'pack_static', 'broadcast_batch', 'curve_params',
           'g_abs', 's_visc', 'sign', 'StaticFriction']

#: Order of the curve parameters in the packed coefficient arrays.
PARAMETERS = ('fc', 'fs', 'fv', 'vs', 'delta_v')
FC, FS, FV, VS, DV = range(5)

VS_MIN = 1e-9
DV_MIN = 0.05


class PackedStatic:
    """
    Static-curve coefficients of a batch of B parameter sets as arrays.

    Attributes
    ----------
    temp : ndarray, shape (B, 5, nT)
        Temperature coefficients (powers 0..nT-1) of fc, fs, fv, vs, delta_v.
    load : ndarray, shape (B, 5, nL)
        Load coefficients (powers 1..nL).
    delta_s, velocity_scale, t_lo, t_hi, offset : ndarray, shape (B,)

    """

    __slots__ = ('temp', 'load', 'delta_s', 'velocity_scale', 't_lo', 't_hi', 'offset')

    def __init__(self, temp, load, delta_s, velocity_scale, t_lo, t_hi, *, offset=None):
        self.temp = temp
        self.load = load
        self.delta_s = delta_s
        self.velocity_scale = velocity_scale
        self.t_lo = t_lo
        self.t_hi = t_hi
        self.offset = np.zeros(len(delta_s)) if offset is None else offset

    @property
    def batch(self):
        return self.temp.shape[0]

    def args(self):
        """Return the arrays in the order the kernels take them."""
        return (self.temp, self.load, self.delta_s, self.velocity_scale,
                self.t_lo, self.t_hi)


def pack_static(frictions):
    """
    Pack one or more :class:`~friction_joint.gear.FrictionParams`.

    Parameters
    ----------
    frictions : FrictionParams or sequence of FrictionParams
        One parameter set, or B of them.

    Returns
    -------
    PackedStatic

    """
    if not isinstance(frictions, (list, tuple)):
        frictions = [frictions]
    n = len(frictions)
    lists_t, lists_l = [], []
    for f in frictions:
        fs_t = f.fs if f.fs is not None else f.fc        # no Stribeck: Fs = Fc
        fs_l = f.fs_load if f.fs is not None else f.fc_load
        vs_t = f.vs if f.vs is not None else (1.0,)
        lists_t.append((f.fc, fs_t, f.fv, vs_t, f.delta_v))
        lists_l.append((f.fc_load, fs_l, f.fv_load, f.vs_load, f.delta_v_load))
    nt = max(1, max(len(c) for lt in lists_t for c in lt))
    nl = max(1, max(len(c) for ll in lists_l for c in ll))
    temp = np.zeros((n, 5, nt))
    load = np.zeros((n, 5, nl))
    for b in range(n):
        for p in range(5):
            temp[b, p, :len(lists_t[b][p])] = lists_t[b][p]
            load[b, p, :len(lists_l[b][p])] = lists_l[b][p]
    return PackedStatic(
        temp, load,
        np.array([f.delta_s for f in frictions], dtype=float),
        np.array([f.velocity_scale for f in frictions], dtype=float),
        np.array([f.temperature_range[0] for f in frictions], dtype=float),
        np.array([f.temperature_range[1] for f in frictions], dtype=float),
        offset=np.array([f.offset for f in frictions], dtype=float))


# ---------------------------------------------------------------- kernels ---

@njit(inline='always')
def _poly(temp, load, b, p, x, tl):
    acc = 0.0
    xp = 1.0
    for i in range(temp.shape[2]):
        acc += temp[b, p, i] * xp
        xp *= x
    lp = tl
    for j in range(load.shape[2]):
        acc += load[b, p, j] * lp
        lp *= tl
    return acc


@njit(inline='always')
def curve_params(temp, load, t_range, b, xi, tl):
    """
    (F_c, F_s, F_v, v_s, delta_v) of set b at temperature xi, load tl.

    ``t_range`` is ``(t_lo, t_hi)``, the arrays of the sets' temperature ranges.
    """
    x = min(max(xi, t_range[0][b]), t_range[1][b])
    fc = max(_poly(temp, load, b, FC, x, tl), 0.0)
    fs = max(_poly(temp, load, b, FS, x, tl), 0.0)
    fv = max(_poly(temp, load, b, FV, x, tl), 0.0)
    vs = max(_poly(temp, load, b, VS, x, tl), VS_MIN)
    dv = max(_poly(temp, load, b, DV, x, tl), DV_MIN)
    return fc, fs, fv, vs, dv


@njit
def g_abs(fc, fs, vs, ds, kappa, v):
    """|g(v)|: magnitude of the Stribeck curve (eq. 1); F_s at v = 0."""
    x = kappa * v / vs
    if ds == 2.0:
        return fc + (fs - fc) * math.exp(-x * x)
    return fc + (fs - fc) * math.exp(-abs(x) ** ds)


@njit
def s_visc(fv, dv, kappa, v):
    """Nonlinear viscous term s(v) = F_v sign(v) |kappa v|^delta_v (eq. 5)."""
    if v == 0.0:
        return 0.0
    r = fv * abs(kappa * v) ** dv
    return r if v > 0.0 else -r


@njit
def sign(v):
    if v > 0.0:
        return 1.0
    if v < 0.0:
        return -1.0
    return 0.0


@njit
def _static_eval(temp, load, delta_s, kappa, t_lo, t_hi, qd, xi, tl, out_g, out_s):
    nb, nt = qd.shape
    for b in range(nb):
        for k in range(nt):
            fc, fs, fv, vs, dv = curve_params(temp, load, (t_lo, t_hi), b, xi[b, k], tl[b, k])
            v = qd[b, k]
            out_g[b, k] = sign(v) * g_abs(fc, fs, vs, delta_s[b], kappa[b], v)
            out_s[b, k] = s_visc(fv, dv, kappa[b], v)


@njit
def _param_eval(temp, load, t_lo, t_hi, xi, tl, out):
    nb, nt = xi.shape
    for b in range(nb):
        for k in range(nt):
            fc, fs, fv, vs, dv = curve_params(temp, load, (t_lo, t_hi), b, xi[b, k], tl[b, k])
            out[0, b, k] = fc
            out[1, b, k] = fs
            out[2, b, k] = fv
            out[3, b, k] = vs
            out[4, b, k] = dv


def _as_2d(a):
    if a.ndim == 0:
        return a.reshape(1, 1)
    if a.ndim == 1:
        return a.reshape(1, -1)
    if a.ndim == 2:
        return a
    raise ValueError('inputs must be scalars, 1-D (T,) or 2-D (B, T) arrays')


def broadcast_batch(batch, *arrays):
    """Broadcast inputs to contiguous float arrays of shape (batch, T)."""
    arrs = [_as_2d(np.asarray(a, dtype=float)) for a in arrays]
    t = max(a.shape[1] for a in arrs)
    for a in arrs:
        if a.shape[0] not in (1, batch):
            raise ValueError(f'batch dimension {a.shape[0]} does not match '
                             f'{batch} parameter sets')
        if a.shape[1] not in (1, t):
            raise ValueError(f'time dimension {a.shape[1]} does not match {t}')
    return [np.ascontiguousarray(np.broadcast_to(a, (batch, t))) for a in arrs]


class StaticFriction:
    """
    The static friction map tau_rs(qd, xi, tau_L) of eq. 6 for a batch of gears.

    Parameters
    ----------
    frictions : FrictionParams or sequence of FrictionParams
        One parameter set, or B of them (batch dimension first in results).

    """

    def __init__(self, frictions: FrictionParams | Sequence[FrictionParams]) -> None:
        self.single = not isinstance(frictions, (list, tuple))
        self.packed = pack_static(frictions)

    @classmethod
    def from_packed(cls, packed: PackedStatic) -> StaticFriction:
        """
        Return a batch model over already packed coefficients (results keep the batch axis).

        Parameters
        ----------
        packed : PackedStatic
            The coefficients of B parameter sets, see :func:`pack_static`.

        Returns
        -------
        StaticFriction

        """
        obj = cls.__new__(cls)
        obj.single = False
        obj.packed = packed
        return obj

    def _out(self, a):
        return a[0] if self.single else a

    def components(self, qd: ArrayLike, xi: ArrayLike,
                   tau_l: ArrayLike = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """
        Return ``(g, s)``: Stribeck part and viscous part, each (B, T) or (T,).

        Parameters
        ----------
        qd : array_like, scalar, (T,) or (B, T)
            Velocity (rad/s).
        xi : array_like, scalar, (T,) or (B, T)
            Gear temperature (degC).
        tau_l : array_like, scalar, (T,) or (B, T)
            Load torque (Nm); its magnitude enters the load polynomials.

        Returns
        -------
        g, s : ndarray
            Stribeck part ``g`` (eq. 1) and viscous part ``s`` (eq. 5), Nm.

        """
        qd, xi, tl = broadcast_batch(self.packed.batch, qd, xi, tau_l)
        g = np.empty_like(qd)
        s = np.empty_like(qd)
        p = self.packed
        _static_eval(p.temp, p.load, p.delta_s, p.velocity_scale, p.t_lo, p.t_hi,
                     qd, xi, np.abs(tl), g, s)
        return self._out(g), self._out(s)

    def torque(self, qd: ArrayLike, xi: ArrayLike, tau_l: ArrayLike = 0.0) -> np.ndarray:
        """
        Return the static friction torque tau_rs (Nm) at velocity qd (rad/s).

        The torque includes ``friction.offset``.

        Parameters
        ----------
        qd : array_like, scalar, (T,) or (B, T)
            Velocity (rad/s).
        xi : array_like, scalar, (T,) or (B, T)
            Gear temperature (degC).
        tau_l : array_like, scalar, (T,) or (B, T)
            Load torque (Nm); its magnitude enters the load polynomials.

        Returns
        -------
        ndarray, (B, T) or (T,)
            The friction torque (Nm).

        """
        g, s = self.components(qd, xi, tau_l)
        off = self.packed.offset[0] if self.single else self.packed.offset[:, None]
        return g + s + off

    def parameters(self, xi: ArrayLike, tau_l: ArrayLike = 0.0) -> dict[str, np.ndarray]:
        """
        Return the evaluated curve parameters as a dict of arrays, keys :data:`PARAMETERS`.

        Parameters
        ----------
        xi : array_like, scalar, (T,) or (B, T)
            Gear temperature (degC).
        tau_l : array_like, scalar, (T,) or (B, T)
            Load torque (Nm); its magnitude enters the load polynomials.

        Returns
        -------
        dict of str to ndarray
            Each parameter, (B, T) or (T,).

        """
        xi, tl = broadcast_batch(self.packed.batch, xi, tau_l)
        out = np.empty((5,) + xi.shape)
        p = self.packed
        _param_eval(p.temp, p.load, p.t_lo, p.t_hi, xi, np.abs(tl), out)
        return {name: self._out(out[i]) for i, name in enumerate(PARAMETERS)}
