#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Our LuGre joint integrator against MuJoCo's dcmotor LuGre friction, both against Radau.

    .venv/bin/python -m pip install -r benchmarks/requirements-bench.txt   # mujoco==4.0.0
    .venv/bin/python benchmarks/bench_mujoco_lugre.py                # full grid, ~10-15 min
    .venv/bin/python benchmarks/bench_mujoco_lugre.py --quick        # < 2 min
    .venv/bin/python benchmarks/bench_mujoco_lugre.py --json out.json

What it does
------------
1. The same ODE three ways, a unit mass/inertia J = 1 on a spring k with
   LuGre friction (Canudas de Wit et al. 1995, Table I; delta_v = 1,
   delta_s = 2):

       q' = qd,   J qd' = u - tau_r - k q - tau_ext_in
       z' = qd - sigma0 |qd| z / g(qd),   g = F_c + (F_s - F_c) exp(-(qd/v_s)^2)
       tau_r = sigma0 z + sigma1 z' + F_v qd

   * ours: :class:`friction_joint.Joint` (model ``lugre``, ``k_ext = k``),
     gear from :func:`friction_joint.experiments.classic.canudas_gear`;
   * MuJoCo 4.0.0: one hinge joint (inertia J, ``stiffness = k``) driven by
     a ``<dcmotor input="ff" motorconst="1 1" resistance="1"
     damping="F_v" lugre="sigma0 sigma1 F_c F_s v_s">``: no inductance (the
     current is algebraic) and the torque-feedforward input compensates the
     back-EMF, so the delivered torque is exactly ``ctrl``; the LuGre force
     is the actuator's bias, F_v the actuator damping.  Integrators Euler,
     RK4 and implicitfast, run with :func:`mujoco.rollout.rollout`;
   * reference: :class:`scipy.integrate.Radau`, rtol 1e-10 (atol = rtol x
     (0.01 m, 0.01 m/s, 10 F_s / sigma0)), right-hand side and Jacobian
     written here from the equations above (``--check-ref`` compares the
     hardest reference with one at rtol 1e-11).
2. Inputs are a zero-order hold at 1 kHz (``HOLD``): u and tau_ext_in are
   sampled at the middle of each 1 ms interval and held over it.  Every
   step of every dt in the grid (1e-3, 1/3000, 1e-4 s) lies inside one hold
   interval, so all simulators see piecewise-constant inputs per step and
   every dt integrates the same continuous problem.  Radau integrates each
   hold interval separately (the input jumps are respected exactly) and is
   sampled at every step end of every dt (its dense output inside an
   interval).  References are computed once per (scenario, sigma0, sigma1)
   in ``--jobs`` worker processes and kept in memory only.
3. Before the grid it verifies the MuJoCo set-up: the actuator force law at
   random states, which instant the ``actuatorfrc`` sensor belongs to, how
   the bristle state is advanced, and that MuJoCo Euler converges to the
   Radau solution as dt -> 0 (first order).
4. Scenarios: ``stick-slip`` (Canudas Fig. 6: k = 2 N/m pulled at
   v_p = 0.1 m/s, tau_ext_in = -k v_p t, from rest; slip onsets are the
   upward crossings of 0.05 m/s, :func:`~friction_joint.experiments.classic.slip_onsets`;
   21 s, three onsets) and ``reversal`` (u = 2.5 sin(2 pi t) N > F_s on the
   same spring, 4 s: velocity reversals with short sticking).  Grid: sigma0
   in {1e5, 1e7}, sigma1 in {0, 1, 10, sqrt(sigma0), 2 sqrt(sigma0 J)}, dt
   as above.  ``--quick``: 10 s (one onset) and 2 s, sigma0 = 1e5 and
   sigma1 in {0, sqrt(sigma0), 2 sqrt(sigma0 J)}.
5. Errors against Radau: max and RMS of q, qd at the step ends and of
   tau_r at the instant each simulator reports it for (ours: step end;
   MuJoCo: step start, where its actuator force is computed), and the
   largest slip-onset deviation (a run with a different number of onsets
   than the reference is printed ``n/m on``).  A run whose state becomes
   non-finite or |qd| > 1e3 counts as diverged (error inf, printed ``div``).
6. Speed: ns per step, best of several runs after a warm-up, single
   instance (60 s at 3 kHz, stick-slip, Canudas set) and a batch of 64
   parameter sets (sigma1 in [0, 2 sqrt(sigma0 J)], 10 s each; ours: one
   batched ``Joint``, one thread; MuJoCo: ``rollout`` over 64 models, 2
   threads).

The last line is always

    speed_ratio_single=<x> speed_ratio_batched=<y> worst_accuracy_ratio=<r>

