# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Identification excitation: the paper's constant-velocity plateaus on the simulated test bed.

The seed paper (Section V-A) identifies the static friction model from
thirty-four constant-velocity points "covering the considered velocity range
over different constant temperatures", denser at low velocity, with the
temperature held within +-0.1 degC during each point, plus low-velocity
pre-sliding experiments for the LuGre/GMS parameters.  :func:`simulate_identification`
runs that experiment on the :class:`~friction_joint.testbed.plant.Plant` (the TRUTH
gear file) and returns the contract topics of a recording; the command
``friction_joint experiment identification --truth T.yaml --out BAG`` writes
them as a rosbag2 MCAP recording for ``friction_joint identify``.

What the experiment does (:data:`EXCITATION` holds the numbers)
-----------------------------------------------------------------
* **Temperature blocks.**  ``n_temperatures`` (4) housing temperatures
  spread over the truth's ``friction.temperature_range`` (1 degC inside the
  low end, 1.5 degC inside the high end, because the gear warms by its own
  losses).  Each block is run on a fresh plant whose thermal ambient and
  initial temperature are set to the block temperature: a *temperature
  chamber*.  The frictional losses still warm the housing a little (a few
  tenths of a degC per block); every plateau is used with its own measured
  mean temperature, so the temperature need not be exactly constant.  The
  blocks follow each other in one recording with a gap of ``gap`` seconds
  (no messages) between them.
* **Plateaus.**  ``n_speeds`` (15) speeds log-spaced over
  ``v_min``..``v_max`` (0.01..3.5 rad/s, output side), each run as a
  back-and-forth pair (+v, then -v over the same stretch) under stiff
  position/velocity control (PD on the ramp reference with inertia and
  lever-gravity feed-forward; see :data:`EXCITATION` ``bandwidth``).  Each
  plateau has ``settle`` seconds to settle and a measuring window of at least
  ``window`` seconds (times ``duration_scale``, at least ``min_window``) that
  covers at least one period of the gear's position ripple (two tooth
  engagements per wave-generator turn: 2 pi / (2 N) rad of output travel), so
  the ripple averages out of the plateau mean.  Fast and slow speeds
  alternate (slowest, fastest, second slowest, ...), so the housing warms in
  short bursts rather than through a long fast stretch.  The temperature
  sensor (lag and 0.0625 degC steps) still reads about 0.1-0.2 degC below
  the gear during the fastest plateaus; at the low end of the range, where
  the viscous part changes fastest with temperature, that is about 1 % of
  the friction torque there -- the largest systematic error of the
  identification on the simulated test bed (the paper kept its temperature
  within +-0.1 degC per point).
* **Load.**  The lever's gravity m g l sin q is the load.  Each pair runs
  centred at one of the lever angles ``centers`` (0, pi/2, -pi/6, -pi/3:
  |sin| = 0, 1, 0.5, 0.87), chosen in a Latin-square pattern over speeds and
  temperature blocks, so every speed is seen at every load level and load
  and velocity are not confounded.  (At the highest speeds a plateau
  travels more than a revolution and the load averages over it.)
* **Pre-sliding.**  At the end of each block the lever hangs at q = 0
  (low load); the joint slides slowly (``presliding_slide`` rad at
  ``presliding_speed``) so the friction state is a known sliding one, and
  then follows small position sinusoids of ``presliding_frequency`` (1 Hz)
  with amplitudes ``presliding_amplitudes`` (0.1..3 mrad: below, around and
  above the pre-sliding deflection F_s / sigma0 of a CSD-25, ~0.2 mrad),
  ``presliding_periods`` periods each.  Every reversal passes through
  pre-sliding.  These segments are for step 3 (pre-sliding parameters,
  :mod:`friction_joint.identification.presliding`) and are ignored by the plateau detection.

Topics: ``/joint_states`` (decimated from the 3 kHz plant to 1 kHz),
``/joint_temperature`` (the plant's 4 Hz sensor), ``/link_torque`` (output
torque sensor), ``/joint_command`` (commanded effort; q_d, qd_d of the
reference).

On hardware
-----------
Run the same pattern (:func:`plan_block` gives the reference of one block)
with the joint's own velocity/position controller, at several housing
temperatures: either in a temperature chamber, or warm the gear by running it
at high speed until the housing reaches the next temperature and record the
block right away (a block of the default plan lasts about a minute; the
housing time constant of a CSD-25 unit is several minutes).  Cover at least
three temperatures for a second-order temperature polynomial (one more than
the highest order asked for), and keep the lever on so the load varies.

