# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A simulated robot fleet: one recording per joint and day, some joints wearing.

:func:`draw_fleet` plans what a fleet's log collection would hold
(docs/fleet.md), :func:`fleet_recording` simulates one joint-day's topics,
:func:`manifest_rows` gives the manifest's rows (``recording``, ``joint``,
``time``, ``travel``: the joint's odometer, rad of output travel, as a robot
controller counts it) and :func:`fleet_truth` the truth.  Nothing is written
here: :func:`friction_joint.jobs.fleet_simulation.run_fleet_simulation` writes
``DIR/manifest.csv``, the recordings under ``DIR/recordings/`` and the truth in
``DIR/truth.json``, a separate file that ``friction_joint fleet`` never reads.

Every joint and day
-------------------
* the site's ambient temperature: a fleet-wide seasonal drift (drawn, up to
  +-0.5 degC per day) plus a daily draw, kept in 10..40 degC;
* a duty (0.1..1): the joint's working motion that day.  It sets the travel
  of the day (``travel_per_day`` x duty) and the self-heating: the housing
  runs ``R_th x P`` above ambient (the thermal model's resistance times the
  friction power of the working motion, ``duty`` x tau_r(v_work) x v_work,
  at the steady state), so a busy day runs warm;
* a payload: the lever mass times 0.5..1.5 (load tau_L up to ~16 N m);
* the recording: the joint's daily test motion at that temperature, run
  closed loop on the simulated test bed (:class:`~friction_joint.testbed.plant.Plant`,
  its thermal model warming or cooling the housing towards ambient during the
  motion, its sensors): constant-velocity plateau pairs (+v, -v) at
  ``speeds``, each pair at a random lever angle, with ``/joint_states``,
  ``/joint_temperature`` and ``/link_torque``.

Joints differ (a drawn offset of +-8 % of F_c and F_v, the spread of a
production lot).  A drawn subset of joints wears: from a drawn onset time,
F_c and F_v rise with the accumulated travel at a drawn rate, reaching
5..30 % (``wear_end``) of their values at the middle of the gear's
temperature range by the last day.  Wear adds a temperature-independent
friction torque (the constant coefficients of the fc and fv polynomials
grow); the joint offset is added the same way.