x and y are MuJoCo-Euler ns/step / ours; r is the largest ours / MuJoCo-Euler
error over the dt = 1/3000 rows and the three table metrics (onset
deviation, tau_r RMS, q max; 0 where MuJoCo diverged).  Exit status 2 if
mujoco cannot be imported.
"""
import argparse
from concurrent.futures import ProcessPoolExecutor
import json
import math
import multiprocessing
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)

from friction_joint import Joint  # noqa: E402
from friction_joint.experiments.classic import CANUDAS_1995, canudas_gear  # noqa: E402
from friction_joint.experiments.classic import slip_onsets  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import Radau  # noqa: E402

try:
    import mujoco
    from mujoco import rollout as mj_rollout
except ImportError:     # reported in main()
    mujoco = None

XI = 25.0               # temperature input of ours (the Canudas set has no temperature law)
J = CANUDAS_1995['mass']
K_SPRING = 2.0
VP = 0.1
THRESHOLD = 0.05        # slip onset: upward crossing of this velocity (m/s)
V_DIVERGED = 1e3
RTOL = 1e-10
HOLD = 1e-3
DTS = (1e-3, 1.0 / 3000.0, 1e-4)
METHODS = ('ours', 'Euler', 'RK4', 'implicitfast')


def sigma1_grid(sigma0):
    """sigma1 values of the grid for one sigma0 (names, values)."""
    return [('0', 0.0), ('1', 1.0), ('10', 10.0), ('sqrt(s0)', math.sqrt(sigma0)),
            ('2sqrt(s0J)', 2.0 * math.sqrt(sigma0 * J))]


def params(sigma0, sigma1):
    """Canudas 1995 parameter dict with sigma0, sigma1 replaced."""
    return dict(CANUDAS_1995, sigma0=float(sigma0), sigma1=float(sigma1))


# ------------------------------------------------------------- inputs -------

def hold_inputs(scenario, horizon, hold):
    """Drive u and external input tau_ext_in per hold interval (sampled at its middle)."""
    n = int(round(horizon / hold))
    tm = hold * (np.arange(n) + 0.5)
    if scenario == 'stick-slip':
        return np.zeros(n), -K_SPRING * VP * tm
    if scenario == 'reversal':
        return 2.5 * np.sin(2.0 * math.pi * tm), np.zeros(n)
    raise ValueError(scenario)


def per_step(x, m):
    """Hold-interval samples repeated for m steps per interval."""
    return np.repeat(x, m)


# ------------------------------------------------------------- reference ----

class LuGreODE:
    """Right-hand side, Jacobian and friction torque of the ODE in the module docstring."""

    def __init__(self, p, k):
        self.p = (p['sigma0'], p['sigma1'], p['fc'], p['fs'], p['vs'], p['sigma2'], J, k)
        self.f = 0.0            # u - tau_ext_in of the current hold interval

    def rhs(self, t, y):
        s0, s1, fc, fs, vs, fv, jj, k = self.p
        q, v, z = y
        g = fc + (fs - fc) * math.exp(-(v / vs) ** 2)
        zd = v - s0 * abs(v) * z / g
        return np.array([v, (self.f - s0 * z - s1 * zd - fv * v - k * q) / jj, zd])

    def jac(self, t, y):
        s0, s1, fc, fs, vs, fv, jj, k = self.p
        q, v, z = y
        e = math.exp(-(v / vs) ** 2)
        g = fc + (fs - fc) * e
        dg = -2.0 * (fs - fc) * e * v / (vs * vs)
        sv = math.copysign(1.0, v) if v != 0.0 else 0.0
        dzz = -s0 * abs(v) / g
        dzv = 1.0 - s0 * z * (sv * g - abs(v) * dg) / (g * g)
        return np.array([[0.0, 1.0, 0.0],
                         [-k / jj, -(s1 * dzv + fv) / jj, -(s0 + s1 * dzz) / jj],
                         [0.0, dzv, dzz]])

    def tau_r(self, y):
        """Friction torque at states y (..., 3)."""
        s0, s1, fc, fs, vs, fv, _, _ = self.p
        v, z = y[..., 1], y[..., 2]
        g = fc + (fs - fc) * np.exp(-(v / vs) ** 2)
        return s0 * z + s1 * (v - s0 * np.abs(v) * z / g) + fv * v


def sample_fractions(hold, dts):
    """Return the common denominator L and numerators j (1..L) of all step ends in a hold."""
    ms = [int(round(hold / dt)) for dt in dts]
    for m, dt in zip(ms, dts, strict=True):
        if abs(m * dt - hold) > 1e-12 * hold:
            raise ValueError(f'dt={dt} does not divide the hold interval {hold}')
    lcm = math.lcm(*ms)
    nums = sorted({lcm // m * j for m in ms for j in range(1, m + 1)})
    return lcm, nums


def radau_reference(p, f, *, k, hold, fracs, rtol=RTOL):
    """
    Radau over each hold interval separately, sampled at the given fractions of each.

    Returns y of shape (n_intervals, len(fracs), 3): the state at
    (i + fracs[j]) * hold; fracs[-1] must be 1 (the interval end).  The
    step size is carried over from one interval to the next.
    """
    ode = LuGreODE(p, k)
    atol = rtol * np.array([1e-2, 1e-2, 10.0 * p['fs'] / p['sigma0']])
    fr = np.asarray(fracs, float)
    out = np.empty((len(f), len(fr), 3))
    y = np.zeros(3)
    h = None
    nsteps = 0
    for i, fi in enumerate(f):
        ode.f = float(fi)
        t0, t1 = i * hold, (i + 1) * hold
        ts = t0 + hold * fr[:-1]
        s = Radau(ode.rhs, t0, y, t1, rtol=rtol, atol=atol, jac=ode.jac,
                  first_step=None if h is None else min(h, t1 - t0))
        j = 0
        last = t1 - t0
        while s.status == 'running':
            s.step()
            nsteps += 1
            last = s.t - s.t_old
            if j < len(ts) and ts[j] <= s.t:
                m = int(np.searchsorted(ts, s.t, side='right'))
                out[i, j:m] = s.dense_output()(ts[j:m]).T
                j = m
        if s.status != 'finished':
            raise RuntimeError(f'Radau failed in interval {i}: {s.status}')
        y = s.y.copy()
        out[i, -1] = y
        h = min(max(s.h_abs, last), hold)
    return out, nsteps


def _reference_job(job):
    """Worker: one reference (scenario, sigma0, sigma1); returns (key, data)."""
    key, p, horizon, hold, lcm, nums, rtol = job
    u, te = hold_inputs(key[0], horizon, hold)
    t0 = time.perf_counter()
    y, nsteps = radau_reference(p, u - te, k=K_SPRING, hold=hold,
                                fracs=[j / lcm for j in nums], rtol=rtol)
    return key, {'y': y, 'nsteps': nsteps, 'wall': time.perf_counter() - t0}


def reference_at(ref, dt, *, hold, lcm, nums):
    """Return the reference states (N + 1, 3) at t_0 = 0, t_1 = dt, ..., t_N."""
    m = int(round(hold / dt))
    cols = [nums.index(lcm // m * j) for j in range(1, m + 1)]
    y = ref['y'][:, cols, :].reshape(-1, 3)
    return np.vstack([np.zeros((1, 3)), y])


# ------------------------------------------------------------- simulators ---

def run_ours(p, u, te, dt):
    """Joint.simulate; q, qd at step ends, tau_r at step ends (shift 0)."""
    joint = Joint(canudas_gear(p), model='lugre', k_ext=K_SPRING)
    tr = joint.simulate(u, dt, xi=XI, tau_ext=te)
    return {'q': tr.q, 'v': tr.qd, 'tr': tr.tau_r, 'shift': 0}


def mujoco_model(p, *, dt, integrator):
    """One hinge, inertia J, spring k, torque-controlled dcmotor with LuGre friction."""
    def num(x):
        return '%.17g' % float(x)
    lugre = ' '.join(num(p[n]) for n in ('sigma0', 'sigma1', 'fc', 'fs', 'vs'))
    xml = f"""