``duration_scale`` multiplies the measuring windows and the number of
pre-sliding periods; the temperature blocks, speeds and lever angles stay, so
even a short run has everything the identification needs.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping
import math
from typing import Any, TYPE_CHECKING

import numpy as np

from ._common import check_steps
from ..exceptions import ArgumentError
from ..testbed.plant import Plant

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['EXCITATION', 'BlockPlan', 'plan_block', 'block_temperatures', 'speeds',
           'record_segment', 'segment_topics', 'simulate_identification']

#: the default identification experiment
EXCITATION: dict[str, Any] = {
    'v_min': 0.01,                  # rad/s, slowest plateau
    'v_max': 3.5,                   # rad/s, fastest plateau
    'n_speeds': 15,                 # log-spaced speeds (denser at low velocity)
    'n_temperatures': 4,            # temperature blocks
    'temperature_margin': (1.0, 1.5),   # degC inside the truth's temperature_range (lo, hi)
    'settle': 0.15,                 # s at plateau speed before the measuring window, plus
    'settle_travel': 2e-3,          # ... the time to travel this far (rad): the PD loop's error
                                    #   has to build up the friction torque at low speed
    'window': 1.0,                  # s, nominal measuring window (times duration_scale)
    'min_window': 0.3,              # s, shortest measuring window
    'max_window': 6.0,              # s, longest measuring window (slowest plateaus)
    'ripple_periods': 1,            # measuring window covers >= this many ripple periods
    'accel': 30.0,                  # rad/s^2, peak acceleration of plateau ramps
    'move_accel': 60.0,             # rad/s^2, peak acceleration of positioning moves
    'move_speed': 4.0,              # rad/s, peak speed of positioning moves
    'reverse_pause': 0.05,          # s at rest between the two plateaus of a pair
    'centers': (0.0, math.pi / 2, -math.pi / 6, -math.pi / 3),   # rad, lever angles
    'bandwidth': 200.0,             # rad/s, closed-loop bandwidth (critically damped PD)
    'hold': 0.3,                    # s at rest at the start of each block
    'gap': 1.0,                     # s without messages between blocks
    'presliding_slide': 5e-3,       # rad, slow slide before the pre-sliding sinusoids
    'presliding_speed': 5e-3,       # rad/s, speed of that slide
    'presliding_amplitudes': (1e-4, 3e-4, 1e-3, 3e-3),   # rad, position sinusoids
    'presliding_frequency': 1.0,    # Hz
    'presliding_periods': 2,        # periods per amplitude (times duration_scale, >= 1)
    'publish_rate': 1000.0,         # Hz, /joint_states, /link_torque, /joint_command
}


def speeds(cfg=EXCITATION):
    """Return the plateau speeds, log-spaced from ``v_min`` to ``v_max`` (rad/s)."""
    return np.geomspace(cfg['v_min'], cfg['v_max'], int(cfg['n_speeds']))


def block_temperatures(truth, cfg=EXCITATION):
    """Block temperatures (degC) spread over the truth's temperature range (inside the margins)."""
    lo, hi = truth.friction.temperature_range
    m_lo, m_hi = cfg['temperature_margin']
    a, b = lo + m_lo, hi - m_hi
    if not a < b:
        a = b = 0.5 * (lo + hi)
    n = int(cfg['n_temperatures'])
    return np.linspace(a, b, n) if n > 1 else np.array([0.5 * (a + b)])


