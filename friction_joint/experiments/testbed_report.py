# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Report text of the test-bed experiments: what was run, what the figure shows, the paper beside us.

:func:`testbed_markdown` turns the ``summary.json`` of each experiment, run
against each hardware model (LuGre and GMS truth), into Markdown: one
paragraph per experiment and a table with the paper's number next to ours.
Numbers are rounded to what they mean (0.1 % for tracking errors, 0.01 Nm for
torques, 0.001 rad/s for velocities).  The paper's numbers, quoted from its
Section V and conclusion, come from :data:`~friction_joint.paper.PAPER`.
"""
from ..paper import PAPER

__all__ = ['testbed_markdown']

NAMES = {'none': 'no friction model', 'lugre': 'LuGre', 'gms': 'GMS', 'fc': 'F_c', 'fs': 'F_s',
         'fv': 'F_v', 'vs': 'v_s'}
HARDWARE = {'lugre': 'LuGre hardware', 'gms': 'GMS hardware'}


def _p(key):
    """Return the paper's number ``key`` (:data:`~friction_joint.paper.PAPER`)."""
    return PAPER[key].value


def _f(x, digits=1):
    return '–' if x is None else f'{x:.{digits}f}'


def _images(rel_dir, names):
    return [f'![{n}]({rel_dir}/{n})' for n in names]


def _figures(runs, rel, experiment, names):
    """Figures of ``experiment`` for every hardware model, each under a bold label."""
    lines = []
    for hw in runs:
        lines += [f'**{HARDWARE[hw]}**', ''] + _images(f'{rel}/{hw}/{experiment}', names) + ['']
    return lines


def _loop_sentence(s):
    g, lp = s['gains'], s['loop']
    design = (f'designed for {g["design_inertia"]:.3g} kg m² (preset `{g["preset"]}`)'
              if g.get('design_inertia') else f'given directly (`{g["preset"]}`)')
    return (f'Gains k_p = {g["kp"]:.1f} Nm/rad, k_d = {g["kd"]:.2f} Nm s/rad, {design} '
            f'for {_p("rise_time"):g} s rise time and {_p("overshoot"):g} % overshoot; on the '
            'hardware’s '
            f'{lp["inertia"]:.3g} kg m² they make a loop with '
            f'ω_n = {lp["omega_n"]:.1f} rad/s, ζ = {lp["zeta"]:.2f}, '
            f'{100 * lp["overshoot"]:.0f} % overshoot and {1e3 * lp["rise_time"]:.0f} ms '
            'rise time.')


