# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Identification checked over joints drawn at random, not one truth file.

Every plant, excitation and hidden effect here is drawn from continuous ranges
(:mod:`friction_joint.experiments.identification_draws`) with seeds drawn from a
seeded generator; the identification sees only the plateaus or the recording and the
case's structure file.
"""
import warnings

from friction_joint.bag import read_recording, write_recording
from friction_joint.experiments.identification_draws import (
    draw_identification_case, draw_plateaus, simulate_case)
from friction_joint.identification import find_plateaus, plateaus_from_arrays, StaticIdentifier
from friction_joint.identification.physical_problem import DELTA_S_BOUNDS, FS_RATIO_MAX, vs_band
from friction_joint.identification.pipeline import identify_recordings
from friction_joint.identification.stick_slip import stick_slip_summary
from friction_joint.models.static import StaticFriction
import numpy as np
import pytest

pytestmark = pytest.mark.filterwarnings('ignore::friction_joint.exceptions.GearConfigWarning')

SEEDS = [int(s) for s in np.random.default_rng(3030).integers(1000, 10 ** 6, 40)]
#: a short excitation for the recordings simulated here
SHORT = {'n_speeds': (5, 6), 'repetitions': (1, 1), 'plateau': (1.2, 1.6)}


def curve_error(gear, truth, plateaus):
    """Largest relative static-curve error over the plateaus' speed, temperature, load ranges."""
    speed = np.abs(plateaus.qd)
    v = np.geomspace(speed.min(), speed.max(), 150)
    got, want = StaticFriction(gear.friction), StaticFriction(truth.friction)
    return max(float(np.max(np.abs(got.torque(s * v, x, lo) / want.torque(s * v, x, lo) - 1.0)))
               for x in (plateaus.xi.min(), plateaus.xi.max()) for s in (1.0, -1.0)
               for lo in (plateaus.load.min(), plateaus.load.max()))


def fit(case, *, seed, noise=0.002, plateaus=None):
    p = draw_plateaus(case, seed=seed, noise=noise) if plateaus is None else plateaus
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        return p, StaticIdentifier(case.structure).fit(p)


# ------------------------------------------------------------ 1. stamp epoch ---

@pytest.fixture(scope='module')
def simulated():
    """Simulate one drawn plant's plateau excitation (relative time and its stamps)."""
    case = draw_identification_case(SEEDS[0], excitation_ranges=SHORT)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        topics = simulate_case(case)
    return case, topics


def test_plateau_set_does_not_depend_on_the_stamp_epoch(simulated, tmp_path):
    """
    A gap-free, regularly stamped recording finds the same plateaus at any epoch.

    Stamps are integer nanoseconds (as a logger writes them) read as float seconds; at
    an epoch of about 1.7e9 s float64 quantises them to about 0.24 us.
    """
    case, topics = simulated
    js = topics['/joint_states']
    rel_ns = np.round((js['t'] - case.epoch) * 1e9 / 1e3).astype(np.int64) * 1000
    xi = np.interp(js['t'], topics['/joint_temperature']['t'], topics['/joint_temperature']['xi'])
    tau = case.truth.lever_torque(js['q'])
    out = []
    for epoch in (0, int(case.epoch * 1e9)):
        t = (rel_ns + epoch) / 1e9
        out.append(plateaus_from_arrays(t, js['q'], js['qd'], js['effort'], xi, tau,
                                        inertia=case.structure.inertia))
    a, b = out
    assert len(a) == len(b) > 8
    assert np.array_equal(np.round(a.qd, 9), np.round(b.qd, 9))
    assert np.allclose(a.tau_r, b.tau_r, rtol=0, atol=1e-9)
    assert np.allclose(a.t0, b.t0 - case.epoch, atol=1e-5)
    # the same through recordings written and read back, at the epoch and at zero
    found = []
    for name, shift in (('at_epoch', 0.0), ('at_zero', case.epoch)):
        moved = {k: dict(v, t=v['t'] - shift) for k, v in topics.items()}
        path = write_recording(tmp_path / name, moved)
        found.append(find_plateaus(read_recording(path), case.structure))
    assert len(found[0]) == len(found[1]) > 8
    assert np.allclose(found[0].tau_r, found[1].tau_r, rtol=0, atol=1e-6)