The simulation is short on purpose (a few seconds of motion per recording,
``rate`` 1 kHz, published at 500 Hz) so that a fleet of hundreds of recordings
is simulated in minutes.
"""
from __future__ import annotations

from collections.abc import Mapping
import datetime
import math
import os
from typing import Any, TYPE_CHECKING
import warnings

import numpy as np

from .excitation import BlockPlan, record_segment, segment_topics
from ..control.controller import Controller, pd_gains
from ..exceptions import ExperimentError, GearConfigWarning
from ..models.static import StaticFriction
from ..testbed.plant import Plant

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['FLEET', 'MAX_RECORDINGS', 'fleet_recording', 'draw_fleet', 'manifest_rows',
           'MANIFEST_COLUMNS', 'fleet_truth', 'default_gear', 'check_fleet_size']

#: simulator settings (keyword ``cfg`` of :func:`draw_fleet` overrides them)
FLEET = {
    'start': '2026-03-02T00:00:00+00:00',   # first day (UTC)
    'ambient': (10.0, 40.0),        # degC, limits of the site's ambient temperature
    'ambient_spread': 6.0,          # degC, daily scatter (standard deviation)
    'season': 0.5,                  # degC/day, largest seasonal drift (drawn +-)
    'duty': (0.1, 1.0),
    'v_work': 1.5,                  # rad/s, speed of the working motion (self-heating)
    'travel_per_day': 4000.0,       # rad of output travel at duty 1
    'payload': (0.5, 1.5),          # factor on the lever mass
    'joint_spread': 0.08,           # relative offset of F_c, F_v between joints
    'wear_share': (0.25, 0.5),      # share of wearing joints (at least one wears, one not)
    'onset': (0.1, 0.6),            # onset time as a share of the period
    'wear_end': (0.05, 0.30),       # relative rise of F_c and F_v by the last day
    'hours': (6.0, 20.0),           # time of day of the recording
    'speeds': (0.25, 0.5, 1.0, 2.0),   # rad/s, plateau speeds of the daily test motion
    'pairs': 1,                     # plateau pairs per speed (each at its own lever angle)
    'window': 0.4,                  # s of constant velocity per plateau (after settling)
    'settle': 0.15,                 # s
    'center_range': 1.2,            # rad, lever angles of the pairs
    'rate': 1000.0,                 # Hz, simulation
    'publish_rate': 500.0,          # Hz, /joint_states and /link_torque
}


#: most recordings (joints x days) a simulated fleet may have: bounded before any work
MAX_RECORDINGS = 20000
#: rough cost of one recording at the default settings: seconds on one core, bytes on disk
_COST = (0.7, 0.35e6)


def check_fleet_size(joints: int, days: int, seed: int = 0) -> None:
    """
    Check a simulated fleet's size and seed before any work; raise ExperimentError if refused.

    ``joints`` >= 1, ``days`` >= 2, ``joints x days`` at most :data:`MAX_RECORDINGS`
    (the message estimates the time and disk a larger fleet would take), ``seed``
    a whole number >= 0.
    """
    for name, v in (('--joints', joints), ('--days', days), ('--seed', seed)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            raise ExperimentError(f'{name} must be a whole number, got {v!r}')
    if seed < 0:
        raise ExperimentError(f'--seed must be >= 0, got {seed}')
    if joints < 1 or days < 2:
        raise ExperimentError(f'a fleet needs >= 1 joint and >= 2 days, got {joints} x {days}')
    n = int(joints) * int(days)
    if n > MAX_RECORDINGS:
        hours = n * _COST[0] / 3600.0
        gb = n * _COST[1] / 1e9
        raise ExperimentError(f'--joints {joints} x --days {days} = {n} recordings, about '
                              f'{hours:.3g} h of simulation on one core and {gb:.3g} GB: more '
                              f'than the {MAX_RECORDINGS} a simulated fleet may have')


def _iso(t):
    return t.isoformat(timespec='seconds')


def draw_fleet(gear: GearParams, joints: int, days: int, *, seed: int = 0,
               cfg: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """
    Draw a fleet's plan: per joint its offset and wear, per joint and day the conditions.

    Parameters
    ----------
    gear : GearParams
        The joints' nominal gear (friction, lever, thermal sections).
    joints : int
        Number of joints.
    days : int
        Number of days (one recording per joint and day).
    seed : int
        Seed of every draw.
    cfg : dict, optional
        Overrides of :data:`FLEET`.

    Returns
    -------
    dict
        ``joints``: id -> truth; ``recordings``: one dict per joint and day (``joint``,
        ``day``, ``time``, ``ambient``, ``xi``, ``duty``, ``payload``, ``travel``,
        ``wear``, ``seed``); ``season`` (degC/day); ``cfg``.

    """
    check_fleet_size(joints, days, seed)
    c = _config(cfg)
    joints, days = int(joints), int(days)
    rng = np.random.default_rng(seed)
    start = datetime.datetime.fromisoformat(c['start'])
    season = float(rng.uniform(-c['season'], c['season']))
    mean_ambient = float(rng.uniform(c['ambient'][0] + 8.0, c['ambient'][1] - 8.0))
    ids = [f'j{k + 1:02d}' for k in range(joints)]
    share = rng.uniform(*c['wear_share'])
    wears = rng.random(joints) < share
    if joints >= 2:
        if not wears.any():
            wears[rng.integers(joints)] = True
        if wears.all():
            wears[rng.integers(joints)] = False
    mid = 0.5 * (gear.friction.temperature_range[0] + gear.friction.temperature_range[1])
    ref = StaticFriction(gear.friction).parameters(mid)
    fc_ref, fv_ref = float(ref['fc'][0]), float(ref['fv'][0])
    heat = _heating(gear, c)
    truth, recs = {}, []
    for j, jid in enumerate(ids):
        hours = rng.uniform(c['hours'][0], c['hours'][1], days)
        times = np.arange(days) + hours / 24.0                 # days since start
        duty = rng.uniform(c['duty'][0], c['duty'][1], days)
        rate = c['travel_per_day'] * duty                       # rad/day, during day d
        odo_day = np.concatenate([[0.0], np.cumsum(rate)])      # travel at midnight

        def odometer(t, rate=rate, odo_day=odo_day):
            d = min(int(math.floor(t)), days - 1)
            return float(odo_day[d] + rate[d] * (t - d))

        travel = np.array([odometer(t) for t in times])
        offset = rng.uniform(-1.0, 1.0, 2) * c['joint_spread']
        onset = float(rng.uniform(*c['onset']) * days)
        wear_end = float(rng.uniform(*c['wear_end']))
        onset_travel = odometer(onset)
        per_rad = wear_end / max(travel[-1] - onset_travel, 1e-9)
        w = np.where(wears[j], per_rad * np.clip(travel - onset_travel, 0.0, None), 0.0)
        truth[jid] = {
            'wear': bool(wears[j]),
            'onset': _iso(start + datetime.timedelta(days=onset)) if wears[j] else None,
            'onset_day': onset if wears[j] else None,
            'onset_travel': onset_travel if wears[j] else None,
            'rate_per_rad': per_rad if wears[j] else 0.0,
            'wear_end': wear_end if wears[j] else 0.0,
            'fc_offset': float(offset[0] * fc_ref), 'fv_offset': float(offset[1] * fv_ref),
            'fc_ref': fc_ref, 'fv_ref': fv_ref, 'xi_ref': mid}
        for d in range(days):
            amb = mean_ambient + season * (d - 0.5 * days) + rng.normal(0.0, c['ambient_spread'])
            amb = float(np.clip(amb, *c['ambient']))
            recs.append({
                'joint': jid, 'day': d, 'time': _iso(start + datetime.timedelta(days=times[d])),
                'ambient': amb, 'xi': float(amb + heat(amb) * duty[d]), 'duty': float(duty[d]),
                'payload': float(rng.uniform(*c['payload'])), 'travel': float(travel[d]),
                'wear': float(w[d]), 'seed': int(rng.integers(2 ** 31))})
    return {'joints': truth, 'recordings': recs, 'season': season, 'cfg': c,
            'mean_ambient': mean_ambient}


def _config(cfg):
    c = dict(FLEET)
    if cfg:
        unknown = sorted(set(cfg) - set(FLEET))
        if unknown:
            raise ExperimentError(f'unknown fleet option(s) {", ".join(unknown)}')
        c.update(cfg)
    return c


def _heating(gear, c):
    """``heat(ambient)`` -> steady self-heating (degC) at duty 1: R_th x friction power."""
    fr = StaticFriction(gear.friction)
    r_th = gear.section('thermal')['resistance']
    v = c['v_work']

    def heat(ambient):
        xi = ambient
        for _ in range(3):                                    # fixed point: warmer, other friction
            xi = ambient + r_th * abs(float(fr.torque(v, xi)[0])) * v
        return xi - ambient
    return heat


def _truth_gear(gear, joint, rec, c):
    """Return the joint's gear on that day: offset and wear added, payload on the lever."""
    fr = gear.friction
    add_c = joint['fc_offset'] + rec['wear'] * joint['fc_ref']
    add_v = joint['fv_offset'] + rec['wear'] * joint['fv_ref']
    fc = list(fr.fc)
    fv = list(fr.fv)
    fc[0] += add_c
    fv[0] += add_v
    changes = {'friction': {'fc': fc, 'fv': fv, 'model': 'static'},
               'lever': {'mass': gear.section('lever')['mass'] * rec['payload']},
               'thermal': {'ambient': rec['ambient'], 'initial': rec['xi']},
               'simulation': {'rate': c['rate']}}
    sens = gear.section('sensors')
    if sens['velocity_cutoff'] >= 0.4 * c['rate']:
        changes['sensors'] = {'velocity_cutoff': 0.2 * c['rate']}
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', GearConfigWarning)
        return gear.replace(changes)