def _compensation(runs, rel):
    lines = ['### Friction compensation (paper Fig. 6 and Fig. 7)', '']
    first = next(iter(runs.values()))
    temps = list(first['warm_up'])
    warm = ', '.join(f'{first["warm_up"][t]["reached"]:.1f} °C after '
                     f'{first["warm_up"][t]["elapsed_s"]:.0f} s' for t in temps)
    lo, hi = _p('uncompensated_band')
    lines += [
        'The joint tracks q_d = a sin(1.5 t) for a = 0.4 rad (peak '
        f'{_p("peak_velocity_low"):g} rad/s, the paper’s low velocity) and a = 2.4 rad '
        '(3.6 rad/s) with the controller of eq. 17, without friction '
        'feed-forward and with LuGre or GMS feed-forward, the same gains in every run. '
        + _loop_sentence(first) + ' The gear is heated to the three operating temperatures by '
        'its own friction losses on a 2.4 rad sinusoid, then brought to rest at q = 0 '
        f'(the LuGre hardware reached {warm}). The maximum of |q_d − q| over two periods after '
        'a 1 s settling interval is given in % of a; the figures show the error over time '
        '(Fig. 6) and the maxima as bars with the RMSE as thin bars (Fig. 7).', '',
        f'The paper reports {lo:g}-{hi:g} % without compensation at a = 0.4 rad, depending on '
        f'the temperature, and {_p("compensated_lugre"):g} % (LuGre) and '
        f'{_p("compensated_gms"):g} % (GMS) with it. Its hardware is one gear with one '
        'friction; ours is simulated twice, once with LuGre and once with GMS friction, '
        'so the table shows the matching model (the one playing the hardware), beside the '
        "paper's number for it, and the mismatched one, which the paper has no case "
        'for.', '']
    head = '| hardware | feed-forward | ' + ' | '.join(f'{t} °C' for t in temps)
    head += ' | RMSE at ' + temps[0] + ' °C (mrad) | paper |'
    lines += ['Maximum tracking error at a = 0.4 rad, % of a:', '', head,
              '|' + '---|' * (len(temps) + 4)]
    for hw, s in runs.items():
        for m in ('none', 'lugre', 'gms'):
            mx = s['max_error_pct'][m]
            paper = (f'{lo:g}-{hi:g} %' if m == 'none' else
                     f'{_p("compensated_" + m):g} %' if m == hw else '– (no such case)')
            match = ' (matching)' if m == hw else (' (mismatched)' if m != 'none' else '')
            lines.append(f'| {HARDWARE[hw]} | {NAMES[m]}{match} | '
                         + ' | '.join(_f(mx[t]['0.4']) for t in temps)
                         + f' | {_f(1e3 * s["rmse"][m][temps[0]]["0.4"], 2)} | {paper} |')
    lines += ['', 'At a = 2.4 rad (high velocity) the maxima are '
              + '; '.join(f'{HARDWARE[hw]}: '
                          + ', '.join(f'{NAMES[m]} {_f(s["max_error_pct"][m][temps[0]]["2.4"])}'
                                      for m in ('none', 'lugre', 'gms'))
                          + f' % at {temps[0]} °C' for hw, s in runs.items())
              + ' (the paper shows this case in Fig. 6(c, d) without a number).', '']
    for hw, s in runs.items():
        for m in ('lugre', 'gms'):
            if m == hw or 'gms' not in (m, hw):
                continue
            worst = max(t['0.4'] for t in s['max_error_pct'][m].values())
            matching = max(t['0.4'] for t in s['max_error_pct'][hw].values())
            if m == 'gms' and worst > 2.0 * matching:
                lines += [
                    f'GMS feed-forward on the LuGre hardware does much worse (up to '
                    f'{worst:.1f} % against {matching:.1f} % for LuGre). At a reversal of q_d '
                    'the joint sticks while the measured velocity still flickers around zero; '
                    'slipping GMS elements relax at a rate that does not depend on the speed, '
                    'so every small flicker in the old direction pulls the feed-forward back '
                    "towards the old direction's friction level, and it holds the joint for a "
                    'few tenths of a second (the zoom in Fig. 6).', '']
    return lines + _figures(runs, rel, 'compensation',
                            ['compensation_error.png', 'compensation_bars.png'])