# ------------------------------------------------------- 2. physical by construction ---

@pytest.mark.parametrize('seed', SEEDS[1:9])
def test_identified_curve_is_physical_on_drawn_plants(seed):
    case = draw_identification_case(seed)
    p, ident = fit(case, seed=seed)
    xi = np.linspace(p.xi.min(), p.xi.max(), 25)
    for load in (0.0, float(p.load.max())):
        par = ident.predict_parameters(xi, load)
        raw = ident.layout.physics(ident.theta[None, :], xi, np.full_like(xi, load))[0]
        assert np.all(raw[0] >= 0.0) and np.all(raw[2] >= 0.0)           # F_c, F_v
        assert np.all(par['fs'] >= par['fc'] - 1e-9)
        assert np.all(par['fs'] <= FS_RATIO_MAX * par['fc'] + 1e-9)
    lo, hi = vs_band(p)
    assert lo * (1 - 1e-9) <= ident.gear.friction.vs[0] <= hi * (1 + 1e-9)
    assert DELTA_S_BOUNDS[0] <= ident.gear.friction.delta_s <= DELTA_S_BOUNDS[1]
    # nothing absurd unless said: every parameter within a factor two of the truth at the
    # middle temperature, or reported as kept or weakly pinned
    idf = ident.identifiability
    said = set(idf['not_identified']) | {k.split()[0] for k in idf['weak']}
    xm = np.array([0.5 * (p.xi.min() + p.xi.max())])
    got = StaticFriction(ident.gear.friction).parameters(xm)
    want = StaticFriction(case.truth.friction).parameters(xm)
    for name in ('fc', 'fs', 'fv', 'vs', 'delta_v'):
        if name not in said:
            assert 0.5 < float(got[name][0] / want[name][0]) < 2.0, name
    if not said:
        assert curve_error(ident.gear, case.truth, p) < 0.02


# ------------------------------------------------ 3. identifiability, said out loud ---

@pytest.mark.parametrize('seed', SEEDS[9:14])
def test_a_stribeck_dip_below_every_plateau_is_said_and_kept(seed):
    """v_s drawn a factor 8-30 below the slowest plateau: not identified, kept, curve right."""
    rng = np.random.default_rng(seed)
    v_low = float(rng.uniform(0.03, 0.08))
    vs = v_low / float(rng.uniform(8.0, 30.0))
    case = draw_identification_case(seed, plant_ranges={'vs': (vs, vs * 1.0001),
                                                        'fs_ratio': (1.2, 1.8),
                                                        'delta_s': (1.5, 2.5)},
                                    excitation_ranges={'v_low': (v_low, v_low * 1.0001)})
    p, ident = fit(case, seed=seed)
    kept = ident.identifiability['not_identified']
    assert {'vs', 'fs'} <= set(kept)
    assert f'the slowest plateau is {np.abs(p.qd).min():.3g} rad/s' in kept['vs']['why']
    assert kept['vs']['advice'].startswith('record ') and 'plateaus' in kept['vs']['advice']
    assert any(line.startswith('vs not identified') for line in ident.identifiability['lines'])
    xm = np.array([0.5 * (p.xi.min() + p.xi.max())])
    prior = StaticFriction(case.structure.friction).parameters(xm)
    got = StaticFriction(ident.gear.friction).parameters(xm)
    ratio = max(1.0, float(prior['fs'][0] / prior['fc'][0]))
    if 'fitted as a ratio' not in kept['fs']['kept']:
        assert float(got['fs'][0] / got['fc'][0]) == pytest.approx(ratio, rel=1e-6)
    assert ident.gear.friction.vs[0] <= ident.identifiability['intervals']['vs']['high']
    assert curve_error(ident.gear, case.truth, p) < 0.02