class BlockPlan:
    """
    Sampled reference of one temperature block.

    Attributes
    ----------
    dt : float
        Sample period (s).
    q, qd, qdd : ndarray
        Reference position, velocity, acceleration at t = k dt.
    plateaus : list of dict
        Planned plateaus: ``t0``, ``t1`` (measuring window, s), ``v`` (rad/s),
        ``center`` (rad).
    presliding : list of dict
        Pre-sliding sinusoids: ``t0``, ``t1``, ``amplitude`` (rad), ``frequency`` (Hz),
        ``center`` (rad).

    """

    def __init__(self, dt):
        self.dt = dt
        self._parts = []
        self.plateaus = []
        self.presliding = []
        self.q_end = 0.0
        self.n = 0

    @property
    def t_end(self):
        return self.n * self.dt

    def _add(self, q, qd, qdd):
        self._parts.append((q, qd, qdd))
        self.n += len(q)
        if len(q):
            self.q_end = float(q[-1])

    def _times(self, duration):
        # the whole plan so far and this segment: checked before np.arange allocates it
        check_steps(self.n * self.dt + duration, self.dt, 'an excitation plan')
        m = max(1, int(round(duration / self.dt)))
        return self.dt * np.arange(1, m + 1), m * self.dt

    def hold(self, duration):
        t, _ = self._times(duration)
        z = np.zeros_like(t)
        self._add(self.q_end + z, z, z)

    def move(self, target, accel, vmax):
        """Minimum-jerk point-to-point move to ``target`` (rad)."""
        d = target - self.q_end
        if abs(d) < 1e-12:
            return
        T = max(0.2, math.sqrt(5.7735 * abs(d) / accel), 1.875 * abs(d) / vmax)
        t, T = self._times(T)
        s = t / T
        q0 = self.q_end
        self._add(q0 + d * (10 * s**3 - 15 * s**4 + 6 * s**5),
                  d / T * (30 * s**2 - 60 * s**3 + 30 * s**4),
                  d / T**2 * (60 * s - 180 * s**2 + 120 * s**3))

    def ramp(self, v0, v1, accel):
        """Velocity blend v0 -> v1 with a half-cosine profile (peak acceleration ``accel``)."""
        T = max(0.05, math.pi * abs(v1 - v0) / (2.0 * accel))
        t, T = self._times(T)
        dv = v1 - v0
        w = math.pi / T
        q0 = self.q_end
        self._add(q0 + v0 * t + 0.5 * dv * (t - np.sin(w * t) / w),
                  v0 + 0.5 * dv * (1.0 - np.cos(w * t)),
                  0.5 * dv * w * np.sin(w * t))

    def constant(self, v, duration):
        t, T = self._times(duration)
        q0 = self.q_end
        self._add(q0 + v * t, np.full_like(t, v), np.zeros_like(t))
        return T

    def sine(self, amplitude, frequency, periods):
        """Position sinusoid q_end + a sin(2 pi f t) over whole periods."""
        t, T = self._times(periods / frequency)
        w = 2.0 * math.pi * frequency
        t0, c = self.t_end, self.q_end
        self._add(c + amplitude * np.sin(w * t), amplitude * w * np.cos(w * t),
                  -amplitude * w * w * np.sin(w * t))
        self.presliding.append({'t0': t0, 't1': t0 + T, 'amplitude': amplitude,
                                'frequency': frequency, 'center': c})

    def arrays(self):
        """``(q, qd, qdd)`` of the whole block, with the state at t = 0 first."""
        return tuple(np.concatenate([np.zeros(1)] + [p[i] for p in self._parts])
                     for i in range(3))


def _window(v, gear_ratio, scale, cfg):
    ripple = 2.0 * math.pi / (2.0 * gear_ratio)            # output travel per ripple period
    w = float(max(cfg['window'], cfg['ripple_periods'] * ripple / abs(v)))
    return float(np.clip(w * scale, cfg['min_window'], cfg['max_window']))


def plan_block(index, gear_ratio, dt, duration_scale=1.0, cfg=EXCITATION, presliding=True):
    """
    Plan the reference of temperature block ``index`` (see the module docstring).

    Parameters
    ----------
    index : int
        Block number; selects the lever angles of the Latin-square pattern.
    gear_ratio : float
        Sets the ripple period the measuring windows cover.
    dt : float
        Sample period (s).
    duration_scale : float
        Multiplies the measuring windows and pre-sliding periods.
    cfg : dict
        The excitation settings, all keys of :data:`EXCITATION` (the default).
    presliding : bool
        Append the pre-sliding slide and sinusoids.

    Returns
    -------
    BlockPlan

    """
    plan = BlockPlan(dt)
    plan.hold(cfg['hold'])
    centers = cfg['centers']
    accel, amove, vmove = cfg['accel'], cfg['move_accel'], cfg['move_speed']
    vs = speeds(cfg)
    for i in _interleaved(len(vs)):
        v = vs[i]
        c = centers[(i + index) % len(centers)]
        window = _window(v, gear_ratio, duration_scale, cfg)
        settle = cfg['settle'] + cfg['settle_travel'] / v
        t_ramp = max(0.05, math.pi * v / (2.0 * accel))
        travel = v * (settle + window) + v * t_ramp           # plateau + both ramp halves
        start = c - 0.5 * travel
        # nearest equivalent of the start angle (the lever's gravity is 2 pi periodic)
        start += 2.0 * math.pi * round((plan.q_end - start) / (2.0 * math.pi))
        plan.move(start, amove, vmove)
        for direction in (1.0, -1.0):
            plan.ramp(0.0, direction * v, accel)
            t0 = plan.t_end + settle
            plan.constant(direction * v, settle + window)
            plan.plateaus.append({'t0': t0, 't1': plan.t_end, 'v': direction * v, 'center': c})
            plan.ramp(direction * v, 0.0, accel)
            plan.hold(cfg['reverse_pause'])
    if presliding:
        slide, v = cfg['presliding_slide'], cfg['presliding_speed']
        home = 2.0 * math.pi * round(plan.q_end / (2.0 * math.pi))
        plan.move(home - slide, amove, vmove)
        plan.hold(cfg['hold'])
        plan.ramp(0.0, v, accel)
        plan.constant(v, max(0.0, slide / v - max(0.05, math.pi * v / (2.0 * accel))))
        periods = cfg['presliding_periods'] * duration_scale
        check_steps(plan.t_end + periods * len(cfg['presliding_amplitudes'])
                    / cfg['presliding_frequency'], dt, 'an excitation plan')
        periods = max(1, int(round(periods)))
        for amp in cfg['presliding_amplitudes']:
            plan.sine(amp, cfg['presliding_frequency'], periods)
        plan.hold(cfg['hold'])
    return plan