def _estimation(runs, rel):
    first = next(iter(runs.values()))
    lines = ['### External torque estimation (paper Fig. 8)', '',
             'The joint follows a sum of two sinusoids over most of ±1.5 rad, so the lever’s '
             f'gravity sweeps about ±{first["load_amplitude"]:.1f} Nm at varying speed, at '
             f'{first["xi0"]:g} °C. The disturbance observer of eq. 15 (β = '
             f'{first["beta"]:g} rad/s) leaves gravity out, so the lever load is the external '
             'torque it has to find, as in the paper; it runs without a friction model '
             '(eq. 4), with LuGre and with GMS. The figure shows the applied and estimated '
             'torque and the estimation error. The paper reports an error below '
             f'{_p("estimation_max"):g} Nm and "approximately '
             f'{_p("estimation_pct"):g} %".', '',
             '| hardware | observer model | max error (Nm) | RMS error (Nm) | RMS (% of load) '
             '| max (% of load) | paper |', '|---|---|---|---|---|---|---|']
    for hw, s in runs.items():
        for m in ('none', 'lugre', 'gms'):
            match = ' (matching)' if m == hw else (' (mismatched)' if m != 'none' else '')
            paper = ('–' if m == 'none' else '– (no such case)' if m != hw else
                     f'< {_p("estimation_max"):g} Nm, ≈ {_p("estimation_pct"):g} %')
            lines.append(f'| {HARDWARE[hw]} | {NAMES[m]}{match} | {_f(s["max_error"][m], 2)} | '
                         f'{_f(s["rms_error"][m], 2)} | {_f(s["rms_error_pct"][m])} | '
                         f'{_f(s["max_error_pct"][m])} | {paper} |')
    lines += ['']
    for hw, s in runs.items():
        near, span = s.get('reversal_distance_of_max_error'), s.get('large_error_reversal_span')
        if not near:
            continue
        for m in ('lugre', 'gms'):
            if m == hw or near.get(m) is None or (span or {}).get(m) is None:
                continue                  # a run too short to hold a reversal
            lines += [f'The mismatched {NAMES[m]} observer on the {HARDWARE[hw]} has its largest '
                      f'error, {s["max_error"][m]:.2f} Nm, {1e3 * near[m]:.0f} ms from a '
                      'velocity reversal, and every error above a quarter of it lies within '
                      f'{1e3 * span[m]:.0f} ms of one (see the zoom). Reversals are where the '
                      'two families differ: LuGre has one bristle state, GMS elements that '
                      'stick one by one and, while slipping, relax at a rate that does not '
                      'depend on the speed; the model that does not match the hardware '
                      f'mispredicts the friction jump there. The matching {NAMES[hw]} '
                      f'observer stays at {s["max_error"][hw]:.2f} Nm.', '']
    hw = first.get('hardware')
    if hw:
        matching = [s['rms_error_pct'][k] for k, s in runs.items() if k in s['rms_error_pct']]
        lines += [
            f'Why our matching observers reach {_span(matching)} RMS where the paper reports '
            f'"approximately {_p("estimation_pct"):g} %": the simulated hardware is '
            'kinder than a real test bed. The observer sees everything the simulator '
            'models but for small parameter errors: the joint is one rigid inertia '
            f'({hw["inertia"]:.3g} kg m² against the model’s {hw["model_inertia"]:.3g}), with '
            'no compliance or resonance of the flexspline between motor and link; its '
            'friction follows exactly the equations and polynomial structure of the model '
            '(the family of the hardware) with parameter errors of '
            + ', '.join(f'{NAMES.get(k, k)} {v:+.0f} %' for k, v in
                        hw.get('parameter_error_pct', {}).items())
            + f' at {first["xi0"]:g} °C; the only '
            f'unmodelled torque is a {hw["ripple_amplitude"]:.2g} Nm ripple at '
            f'{hw["ripple_cycles_per_rev"]:g} cycles per revolution; and the drive torque the '
            'observer uses is the applied one, behind the current loop (bandwidth '
            f'{hw["current_bandwidth_hz"]:g} Hz, torque noise {hw["torque_noise"]:g} Nm) and '
            f'with {hw["effort_noise"]:g} Nm measurement noise, but without a torque-constant '
            'error. The paper’s gear has what its model '
            'leaves out ("position dependency ..., HD resonance frequencies, and HD ripple", '
            'its Section I) and a friction that no model matches exactly; those are what '
            'an estimate on real hardware has to absorb. The paper does not say what its '
            f'{_p("estimation_pct"):g} % is relative to; ours is the RMS error in % of the '
            'largest load (the table gives the maximum too).', '']
    return lines + _figures(runs, rel, 'estimation', ['estimation.png'])


