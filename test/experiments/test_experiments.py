# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The paper's evaluation experiments through the command line, shortened with --duration-scale."""
import inspect
import json
import os
import time

from friction_joint.cli import main
from friction_joint.experiments import runner
from friction_joint.experiments._common import reversal_peak_window
from friction_joint.experiments.compensation import compensation
import friction_joint.jobs.experiment as experiment_job
from friction_joint.jobs.experiment import run_experiment
from friction_joint.results import ExperimentResult
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')

#: duration scales: the compensation window must still contain a reversal of
#: q_d (t = pi / 3 s), the chirp several stick-slip cycles
SCALES = {'chirp': 0.2, 'compensation': 0.2, 'estimation': 0.25}
FIGURES = {'chirp': ['chirp.png'],
           'compensation': ['compensation_error.png', 'compensation_bars.png'],
           'estimation': ['estimation.png']}


def _run(name, out, *extra, model=MODEL, truth=TRUTH):
    return main(['experiment', name, '--model', model, '--truth', truth, '--out', str(out),
                 *extra])


def fast_heating_truth(directory, factor=10.0):
    """Write the LuGre truth with a heat capacity ``factor`` times smaller (quicker warm-up)."""
    import yaml
    from friction_joint.gear import load_gear
    truth = load_gear(TRUTH)
    fast = truth.replace({'thermal': {'capacity': truth.section('thermal')['capacity'] / factor}})
    path = os.path.join(str(directory), 'truth_fast_heating.yaml')
    with open(path, 'w') as fh:
        yaml.safe_dump(fast.to_dict(), fh)
    return path


@pytest.fixture(scope='module')
def results(tmp_path_factory):
    """Run each experiment once; name -> (output dir, summary)."""
    out = {}
    truth = fast_heating_truth(tmp_path_factory.mktemp('truth'))
    for name, scale in SCALES.items():
        d = tmp_path_factory.mktemp(name) / 'out'         # created by the command
        assert _run(name, d, '--duration-scale', str(scale), truth=truth) == 0
        with open(d / 'summary.json') as fh:
            out[name] = (d, json.load(fh))
    return out


@pytest.mark.slow
@pytest.mark.parametrize('name', sorted(SCALES))
def test_figures_and_summary_written(results, name):
    d, summary = results[name]
    for fig in FIGURES[name]:
        data = (d / fig).read_bytes()
        assert data.startswith(b'\x89PNG') and len(data) > 10000, fig
    assert summary['experiment'] == name
    assert summary['duration_scale'] == SCALES[name]
    # nothing but the results: no temporary files left behind
    assert sorted(os.listdir(d)) == sorted(FIGURES[name] + ['summary.json'])


def test_chirp_models_follow_measured_velocity(results):
    _, s = results['chirp']
    low, high = (f'{a:g}' for a in s['amplitudes'])
    assert s['peak_velocity'][high] > s['peak_velocity'][low] > 0.5
    assert s['stiction_fraction'][low] > 0.1           # stick-slip: long stiction phases
    for m in ('lugre', 'gms'):
        for a in (low, high):
            assert s['velocity_rmse_rel'][m][a] < 0.3, (m, a)
            assert s['velocity_rmse'][m][a] < 0.3 * s['peak_velocity'][a], (m, a)
            assert s['velocity_corr'][m][a] > 0.95, (m, a)
            assert s['friction_rmse'][m][a] < 1.0, (m, a)     # Nm, against ~5 Nm friction
    assert max(s['effort_rmse'].values()) < 0.05          # current loop follows the command


def test_compensation_beats_no_compensation(results):
    _, s = results['compensation']
    mx, rmse = s['max_error_pct'], s['rmse']
    assert set(mx) == {'none', 'lugre', 'gms'}
    assert s['gains']['preset'] == 'paper' and s['truth_model'] == 'lugre'
    assert 0.1 < s['loop']['zeta'] < 0.3                   # the soft loop of the paper regime
    for t in ('27', '31', '35'):
        # reached by self-heating from the 25 degC ambient, not imposed (this truth's
        # small heat capacity cools by some 0.1 K while the joint returns to rest)
        assert abs(s['warm_up'][t]['reached'] - float(t)) < 1.0
        assert s['warm_up'][t]['heating_s'] > 1.0
        for a in ('0.4', '2.4'):
            # the model matching the hardware (LuGre) compensates; GMS is only reported
            assert mx['lugre'][t][a] < 0.6 * mx['none'][t][a], (t, a)
            assert rmse['lugre'][t][a] < 0.5 * rmse['none'][t][a], (t, a)
            assert mx['gms'][t][a] > 0.0
    # the desired-velocity variant is reported for both models
    var = s['ff_velocity_variants']['desired']['max_error_pct']
    assert set(var) == {'lugre', 'gms'} and var['gms']['35']['2.4'] > 0.0
    assert s['ff_velocity'] == 'measured'


def test_estimation_better_with_friction_model(results):
    _, s = results['estimation']
    rms, rms_pct = s['rms_error'], s['rms_error_pct']
    assert s['load_amplitude'] > 5.0                       # the lever load swings widely
    for m in ('lugre', 'gms'):
        assert rms[m] < 0.25 * rms['none'], m
        assert s['max_error'][m] < s['max_error']['none'], m
    assert rms_pct['lugre'] <= 5.0                         # issue target
    assert s['max_error']['lugre'] < 1.0                   # paper: < 1 Nm
    assert rms_pct['none'] > 15.0                          # friction dominates without model
    assert s['link_sensor_rms_error'] < 0.1


