# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Rigid single joint with friction: J qdd = tau - tau_r - tau_ext (docs/interfaces.md).

tau is the drive torque, tau_r the friction torque (static, LuGre or GMS),
tau_ext everything from the link side: an input profile plus a linear spring
k_ext q plus the lever's gravity mgl sin(q - q_0) (q_0 the lever's angle
offset, where it hangs down).  The load seen by the friction
model is tau_L = |tau_ext|.

Integration scheme
------------------
The joint and the friction state are integrated *together*: with bristle or
element stiffnesses up to 1e7 Nm/rad the mass-bristle oscillation is far
above any control rate (sqrt(1e7/0.12) = 9 krad/s against 3 kHz sampling), so
updating friction and velocity one after the other (explicit coupling)
diverges.  Over each step the drive torque, external torque, temperature and
load are held constant and the coupled equations are linearised; the
resulting 2x2 affine system

    d/dt [z, qd] = A [z, qd] + b

is solved *exactly* (matrix exponential in closed form via phi-functions,
:mod:`~friction_joint.models._expint`), so the step is A-stable for any
stiffness and exact for frozen coefficients.  First a cheap implicit-Euler
predictor of the end velocity (viscous term s held at its start value, or
solved implicitly where its slope is stiff, which is always the case near
qd = 0 when delta_v < 1: this keeps a sticking joint from chattering across
zero velocity); s then enters by its chord between the start and predicted
end velocity (s has an infinite slope at qd = 0 when delta_v < 1, so a
tangent would be wrong).

LuGre: an exponential Rosenbrock-Euler step, the system linearised at the
step's start with its exact Jacobian, including the derivative of the
bristle relaxation a(qd) z (a = sigma0 |qd| / g(qd)) with respect to qd.
That term matters where the relaxation is stiff (a h >> 1, e.g. sigma0 =
1e5 at 0.1 rad/s: a = 1e4 /s): the step's end then lies on the linearised
quasi-equilibrium, and only with d(a z)/dqd is that exact to O(h^2); with
a frozen at the mid-step velocity it is off by O(h), and so is the damping
torque sigma1 dz/dt (error sigma1 h |qdd| / 2).  Every term, sigma1 dz/dt
included, is second order: against Radau (rtol 1e-10) the Canudas de Wit
(1995) stick-slip at h = 1/3000 s has friction-torque RMS errors of 3e-6 to
2e-5 N for sigma1 from 0 to 2 sqrt(sigma0 m), slip onsets within 1 us, and
converges at second order.  A step in which the velocity reverses (or starts
from rest) freezes a at the mid-step velocity instead (|qd| has a kink).

GMS: sticking elements act as springs in A; the torque of the others
(slipping, or changing state in the step) is a load taken linear in time
over the step (predicted by a first pass, trapezoidal in the second); the
element laws are then advanced exactly with the velocity ramping from the
step's start to its end (:func:`friction_joint.models.gms.gms_update_ramp`).
A predicted velocity reversal splits the step at its zero crossing, so the
elements stick again at the reversal and not a step late; a predicted slip
onset splits it there too.  The onset is where the element torque meets
alpha_i g(qd) at the velocity of that instant: taking g at the step's mean
velocity put it O(h) off wherever g changes within the step (pre-sliding
oscillation, break-away through the Stribeck range), and the element
torque with it, which then decays only at the rate C / g: a first-order
global error (numbers below).  The split keeps the elements' torque
smooth inside each substep (a kink inside a step leaves an O(h^2) velocity
error proportional to the stiffness).
Against an event-driven reference (scipy Radau restarted at every stick/slip
transition and reversal, three elements) the step is second order: sliding
with the velocity keeping its sign 4.1e-7, 5.8e-8, 6.7e-9 m at 1/1000,
1/3000, 1/9000 s (was 3.8e-5, 4.9e-6, 8.7e-7 m); 1 s of pre-sliding
reversals (two elements slipping and sticking again), then a break-away,
a near stop at 0.6 mm/s and a re-acceleration through the Stribeck range
1.9e-4, 1.9e-5, 1.9e-6 m (was 3.5e-4, 4.5e-4, 9.5e-5 m).  Where the near
stop is much slower (0.08 mm/s) the unstable Stribeck range amplifies every
error by orders of magnitude: 7.1e-3, 8.5e-4, 1.3e-4 m at 1/3000, 1/9000,
1/27000 s (was 1.2e-2, 9.5e-3, 7.0e-3 m).