@pytest.mark.parametrize('seed', SEEDS[14:18])
def test_a_stribeck_dip_the_plateaus_cross_is_identified(seed):
    rng = np.random.default_rng(seed)
    v_low = float(rng.uniform(0.005, 0.01))
    vs = v_low * float(rng.uniform(4.0, 15.0))
    case = draw_identification_case(seed, plant_ranges={'vs': (vs, vs * 1.0001),
                                                        'fs_ratio': (1.3, 1.8)},
                                    excitation_ranges={'v_low': (v_low, v_low * 1.0001),
                                                       'n_speeds': (9, 11),
                                                       'repetitions': (2, 2)})
    p, ident = fit(case, seed=seed)
    assert 'vs' not in ident.identifiability['not_identified']
    assert abs(ident.gear.friction.vs[0] / vs - 1.0) < 0.3
    assert curve_error(ident.gear, case.truth, p) < 0.02


# ------------------------------------------------------- 4. honest standard errors ---

def test_two_standard_errors_cover_the_truth():
    covered = []
    for seed in SEEDS[18:33]:
        case = draw_identification_case(seed)
        _, ident = fit(case, seed=seed)
        idf = ident.identifiability
        said = set(idf['not_identified']) | {k.split()[0] for k in idf['weak']}
        tf = case.truth.friction
        for name, vals in ident.coefficients.items():
            if name in said or name == 'fs_ratio':
                continue
            truth = [tf.delta_s] if name == 'delta_s' else list(getattr(tf, name) or [])
            for i, (v, se) in enumerate(zip(vals, ident.standard_errors[name], strict=True)):
                assert np.isfinite(se) and se > 0.0, (seed, name)
                covered.append(abs(v - (truth[i] if i < len(truth) else 0.0)) <= 2.0 * se)
    print(f'\ntruth within +-2 SE: {sum(covered)}/{len(covered)}')
    assert len(covered) > 80
    assert np.mean(covered) >= 0.85


# -------------------------------------------------------- 5. held-out validation ---

@pytest.mark.parametrize('seed', SEEDS[33:36])
def test_held_out_validation_measures_the_noise_and_grows_where_the_model_misses(seed):
    """
    Held-out errors per speed band: about the noise on a clean plant.

    They are larger in the band where an unmodelled bump of drawn size sits (drawn band,
    drawn plant).
    """
    import dataclasses
    rng = np.random.default_rng(seed)
    case = draw_identification_case(seed, excitation_ranges={'n_speeds': (10, 11),
                                                             'repetitions': (2, 2)})
    noise = 0.002
    clean = draw_plateaus(case, seed=seed, noise=noise)
    speed = np.abs(clean.qd)
    edges = np.geomspace(speed.min(), speed.max() * (1 + 1e-9), 5)
    band = int(rng.integers(0, 4))
    inside = (speed >= edges[band]) & (speed < edges[band + 1])
    size = float(rng.uniform(0.04, 0.08))
    tau = clean.tau_r + np.where(inside, size * clean.tau_r, 0.0)
    _, ident0 = fit(case, seed=seed, plateaus=clean)
    _, ident = fit(case, seed=seed, plateaus=dataclasses.replace(clean, tau_r=tau))
    v0, v1 = ident0.validation, ident.validation
    assert v0['blocks'] >= 2 and len(v0['bands']) == len(v1['bands']) == 4
    sigma = noise * float(np.median(np.abs(clean.tau_r[speed < edges[1]])))
    for b in v0['bands']:
        assert b['rms'] < 6.0 * sigma + 1e-3 * float(np.max(np.abs(clean.tau_r)))
    assert v0['rms'] >= 0.8 * v0['rms_in_sample']
    assert v1['bands'][band]['rms'] > 2.0 * v0['bands'][band]['rms']


# ------------------------------------------------------------ 6. stick-slip ---