def _interleaved(n):
    """
    Return the plateau order 0, n-1, 1, n-2, ... for n plateaus.

    Fast and slow plateaus alternate, so the housing warms in short bursts and
    the lagging temperature sensor stays close to the gear.
    """
    lo, hi = 0, n - 1
    out = []
    while lo <= hi:
        out.append(lo)
        if hi != lo:
            out.append(hi)
        lo, hi = lo + 1, hi - 1
    return out


def _gains(inertia, bandwidth):
    """Critically damped PD: kp = J w^2, kd = 2 J w."""
    return inertia * bandwidth ** 2, 2.0 * inertia * bandwidth


def segment_topics(cat, temp_t, temp_xi, gear):
    """Return ``/joint_states`` and ``/joint_temperature`` of joined recorded segments."""
    return {
        '/joint_states': {'t': cat['t'], 'q': cat['q'], 'qd': cat['qd'],
                          'effort': cat['effort'], 'name': gear.joint_name},
        '/joint_temperature': {'t': np.concatenate(temp_t), 'xi': np.concatenate(temp_xi),
                               'variance': gear.section('sensors')[
                                   'temperature_resolution'] ** 2 / 12.0},
    }


def record_segment(plant, command, q_ref, qd_ref, every, t_off, *, out, temp_t, temp_xi):
    """
    Run ``plant`` closed loop over a reference and append the measured record.

    ``command(sample, k) -> tau`` is the control law for step k.  Appends to
    ``out`` (lists per key: t, q, qd, effort, tau (link torque), cmd, q_d,
    qd_d; decimated by ``every``, times shifted by ``t_off``) and to the
    temperature sample lists ``temp_t``, ``temp_xi``.
    """
    n = len(q_ref)
    rec = {k: np.empty(n) for k in ('t', 'q', 'qd', 'effort', 'tau', 'cmd')}
    s = plant.last
    tt, tx = [s.t], [s.xi]
    step = plant.step
    for k in range(n):
        cmd = command(s, k)
        rec['t'][k] = s.t
        rec['q'][k] = s.q
        rec['qd'][k] = s.qd
        rec['effort'][k] = s.effort
        rec['tau'][k] = s.tau_link
        rec['cmd'][k] = cmd
        s = step(cmd)
        if s.xi_new:
            tt.append(s.t)
            tx.append(s.xi)
    sel = slice(0, n, every)
    for key in ('t', 'q', 'qd', 'effort', 'tau', 'cmd'):
        out[key].append(rec[key][sel] + (t_off if key == 't' else 0.0))
    out['q_d'].append(q_ref[sel])
    out['qd_d'].append(qd_ref[sel])
    temp_t.append(np.asarray(tt) + t_off)
    temp_xi.append(np.asarray(tx))