<mujoco model="lugre_dcmotor">
  <option timestep="{num(dt)}" integrator="{integrator}" gravity="0 0 0">
    <flag contact="disable" constraint="disable" autoreset="disable"/>
  </option>
  <worldbody>
    <body name="link">
      <joint name="q" type="hinge" axis="0 0 1" stiffness="{num(K_SPRING)}"/>
      <inertial pos="0 0 0" mass="1" diaginertia="{num(J)} {num(J)} {num(J)}"/>
    </body>
  </worldbody>
  <actuator>
    <dcmotor name="drive" joint="q" input="ff" motorconst="1 1" resistance="1"
             damping="{num(p['sigma2'])}" lugre="{lugre}"/>
  </actuator>
  <sensor>
    <actuatorfrc actuator="drive"/>
  </sensor>
</mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def state_index(m):
    """Offsets of qpos, qvel, act in a FULLPHYSICS state vector."""
    st = mujoco.mjtState
    iq = mujoco.mj_stateSize(m, st.mjSTATE_TIME)
    return iq, iq + m.nq, iq + m.nq + m.nv


def rollout(models, ctrl, *, nthread=0):
    """mujoco.rollout from rest; returns (states (B, T, n), sensordata (B, T, 1))."""
    models = models if isinstance(models, list) else [models]
    data = [mujoco.MjData(models[0]) for _ in range(max(nthread, 1))]
    st = mujoco.mjtState.mjSTATE_FULLPHYSICS
    x0 = np.empty(mujoco.mj_stateSize(models[0], st))
    mujoco.mj_getState(models[0], data[0], x0, st)
    ctrl = np.asarray(ctrl, float)
    ctrl = ctrl.reshape((-1, ctrl.shape[-1], 1))
    return mj_rollout.rollout(models if len(models) > 1 else models[0],
                              data if nthread > 1 else data[0], x0[None, :], ctrl)


def run_mujoco(p, ctrl, dt, integrator):
    """
    Run MuJoCo (rollout); q, qd at step ends, tau_r at step starts (shift 1).

    tau_r = ctrl - actuatorfrc + F_v qd, all of the state at the start of the step
    (the sensor is evaluated in mj_forward before the integration).
    """
    m = mujoco_model(p, dt=dt, integrator=integrator)
    state, sens = rollout(m, ctrl)
    iq, iv, _ = state_index(m)
    q, v = state[0, :, iq], state[0, :, iv]
    vstart = np.concatenate(([0.0], v[:-1]))
    tr = ctrl - sens[0, :, 0] + p['sigma2'] * vstart
    return {'q': q, 'v': v, 'tr': tr, 'shift': 1}


