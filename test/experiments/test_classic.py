# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The classic LuGre experiments (friction_joint.experiments.classic) against independent references.

The references integrate the original LuGre equations (seed eq. 10 with the
linear viscous term, Canudas de Wit et al. 1995) with scipy's Radau; their
right-hand sides are written out below from the paper, not taken from the
package.
"""
import json
import math
import os
import warnings

from friction_joint.cli import main
from friction_joint.exceptions import GearConfigWarning
from friction_joint.experiments import classic, classic_report
from friction_joint.gear import passivity_bound
import friction_joint.jobs.classic as classic_job
from friction_joint.results import ExperimentResult
import numpy as np
import pytest
from scipy.integrate import solve_ivp

# Table I of Canudas de Wit et al. (1995), unit mass
S0, S1, S2 = 1e5, math.sqrt(1e5), 0.4
FC, FS, VS, M = 1.0, 1.5, 1e-3, 1.0


def lugre_rhs(applied):
    """
    Right-hand side and Jacobian of m x'' = applied(t, x) - F, eq. 10.

    State y = (x, v, z);  g(v) = Fc + (Fs - Fc) exp(-(v/vs)^2),
    z' = v - sigma0 |v| z / g(v),  F = sigma0 z + sigma1 z' + sigma2 v.
    ``applied`` returns (force, d force / d x).
    """
    def rhs(t, y):
        x, v, z = y
        g = FC + (FS - FC) * math.exp(-(v / VS) ** 2)
        zd = v - S0 * abs(v) / g * z
        return [v, (applied(t, x)[0] - S0 * z - S1 * zd - S2 * v) / M, zd]

    def jac(t, y):
        x, v, z = y
        e = math.exp(-(v / VS) ** 2)
        g = FC + (FS - FC) * e
        dg = (FS - FC) * e * (-2.0 * v / VS ** 2)
        dzd_dz = -S0 * abs(v) / g
        dzd_dv = 1.0 - S0 * z * (math.copysign(1.0, v) / g - abs(v) * dg / g ** 2)
        return [[0.0, 1.0, 0.0],
                [applied(t, x)[1] / M, -(S1 * dzd_dv + S2) / M, -(S0 + S1 * dzd_dz) / M],
                [0.0, dzd_dv, dzd_dz]]
    return rhs, jac


def lugre_friction(y):
    """Friction force of eq. 10 along a Radau solution y = (x, v, z) (3, T)."""
    x, v, z = y
    g = FC + (FS - FC) * np.exp(-(v / VS) ** 2)
    zd = v - S0 * np.abs(v) / g * z
    return S0 * z + S1 * zd + S2 * v


# ------------------------------------------------------------ parameters ---

def test_canudas_gear_is_table_one_and_silences_only_its_own_warning():
    with warnings.catch_warnings():
        warnings.simplefilter('error')           # any warning escaping would fail here
        gear = classic.canudas_gear()
    f = gear.friction
    assert (f.lugre.sigma0, f.lugre.sigma1) == (S0, S1)
    assert (f.fc, f.fs, f.fv, f.vs) == ((FC,), (FS,), (S2,), (VS,))
    assert (f.delta_v, f.delta_s) == ((1.0,), 2.0)
    assert gear.inertia == M
    # the suppressed warning is real: sigma1 exceeds sigma2 Fc / (Fs - Fc) = 0.8
    assert S1 > passivity_bound(f, 25.0)[0] == pytest.approx(0.8)
    with pytest.warns(GearConfigWarning):
        gear.replace({})


# ------------------------------------------------------------ presliding ---

@pytest.fixture(scope='module')
def presliding_result():
    return classic.presliding()


def test_presliding_is_spring_like_with_stiffness_sigma0(presliding_result):
    s = presliding_result.summary
    assert s['force_amplitude'] == pytest.approx(0.95 * FS)
    # never slides: micrometre displacements, velocities far below v_s
    assert s['v_peak'] < 0.1 * VS
    assert 0.0 < s['x_max'] < 1e-4 and -1e-4 < s['x_min'] < 0.0
    # at zero force z = 0 and eq. 10 gives dF/dx = sigma0 exactly (quasi-static);
    # fitted over |F| <= 0.02 Fs the curvature bias is O(1e-4), the sigma1 z'
    # offset during the ramp shifts but does not tilt the line: 1 % tolerance
    assert len(s['stiffness_passages']) == 3
    for k in s['stiffness_passages']:
        assert k == pytest.approx(S0, rel=1e-2)
    # on the virgin curve the tangent is sigma0 (1 - F/Fs): mean ~ 0.993 sigma0
    assert s['stiffness_virgin'] == pytest.approx(S0 * (1.0 - 0.01 / 1.5), rel=5e-3)
    # rate-independent hysteresis: the loop closes and the full cycle ending
    # at zero force brings the mass back to the origin (up to the dynamics,
    # many orders below the micrometre displacements)
    assert abs(s['loop_closure']) < 1e-6 * s['x_max']
    assert abs(s['x_end']) < 1e-6 * s['x_max']
    # quasi-static closed form x(+-A) = -Fs/sigma0 ln(1 -+ A/Fs); the creep
    # velocity near 0.95 Fs lowers g(v) slightly, so allow 3 %
    assert s['x_max'] == pytest.approx(s['x_max_quasistatic'], rel=3e-2)
    assert s['x_min'] == pytest.approx(s['x_min_quasistatic'], rel=3e-2)


def test_presliding_displacement_matches_radau():
    # a shorter protocol without holds keeps Radau cheap (the |v| kink at
    # standstill makes it crawl through holds); 1.2 N/s stays below the
    # break-away force at that rate
    amp, ramp = 1.2, 1.0
    res = classic.presliding(amplitude=amp, ramp_time=ramp, hold_time=0.0, dt=1e-4)
    knots_t = np.cumsum([0.0, ramp, 2 * ramp, 2 * ramp, 2 * ramp, ramp])
    knots_f = [0.0, amp, -amp, amp, -amp, 0.0]
    rhs, jac = lugre_rhs(lambda t, x: (float(np.interp(t, knots_t, knots_f)), 0.0))
    t_cmp = np.round(0.01 * np.arange(1, int(round(knots_t[-1] / 0.01)) + 1), 12)
    y0, xs = [0.0, 0.0, 0.0], []
    for t0, t1 in zip(knots_t[:-1], knots_t[1:], strict=True):   # ramp by ramp: kinks at the knots
        te = t_cmp[(t_cmp > t0 + 1e-9) & (t_cmp <= t1 + 1e-9)]
        sol = solve_ivp(rhs, (t0, t1), y0, method='Radau', t_eval=te, jac=jac,
                        rtol=1e-8, atol=1e-14)
        assert sol.success
        xs.append(sol.y[0])
        y0 = sol.y[:, -1]
    x_ref = np.concatenate(xs)
    x = np.interp(t_cmp, res.series['t'], res.series['x'])
    x_max = np.abs(x_ref).max()
    assert x_max > 1e-5
    # the coupled joint step is second order (error 4x smaller per halving
    # of dt, measured 2.1e-4 x_max at dt = 1e-4; the Radau solution agrees
    # with rtol 1e-9/atol 1e-15 to 1e-14 m): 1e-3 x_max = 24 nm
    assert np.abs(x - x_ref).max() < 1e-3 * x_max
    assert res.summary['stiffness'] == pytest.approx(S0, rel=1e-2)


# --------------------------------------------------------- frictional lag ---

def test_lag_loops_widen_monotonically_with_frequency():
    res = classic.frictional_lag()
    s = res.summary
    assert s['omegas'] == [1.0, 10.0, 25.0]
    w, a = s['loop_width'], s['loop_area']
    assert w[0] > 1e-3                                # a real loop even at 1 rad/s
    assert w[0] < w[1] < w[2] and a[0] < a[1] < a[2]
    assert w[2] > 5 * w[0]
    # friction lags the velocity: in the Stribeck region (friction falling
    # with velocity) it is lower while the velocity decreases (first half of
    # the period, from the velocity maximum) than while it increases, as
    # Canudas et al. report
    for v, f in zip(res.series['v'], res.series['friction'], strict=True):
        k = int(np.argmin(v))
        vm = 0.5 * (v.min() + v.max())
        f_dec = np.interp(vm, v[:k + 1][::-1], f[:k + 1][::-1])
        f_acc = np.interp(vm, v[k:], f[k:])
        assert f_dec < f_acc
    # the slowest loop hugs the steady-state curve
    v0, f0 = res.series['v'][0], res.series['friction'][0]
    f_ss = np.interp(v0, res.series['v_static'], res.series['friction_static'])
    assert np.abs(f0 - f_ss).max() < 0.02


# -------------------------------------------------------------- break-away ---

def test_breakaway_force_falls_with_force_rate():
    s = classic.breakaway().summary
    fb = s['breakaway_force']
    assert all(f is not None for f in fb)
    assert all(a > b for a, b in zip(fb, fb[1:], strict=False)), fb      # strictly decreasing
    assert fb[0] == pytest.approx(FS, abs=0.03)             # slow ramp: near F_s
    assert fb[-1] < 1.1 and fb[-1] > FC                     # 30 N/s: near F_c
    # the applied force at that instant falls too
    fa = s['applied_force_at_breakaway']
    assert all(a > b for a, b in zip(fa, fa[1:], strict=False))


def test_breakaway_peak_matches_radau():
    rate = 10.0
    s = classic.breakaway(rates=(rate,)).summary
    rhs, jac = lugre_rhs(lambda t, x: (rate * t, 0.0))
    sol = solve_ivp(rhs, (0.0, 0.2), [0.0, 0.0, 0.0], method='Radau', jac=jac,
                    rtol=1e-9, atol=1e-14, dense_output=True)
    assert sol.success
    t = np.linspace(0.0, 0.2, 200001)
    f = lugre_friction(sol.sol(t))
    k = classic._first_peak(f, 0.01)
    assert s['breakaway_force'][0] == pytest.approx(f[k], abs=1e-4)
    assert s['time_to_breakaway'][0] == pytest.approx(t[k], abs=1e-4)


def test_breakaway_has_no_peak_for_fast_ramps():
    # beyond ~35 N/s the bristle velocity r/sigma0 is comparable to v_s and
    # friction rises to the kinetic level without a stiction peak
    s = classic.breakaway(rates=(60.0,)).summary
    assert s['breakaway_force'] == [None]


# -------------------------------------------------------------- stick-slip ---

@pytest.fixture(scope='module')
def stick_slip_reference():
    """Radau solution of the spring-pulled mass, slip onsets by event location."""
    k, vp = 2.0, 0.1
    rhs, jac = lugre_rhs(lambda t, x: (k * (vp * t - x), -k))

    def onset(t, y):
        return y[1] - 0.05
    onset.direction = 1.0
    # converged: rtol 1e-8 ... 1e-10 give the same onsets to 1 us
    sol = solve_ivp(rhs, (0.0, 30.0), [0.0, 0.0, 0.0], method='Radau', jac=jac,
                    events=onset, rtol=1e-9, atol=1e-11)
    assert sol.success
    return {'slip_onsets': list(sol.t_events[0]), 'x_end': sol.y[0, -1],
            'v_max': sol.y[1].max()}


def test_stick_slip_matches_radau(stick_slip_reference):
    ref = stick_slip_reference
    s = classic.stick_slip().summary
    assert set(s) == {'slip_onsets', 'period', 'v_max', 'x_end', 'spring_stiffness',
                      'pull_velocity', 'spring_force_at_slip'}
    # each slip starts once the spring pulls beyond the static level F_s (not above
    # the peak of the Stribeck curve by more than the mass's acceleration needs)
    for f in s['spring_force_at_slip']:
        assert classic.CANUDAS_1995['fc'] < f < 1.1 * classic.CANUDAS_1995['fs']
    assert len(s['slip_onsets']) == len(ref['slip_onsets']) == 4
    # periodic: equal intervals between onsets
    d = np.diff(s['slip_onsets'])
    assert np.ptp(d) < 1e-3
    assert s['period'] == pytest.approx(np.mean(np.diff(ref['slip_onsets'])), abs=5e-4)
    # dt = 5e-5: every onset within 0.1 us of Radau (0.3 us at dt = 1/3000), x_end
    # within 2e-10 m; the integrator before the exact-Jacobian LuGre step was 0.05, 0.13,
    # 0.21, 0.30 ms off (first order in the sigma1 dz/dt term).  The reference itself
    # is converged to about 1 us, hence the bound
    for a, b in zip(s['slip_onsets'], ref['slip_onsets'], strict=True):
        assert abs(a - b) < 5e-6
    assert s['x_end'] == pytest.approx(ref['x_end'], abs=1e-7)
    assert s['v_max'] == pytest.approx(ref['v_max'], rel=1e-3)     # Radau samples only its steps


def test_slip_onsets_counts_each_slip_once():
    # three slips starting at 0.5, 1.5, 2.5 s; inside each the velocity
    # ripples through the threshold (0.04 ... 0.08 m/s) without sticking again
    t = np.linspace(0.0, 3.0, 3001)
    phase = t % 1.0
    slip = (phase >= 0.5) & (phase < 0.9)
    v = np.where(slip, 0.06 + 0.02 * np.sin(2 * np.pi * 20 * (phase - 0.5)), 0.0)
    assert classic.slip_onsets(t, v, 0.05) == pytest.approx([0.5, 1.5, 2.5], abs=2e-3)


# --------------------------------------------------------------------- CLI ---

@pytest.mark.parametrize('name', ['presliding', 'lag', 'breakaway', 'stick-slip'])
def test_cli_writes_png_and_json(tmp_path, name):
    out = tmp_path / 'new' / 'dir'                      # created by the command
    assert main(['classic', name, '--out', str(out)]) == 0
    png = out / f'{name}.png'
    assert png.stat().st_size > 10000
    assert png.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    data = json.loads((out / f'{name}.json').read_text())
    required = {'presliding': {'stiffness', 'sigma0', 'x_max', 'force_amplitude'},
                'lag': {'omegas', 'loop_width'},
                'breakaway': {'rates', 'breakaway_force'},
                'stick-slip': {'slip_onsets', 'period', 'v_max', 'x_end', 'spring_stiffness',
                               'pull_velocity', 'spring_force_at_slip'}}[name]
    assert required <= set(data)
    if name == 'stick-slip':
        assert set(data) == required
        assert len(data['slip_onsets']) == 4
        assert data['slip_onsets'][0] == pytest.approx(7.5404, abs=2e-3)
    assert sorted(os.listdir(out)) == sorted([f'{name}.png', f'{name}.json'])


def test_cli_leaves_nothing_on_error(tmp_path, monkeypatch):
    def broken(draw, size, dpi=100):
        raise RuntimeError('figure failed')
    monkeypatch.setattr(classic_job, 'render_png', broken)
    monkeypatch.setitem(classic.CLASSIC_EXPERIMENTS, 'lag',
                        lambda: classic.frictional_lag(samples_per_period=2000))
    out = tmp_path / 'out'
    out.mkdir()
    with pytest.raises(RuntimeError):
        main(['classic', 'lag', '--out', str(out)])
    assert os.listdir(out) == []


def test_cli_reports_unwritable_out(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(classic.CLASSIC_EXPERIMENTS, 'lag',
                        lambda: classic.frictional_lag(samples_per_period=2000))
    blocker = tmp_path / 'file'
    blocker.write_text('not a directory')
    assert main(['classic', 'lag', '--out', str(blocker)]) == 2
    assert 'cannot create output directory' in capsys.readouterr().err
    assert blocker.read_text() == 'not a directory'


def test_summary_markdown_gives_outputs_with_units(presliding_result):
    lag = classic_report.summary_markdown(
        'lag', classic.frictional_lag(samples_per_period=2000).summary)
    assert '| ω (rad/s) | loop width (N) | loop area (N mm/s) |' in lag
    assert sum(line.startswith('| 25 |') for line in lag) == 1     # one row per frequency
    brk = classic.breakaway(rates=(1.0, 60.0)).summary
    rows = classic_report.summary_markdown('breakaway', brk)
    assert any(line.startswith('| force rate r (N/s) | break-away force (N)') for line in rows)
    assert f'| 1 | {brk["breakaway_force"][0]:.3f} |' in '\n'.join(rows)
    assert any(line.startswith('| 60 | no peak') for line in rows)   # None: said in words
    pre = '\n'.join(classic_report.summary_markdown('presliding', presliding_result.summary))
    assert '| N/m |' in pre and '| µm |' in pre


def test_a_result_is_an_object_with_plain_json_and_a_figure(presliding_result):
    from matplotlib.figure import Figure
    assert isinstance(presliding_result, ExperimentResult)
    assert list(presliding_result.figures) == ['presliding.png']
    assert presliding_result.name == 'presliding'
    doc = json.loads(json.dumps(presliding_result.to_dict(), allow_nan=False))
    assert doc['stiffness'] == presliding_result.summary['stiffness']
    fig = Figure()
    presliding_result.plot(fig)
    assert len(fig.axes) == 3 and 'Pre-sliding' in fig._suptitle.get_text()