def _plan(rng, dt, c):
    plan = BlockPlan(dt)
    plan._add(np.array([0.0]), np.zeros(1), np.zeros(1))
    plan.hold(0.2)
    speeds = [v for v in c['speeds'] for _ in range(int(c['pairs']))]
    accel, move_accel, move_speed = 30.0, 40.0, 3.0
    for i in rng.permutation(len(speeds)):
        v = float(speeds[i])
        centre = float(rng.uniform(-c['center_range'], c['center_range']))
        t_ramp = max(0.05, math.pi * v / (2.0 * accel))
        hold = c['settle'] + c['window']
        plan.move(centre - 0.5 * v * (hold + t_ramp), move_accel, move_speed)
        for direction in (1.0, -1.0):
            plan.ramp(0.0, direction * v, accel)
            plan.constant(direction * v, hold)
            plan.ramp(direction * v, 0.0, accel)
            plan.hold(0.05)
    plan.hold(0.1)
    q, qd, qdd = plan.arrays()
    return q[1:], qd[1:], qdd[1:]


def fleet_recording(gear: GearParams, joint: dict[str, Any], rec: dict[str, Any],
                    cfg: Mapping[str, Any] | None = None) -> dict[str, dict[str, Any]]:
    """
    Simulate one joint-day (a ``recordings`` entry of :func:`draw_fleet`).

    Parameters
    ----------
    gear : GearParams
        The joints' nominal gear.
    joint : dict
        The joint's truth (a ``joints`` entry of :func:`draw_fleet`).
    rec : dict
        The joint-day (a ``recordings`` entry of :func:`draw_fleet`).
    cfg : dict, optional
        Overrides of :data:`FLEET` (the plan's ``cfg``).

    Returns
    -------
    dict
        Topic -> arrays, for :func:`~friction_joint.bag.write_recording` (joint
        ``gear.joint_name``).

    """
    c = _config(cfg)
    truth = _truth_gear(gear, joint, rec, c)
    rng = np.random.default_rng(rec['seed'])
    dt = 1.0 / c['rate']
    q_ref, qd_ref, qdd_ref = _plan(rng, dt, c)
    every = max(1, int(round(c['rate'] / c['publish_rate'])))
    plant = Plant(truth, xi0=rec['xi'], seed=rec['seed'], q0=float(q_ref[0]))
    kp, kd = pd_gains(gear.inertia)
    ctrl = Controller(truth, kp, kd, friction='none', dt=dt)
    out: dict[str, list[Any]] = {k: [] for k in ('t', 'q', 'qd', 'effort', 'tau', 'cmd',
                                                 'q_d', 'qd_d')}
    temp_t: list[Any] = []
    temp_xi: list[Any] = []
    record_segment(plant, lambda s, k: ctrl(s.q, s.qd, s.xi, q_ref[k], qd_ref[k], qdd_ref[k]),
                   q_ref, qd_ref, every, 0.0, out=out, temp_t=temp_t, temp_xi=temp_xi)
    cat = {k: np.concatenate(v) for k, v in out.items()}
    topics = segment_topics(cat, temp_t, temp_xi, truth)
    topics['/joint_states']['name'] = gear.joint_name
    topics['/link_torque'] = {'t': cat['t'], 'tau': cat['tau']}
    return topics