class CountWarnings:
    """Context manager: count MuJoCo's warnings instead of printing them."""

    def __enter__(self):
        self.count = 0
        self._old = mujoco.get_mju_user_warning()
        mujoco.set_mju_user_warning(self._add)
        return self

    def _add(self, msg):
        self.count += 1

    def __exit__(self, *exc):
        mujoco.set_mju_user_warning(self._old)
        return False


# ------------------------------------------------------------- analysis -----

def diverged(run):
    """Return True if the state became non-finite or |qd| exceeded V_DIVERGED."""
    v = run['v']
    return not (np.all(np.isfinite(v)) and np.all(np.isfinite(run['q']))
                and np.all(np.isfinite(run['tr'])) and np.max(np.abs(v)) < V_DIVERGED)


def onsets_of(dt, v):
    """Slip onsets (s) of step-end velocities v (t = dt, 2 dt, ...), starting from rest."""
    t = dt * np.arange(len(v) + 1)
    return slip_onsets(t, np.concatenate(([0.0], v)), THRESHOLD)


def compare(run, ode, yref, dt, *, stride=1, with_onsets=False):
    """Error metrics of one run against the reference states yref (t_0 .. t_N at dt * stride)."""
    if diverged(run):
        out = {f'{a}_{b}': math.inf for a in ('q', 'qd', 'tau_r') for b in ('max', 'rms')}
        out.update(diverged=True, onset_ms=math.inf if with_onsets else None)
        return out
    n = len(yref) - 1
    ends = stride * np.arange(1, n + 1) - 1     # run index of the step ending at t_i
    tr_ref = ode.tau_r(yref)
    e = {'q': run['q'][ends] - yref[1:, 0], 'qd': run['v'][ends] - yref[1:, 1]}
    if run['shift']:                            # tau_r[k] belongs to the start t_k of step k
        e['tau_r'] = run['tr'][ends + 1 - stride] - tr_ref[:-1]
    else:                                       # tau_r[k] belongs to the end t_{k+1}
        e['tau_r'] = run['tr'][ends] - tr_ref[1:]
    out = {'diverged': False}
    for name, err in e.items():
        out[f'{name}_max'] = float(np.max(np.abs(err)))
        out[f'{name}_rms'] = float(np.sqrt(np.mean(err * err)))
    out['onset_ms'] = None
    if with_onsets:
        ref_on = onsets_of(dt * stride, yref[1:, 1])
        on = onsets_of(dt, run['v'])
        out['onsets'] = on
        if not ref_on:
            out['onset_ms'] = None
        elif len(on) != len(ref_on):
            out['onset_ms'] = math.inf
            out['onset_count'] = f'{len(on)}/{len(ref_on)}'
        else:
            out['onset_ms'] = 1e3 * float(np.max(np.abs(np.subtract(on, ref_on))))
    return out


def fmt(err, key, width=8):
    """Table cell: number, 'div' (diverged), 'n/m on' (n onsets, reference m) or '-'."""
    x = err[key]
    if x is None:
        return '-'.rjust(width)
    if math.isinf(x):
        if key == 'onset_ms' and not err['diverged']:
            return f'{err["onset_count"]} on'.rjust(width)
        return 'div'.rjust(width)
    return f'{x:.2e}'.rjust(width) if x != 0 else '0'.rjust(width)


# ------------------------------------------------------------- verification -