def _chirp(runs, rel):
    first = next(iter(runs.values()))
    amps = [f'{a:g}' for a in first['amplitudes']]
    lines = ['### Dynamic simulation (paper Fig. 5)', '',
             f'Two chirp torques ({first["f0_hz"]:g} → {first["f1_hz"]:g} Hz over '
             f'{first["duration_s"]:g} s, {amps[0]} Nm and {amps[1]} Nm) drive the hardware '
             'open loop against the lever’s gravity; the low one gives stick-slip with long '
             'stiction phases, the high one reaches higher velocity. The LuGre and GMS joint '
             'models are then simulated with the measured applied torque and temperature as '
             'inputs, as in the paper, and their velocity is compared with the measured one. '
             'The paper states no number ("high accuracy ... including the discontinuity '
             'behavior"); the table gives ours.', '',
             '| hardware | model | ' + ' | '.join(
                 f'velocity RMSE, {a} Nm (rad/s) | correlation, {a} Nm' for a in amps) + ' |',
             '|' + '---|' * (2 + 2 * len(amps))]
    for hw, s in runs.items():
        for m in ('lugre', 'gms'):
            match = ' (matching)' if m == hw else ' (mismatched)'
            lines.append(f'| {HARDWARE[hw]} | {NAMES[m]}{match} | ' + ' | '.join(
                f'{_f(s["velocity_rmse"][m][a], 3)} | {_f(s["velocity_corr"][m][a], 3)}'
                for a in amps) + ' |')
    peaks = '; '.join(f'{HARDWARE[hw]} ' + ', '.join(
        f'{_f(s["peak_velocity"][a], 2)} rad/s at {a} Nm' for a in amps)
        for hw, s in runs.items())
    stiction = ', '.join(f'{100 * s["stiction_fraction"][amps[0]]:.0f} %' for s in runs.values())
    lines += ['', f'Measured peak velocity: {peaks}; share of time in stiction at the low '
              f'amplitude: {stiction}.', '']
    return lines + _figures(runs, rel, 'chirp', ['chirp.png'])


def _sweep(s, rel):
    lo, hi = s['band']
    temps = list(s['max_error_pct']['none'])
    edges = '; '.join(
        f'at {t} °C between {_f(s["band_inertia"][t][1], 3)} and '
        f'{_f(s["band_inertia"][t][0], 3)} kg m²' for t in temps)
    return ['### Where the paper’s regime lies: the design inertia of the gains', '',
            f'The paper designs its gains for {_p("rise_time"):g} s rise time and '
            f'{_p("overshoot"):g} % overshoot but does not say for which inertia. Designed '
            'for the whole joint '
            f'({s["model_inertia"]:g} kg m²) they leave only a few % of tracking error '
            'without compensation; the sweep below runs the uncompensated and the '
            'LuGre-compensated tracking at a = 0.4 rad for design inertias from 1/40 of the '
            'joint inertia up to all of it. The uncompensated error is in the paper’s '
            f'{lo:g}-{hi:g} % band ({edges}); the `paper` preset, 0.016 kg m², is inside it '
            'and is of the order of the drive’s own inertia ("the torque constant and the '
            'motor inertia", Section V-B). This is an inference, not a number of the paper.',
            ''] + _images(f'{rel}/gain_sweep', ['gain_sweep.png']) + ['']


def _span(values, digits=1, unit=' %'):
    """``lo-hi unit`` of ``values`` (one number if they round alike)."""
    values = list(values)
    lo_text, hi_text = (f'{x:.{digits}f}' for x in (min(values), max(values)))
    return f'{lo_text}{unit}' if lo_text == hi_text else f'{lo_text}-{hi_text}{unit}'