def test_zoom_windows_hold_the_reported_maximum(results):
    # Fig. 8: the zoom holds the sample of the larger LuGre/GMS maximum of the table
    _, s = results['estimation']
    worst = max(('lugre', 'gms'), key=lambda m: s['max_error'][m])
    zoom = s['zoom']
    assert zoom['model'] == worst and zoom['max_error'] == s['max_error'][worst]
    t0, t1 = zoom['window_s']
    assert t0 <= s['max_error_time'][worst] <= t1
    assert s['max_error_time'][worst] >= s['settle_s']
    # Fig. 6: each panel's zoom holds its larger LuGre/GMS maximum
    _, c = results['compensation']
    for tk, per_amp in c['zoom'].items():
        for ak, z in per_amp.items():
            worst = max(('lugre', 'gms'), key=lambda m: c['max_error'][m][tk][ak])
            assert z['model'] == worst
            assert z['window_s'][0] <= c['max_error_time'][worst][tk][ak] <= z['window_s'][1]


def test_reversal_peak_window_holds_a_maximum_away_from_reversals():
    # the largest error lies 0.35 s after a reversal, beyond the 0.3 s the window
    # shows after one: the window of the reversal with the largest error inside it
    # (at 5 s) would miss it
    t = np.arange(0.0, 10.0, 1e-3)
    err = 0.5 * np.exp(-((t - 5.0) / 0.02) ** 2) + 2.0 * np.exp(-((t - 7.35) / 0.02) ** 2)
    t0, t1 = reversal_peak_window(t, [err, 0.5 * err], [2.0, 5.0, 7.0], 1.0, 0.1, 0.3)
    assert t0 <= 7.35 <= t1 and t0 <= 7.0 - 0.1 + 1e-9     # the reversal framed too
    # no reversal near: centred on the maximum
    t0, t1 = reversal_peak_window(t, [err], [2.0], 1.0, 0.1, 0.3)
    assert t0 <= 7.35 <= t1 and t1 - t0 == pytest.approx(0.4, abs=2e-3)
    # a larger error in the settling interval does not count
    t0, t1 = reversal_peak_window(t, [err + 5.0 * (t < 1.0)], [0.5, 7.0], 1.0, 0.1, 0.3)
    assert t0 <= 7.35 <= t1


def test_progress_reaches_the_experiments_that_take_it(tmp_path, monkeypatch):
    assert 'progress' in inspect.signature(compensation).parameters

    def stub(model, truth, duration_scale=1.0, *, gains=None, progress=None):
        progress('warm-up to 27 degC by self-heating')
        return ExperimentResult('stub', {'experiment': 'compensation'})
    monkeypatch.setitem(runner.EXPERIMENTS, 'compensation',
                        runner.EXPERIMENTS['compensation']._replace(func=stub))
    said = []
    run_experiment('compensation', MODEL, TRUTH, tmp_path / 'out', progress=said.append)
    assert said == ['warm-up to 27 degC by self-heating']
    # an experiment without the parameter runs as before; the job says that it runs once it
    # has run QUIET_FOR s (a quick run, or one refused at once, stays silent)
    monkeypatch.setitem(runner.EXPERIMENTS, 'compensation', runner.EXPERIMENTS[
        'compensation']._replace(func=lambda model, truth, scale: ExperimentResult('stub', {})))
    said = []
    run_experiment('compensation', MODEL, TRUTH, tmp_path / 'out2', progress=said.append)
    assert said == []
    monkeypatch.setattr(experiment_job, 'QUIET_FOR', 0.05)

    def slow(model, truth, scale):
        time.sleep(0.5)
        return ExperimentResult('stub', {})
    monkeypatch.setitem(runner.EXPERIMENTS, 'compensation', runner.EXPERIMENTS[
        'compensation']._replace(func=slow))
    run_experiment('compensation', MODEL, TRUTH, tmp_path / 'out3', progress=said.append)
    assert said[0].startswith('compensation: still simulating on the test bed after'), said
    assert said[1].startswith('compensation: simulated in ') and len(said) == 2, said


def test_missing_model_file_exits_2_without_output(tmp_path, capsys):
    out = tmp_path / 'out'
    assert _run('chirp', out, model=str(tmp_path / 'nope.yaml')) == 2
    assert 'nope.yaml' in capsys.readouterr().err
    assert not (out / 'summary.json').exists()
    assert not out.exists()


@pytest.mark.parametrize('scale', ['0', '-1', 'nan', '1e-6'])
def test_bad_duration_scale_exits_2(tmp_path, capsys, scale):
    out = tmp_path / 'out'
    assert _run('compensation', out, '--duration-scale', scale) == 2
    assert 'duration' in capsys.readouterr().err
    assert not out.exists()


def test_model_without_gms_section_exits_2(tmp_path, capsys):
    text = open(MODEL).read()
    start = text.index('      gms:')
    end = text.index('    lever:')
    model = tmp_path / 'no_gms.yaml'
    model.write_text(text[:start] + text[end:])
    out = tmp_path / 'out'
    assert _run('estimation', out, model=str(model)) == 2
    assert 'friction.gms' in capsys.readouterr().err
    assert not out.exists()