def verify_mujoco(p, refs, *, lcm, nums, horizon):
    """Check the MuJoCo model against the equations; print and return the numbers."""
    rng = np.random.default_rng(1)
    s0, s1, fc, fs, vs, fv = (p[n] for n in ('sigma0', 'sigma1', 'fc', 'fs', 'vs', 'sigma2'))
    out = {}
    m = mujoco_model(p, dt=1e-4, integrator='Euler')
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    mass = np.zeros((1, 1))
    mujoco.mj_fullM(m, d, mass)
    out['inertia'] = float(mass[0, 0])
    worst = {'force': 0.0, 'act_dot': 0.0, 'passive': 0.0}
    for _ in range(200):
        z = rng.uniform(-1.5, 1.5) * fs / s0
        v = rng.choice([0.0, rng.normal(0, 3 * vs), rng.normal(0, 0.3)])
        q, u = rng.normal(0, 0.1), rng.normal(0, 2.0)
        d.qpos[0], d.qvel[0], d.act[0], d.ctrl[0] = q, v, z, u
        mujoco.mj_forward(m, d)
        g = fc + (fs - fc) * math.exp(-(v / vs) ** 2)
        zd = v - s0 * abs(v) * z / g
        fr = s0 * z + s1 * zd
        worst['force'] = max(worst['force'],
                             abs(d.actuator_force[0] - (u - fr)) / max(1.0, abs(fr)))
        worst['act_dot'] = max(worst['act_dot'], abs(d.act_dot[0] - zd) / max(abs(zd), 1e-3))
        worst['passive'] = max(worst['passive'], abs(d.qfrc_passive[0] + fv * v + K_SPRING * q))
    out['force_law'] = worst
    print(f'  model: hinge, M = mj_fullM = {out["inertia"]:g} (J = {J:g}); dcmotor input="ff" '
          'K = 1, R = 1, no inductance; LuGre in the actuator bias')
    print(f'  force law at 200 random (q, qd, z, ctrl): |actuator_force - (ctrl - sigma0 z - '
          f'sigma1 z\')| <= {worst["force"]:.1e} (rel.), act_dot = z\' to {worst["act_dot"]:.1e} '
          f'(rel.), qfrc_passive = -F_v qd - k q to {worst["passive"]:.1e} Nm')
    # bristle update over one step, all integrators
    h = 1e-3
    bristle = {}
    for integ in METHODS[1:]:
        mm = mujoco_model(p, dt=h, integrator=integ)
        dd = mujoco.MjData(mm)
        z, v = 0.3 * fs / s0, 0.02
        dd.qvel[0], dd.act[0], dd.ctrl[0] = v, z, 0.7
        mujoco.mj_step(mm, dd)
        a = s0 * abs(v) / (fc + (fs - fc) * math.exp(-(v / vs) ** 2))
        exact = v / a + (z - v / a) * math.exp(-a * h)
        bristle[integ] = {'act': float(dd.act[0]), 'exact_frozen_v': exact,
                          'explicit_euler': z + h * (v - a * z)}
    out['bristle_step'] = bristle
    dev = max(abs(b['act'] - b['exact_frozen_v']) / abs(b['exact_frozen_v'])
              for b in bristle.values())
    print(f'  bristle state over one step (h = 1 ms, qd = 0.02, z = 0.3 F_s/sigma0): every '
          f'integrator gives z(h) = exact exponential with qd frozen at the step start '
          f'(rel. dev. {dev:.1e}; explicit Euler would give '
          f'{bristle["Euler"]["explicit_euler"] / bristle["Euler"]["act"]:.2f}x that)')
    # sensor instant and convergence on the reversal scenario
    ode = LuGreODE(p, K_SPRING)
    ref = refs[('reversal', p['sigma0'], p['sigma1'])]
    yref = reference_at(ref, 1e-4, hold=HOLD, lcm=lcm, nums=nums)
    n_hold = int(round(horizon / HOLD))
    yref = yref[:10 * n_hold + 1]
    u, te = hold_inputs('reversal', horizon, HOLD)
    instants = {}
    for integ in METHODS[1:]:
        mm = mujoco_model(p, dt=1e-4, integrator=integ)
        ctrl = per_step(u - te, 10)
        state, sens = rollout(mm, ctrl)
        iq, iv, ia = state_index(mm)
        y = state[0][:, [iq, iv, ia]]
        tr_state = ode.tau_r(y)                      # force law at the state at t_{k+1}
        tr_sens = ctrl - sens[0, :, 0] + fv * np.concatenate(([0.0], y[:-1, 1]))
        instants[integ] = {'start': float(np.max(np.abs(tr_sens[1:] - tr_state[:-1]))),
                           'end': float(np.max(np.abs(tr_sens - tr_state)))}
    out['sensor_instant'] = instants
    print('  actuatorfrc of step k vs force law at the state at the START of the step: max diff '
          + ', '.join(f'{i} {x["start"]:.1e}' for i, x in instants.items())
          + '; at the END: ' + ', '.join(f'{i} {x["end"]:.1e}' for i, x in instants.items())
          + ' Nm')
    conv = {}
    for dt in (1e-5, 1e-6):
        s = int(round(1e-4 / dt))
        ctrl = per_step(u - te, 10 * s)
        r = run_mujoco(p, ctrl, dt, 'Euler')
        conv[f'mujoco_euler_{dt:g}'] = compare(r, ode, yref, dt, stride=s)
    r = run_ours(p, per_step(u, 100), per_step(te, 100), 1e-5)
    conv['ours_1e-05'] = compare(r, ode, yref, 1e-5, stride=10)
    out['convergence'] = conv
    a, b = conv['mujoco_euler_1e-05'], conv['mujoco_euler_1e-06']
    print(f'  convergence, reversal {horizon:g} s, sigma0 = {p["sigma0"]:g}, sigma1 = '
          f'{p["sigma1"]:.4g}, errors at the 0.1 ms points against Radau:')
    for name, c in conv.items():
        print(f'    {name:20s} q max {c["q_max"]:.2e} m  qd max {c["qd_max"]:.2e} m/s  '
              f'tau_r max {c["tau_r_max"]:.2e} rms {c["tau_r_rms"]:.2e} N')
    out['euler_order'] = math.log10(a['q_max'] / b['q_max'])
    print(f'  MuJoCo Euler q error drops {a["q_max"] / b["q_max"]:.1f}x from dt = 1e-5 to 1e-6 '
          f'(order {out["euler_order"]:.2f}): it integrates the same ODE')
    return out


