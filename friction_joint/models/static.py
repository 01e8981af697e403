# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

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
from numpy.typing import ArrayLike, NDArray

from .._jit import njit

if TYPE_CHECKING:
    from .params import FrictionParams

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

    def __init__(self, temp: NDArray[np.float64], load: NDArray[np.float64],
                 delta_s: NDArray[np.float64], velocity_scale: NDArray[np.float64],
                 t_lo: NDArray[np.float64], t_hi: NDArray[np.float64], *,
                 offset: NDArray[np.float64] | None = None) -> None:
        self.temp = temp
        self.load = load
        self.delta_s = delta_s
        self.velocity_scale = velocity_scale
        self.t_lo = t_lo
        self.t_hi = t_hi
        self.offset = np.zeros(len(delta_s)) if offset is None else offset

    @property
    def batch(self) -> int:
        return int(self.temp.shape[0])

    def args(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                            NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Return the arrays in the order the kernels take them."""
        return (self.temp, self.load, self.delta_s, self.velocity_scale,
                self.t_lo, self.t_hi)


def pack_static(frictions: FrictionParams | list[FrictionParams] | tuple[FrictionParams, ...]
                ) -> PackedStatic:
    """
    Pack one or more :class:`~friction_joint.gear.FrictionParams`.

    Parameters
    ----------
    frictions : FrictionParams or list or tuple of FrictionParams
        One parameter set, or B of them.

    Returns
    -------
    PackedStatic

    """
    if not isinstance(frictions, (list, tuple)):
        frictions = [frictions]
    n = len(frictions)
    lists_t: list[tuple[tuple[float, ...], ...]] = []
    lists_l: list[tuple[tuple[float, ...], ...]] = []
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
def _poly(temp: NDArray[np.float64], load: NDArray[np.float64], b: int, p: int, x: float,
          tl: float) -> float:
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
def curve_params(temp: NDArray[np.float64], load: NDArray[np.float64],
                 t_range: tuple[NDArray[np.float64], NDArray[np.float64]], b: int, xi: float,
                 tl: float) -> tuple[float, float, float, float, float]:
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
def g_abs(fc: float, fs: float, vs: float, ds: float, kappa: float, v: float) -> float:
    """|g(v)|: magnitude of the Stribeck curve (eq. 1); F_s at v = 0."""
    x = kappa * v / vs
    if ds == 2.0:
        return fc + (fs - fc) * math.exp(-x * x)
    return fc + (fs - fc) * math.exp(-abs(x) ** ds)


@njit
def s_visc(fv: float, dv: float, kappa: float, v: float) -> float:
    """Nonlinear viscous term s(v) = F_v sign(v) |kappa v|^delta_v (eq. 5)."""
    if v == 0.0:
        return 0.0
    r: float = fv * abs(kappa * v) ** dv
    return r if v > 0.0 else -r


@njit
def sign(v: float) -> float:
    if v > 0.0:
        return 1.0
    if v < 0.0:
        return -1.0
    return 0.0


@njit
def _static_eval(temp: NDArray[np.float64], load: NDArray[np.float64],
                 delta_s: NDArray[np.float64], kappa: NDArray[np.float64],
                 t_lo: NDArray[np.float64], t_hi: NDArray[np.float64], qd: NDArray[np.float64],
                 xi: NDArray[np.float64], tl: NDArray[np.float64], out_g: NDArray[np.float64],
                 out_s: NDArray[np.float64]) -> None:
    nb, nt = qd.shape
    for b in range(nb):
        for k in range(nt):
            fc, fs, fv, vs, dv = curve_params(temp, load, (t_lo, t_hi), b, xi[b, k], tl[b, k])
            v = qd[b, k]
            out_g[b, k] = sign(v) * g_abs(fc, fs, vs, delta_s[b], kappa[b], v)
            out_s[b, k] = s_visc(fv, dv, kappa[b], v)


@njit
def _param_eval(temp: NDArray[np.float64], load: NDArray[np.float64],
                t_lo: NDArray[np.float64], t_hi: NDArray[np.float64], xi: NDArray[np.float64],
                tl: NDArray[np.float64], out: NDArray[np.float64]) -> None:
    nb, nt = xi.shape
    for b in range(nb):
        for k in range(nt):
            fc, fs, fv, vs, dv = curve_params(temp, load, (t_lo, t_hi), b, xi[b, k], tl[b, k])
            out[0, b, k] = fc
            out[1, b, k] = fs
            out[2, b, k] = fv
            out[3, b, k] = vs
            out[4, b, k] = dv


def _as_2d(a: NDArray[np.float64]) -> NDArray[np.float64]:
    if a.ndim == 0:
        return a.reshape(1, 1)
    if a.ndim == 1:
        return a.reshape(1, -1)
    if a.ndim == 2:
        return a
    raise ValueError('inputs must be scalars, 1-D (T,) or 2-D (B, T) arrays')


def broadcast_batch(batch: int, *arrays: ArrayLike) -> list[NDArray[np.float64]]:
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
    frictions : FrictionParams or list or tuple of FrictionParams
        One parameter set, or B of them (batch dimension first in results).

    """

    def __init__(self, frictions: FrictionParams | list[FrictionParams]
                 | tuple[FrictionParams, ...]) -> None:
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

    def _out(self, a: NDArray[np.float64]) -> NDArray[np.float64]:
        return a[0] if self.single else a

    def components(self, qd: ArrayLike, xi: ArrayLike,
                   tau_l: ArrayLike = 0.0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
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
        qd2, xi2, tl = broadcast_batch(self.packed.batch, qd, xi, tau_l)
        g = np.empty_like(qd2)
        s = np.empty_like(qd2)
        p = self.packed
        _static_eval(p.temp, p.load, p.delta_s, p.velocity_scale, p.t_lo, p.t_hi,
                     qd2, xi2, np.abs(tl), g, s)
        return self._out(g), self._out(s)

    def torque(self, qd: ArrayLike, xi: ArrayLike,
               tau_l: ArrayLike = 0.0) -> NDArray[np.float64]:
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
        out: NDArray[np.float64] = g + s + off
        return out

    def parameters(self, xi: ArrayLike,
                   tau_l: ArrayLike = 0.0) -> dict[str, NDArray[np.float64]]:
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
        xi2, tl = broadcast_batch(self.packed.batch, xi, tau_l)
        out = np.empty((5,) + xi2.shape)
        p = self.packed
        _param_eval(p.temp, p.load, p.t_lo, p.t_hi, xi2, np.abs(tl), out)
        return {name: self._out(out[i]) for i, name in enumerate(PARAMETERS)}