The friction torque ``tau_r`` each step reports is the one at the step's
**end**, evaluated from the end state (q, qd, z) it is returned with.

The static model uses a Karnopp stick zone: the joint sticks when its
velocity would cross zero inside a step and the net torque is below F_s.
"""
from __future__ import annotations

import math
from typing import Any, Callable, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._coupled import _gms_joint_step, _lugre_joint_step, _static_joint_step
from .gms import pack_gms
from .static import broadcast_batch, curve_params, pack_static
from .._jit import njit
from ..exceptions import GearConfigError

if TYPE_CHECKING:
    from typing import TypeAlias

    from .params import FrictionParams, GearLike, LuGreParams

    #: a float array: the kernels' batch arrays (B,), (B, N), (B, T) and their rows
    _A: TypeAlias = NDArray[np.float64]

__all__ = ['Joint', 'JointTrajectory']


@njit(inline='always')
def _inputs(temp: _A, load: _A, t_lo: _A, t_hi: _A, kext: _A, mgl: _A, qoff: _A, rip_a: _A,
            rip_p: _A, rip_c: _A, rip_o: _A, b: int, q: float, te_in: float,
            xi: float) -> tuple[float, float, float, float, float, float, float]:
    """
    External torque, ripple torque and curve parameters for set b at position q.

    Called with the half-step position q + h qd / 2: together with the
    trapezoidal position update this makes the position-dependent torques
    a position-Verlet (symplectic, second-order) scheme.
    """
    te = te_in + kext[b] * q + mgl[b] * math.sin(q - qoff[b])
    rip = rip_o[b]
    for n in range(rip_a.shape[1]):
        rip += rip_a[b, n] * math.sin((n + 1) * rip_c[b] * q + rip_p[b, n])
    fc, fs, fv, vs, dv = curve_params(temp, load, (t_lo, t_hi), b, xi, abs(te))
    return te, rip, fc, fs, fv, vs, dv


@njit
def _run_lugre(temp: _A, load: _A, delta_s: _A, kappa: _A, t_lo: _A, t_hi: _A, rip_a: _A,
               rip_p: _A, rip_c: _A, rip_o: _A, sg0: _A, sg1: _A, jj: _A, mgl: _A, qoff: _A,
               kext: _A, tau: _A, tau_ext_in: _A, xi: _A, h: float, q: _A, v: _A, z: _A,
               out_q: _A, out_v: _A, out_tr: _A, out_te: _A) -> None:
    nb, nt = tau.shape
    for b in range(nb):
        for k in range(nt):
            te, rip, fc, fs, fv, vs, dv = _inputs(temp, load, t_lo, t_hi, kext, mgl, qoff, rip_a,
                                                  rip_p, rip_c, rip_o, b, q[b] + 0.5 * h * v[b],
                                                  tau_ext_in[b, k], xi[b, k])
            q[b], v[b], z[b], tr = _lugre_joint_step(
                q[b], v[b], z[b], tau[b, k] - te - rip, jj[b], sg0[b], sg1[b],
                fc, fs, fv, vs, dv, delta_s[b], kappa[b], h)
            out_q[b, k] = q[b]
            out_v[b, k] = v[b]
            out_tr[b, k] = tr + rip
            out_te[b, k] = te


@njit
def _run_gms(temp: _A, load: _A, delta_s: _A, kappa: _A, t_lo: _A, t_hi: _A, rip_a: _A,
             rip_p: _A, rip_c: _A, rip_o: _A, k_el: _A, alpha: _A, cc: _A, jj: _A, mgl: _A,
             qoff: _A, kext: _A, tau: _A, tau_ext_in: _A, xi: _A, h: float, q: _A, v: _A,
             z: _A, stick: NDArray[np.int8], slipdir: _A, out_q: _A, out_v: _A, out_tr: _A,
             out_te: _A) -> None:
    nb, nt = tau.shape
    for b in range(nb):
        for k in range(nt):
            te, rip, fc, fs, fv, vs, dv = _inputs(temp, load, t_lo, t_hi, kext, mgl, qoff, rip_a,
                                                  rip_p, rip_c, rip_o, b, q[b] + 0.5 * h * v[b],
                                                  tau_ext_in[b, k], xi[b, k])
            q[b], v[b], tr = _gms_joint_step(
                q[b], v[b], z[b], stick[b], slipdir[b], k_el[b], alpha[b], cc[b],
                tau[b, k] - te - rip, jj[b], fc, fs, fv, vs, dv, delta_s[b], kappa[b], h)
            out_q[b, k] = q[b]
            out_v[b, k] = v[b]
            out_tr[b, k] = tr + rip
            out_te[b, k] = te


@njit
def _run_static(temp: _A, load: _A, delta_s: _A, kappa: _A, t_lo: _A, t_hi: _A, rip_a: _A,
                rip_p: _A, rip_c: _A, rip_o: _A, jj: _A, mgl: _A, qoff: _A, kext: _A, tau: _A,
                tau_ext_in: _A, xi: _A, h: float, q: _A, v: _A, out_q: _A, out_v: _A,
                out_tr: _A, out_te: _A) -> None:
    nb, nt = tau.shape
    for b in range(nb):
        for k in range(nt):
            te, rip, fc, fs, fv, vs, dv = _inputs(temp, load, t_lo, t_hi, kext, mgl, qoff, rip_a,
                                                  rip_p, rip_c, rip_o, b, q[b] + 0.5 * h * v[b],
                                                  tau_ext_in[b, k], xi[b, k])
            q[b], v[b], tr = _static_joint_step(q[b], v[b], tau[b, k] - te - rip, jj[b],
                                                fc, fs, fv, vs, dv, delta_s[b], kappa[b], h)
            out_q[b, k] = q[b]
            out_v[b, k] = v[b]
            out_tr[b, k] = tr + rip
            out_te[b, k] = te


def pack_ripple(flist: list[FrictionParams]) -> tuple[_A, _A, _A, _A]:
    """Ripple amplitudes/phases (B, n), fundamentals (B,) and offsets (B,) (zeros where absent)."""
    n = max([len(f.position_ripple.amplitude) for f in flist if f.position_ripple] + [1])
    amp = np.zeros((len(flist), n))
    phase = np.zeros((len(flist), n))
    cyc = np.zeros(len(flist))
    for b, f in enumerate(flist):
        r = f.position_ripple
        if r is not None:
            amp[b, :len(r.amplitude)] = r.amplitude
            phase[b, :len(r.phase)] = r.phase
            cyc[b] = r.cycles_per_rev
    return amp, phase, cyc, np.array([f.offset for f in flist], dtype=float)


class JointTrajectory:
    """
    Result of :meth:`Joint.simulate`: arrays (T,) or (B, T) at the end of each step.

    Parameters
    ----------
    t : ndarray
        Time (s) at the end of each step.
    q : ndarray
        Position (rad).
    qd : ndarray
        Velocity (rad/s).
    tau_r : ndarray
        Friction torque (Nm).
    tau_ext : ndarray
        External torque used in the step (Nm).

    """

    def __init__(self, t: NDArray[np.float64], q: NDArray[np.float64], qd: NDArray[np.float64],
                 tau_r: NDArray[np.float64], tau_ext: NDArray[np.float64]) -> None:
        self.t, self.q, self.qd, self.tau_r, self.tau_ext = t, q, qd, tau_r, tau_ext


class Joint:
    """
    Rigid joint with friction for one gear or a batch of B gears.

    Parameters
    ----------
    gears : GearParams or list or tuple of GearParams
        Inertia and friction parameters.
    model : {'static', 'lugre', 'gms'}, optional
        Friction model; default each gear's ``friction.model`` (must agree
        across a batch).
    mgl : float or array_like (B,)
        Lever gravity amplitude m g l (Nm): tau_ext includes mgl sin(q - lever_offset).
    k_ext : float or array_like (B,)
        Link-side spring (Nm/rad): tau_ext includes k_ext q.
    inertia : float or array_like (B,), optional
        Overrides the gears' inertia.
    lever_offset : float or array_like (B,)
        Angle (rad) at which the lever hangs down (``GearParams.lever_offset``).

    """

    def __init__(self, gears: GearLike | list[GearLike] | tuple[GearLike, ...], *,
                 model: str | None = None,
                 mgl: ArrayLike = 0.0, k_ext: ArrayLike = 0.0, inertia: ArrayLike | None = None,
                 lever_offset: ArrayLike = 0.0) -> None:
        self.single = not isinstance(gears, (list, tuple))
        glist = list(gears) if isinstance(gears, (list, tuple)) else [gears]
        models = {model or g.friction.model for g in glist}
        if len(models) != 1:
            raise GearConfigError(f'a batch must use one friction model, got {sorted(models)}')
        self.model = models.pop()
        flist = [g.friction for g in glist]
        self.packed = pack_static(flist)
        self.ripple = pack_ripple(flist)
        n = len(glist)
        self.inertia = np.broadcast_to(
            np.asarray([g.inertia for g in glist] if inertia is None else inertia, float),
            (n,)).copy()
        self.mgl = np.broadcast_to(np.asarray(mgl, float), (n,)).copy()
        self.lever_offset = np.broadcast_to(np.asarray(lever_offset, float), (n,)).copy()
        self.k_ext = np.broadcast_to(np.asarray(k_ext, float), (n,)).copy()
        if self.model == 'lugre':
            lugres: list[LuGreParams] = [f.lugre for f in flist if f.lugre is not None]
            if len(lugres) != len(flist):
                raise GearConfigError('model lugre needs friction.lugre in every gear')
            self.sigma0 = np.array([p.sigma0 for p in lugres])
            self.sigma1 = np.array([p.sigma1 for p in lugres])
        elif self.model == 'gms':
            self.k_el, self.alpha, self.c = pack_gms(flist)
        self.reset()

    @property
    def batch(self) -> int:
        return self.packed.batch

    def reset(self, *, q: ArrayLike = 0.0, qd: ArrayLike = 0.0) -> None:
        """
        Put the joint at (q, qd) with relaxed friction state.

        Parameters
        ----------
        q : float or array_like (B,)
            Position (rad).
        qd : float or array_like (B,)
            Velocity (rad/s).

        """
        self._step_args: tuple[Any, ...] | None = None
        n = self.batch
        self.q = np.broadcast_to(np.asarray(q, float), (n,)).copy()
        self.qd = np.broadcast_to(np.asarray(qd, float), (n,)).copy()
        if self.model == 'lugre':
            self.z = np.zeros(n)
        elif self.model == 'gms':
            self.z = np.zeros_like(self.k_el)
            self.stick = np.ones(self.k_el.shape, dtype=np.int8)
            self.slipdir = np.zeros(self.k_el.shape)

    def simulate(self, tau: ArrayLike, dt: float, *, xi: ArrayLike = 25.0,
                 tau_ext: ArrayLike = 0.0) -> JointTrajectory:
        """
        Integrate from the current state over sampled inputs.

        Parameters
        ----------
        tau : array_like (T,) or (B, T)
            Drive torque held over each step (Nm).
        dt : float
            Step (s).
        xi : array_like, scalar, (T,) or (B, T)
            Gear temperature (degC).
        tau_ext : array_like, scalar, (T,) or (B, T)
            External torque input (Nm), added to the spring and gravity terms.

        Returns
        -------
        JointTrajectory

        """
        if not (np.isfinite(dt) and dt > 0):
            raise ValueError(f'dt must be a positive number, got {dt}')
        tau_b, te_in, xi_b = broadcast_batch(self.batch, tau, tau_ext, xi)
        for name, arr in (('tau', tau_b), ('tau_ext', te_in), ('xi', xi_b)):
            if not np.all(np.isfinite(arr)):
                raise ValueError(f'{name} contains NaN or inf')
        outs = [np.empty_like(tau_b) for _ in range(4)]
        p = self.packed.args() + self.ripple
        h = float(dt)
        if self.model == 'lugre':
            _run_lugre(*p, self.sigma0, self.sigma1, self.inertia, self.mgl, self.lever_offset,
                       self.k_ext,
                       tau_b, te_in, xi_b, h, self.q, self.qd, self.z, *outs)
        elif self.model == 'gms':
            _run_gms(*p, self.k_el, self.alpha, self.c, self.inertia, self.mgl, self.lever_offset,
                     self.k_ext,
                     tau_b, te_in, xi_b, h, self.q, self.qd, self.z, self.stick, self.slipdir,
                     *outs)
        else:
            _run_static(*p, self.inertia, self.mgl, self.lever_offset, self.k_ext,
                        tau_b, te_in, xi_b, h, self.q, self.qd, *outs)
        t = h * np.arange(1, tau_b.shape[1] + 1)
        if self.single:
            outs = [o[0] for o in outs]
        return JointTrajectory(t, *outs)

    def __getstate__(self) -> dict[str, Any]:
        """Drop the cached step arguments: they hold views of arrays a copy replaces."""
        state = self.__dict__.copy()
        state['_step_args'] = None
        return state

    def step(self, tau: float, dt: float, *, xi: float,
             tau_ext: float = 0.0) -> tuple[float, float, float, float]:
        """
        Advance a single gear by one step; low-overhead path for real-time loops.

        Parameters
        ----------
        tau : float
            Drive torque held over the step (Nm).
        dt : float
            Step (s).
        xi : float
            Gear temperature (degC).
        tau_ext : float
            External torque input (Nm), added to the spring and gravity terms.

        Returns
        -------
        (q, qd, tau_r, tau_ext) : floats at the end of the step

        """
        if self.batch != 1:
            raise ValueError('step() is for a single gear; use simulate() for a batch')
        if self._step_args is None or self._step_dt != dt:
            self._inp = np.zeros((3, 1, 1))
            self._out = np.zeros((4, 1, 1))
            p = self.packed.args() + self.ripple
            state: tuple[NDArray[Any], ...]
            pars: tuple[NDArray[np.float64], ...]
            if self.model == 'lugre':
                state, pars = (self.q, self.qd, self.z), (self.sigma0, self.sigma1)
            elif self.model == 'gms':
                state = (self.q, self.qd, self.z, self.stick, self.slipdir)
                pars = (self.k_el, self.alpha, self.c)
            else:
                state, pars = (self.q, self.qd), ()
            self._step_args = (p + pars + (self.inertia, self.mgl, self.lever_offset, self.k_ext,
                               self._inp[0], self._inp[1], self._inp[2], float(dt)) + state
                               + tuple(self._out))
            kernels: dict[str, Callable[..., None]] = {'lugre': _run_lugre, 'gms': _run_gms,
                                                       'static': _run_static}
            self._step_fn = kernels[self.model]
            self._step_dt: float = dt
        self._inp[0, 0, 0] = tau
        self._inp[1, 0, 0] = tau_ext
        self._inp[2, 0, 0] = xi
        self._step_fn(*self._step_args)
        o = self._out
        return o[0, 0, 0], o[1, 0, 0], o[2, 0, 0], o[3, 0, 0]