# ------------------------------------------------------------- timing -------

def best_of(fn, repeat):
    """Best wall time of repeat calls of fn() (after one warm-up call)."""
    fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def timing(*, horizon, horizon_batch, batch, repeat):
    """ns/step of ours and MuJoCo, single instance and batched; prints and returns them."""
    dt = 1.0 / 3000.0
    p = params(1e5, math.sqrt(1e5))
    u, te = hold_inputs('stick-slip', horizon, HOLD)
    m = int(round(HOLD / dt))
    u, te = per_step(u, m), per_step(te, m)
    n = len(u)
    res = {'dt': dt, 'steps_single': n}
    joint = Joint(canudas_gear(p), model='lugre', k_ext=K_SPRING)

    def ours():
        joint.reset()
        return joint.simulate(u, dt, xi=XI, tau_ext=te)
    res['ours'] = 1e9 * best_of(ours, repeat) / n
    res['ours_finite'] = bool(np.all(np.isfinite(ours().q)))
    for integ in METHODS[1:]:
        model = mujoco_model(p, dt=dt, integrator=integ)
        ctrl = u - te
        res[integ] = 1e9 * best_of(lambda model=model, ctrl=ctrl: rollout(model, ctrl),
                                   repeat) / n
        st, _ = rollout(model, ctrl)
        res[f'{integ}_finite'] = bool(np.all(np.isfinite(st)))
    # Python loop over mj_step (informative)
    model = mujoco_model(p, dt=dt, integrator='Euler')
    data = mujoco.MjData(model)
    npy = min(n, 30000)
    ctrl = u - te

    def pyloop():
        mujoco.mj_resetData(model, data)
        for i in range(npy):
            data.ctrl[0] = ctrl[i]
            mujoco.mj_step(model, data)
    res['Euler_python_loop'] = 1e9 * best_of(pyloop, 2) / npy
    # batch: sigma1 spread over [0, 2 sqrt(sigma0 J)], sigma0 = 1e5
    s1s = np.linspace(0.0, 2.0 * math.sqrt(1e5 * J), batch)
    ps = [params(1e5, s1) for s1 in s1s]
    ub, teb = hold_inputs('stick-slip', horizon_batch, HOLD)
    ub, teb = per_step(ub, m), per_step(teb, m)
    nb = len(ub)
    jb = Joint([canudas_gear(q) for q in ps], model='lugre', k_ext=K_SPRING)
    ub2 = np.broadcast_to(ub, (batch, nb))

    def ours_b():
        jb.reset()
        return jb.simulate(ub2, dt, xi=XI, tau_ext=teb)
    res['ours_batched'] = 1e9 * best_of(ours_b, repeat) / (nb * batch)
    models = [mujoco_model(q, dt=dt, integrator='Euler') for q in ps]
    cb = np.broadcast_to(ub - teb, (batch, nb))
    nthread = min(2, os.cpu_count() or 1)
    res['Euler_batched'] = 1e9 * best_of(lambda: rollout(models, cb, nthread=nthread),
                                         repeat) / (nb * batch)
    st, _ = rollout(models, cb, nthread=nthread)
    res['Euler_batched_finite_sets'] = int(np.sum(np.all(np.isfinite(st), axis=(1, 2))))
    res.update(batch=batch, steps_batch=nb, nthread_mujoco=nthread)
    return res


# ------------------------------------------------------------- main ---------

def build_grid(quick):
    """Scenarios (name -> horizon), sigma0 values and per-sigma0 sigma1 lists."""
    if quick:
        horizons = {'stick-slip': 10.0, 'reversal': 2.0}
        s0s = [1e5]
        s1 = {1e5: [x for x in sigma1_grid(1e5) if x[0] in ('0', 'sqrt(s0)', '2sqrt(s0J)')]}
    else:
        horizons = {'stick-slip': 21.0, 'reversal': 4.0}
        s0s = [1e5, 1e7]
        s1 = {s0: sigma1_grid(s0) for s0 in s0s}
    return horizons, s0s, s1


def compute_references(jobs, workers):
    """Run the reference jobs (largest first) in a process pool; dict key -> data."""
    jobs = sorted(jobs, key=lambda j: -(j[2] * (1.0 + math.log10(j[1]['sigma0']))))
    if workers <= 1:
        return dict(map(_reference_job, jobs))
    ctx = multiprocessing.get_context('fork')
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as ex:
        return dict(ex.map(_reference_job, jobs))