#: the columns of a simulated fleet's ``manifest.csv``
MANIFEST_COLUMNS = ('recording', 'joint', 'time', 'travel')


def manifest_rows(plan: dict[str, Any]) -> list[dict[str, str]]:
    """
    Name every joint-day's recording and return the manifest's rows.

    Each ``recordings`` entry of ``plan`` gets its ``recording``:
    ``recordings/JOINT_DATE.mcap``, relative to the manifest.

    Parameters
    ----------
    plan : dict
        A plan of :func:`draw_fleet` (its ``recordings`` are named in place).

    Returns
    -------
    list of dict
        One row per joint-day, by :data:`MANIFEST_COLUMNS` (``travel`` as text, 0.1 rad).

    """
    rows = []
    for rec in plan['recordings']:
        rel = f'recordings/{rec["joint"]}_{rec["time"][:10]}.mcap'
        rec['recording'] = rel
        rows.append({'recording': rel, 'joint': rec['joint'], 'time': rec['time'],
                     'travel': f'{rec["travel"]:.1f}'})
    return rows


def fleet_truth(plan: dict[str, Any], gear: str, seed: int) -> dict[str, Any]:
    """
    Return a fleet's truth, as ``truth.json`` holds it.

    Parameters
    ----------
    plan : dict
        A plan of :func:`draw_fleet`, its recordings named (:func:`manifest_rows`).
    gear : str
        The joints' nominal gear file, as given.
    seed : int
        The seed the plan was drawn with.

    Returns
    -------
    dict
        ``joints``, ``recordings``, ``season``, ``mean_ambient``, ``gear``, ``cfg``
        (plain JSON types), ``seed``.

    """
    return {'joints': plan['joints'], 'recordings': plan['recordings'], 'season': plan['season'],
            'mean_ambient': plan['mean_ambient'], 'gear': gear,
            'cfg': {k: list(v) if isinstance(v, tuple) else v for k, v in plan['cfg'].items()},
            'seed': int(seed)}


def default_gear() -> str:
    """Return the path of ``config/csd25.yaml`` (source tree or installed share directory)."""
    here = os.path.dirname(os.path.abspath(__file__))
    for base in (os.path.join(here, '..', '..', 'config'),
                 os.path.join(here, '..', '..', '..', '..', '..', 'share', 'friction_joint',
                              'config')):
        path = os.path.normpath(os.path.join(base, 'csd25.yaml'))
        if os.path.exists(path):
            return path
    raise ExperimentError('cannot find config/csd25.yaml next to the package: give the gear')