@pytest.mark.parametrize('seed', SEEDS[36:39])
def test_stick_slip_windows_are_recognised_and_left_out(seed):
    rng = np.random.default_rng(seed)
    dt = 1.0 / float(rng.uniform(500.0, 2000.0))
    fc = float(rng.uniform(0.5, 3.0))
    parts_v, parts_tau = [], []

    def ramp(v0, v1, n=100):
        parts_v.append(np.linspace(v0, v1, n))
        parts_tau.append(np.sign(v1 or v0) * fc * np.ones(n))

    for v in (0.3, -0.3, 1.0, -1.0, 2.0, -2.0):
        ramp(0.0, v)
        n = int(1.5 / dt)
        parts_v.append(np.full(n, v))
        parts_tau.append(np.full(n, np.sign(v) * (fc + 0.2 * abs(v))))
        ramp(v, 0.0)
    # a slow command the joint follows by sticking and slipping
    mean = float(rng.uniform(0.005, 0.03))
    n = int(3.0 / dt)
    period = int(float(rng.uniform(0.3, 0.6)) / dt)
    slip = max(int(0.25 * period), 2)
    stick = np.zeros(n)
    for k in range(0, n, period):
        stick[k:k + slip] = mean * period / slip
    parts_v.append(stick)
    parts_tau.append(np.full(n, fc))
    qd = np.concatenate(parts_v)
    tau = np.concatenate(parts_tau)
    t = dt * np.arange(len(qd))
    q = np.cumsum(qd) * dt
    command = np.concatenate([np.zeros(len(qd) - n), np.full(n, mean)])
    p = plateaus_from_arrays(t, q, qd, tau, np.full(len(t), 30.0), np.zeros(len(t)),
                             inertia=0.1, qd_command=command)
    assert len(p.stick_slip) >= 1
    assert all(abs(x['speed'] / mean - 1.0) < 0.3 for x in p.stick_slip)
    assert np.abs(p.qd).min() > 0.2                  # no plateau at the stick-slip speed
    text = stick_slip_summary(p)
    assert 'stuck and slipped' in text and 'the joint slides steadily from' in text
    # without the command, moving and resting is not called stick-slip
    assert plateaus_from_arrays(t, q, qd, tau, np.full(len(t), 30.0), np.zeros(len(t)),
                                inertia=0.1).stick_slip == ()


# ---------------------------------------------------- 7. a recording, end to end ---

def test_a_drawn_plant_is_identified_from_its_recording(simulated, tmp_path):
    case, topics = simulated
    path = write_recording(tmp_path / 'rec', topics)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        run = identify_recordings([path], case.structure, presliding='skip')
    idf = run.identifier.identifiability
    assert idf['lines'] and run.identifier.validation['blocks'] >= 2
    if idf['curve_identified']:
        assert curve_error(run.gear, case.truth, run.plateaus) < 0.03
    rep = run.report()
    assert rep['identifiability']['lines'] == idf['lines']
    assert rep['validation']['bands']


# ------------------------------------------- no load sensor: the lever's own error ---

@pytest.mark.parametrize('seed', SEEDS[39:40] + [int(s) for s in SEEDS[1:3]])
def test_the_lever_models_gravity_error_is_fitted_and_said(seed):
    """
    Without /link_torque the lever model's m g l error is fitted along and said.

    tau_ext is then the structure's lever: its m g l error (drawn, 2-8 %) is a
    position-dependent friction error unless fitted along.
    """
    import dataclasses
    rng = np.random.default_rng(seed)
    case = draw_identification_case(seed, excitation_ranges={'mgl': (6.0, 15.0),
                                                             'n_speeds': (9, 11),
                                                             'repetitions': (2, 2)})
    p = draw_plateaus(case, seed=seed, noise=0.002)
    err = float(rng.uniform(0.02, 0.08) * rng.choice([-1.0, 1.0]))
    tau_model = case.structure.mgl * np.sin(np.array(case.centers))
    # measured friction = effort - tau_model: the truth plus e tau_model
    p = dataclasses.replace(p, tau_ext=tau_model, tau_r=p.tau_r + err * tau_model,
                            torque_source=('lever_model',))
    _, ident = fit(case, seed=seed, plateaus=p)
    got = ident.identifiability['parameters']['lever_error']
    assert abs(got['value'] - err) <= 2.0 * got['se'] + 1e-3
    assert any(line.startswith('lever gravity:') for line in ident.identifiability['lines'])
    if ident.identifiability['curve_identified']:
        assert curve_error(ident.gear, case.truth, p) < 0.02