def run_grid(refs, horizons, s1s, *, lcm, nums):
    """Run every method at every dt for every reference; one row of errors each."""
    rows = []
    for (scn, s0, s1), ref in sorted(refs.items(), key=lambda kv: (kv[0][0] != 'stick-slip',
                                                                   kv[0][1], kv[0][2])):
        p = params(s0, s1)
        ode = LuGreODE(p, K_SPRING)
        name = next(n for n, v in s1s[s0] if v == s1)
        u, te = hold_inputs(scn, horizons[scn], HOLD)
        for dt in DTS:
            m = int(round(HOLD / dt))
            yref = reference_at(ref, dt, hold=HOLD, lcm=lcm, nums=nums)
            runs = {'ours': run_ours(p, per_step(u, m), per_step(te, m), dt)}
            for integ in METHODS[1:]:
                runs[integ] = run_mujoco(p, per_step(u - te, m), dt, integ)
            err = {k: compare(r, ode, yref, dt, with_onsets=scn == 'stick-slip')
                   for k, r in runs.items()}
            rows.append({'scenario': scn, 'sigma0': s0, 'sigma1': s1, 'sigma1_name': name,
                         'dt': dt, 'err': err,
                         'ref_onsets': onsets_of(dt, yref[1:, 1]) if scn == 'stick-slip'
                         else None})
    return rows


def print_table(rows, methods):
    """Print the work-precision table."""
    w = 8
    labels = {'implicitfast': 'implfast'}
    grp = ' '.join(f'{labels.get(m, m):>{w}s}' for m in methods)
    print(f'{"scenario":10s} {"sigma0":>6s} {"sigma1":>10s} {"dt":>7s} | '
          f'{"slip-onset deviation ms":^{len(grp)}s} | {"tau_r RMS error Nm":^{len(grp)}s} | '
          f'{"q max error m":^{len(grp)}s}')
    print(f'{"":10s} {"":6s} {"":10s} {"":7s} | {grp} | {grp} | {grp}')
    for r in rows:
        cells = []
        for key in ('onset_ms', 'tau_r_rms', 'q_max'):
            cells.append(' '.join(fmt(r['err'][m], key, w) for m in methods))
        dts = '1/3000' if abs(r['dt'] - 1 / 3000) < 1e-12 else f'{r["dt"]:g}'
        print(f'{r["scenario"]:10s} {r["sigma0"]:6.0e} {r["sigma1_name"]:>10s} {dts:>7s} | '
              + ' | '.join(cells))