def simulate_identification(truth: GearParams, *, duration_scale: float = 1.0,
                            seed: int | None = None, cfg: Mapping[str, Any] | None = None,
                            presliding: bool = True,
                            progress: Callable[[str], None] | None = None,
                            ) -> tuple[dict[str, dict[str, Any]], dict[str, Any]]:
    """
    Run the identification excitation on the simulated test bed.

    Parameters
    ----------
    truth : GearParams
        The simulated hardware (friction, lever, thermal, sensors, simulation).
    duration_scale : float
        Multiplies the plateau measuring windows (at least ``min_window``) and the
        pre-sliding periods.
    seed : int, optional
        Noise seed (default ``simulation.seed``); block k uses seed + k.
    cfg : dict, optional
        Overrides of :data:`EXCITATION` entries.
    presliding : bool
        Include the pre-sliding slide and sinusoids.
    progress : callable, optional
        ``progress(message)`` is called once per block.

    Returns
    -------
    topics : dict
        Topic -> dict of arrays, the input of :func:`friction_joint.bag.write_recording`.
    summary : dict
        Plan and run facts: block temperatures, planned plateaus (times in the
        recording), pre-sliding segments, duration, gains, velocity range.

    """
    conf = dict(EXCITATION)
    if cfg:
        unknown = sorted(set(cfg) - set(EXCITATION))
        if unknown:
            raise ArgumentError(f'unknown excitation option(s) {", ".join(unknown)}; '
                                f'known: {", ".join(EXCITATION)}')
        conf.update(cfg)
    scale = float(duration_scale)
    if not (math.isfinite(scale) and scale > 0):
        raise ArgumentError(f'duration scale must be a finite number > 0, '
                            f'got {duration_scale}')
    sim = truth.section('simulation')
    sens = truth.section('sensors')
    assert sim is not None and sens is not None  # a section with defaults
    rate = sim['rate']
    dt = 1.0 / rate
    every = max(1, int(round(rate / conf['publish_rate'])))
    seed0 = sim['seed'] if seed is None else int(seed)
    J, lever = truth.inertia, truth.lever_torque
    kp, kd = _gains(J, conf['bandwidth'])
    temps = block_temperatures(truth, conf)

    out: dict[str, list[np.ndarray]] = {k: [] for k in ('t', 'q', 'qd', 'effort', 'tau', 'cmd',
                                                        'q_d', 'qd_d')}
    temp_t: list[np.ndarray] = []
    temp_xi: list[np.ndarray] = []
    plateaus, pres, blocks = [], [], []
    t_off = 0.0
    for b, xi0 in enumerate(temps):
        plan = plan_block(b, truth.gear_ratio, dt, scale, conf, presliding)
        q_ref, qd_ref, qdd_ref = plan.arrays()
        gear = truth.replace({'thermal': {'ambient': float(xi0), 'initial': float(xi0)}})
        plant = Plant(gear, xi0=float(xi0), seed=seed0 + b, q0=0.0)
        record_segment(plant, lambda s, k, q_ref=q_ref, qd_ref=qd_ref, qdd_ref=qdd_ref: (
                           J * qdd_ref[k] + kp * (q_ref[k] - s.q) + kd * (qd_ref[k] - s.qd)
                           + lever(s.q)),
                       q_ref, qd_ref, every, t_off, out=out, temp_t=temp_t, temp_xi=temp_xi)
        plateaus += [dict(p, t0=p['t0'] + t_off, t1=p['t1'] + t_off, block=b)
                     for p in plan.plateaus]
        pres += [dict(p, t0=p['t0'] + t_off, t1=p['t1'] + t_off, block=b) for p in plan.presliding]
        blocks.append({'temperature': float(xi0), 't0': t_off, 't1': t_off + plan.t_end,
                       'xi_end': float(plant.thermal.xi)})
        if progress:
            progress(f'block {b + 1}/{len(temps)}: {xi0:.1f} degC, {plan.t_end:.1f} s simulated, '
                     f'housing {xi0:.2f} -> {plant.thermal.xi:.2f} degC')
        t_off += plan.t_end + conf['gap']

    cat = {k: np.concatenate(v) for k, v in out.items()}
    topics = {
        '/joint_states': {'t': cat['t'], 'q': cat['q'], 'qd': cat['qd'], 'effort': cat['effort'],
                          'name': truth.joint_name},
        '/joint_temperature': {'t': np.concatenate(temp_t), 'xi': np.concatenate(temp_xi),
                               'variance': sens['temperature_resolution'] ** 2 / 12.0},
        '/link_torque': {'t': cat['t'], 'tau': cat['tau']},
        '/joint_command': {'t': cat['t'], 'effort': cat['cmd'], 'q_d': cat['q_d'],
                           'qd_d': cat['qd_d'], 'name': truth.joint_name},
    }
    summary = {'experiment': 'identification', 'duration_scale': scale,
               'temperatures': [float(x) for x in temps], 'blocks': blocks,
               'speeds': [float(v) for v in speeds(conf)], 'plateaus': plateaus,
               'presliding': pres, 'duration_s': float(cat['t'][-1] - cat['t'][0]),
               'samples': int(len(cat['t'])), 'gains': {'kp': kp, 'kd': kd},
               'seed': seed0}
    return topics, summary
