# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Plants and plateau excitations drawn at random, for checking the identification.

One truth file is not evidence: :func:`draw_identification_case` draws a joint
(static curve, temperature and load dependency, inertia, lever, LuGre or GMS
pre-sliding, sensors) from continuous ranges (:data:`JOINT_RANGES`) and a
plateau excitation (speed set, plateau length and order, recording rate,
encoder, noise, temperature ramp, load range, with or without a load sensor:
:data:`EXCITATION_RANGES`; plateaus in both directions, or with ``one_direction`` in
one drawn direction only); :func:`simulate_case` runs it on the simulated test
bed (:class:`~friction_joint.testbed.plant.Plant`) and returns the contract
topics of a recording, stamped at a wall-clock epoch as a robot's logger
stamps them.  ``benchmarks/bench_identify.py --plants N`` and the
identification tests use them.

The structure file a case comes with (``IdentificationCase.structure``) is
what a user would give ``identify``: the truth's structure (fc, fs, fv linear
in temperature, vs and delta_v constant, fc and fs linear in load), inertia
and lever within a few percent, and prior coefficient values that are off by
tens of percent (v_s by up to a factor of three, delta_s the common 2).
"""
from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from ..gear import gear_from_dict, GearParams

__all__ = ['JOINT_RANGES', 'EXCITATION_RANGES', 'IdentificationCase', 'draw_identification_case',
           'simulate_case', 'plan_case', 'draw_plateaus']

#: the joints drawn (uniform unless marked log-uniform)
JOINT_RANGES = {
    'fc': (0.3, 6.0),              # Nm at the mid temperature, log-uniform
    'fs_ratio': (1.0, 1.8),        # F_s / F_c
    'vs': (0.005, 0.3),            # rad/s (output side), log-uniform
    'delta_s': (0.5, 2.5),
    'viscous_ratio': (0.2, 3.0),   # F_v |v_max|^delta_v / F_c, log-uniform
    'delta_v': (0.4, 1.2),
    'fc_temp': (-0.025, 0.01),     # relative change of F_c per degC
    'fs_temp': (-0.025, 0.01),
    'fv_temp': (-0.03, -0.002),    # viscous friction falls as the lubricant warms
    'fc_load': (0.0, 0.04),        # Nm of F_c per Nm of load (F_s's: F_s / F_c x 1-1.3 x it)
    'inertia': (0.05, 0.5),        # kg m^2, log-uniform
    'stiffness': (5e3, 5e4),       # Nm/rad pre-sliding stiffness (sigma0, sum of GMS k), log
    'sigma1_ratio': (0.1, 0.8),    # LuGre sigma1 / its passivity bound
}

#: the excitations drawn
EXCITATION_RANGES = {
    'v_low': (0.004, 0.06),        # rad/s slowest plateau, log-uniform
    'v_high': (1.0, 4.0),          # rad/s fastest plateau
    'n_speeds': (6, 11),           # distinct speeds (integers, inclusive)
    'plateau': (1.5, 3.0),         # s at each plateau
    'ramp': (0.1, 0.3),            # s ramps in and out of a plateau
    'repetitions': (1, 2),         # each signed speed (integers, inclusive)
    'rate': (250.0, 3000.0),       # Hz joint-state rate (the plant runs at 3 kHz), log
    'encoder_bits': (14, 25),      # integers, inclusive
    'noise_scale': (0.3, 3.0),     # sensor noise relative to the CSD-25 test bed, log
    'xi_start': (18.0, 32.0),      # degC
    'xi_rise': (0.0, 15.0),        # degC over the recording (temperature only rises)
    'mgl': (0.0, 15.0),            # Nm lever gravity (the load range)
    'bandwidth': (40.0, 200.0),    # rad/s position loop
    'link_sensor': 0.6,            # probability of a /link_torque sensor
    'gms': 0.4,                    # probability of GMS (else LuGre) hardware
    'epoch': (1.5e9, 1.9e9),       # s, the stamps' epoch
}

_BASE: dict[str, Any] = {
    'joint_name': 'joint', 'gear_ratio': 100.0,
    'thermal': {'capacity': 450.0, 'resistance': 1.2, 'ambient': 25.0},
    'sensors': {'velocity_cutoff': 250.0, 'current_bandwidth': 800.0, 'torque_noise': 0.01,
                'effort_noise': 0.005, 'temperature_resolution': 0.0625,
                'temperature_time_constant': 4.0, 'link_torque_noise': 0.03},
    'simulation': {'rate': 3000.0, 'temperature_rate': 4.0, 'seed': 0},
}


@dataclasses.dataclass(frozen=True)
class IdentificationCase:
    """
    One drawn joint, its plateau excitation and the structure file a user would give.

    Attributes
    ----------
    seed : int
        The draw's seed.
    truth : GearParams
        The simulated hardware.
    structure : GearParams
        The structure file for ``identify``.
    speeds : tuple of float
        Signed plateau speeds in the order run (rad/s).
    plateau, ramp : float
        Seconds at each plateau, seconds of each ramp.
    rate : float
        Joint-state rate (Hz).
    xi_start, xi_end : float
        Housing temperature at the start and (about) the end (degC).
    centers : tuple of float
        Lever angle at the middle of each plateau (rad).
    link_sensor : bool
        The recording has ``/link_torque``.
    bandwidth : float
        Position loop bandwidth (rad/s).
    epoch : float
        Wall-clock time of the first sample (s).
    direction : int
        0: plateaus in both directions; +1 or -1: in that direction only.

    """

    seed: int
    truth: GearParams
    structure: GearParams
    speeds: tuple
    plateau: float
    ramp: float
    rate: float
    xi_start: float
    xi_end: float
    centers: tuple
    link_sensor: bool
    bandwidth: float
    epoch: float
    direction: int = 0

    def describe(self) -> dict:
        """Return the drawn truth and excitation as plain JSON types."""
        f = self.truth.friction
        sensors = self.truth.section('sensors')
        # a section with defaults; every drawn truth has a Stribeck curve
        assert sensors is not None and f.fs is not None and f.vs is not None
        return {'seed': self.seed, 'model': f.model, 'fc': list(f.fc), 'fs': list(f.fs),
                'fv': list(f.fv), 'vs': list(f.vs), 'delta_v': list(f.delta_v),
                'delta_s': f.delta_s, 'fc_load': list(f.fc_load), 'fs_load': list(f.fs_load),
                'inertia': self.truth.inertia, 'mgl': self.truth.mgl,
                'speeds': sorted({round(abs(v), 6) for v in self.speeds}),
                'plateau_s': self.plateau, 'rate_hz': self.rate,
                'encoder_bits': sensors['encoder_bits'],
                'xi': [self.xi_start, self.xi_end], 'link_sensor': self.link_sensor,
                'bandwidth': self.bandwidth, 'epoch': self.epoch, 'direction': self.direction}


def _u(rng, lo_hi, log=False):
    lo, hi = lo_hi
    if log:
        return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))
    return float(rng.uniform(lo, hi))


def _linear(value, slope, xm):
    """Coefficients (powers 0, 1 of xi) of value (1 + slope (xi - xm))."""
    return [value * (1.0 - slope * xm), value * slope]


def draw_identification_case(seed: int, *, plant_ranges: dict | None = None,
                             excitation_ranges: dict | None = None,
                             one_direction: bool = False) -> IdentificationCase:
    """
    Draw a joint and its plateau excitation (see the module docstring).

    Parameters
    ----------
    seed : int
        Seed of the draw.
    plant_ranges, excitation_ranges : dict, optional
        Overrides of :data:`JOINT_RANGES` and :data:`EXCITATION_RANGES` entries.
    one_direction : bool
        Every plateau in one direction (drawn, positive or negative; each speed run as
        often as both directions would run it), the moves between them and the slow
        slide too, and no pre-sliding reversals.  The rest of the draw is the
        two-direction draw of the same seed.

    Returns
    -------
    IdentificationCase

    """
    pr = dict(JOINT_RANGES, **(plant_ranges or {}))
    er = dict(EXCITATION_RANGES, **(excitation_ranges or {}))
    rng = np.random.default_rng([7919, int(seed)])
    xi0 = _u(rng, er['xi_start'])
    xi1 = xi0 + _u(rng, er['xi_rise'])
    xm = 0.5 * (xi0 + xi1)
    v_low = _u(rng, er['v_low'], log=True)
    v_high = _u(rng, er['v_high'])
    fc = _u(rng, pr['fc'], log=True)
    fs = fc * _u(rng, pr['fs_ratio'])
    vs = _u(rng, pr['vs'], log=True)
    ds = _u(rng, pr['delta_s'])
    dv = _u(rng, pr['delta_v'])
    fv = fc * _u(rng, pr['viscous_ratio'], log=True) / v_high ** dv
    fc_t, fs_t, fv_t = (_u(rng, pr[k]) for k in ('fc_temp', 'fs_temp', 'fv_temp'))
    mgl = _u(rng, er['mgl'])
    fc_l = _u(rng, pr['fc_load'])
    fs_l = fc_l * fs / fc * _u(rng, (1.0, 1.3))
    inertia = _u(rng, pr['inertia'], log=True)
    length = 0.15
    stiff = _u(rng, pr['stiffness'], log=True)
    model = 'gms' if rng.uniform() < er['gms'] else 'lugre'
    lo_t, hi_t = xi0 - 3.0, xi1 + 3.0
    # a physical truth: F_s >= F_c at every temperature and load of the recording (else
    # F_s follows F_c's relative temperature slope)
    if min(fs * (1 + fs_t * (x - xm)) - fc * (1 + fc_t * (x - xm)) for x in (lo_t, hi_t)) < 0:
        fs_t = fc_t
    # sigma1 below its passivity bound at every temperature (LuGre)
    fv_min = min(fv * (1.0 + fv_t * (x - xm)) for x in (lo_t, hi_t))
    sigma1 = _u(rng, pr['sigma1_ratio']) * max(fv_min, 1e-3) * max(v_high, 1.0)
    k_split = np.array([0.6, 0.25, 0.1, 0.05])
    friction = {
        'model': model,
        'fc': _linear(fc, fc_t, xm), 'fs': _linear(fs, fs_t, xm),
        'fv': _linear(fv, fv_t, xm), 'vs': [vs], 'delta_v': [dv], 'delta_s': ds,
        'fc_load': [fc_l], 'fs_load': [fs_l],
        'fv_load': [], 'velocity_scale': 1.0, 'temperature_range': [lo_t, hi_t],
        'lugre': {'sigma0': stiff, 'sigma1': sigma1},
        'gms': {'k': [float(x) for x in stiff * k_split], 'c': _u(rng, (100.0, 800.0))},
        'position_ripple': {'cycles_per_rev': 200.0, 'amplitude': [0.01 * fc], 'phase': [0.3]},
    }
    noise = _u(rng, er['noise_scale'], log=True)
    base = _BASE['sensors']
    sensors = dict(base, encoder_bits=int(rng.integers(er['encoder_bits'][0],
                                                       er['encoder_bits'][1] + 1)),
                   torque_noise=base['torque_noise'] * noise,
                   effort_noise=base['effort_noise'] * noise,
                   link_torque_noise=base['link_torque_noise'] * noise)
    rate = _u(rng, er['rate'], log=True)
    every = max(1, int(round(3000.0 / rate)))
    n_speeds = int(rng.integers(er['n_speeds'][0], er['n_speeds'][1] + 1))
    grid = np.geomspace(v_low, v_high, n_speeds)
    jitter = np.exp(rng.uniform(-0.1, 0.1, n_speeds))
    mags = grid * jitter
    mags[0], mags[-1] = v_low, v_high
    reps = int(rng.integers(er['repetitions'][0], er['repetitions'][1] + 1))
    # one direction: drawn aside, so the rest of the draw is the two-direction one
    direction = int(np.random.default_rng([7919, int(seed), 1]).choice([-1, 1])) \
        if one_direction else 0
    signed = [(direction or s) * v for v in mags for s in (1.0, -1.0) for _ in range(reps)]
    order = rng.permutation(len(signed))
    speeds = tuple(float(signed[i]) for i in order)
    centers = tuple(float(rng.uniform(-math.pi, math.pi)) for _ in speeds)
    plateau = _u(rng, er['plateau'])
    ramp = _u(rng, er['ramp'])
    duration = len(speeds) * (plateau + 2 * ramp + 2.0)
    # the housing heats from xi0 towards an ambient above xi1: xi1 at the end
    tau_th = duration
    ambient = xi0 + (xi1 - xi0) / (1.0 - math.exp(-1.0))
    truth = gear_from_dict({
        'joint_name': _BASE['joint_name'], 'gear_ratio': _BASE['gear_ratio'],
        'inertia': inertia, 'friction': friction,
        'lever': {'mass': mgl / (9.81 * length), 'length': length},
        'thermal': {'capacity': 450.0, 'resistance': tau_th / 450.0, 'ambient': ambient,
                    'initial': xi0},
        'sensors': sensors,
        'simulation': {'rate': 3000.0, 'temperature_rate': 4.0, 'seed': int(seed) % 100000},
    }, source=f'drawn plant {seed}')
    prior = {
        'fc': _linear(fc * _u(rng, (0.7, 1.4)), 0.0, xm)[:1] + [0.0],
        'fs': _linear(fs * _u(rng, (0.7, 1.4)), 0.0, xm)[:1] + [0.0],
        'fv': _linear(fv * _u(rng, (0.7, 1.4)), 0.0, xm)[:1] + [0.0],
        'vs': [vs * _u(rng, (1.0 / 3.0, 3.0), log=True)],
        'delta_v': [min(1.5, dv * _u(rng, (0.8, 1.25)))], 'delta_s': 2.0,
        'fc_load': [0.0], 'fs_load': [0.0], 'fv_load': [],
        'velocity_scale': 1.0, 'temperature_range': [0.0, 100.0], 'model': model,
        'lugre': {'sigma0': stiff * _u(rng, (0.5, 2.0), log=True),
                  'sigma1': sigma1 * _u(rng, (0.5, 2.0), log=True)},
        'gms': {'k': [float(x) for x in stiff * _u(rng, (0.5, 2.0), log=True) * k_split],
                'c': friction['gms']['c'] * _u(rng, (0.5, 2.0), log=True)},
    }
    structure = gear_from_dict({
        'joint_name': _BASE['joint_name'], 'gear_ratio': _BASE['gear_ratio'],
        'inertia': inertia * _u(rng, (0.9, 1.1)), 'friction': prior,
        'lever': {'mass': mgl / (9.81 * length) * _u(rng, (0.97, 1.03)), 'length': length},
    }, source=f'structure of drawn plant {seed}')
    return IdentificationCase(
        seed=int(seed), truth=truth, structure=structure, speeds=speeds, plateau=plateau,
        ramp=ramp, rate=3000.0 / every, xi_start=xi0, xi_end=xi1, centers=centers,
        link_sensor=bool(rng.uniform() < er['link_sensor']),
        bandwidth=_u(rng, er['bandwidth']), epoch=_u(rng, er['epoch']), direction=direction)


def _turns(offset, direction):
    """
    Return the whole turns to add to reach an angle ``offset`` behind the plan's end.

    Both directions: the nearest; one direction: the nearest ahead in that direction (the
    joint never runs the other way, not even between plateaus).
    """
    turn = 2.0 * math.pi
    if not direction:
        return turn * round(offset / turn)
    return direction * turn * math.ceil(direction * offset / turn)


def plan_case(case: IdentificationCase, dt: float):
    """
    Return the reference ``(q, qd, qdd)`` of a case's excitation and its plateau windows.

    Each plateau: a move to where the plateau's middle passes the lever angle
    ``centers[i]`` (one ``direction``: forward, by whole turns if need be), a half-cosine
    ramp to the speed, ``plateau`` seconds at it, a ramp to rest, a short hold; then slow
    pre-sliding sinusoids for step 3 (not in one direction: no reversal at all).
    """
    from .excitation import BlockPlan
    plan = BlockPlan(dt)
    plan.hold(0.3)
    windows = []
    for v, c in zip(case.speeds, case.centers, strict=True):
        accel = max(abs(v) * math.pi / (2.0 * case.ramp), 1e-3)
        travel = abs(v) * (case.plateau + case.ramp)
        start = c - math.copysign(0.5 * travel, v)
        start += _turns(plan.q_end - start, case.direction)
        plan.move(start, 30.0, 3.0)
        plan.ramp(0.0, v, accel)
        t0 = plan.t_end
        plan.constant(v, case.plateau)
        windows.append((t0, plan.t_end, v))
        plan.ramp(v, 0.0, accel)
        plan.hold(0.1)
    home = 2.0 * math.pi * round(plan.q_end / (2.0 * math.pi))
    if case.direction:                               # the next whole turn ahead
        d = case.direction
        home = d * 2.0 * math.pi * math.ceil(d * plan.q_end / (2.0 * math.pi))
    slide = 5e-3 * (case.direction or 1)             # the slow slide in the plateaus' direction
    plan.move(home - slide, 30.0, 3.0)
    plan.hold(0.3)
    plan.ramp(0.0, slide, 1.0)
    plan.constant(slide, 0.9)
    for amp in (1e-4, 3e-4, 1e-3, 3e-3) if not case.direction else ():
        plan.sine(amp, 1.0, 2)                       # reversals: not in one direction
    plan.hold(0.3)
    q, qd, qdd = plan.arrays()
    return q, qd, qdd, windows


def simulate_case(case: IdentificationCase) -> dict:
    """
    Run a case's excitation on the simulated test bed.

    Returns
    -------
    dict
        Topic -> arrays, the input of :func:`friction_joint.bag.write_recording`
        (``/joint_states``, ``/joint_temperature``, ``/joint_command``, and
        ``/link_torque`` when the case has a load sensor), stamped from ``case.epoch``.

    """
    from .excitation import record_segment
    from ..testbed.plant import Plant
    truth = case.truth
    sim = truth.section('simulation')
    assert sim is not None  # a section with defaults
    dt = 1.0 / sim['rate']
    every = max(1, int(round(sim['rate'] / case.rate)))
    q_ref, qd_ref, qdd_ref, _ = plan_case(case, dt)
    J, lever = truth.inertia, truth.lever_torque
    w = case.bandwidth
    kp, kd = J * w * w, 2.0 * J * w
    plant = Plant(truth, xi0=case.xi_start, q0=0.0)
    out: dict[str, list[np.ndarray]] = {k: [] for k in ('t', 'q', 'qd', 'effort', 'tau', 'cmd',
                                                        'q_d', 'qd_d')}
    temp_t: list[np.ndarray] = []
    temp_xi: list[np.ndarray] = []
    record_segment(plant, lambda s, k: (J * qdd_ref[k] + kp * (q_ref[k] - s.q)
                                        + kd * (qd_ref[k] - s.qd) + lever(s.q)),
                   q_ref, qd_ref, every, case.epoch, out=out, temp_t=temp_t, temp_xi=temp_xi)
    cat = {k: np.concatenate(v) for k, v in out.items()}
    sens = truth.section('sensors')
    assert sens is not None  # a section with defaults
    topics = {
        '/joint_states': {'t': cat['t'], 'q': cat['q'], 'qd': cat['qd'],
                          'effort': cat['effort'], 'name': truth.joint_name},
        '/joint_temperature': {'t': np.concatenate(temp_t), 'xi': np.concatenate(temp_xi),
                               'variance': sens['temperature_resolution'] ** 2 / 12.0},
        '/joint_command': {'t': cat['t'], 'effort': cat['cmd'], 'q_d': cat['q_d'],
                           'qd_d': cat['qd_d'], 'name': truth.joint_name},
    }
    if case.link_sensor:
        topics['/link_torque'] = {'t': cat['t'], 'tau': cat['tau']}
    return topics


def draw_plateaus(case: IdentificationCase, *, noise: float = 0.002, seed: int = 0):
    """
    Plateau data points of a case straight from its truth's static curve, with noise.

    No time simulation: each signed speed of the case becomes one plateau per
    repetition, at a temperature rising linearly from ``xi_start`` to ``xi_end`` in the
    order run and a load ``|m g l sin(center)|``; the friction torque is the truth's
    static curve plus Gaussian noise of ``noise`` x F_c; tau_ext counts as measured
    (``torque_source`` ``'link_torque'``) when the case has a load sensor.  For checking
    the fit itself
    (fast); :func:`simulate_case` checks everything from the recording on.

    Parameters
    ----------
    case : IdentificationCase
        The drawn joint and excitation.
    noise : float
        Noise standard deviation relative to F_c at the mid temperature.
    seed : int
        Noise seed.

    Returns
    -------
    Plateaus

    """
    from ..identification.plateaus import Plateaus
    from ..models.static import StaticFriction
    rng = np.random.default_rng([104729, int(seed)])
    qd = np.array(case.speeds)
    k = np.arange(len(qd))
    xi = case.xi_start + (case.xi_end - case.xi_start) * k / max(len(qd) - 1, 1)
    load = np.abs(case.truth.mgl * np.sin(np.array(case.centers)))
    model = StaticFriction(case.truth.friction)
    tau = model.torque(qd, xi, load)
    fc = float(model.parameters(np.array([0.5 * (case.xi_start + case.xi_end)]))['fc'][0])
    sigma = noise * fc
    tau = tau + sigma * rng.standard_normal(len(qd))
    t0 = case.epoch + k * (case.plateau + 2 * case.ramp + 2.0)
    return Plateaus.from_arrays(qd, tau, xi, load=load, tau_r_se=np.full(len(qd), sigma),
                                t0=t0, t1=t0 + case.plateau, n=1000,
                                sources=(f'drawn plant {case.seed}',),
                                torque_source=('link_torque' if case.link_sensor else 'given',))