def _headline(runs):
    """
    One table: the paper's headline numbers beside ours, like with like.

    Each row is one friction model on one hardware: the paper's number for a
    model stands beside that model on the hardware of its own family (the
    paper's model was identified on its gear); the mismatched pairs, which
    the paper has no counterpart for, follow under their own heading.
    """
    lo, hi = _p('uncompensated_band')
    rows = []

    def row(label, paper, hw, cell):
        try:
            value = cell(runs[hw])
        except KeyError:
            value = '–'
        rows.append(f'| {label} | {paper} | {value} |')

    def comp(m, a='0.4'):
        return lambda r: _span(t[a] for t in r['compensation']['max_error_pct'][m].values())

    def est(m):
        return lambda r: (f'{r["estimation"]["max_error"][m]:.2f} Nm; '
                          f'{r["estimation"]["rms_error_pct"][m]:.1f} %')

    def chirp(m):
        return lambda r: ' / '.join(
            f'{v:.3f}' for v in r['chirp']['velocity_rmse'][m].values()) + ' rad/s'

    paper_est = f'< {_p("estimation_max"):g} Nm; ≈ {_p("estimation_pct"):g} %'
    pairs = [(hw, m) for hw in runs for m in ('lugre', 'gms') if m == hw]
    other = [(hw, m) for hw in runs for m in ('lugre', 'gms') if m != hw]
    for hw in runs:
        row(f'Fig. 7: max tracking error without compensation, a = 0.4 rad, over the '
            f'temperatures; {HARDWARE[hw]}', f'{lo:g}-{hi:g} %', hw, comp('none'))
    for hw, m in pairs:
        row(f'Fig. 7: max tracking error, a = 0.4 rad, **{NAMES[m]} feed-forward on '
            f'{HARDWARE[hw]}**', f'{_p("compensated_" + m):g} %', hw, comp(m))
    for hw, m in pairs:
        row(f'Fig. 8: external torque error, max; RMS in % of the load amplitude, '
            f'**{NAMES[m]} observer on {HARDWARE[hw]}**', paper_est, hw, est(m))
    for hw, m in pairs:
        row(f'Fig. 5: velocity RMSE of the **{NAMES[m]} simulation of {HARDWARE[hw]}**, '
            'low / high amplitude', 'not stated', hw, chirp(m))
    if other:
        rows.append('| *Mismatched: a model of the other family than the hardware’s (no '
                    'counterpart in the paper, whose model was identified on its own '
                    'gear)* | | |')
    for hw, m in other:
        row(f'Fig. 7: max tracking error, a = 0.4 rad, {NAMES[m]} feed-forward on '
            f'{HARDWARE[hw]} (*mismatched*)', '–', hw, comp(m))
    for hw, m in other:
        row(f'Fig. 8: external torque error, max; RMS %, {NAMES[m]} observer on '
            f'{HARDWARE[hw]} (*mismatched*)', '–', hw, est(m))
    for hw, m in other:
        row(f'Fig. 5: velocity RMSE, {NAMES[m]} simulation of {HARDWARE[hw]} '
            '(*mismatched*), low / high amplitude', '–', hw, chirp(m))
    return (['### Headline: the paper’s numbers beside ours', '',
             'Our test bed is simulated twice, with LuGre and with GMS friction in the '
             'hardware. The paper’s number for a friction model stands beside that model '
             'running on the hardware of its own family, which is what the paper did (its '
             'model was identified on its gear). A model of the other family on the '
             'hardware is a second, *mismatched* case the paper has no number for; its '
             'rows come last.', '',
             '| result | paper | ours |', '|---|---|---|'] + rows
            + ['', 'Details, and why the mismatched cases do worse, follow per experiment.',
               ''])


def testbed_markdown(runs, sweep=None, rel='testbed'):
    """
    Return the Markdown lines of the test-bed section of the demo report.

    Parameters
    ----------
    runs : dict
        ``{hardware: {experiment: summary}}``, hardware ``'lugre'`` / ``'gms'``
        (the truth's friction model), experiment ``chirp`` / ``compensation``
        / ``estimation``; summaries as written to ``summary.json``.
    sweep : dict, optional
        Summary of :func:`~friction_joint.experiments.gain_sweep.gain_sweep`.
    rel : str
        Directory of the results relative to the report: figures are at
        ``rel/<hardware>/<experiment>/`` and ``rel/gain_sweep/``.

    """
    lines = ["## Simulated test bed: the paper's three applications", '',
             'Every application runs on the simulated CSD-25 test bed twice: once with '
             'LuGre friction in the hardware (`config/csd25_truth.yaml`) and once with GMS '
             'friction (`config/csd25_truth_gms.yaml`); both differ from the model file '
             '(`config/csd25.yaml`) by identification-sized parameter errors and carry '
             'torque ripple and realistic sensors. The controller and observer use the '
             'model file.', '']
    lines += _headline(runs)
    if sweep is not None:
        lines += _sweep(sweep, rel)
    for name, section in (('compensation', _compensation), ('estimation', _estimation),
                          ('chirp', _chirp)):
        part = {hw: r[name] for hw, r in runs.items() if name in r}
        if part:
            lines += section(part, rel)
    return lines