def acceptance(rows, speed):
    """Check acceptance at dt = 1/3000; print it, return worst_accuracy_ratio, fails, ok."""
    fails = []
    worst = 0.0
    for r in rows:
        if abs(r['dt'] - 1 / 3000) > 1e-12:
            continue
        ours, eul = r['err']['ours'], r['err']['Euler']
        tag = f'{r["scenario"]}/s0={r["sigma0"]:g}/s1={r["sigma1_name"]}'
        for key in ('onset_ms', 'tau_r_rms', 'q_max'):
            a, b = ours[key], eul[key]
            if a is None or b is None:
                continue
            if key != 'q_max' and a > b:
                fails.append(f'{tag} {key} {a:.3g} > {b:.3g}')
            if math.isinf(b):
                ratio = 0.0 if math.isfinite(a) else math.inf
            elif b == 0.0:
                ratio = 0.0 if a == 0.0 else math.inf
            else:
                ratio = a / b
            worst = max(worst, ratio)
    ok_speed = speed['ours'] <= speed['Euler'] / 4.0
    print('acceptance (dt = 1/3000, every sigma0 x sigma1 x scenario): ours onset deviation and '
          'tau_r RMS <= MuJoCo Euler: ' + ('ok' if not fails else f'FAIL ({len(fails)})'))
    for f in fails:
        print(f'  fails: {f}')
    print(f'acceptance speed: ours {speed["ours"]:.1f} ns/step <= MuJoCo Euler '
          f'{speed["Euler"]:.1f} / 4 = {speed["Euler"] / 4:.1f}: '
          + ('ok' if ok_speed else 'FAIL'))
    return worst, fails, ok_speed


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.strip().split('\n')[0])
    ap.add_argument('--quick', action='store_true',
                    help='shorter horizons, sigma0 = 1e5 and 3 sigma1 values only (< 2 min)')
    ap.add_argument('--json', metavar='FILE', help='write all numbers to FILE')
    ap.add_argument('--jobs', type=int, default=2, help='worker processes for the references')
    ap.add_argument('--check-ref', action='store_true',
                    help='recompute one reference at rtol 1e-11 and print the difference')
    args = ap.parse_args(argv)
    if mujoco is None:
        print('bench_mujoco_lugre: mujoco is not importable; install it with '
              '`.venv/bin/python -m pip install -r benchmarks/requirements-bench.txt`')
        return 2
    t_start = time.perf_counter()
    horizons, s0s, s1s = build_grid(args.quick)
    lcm, nums = sample_fractions(HOLD, DTS)
    print(f'MuJoCo {mujoco.__version__}; inputs held over {HOLD * 1e3:g} ms; '
          f'Radau rtol {RTOL:g}; horizons ' + ', '.join(f'{k} {v:g} s'
                                                        for k, v in horizons.items()))
    jobs = [((scn, s0, s1), params(s0, s1), hor, HOLD, lcm, nums, RTOL)
            for scn, hor in horizons.items() for s0 in s0s for _, s1 in s1s[s0]]
    t0 = time.perf_counter()
    refs = compute_references(jobs, args.jobs)
    t_ref = time.perf_counter() - t0
    print(f'references: {len(refs)} Radau runs, {sum(r["nsteps"] for r in refs.values())} '
          f'steps, {t_ref:.0f} s wall ({sum(r["wall"] for r in refs.values()):.0f} s CPU, '
          f'{args.jobs} workers)')
    out = {'mujoco_version': mujoco.__version__, 'hold': HOLD, 'rtol': RTOL,
           'horizons': horizons, 'reference_wall_s': t_ref,
           'reference_steps': {'/'.join(map(str, k)): v['nsteps'] for k, v in refs.items()}}
    if args.check_ref:     # the hardest reference: stick-slip, largest sigma0, sigma1 = 0
        job = max((j for j in jobs if j[0][0] == 'stick-slip' and j[0][2] == 0.0),
                  key=lambda j: j[0][1])
        _, tight = _reference_job(job[:-1] + (RTOL / 10,))
        ode = LuGreODE(job[1], K_SPRING)
        a, b = refs[job[0]]['y'], tight['y']
        dtr = ode.tau_r(a) - ode.tau_r(b)
        out['check_ref'] = {'key': list(job[0]),
                            'q_max': float(np.max(np.abs(a[..., 0] - b[..., 0]))),
                            'qd_max': float(np.max(np.abs(a[..., 1] - b[..., 1]))),
                            'tau_r_max': float(np.max(np.abs(dtr))),
                            'tau_r_rms': float(np.sqrt(np.mean(dtr * dtr)))}
        c = out['check_ref']
        print(f'check-ref {job[0]}: rtol 1e-10 vs 1e-11 (atol / 10): q {c["q_max"]:.1e} m, '
              f'qd {c["qd_max"]:.1e} m/s, tau_r max {c["tau_r_max"]:.1e} rms '
              f'{c["tau_r_rms"]:.1e} N')

    print('\nMuJoCo model verification')
    pv = params(1e5, math.sqrt(1e5))
    out['verification'] = verify_mujoco(pv, refs, lcm=lcm, nums=nums,
                                        horizon=min(2.0, horizons['reversal']))

    t0 = time.perf_counter()
    with CountWarnings() as warn:
        rows = run_grid(refs, horizons, s1s, lcm=lcm, nums=nums)
    t_grid = time.perf_counter() - t0
    print(f'\nwork-precision table (errors against Radau; div = diverged; grid runs '
          f'{t_grid:.0f} s; MuJoCo instability warnings, not printed: {warn.count})')
    print_table(rows, METHODS)

    t0 = time.perf_counter()
    quick = args.quick
    speed = timing(horizon=20.0 if quick else 60.0, horizon_batch=5.0 if quick else 10.0,
                   batch=64, repeat=3)
    t_speed = time.perf_counter() - t0
    print(f'\nspeed, ns/step (dt = 1/3000, stick-slip input, Canudas set; best of several; '
          f'{t_speed:.0f} s)')
    print(f'  single ({speed["steps_single"]} steps): ours {speed["ours"]:.1f}, MuJoCo rollout '
          f'Euler {speed["Euler"]:.1f}, RK4 {speed["RK4"]:.1f}, implicitfast '
          f'{speed["implicitfast"]:.1f}; MuJoCo Euler as a Python loop over mj_step '
          f'{speed["Euler_python_loop"]:.0f}')
    print(f'  finite at the end: ours {speed["ours_finite"]}, Euler {speed["Euler_finite"]}, '
          f'RK4 {speed["RK4_finite"]}, implicitfast {speed["implicitfast_finite"]}')
    print(f'  batched ({speed["batch"]} parameter sets x {speed["steps_batch"]} steps, sigma1 in '
          f'[0, 2 sqrt(sigma0 J)]): ours {speed["ours_batched"]:.1f} (1 thread), MuJoCo Euler '
          f'rollout {speed["Euler_batched"]:.1f} ({speed["nthread_mujoco"]} threads; '
          f'{speed["Euler_batched_finite_sets"]}/{speed["batch"]} sets finite)')
    worst, fails, ok_speed = acceptance(rows, speed)
    total = time.perf_counter() - t_start
    print(f'runtime: references {t_ref:.0f} s, grid {t_grid:.0f} s, speed {t_speed:.0f} s, '
          f'total {total:.0f} s')
    ratio_single = speed['Euler'] / speed['ours']
    ratio_batch = speed['Euler_batched'] / speed['ours_batched']
    out.update(rows=rows, speed=speed, acceptance={'fails': fails, 'speed_ok': ok_speed},
               runtime_s={'references': t_ref, 'grid': t_grid, 'speed': t_speed,
                          'total': total},
               speed_ratio_single=ratio_single, speed_ratio_batched=ratio_batch,
               worst_accuracy_ratio=worst)
    if args.json:
        with open(args.json, 'w', encoding='utf-8') as fh:
            json.dump(out, fh, indent=1, default=float)
    print(f'speed_ratio_single={ratio_single:.2f} speed_ratio_batched={ratio_batch:.2f} '
          f'worst_accuracy_ratio={worst:.3g}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
