# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
Figures and Markdown report of a diagnosis (:func:`friction_joint.diagnosis.pipeline.diagnose`).

Figures (PNG bytes, rendered with :func:`friction_joint.results.render_png`):

* ``torque.png``: measured friction torque vs the held-out predictions of the
  base and the extended model over time, and both residuals;
* ``velocity.png``: measured velocity vs the open-loop simulations of both
  models over a few held-out windows;
* ``cause_<effect>.png``: the base model's held-out residual (before the
  effect was added) and the residual after, against the effect's variable;
* ``gains.png``: held-out gain of every candidate in every greedy round;
* ``residual_scan.png``: the open residual scan
  (:func:`~friction_joint.diagnosis.scan_report.draw_scan`).
"""
from __future__ import annotations

import math

import numpy as np

from .criterion import effect_variables
from .findings import candidate_summary, finding_lines, next_step_lines
from .scan_report import draw_scan, markdown_lines, SCAN_SIZE
from .structures import accumulated_travel
from ..results import render_png

__all__ = ['figures', 'figure_drawers', 'markdown', 'CAUSE_VARIABLES']

#: effect -> axis label of the variable its residual is plotted against
CAUSE_VARIABLES = {
    'thermal': 'housing temperature xi (degC); residual x sign(qd)',
    'load': 'load |tau_ext| (Nm); residual x sign(qd)',
    'position_ripple': 'q modulo the ripple period (fraction of a period)',
    'nonlinear_viscous': '|qd| (rad/s); residual x sign(qd)',
    'stribeck': '|qd| (rad/s); residual x sign(qd)',
    'presliding': 'travel since the last velocity reversal (mrad); residual x sign(qd)',
    'inertia': 'acceleration qdd (rad/s^2)',
    'asymmetry': 'velocity qd (rad/s)',
    'drift': 'accumulated travel (fraction of the total); residual x sign(qd)',
    'gravity': 'output angle q (rad)',
}

#: confound variable -> axis label (criterion.effect_variables)
CONFOUND_AXES = {'thermal': 'housing temperature xi (degC)',
                 'drift': 'accumulated travel (fraction of the total)',
                 'gravity': 'output angle q (rad)',
                 'position_ripple': 'output angle q (rad)', 'load': 'load |tau_ext| (Nm)'}


def _travel_since_reversal(data):
    qf = data.qf
    s = np.sign(np.diff(qf, prepend=qf[0]))
    nz = np.flatnonzero(s)
    rev = np.zeros(len(qf), dtype=np.int64)
    if len(nz) > 1:
        change = nz[1:][s[nz[1:]] != s[nz[:-1]]]
        rev[change] = change
    rev = np.maximum.accumulate(rev)
    return data.average(np.abs(qf - qf[np.maximum(rev - 1, 0)]))


def _variable(effect, data, diag):
    sgn = np.sign(data.average(data.qd))
    if effect == 'thermal':          # F_c and F_v terms: the residual's sign follows qd
        return data.average(data.xi), sgn, False
    if effect == 'load':
        return data.average(data.tl), sgn, False
    if effect == 'position_ripple':
        cyc = diag.report['extended_fit'].get('position_ripple', {}).get(
            'cycles_per_rev', 2 * diag.base.gear_ratio)
        per = 2 * math.pi / cyc
        return np.mod(data.average(data.q), per) / per, 1.0, False
    if effect in ('nonlinear_viscous', 'stribeck'):
        return np.abs(data.average(data.qd)), sgn, True
    if effect == 'presliding':
        return 1e3 * _travel_since_reversal(data), sgn, True
    if effect == 'inertia':
        return data.average(data.qdd), 1.0, False
    if effect == 'gravity':
        return data.average(data.q), 1.0, False
    if effect == 'drift':
        return data.average(accumulated_travel(data)), sgn, False
    return data.average(data.qd), 1.0, False


def _binned(x, r, n=30, log=False):
    lo, hi = np.percentile(x, 1), np.percentile(x, 99)
    if log:
        lo = max(lo, 1e-4)
        edges = np.geomspace(lo, max(hi, lo * 1.01), n + 1)
    else:
        edges = np.linspace(lo, hi if hi > lo else lo + 1, n + 1)
    idx = np.digitize(x, edges) - 1
    ok = (idx >= 0) & (idx < n)
    cnt = np.bincount(idx[ok], minlength=n)
    mean = np.bincount(idx[ok], weights=r[ok], minlength=n) / np.maximum(cnt, 1)
    mid = np.sqrt(edges[1:] * edges[:-1]) if log else 0.5 * (edges[1:] + edges[:-1])
    return mid[cnt > 0], mean[cnt > 0]


def figures(diag):
    """``[(file name, png bytes), ...]`` of a diagnosis (:func:`figure_drawers` rendered)."""
    return [(name, render_png(*spec[:2], tight=spec[2] if len(spec) > 2 else True))
            for name, spec in figure_drawers(diag).items()]


def figure_drawers(diag):
    """
    Return ``{file name: (draw, size[, tight])}`` of a diagnosis's figures.

    For :func:`figures` (the report's PNG files) and
    :func:`friction_joint.results.draw_figures` (:meth:`Diagnosis.plot
    <friction_joint.diagnosis.pipeline.Diagnosis.plot>`).
    """
    data, rep = diag.data, diag.report
    y = data.y
    out = {}
    tb = data.t_bin
    pb, pe = diag.base_cv.pred, diag.final_cv.pred

    def torque(fig):
        ax = fig.subplots(2, 1, sharex=True)
        # models as larger pale points underneath, the measurement on top stays visible
        ax[0].plot(tb, pb, '.', ms=4.0, color='C3', alpha=0.35, label='base model (held out)')
        ax[0].plot(tb, pe, '.', ms=4.0, color='C0', alpha=0.35,
                   label='extended model (held out)')
        ax[0].plot(tb, y, '.', ms=1.2, color='k', zorder=3,
                   label='measured tau - tau_ext - J qdd')
        ax[0].set_ylabel('friction torque (Nm)')
        ax[0].legend(loc='upper right', fontsize=8, markerscale=6)
        ax[1].plot(tb, y - pb, '.', ms=1.5, color='C3',
                   label=f'base: RMSE {rep["baseline"]["torque_rmse"]:.4f} Nm')
        ax[1].plot(tb, y - pe, '.', ms=1.5, color='C0',
                   label=f'extended: RMSE {rep["extended"]["torque_rmse"]:.4f} Nm')
        ax[1].set_ylabel('residual (Nm)')
        ax[1].set_xlabel('time (s), 10 ms bin averages while sliding')
        ax[1].legend(loc='upper right', fontsize=8, markerscale=6)
    out['torque.png'] = (torque, (10, 6.5))

    vel = diag.velocity
    if vel['measured'].size:
        def velocity(fig):
            ax = fig.subplots(1, 1)
            nw = vel['measured'].shape[0]
            pick = np.unique(np.linspace(0, nw - 1, min(nw, 6)).astype(int))
            n = vel['measured'].shape[1]
            for j, w in enumerate(pick):
                x = j * (n + 50) + np.arange(n)
                ax.plot(x, vel['measured'][w], color='k', lw=1,
                        label='measured' if j == 0 else None)
                ax.plot(x, vel['base'][w], color='C3', lw=1,
                        label='base, open loop' if j == 0 else None)
                ax.plot(x, vel['extended'][w], color='C0', lw=1, ls='--',
                        label='extended, open loop' if j == 0 else None)
            ax.set_xlabel('samples (held-out windows side by side)')
            ax.set_ylabel('velocity (rad/s)')
            ax.set_title(f'open-loop simulation from measured states: velocity RMSE base '
                         f'{rep["baseline"]["velocity_rmse"]:.4g}, extended '
                         f'{rep["extended"]["velocity_rmse"]:.4g} rad/s', fontsize=9)
            ax.legend(fontsize=8)
        out['velocity.png'] = (velocity, (10, 4))

    rounds = {r['round']: r for r in diag.rounds}
    for eff in rep['named_causes']:
        entry = next(c for c in rep['candidates'] if c['effect'] == eff)
        rnd = rounds[entry['round']]
        before = y - rnd['cur_cv'].pred
        after = y - rnd['cv'][eff].pred
        x, sgn, log = _variable(eff, data, diag)

        def cause(fig, x=x, sgn=sgn, log=log, before=before, after=after, eff=eff):
            ax = fig.subplots(1, 1)
            ax.plot(x, before * sgn, '.', ms=1.5, color='C3', alpha=0.4,
                    label='residual before (held out)')
            ax.plot(x, after * sgn, '.', ms=1.5, color='C0', alpha=0.4,
                    label=f'after adding {eff}')
            for r, c in ((before, 'C3'), (after, 'C0')):
                bx, bm = _binned(x, r * sgn, log=log)
                ax.plot(bx, bm, '-', color=c, lw=2)
            if log:
                ax.set_xscale('log')
            ax.set_xlabel(CAUSE_VARIABLES[eff])
            ax.set_ylabel('torque residual (Nm)')
            ax.set_title(f'{eff}: held-out gain {100 * entry["gain"]:.1f} %, '
                         f'p (Holm) {entry.get("p_holm", float("nan")):.2g}', fontsize=9)
            ax.legend(fontsize=8, markerscale=6)
        out[f'cause_{eff}.png'] = (cause, (7, 4.5))

    def gains(fig):
        ax = fig.subplots(1, 1)
        effs = [c['effect'] for c in rep['candidates']]
        nr = len(rep['rounds'])
        w = 0.8 / max(nr, 1)
        named = rep['named_causes']
        for i, r in enumerate(rep['rounds']):
            g = {c['effect']: c.get('gain_raw', 0.0) for c in r['candidates']}
            sig = {c['effect'] for c in r['candidates'] if c.get('significant')}
            vals = [100 * g.get(e, np.nan) for e in effs]
            x = np.arange(len(effs)) + i * w
            against = ('against the base model' if i == 0 else
                       'after adding ' + ', '.join(named[:i]))
            bars = ax.bar(x, vals, w, color=f'C{i}', label=f'round {r["round"]}: {against}')
            for e, b in zip(effs, bars):
                if e not in sig:            # not significant: hatched, pale
                    b.set_alpha(0.45)
                    b.set_hatch('//')
            for e, xx, v in zip(effs, x, vals):
                if e in sig and math.isfinite(v):
                    ax.annotate('named' if e in named else 'significant', (xx, v),
                                ha='center', va='bottom', fontsize=7)
        ax.axhline(100 * rep['criterion']['min_gain'], color='k', ls=':', lw=1,
                   label='minimum gain (named only if also significant)')
        ax.bar([np.nan], [np.nan], color='0.7', hatch='//', alpha=0.45,
               label='hatched: not significant (p (Holm) >= '
                     f'{rep["criterion"]["alpha"]:g})')
        ax.set_xticks(np.arange(len(effs)) + 0.4 - w / 2)
        ax.set_xticklabels(effs, rotation=30, ha='right')
        ax.set_ylabel('held-out torque RMSE reduction (%)')
        ax.set_title('gain of each candidate per round; the table gives the last round for '
                     'effects not named', fontsize=9)
        ax.set_ylim(max(-20, ax.get_ylim()[0]), 100)
        ax.legend(fontsize=7)
    out['gains.png'] = (gains, (8, 4.5))
    variables = effect_variables(data, diag.ctx.travel) if rep.get('confounds') else {}
    for pair in rep.get('confounds', []):
        a, b = pair['effects']

        def confound(fig, a=a, b=b, rho=pair['rank_correlation']):
            ax = fig.subplots(1, 1)
            ax.plot(variables[b], variables[a], '.', ms=1.5, color='k')
            ax.set_xlabel(CONFOUND_AXES[b])
            ax.set_ylabel(CONFOUND_AXES[a])
            ax.set_title(f'{a} and {b} confounded in this recording:\nrank correlation '
                         f'{rho:+.2f} over the sliding bins', fontsize=9)
        out[f'confound_{a}_{b}.png'] = (confound, (6, 4.5))
    if diag.scan is not None:
        out['residual_scan.png'] = (lambda fig: draw_scan(fig, diag.scan), SCAN_SIZE, False)
    return out


def _fmt(v, spec='.3g'):
    return '-' if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def _gap_lines(gaps):
    """Sentence on the gaps of the stamps (bridged, split), empty when there are none."""
    if not gaps or not (gaps['bridged'] or gaps['split']):
        return []
    text = f'Gaps in the /joint_states stamps: {gaps["bridged"]} bridged'
    if gaps['bridged']:
        text += (f' (the longest {1e3 * gaps["longest_bridged_s"]:.1f} ms, '
                 f'{gaps["longest_bridged_samples"]:.1f} sample times; interpolated, the samples '
                 'around them left out of the fits)')
    return [text + f', {gaps["split"]} too long to bridge (pieces cut there).  '
            f'Rule: {gaps["rule"]}.', '']


def markdown(diag, figure_names, model_path, out_dir=None):
    """``report.md`` text: findings and next steps first, then the details."""
    rep = diag.report
    crit = rep['criterion']
    xi = rep['data']['xi_range']
    temp = 'no temperature signal'
    if rep['data'].get('has_temperature', True):
        temp = f'temperature {xi[0]:.2f}..{xi[1]:.2f} degC'
    lines = ['# Friction model diagnosis', '',
             *finding_lines(diag),
             *next_step_lines(rep, out_dir, rep['data']['recordings']),
             '## Data', '',
             f'Base model: `{model_path}`  ',
             'Recordings: ' + ', '.join(f'`{p}`' for p in rep['data']['recordings']), '',
             f'{rep["data"]["sliding_s"]:.1f} s of sliding data (10 ms bins), '
             f'{temp}, sliding above {rep["data"]["scales"]["v_stick"]:.3g} rad/s, '
             f'external torque from the {rep["data"]["torque_source"]}.', '',
             *_gap_lines(rep['data'].get('gaps')),
             '## Result', '',
             f'**{rep["headline"]}**', '', *_adequacy_lines(rep), *_confound_lines(rep),
             '| held-out | base | extended |', '|---|---|---|',
             f'| torque RMSE (Nm) | {_fmt(rep["baseline"]["torque_rmse"], ".4f")} | '
             f'{_fmt(rep["extended"]["torque_rmse"], ".4f")} |',
             f'| velocity RMSE, {rep["data"]["window_s"]:g} s open-loop windows (rad/s) | '
             f'{_fmt(rep["baseline"]["velocity_rmse"], ".4g")} | '
             f'{_fmt(rep["extended"]["velocity_rmse"], ".4g")} |', '',
             '## Criterion', '',
             'In plain words: an effect is named only when adding it to the model predicts '
             'the torque of data the fit has not seen better, in most time blocks and by '
             'enough to matter.', '',
             f'{crit["blocks"]} contiguous time blocks; every model is fitted on the other blocks '
             'and predicts the held-out one.  Per block the statistic is '
             f'{crit["statistic"]} (d_k > 0: the candidate predicted block k better); '
             f'{crit["test"]}; {crit["multiplicity"]} (testing several candidates at once '
             'makes a lucky one likely; the correction raises each p-value accordingly).  '
             f'A candidate is significant when its adjusted p-value is below {crit["alpha"]} and '
             f'its gain ({crit["gain"]}) is at least {100 * crit["min_gain"]:.0f} % or the '
             f'RMS torque it explains held out is at least '
             f'{100 * crit.get("min_explained", 0):.0f} % of the friction level.  '
             f'Selection: {crit["selection"]}.', '',
             '## Candidates', '',
             '*gain*: how much smaller the held-out torque error gets with the effect added '
             '(*round 1*: against the base model; *gain*: in the round given, against the model '
             'at that round).  *p*: the chance of an improvement this consistent over the '
             'blocks if the effect were not there; *p (Holm)*: the same corrected for the '
             'number of candidates tested; *blocks improved*: in how many of the time blocks '
             'the candidate predicted better.', '',
             '| effect | testable | gain round 1 | round | gain | p | p (Holm) | '
             'blocks improved | significant | note |',
             '|---|---|---|---|---|---|---|---|---|---|']
    first = {c['effect']: c for c in rep['rounds'][0]['candidates']} if rep['rounds'] else {}
    for c in rep['candidates']:
        if not c.get('testable', True):
            lines.append(f'| {c["effect"]} | no | - | - | - | - | - | - | no | {c["reason"]} |')
            continue
        g1 = first.get(c['effect'], {}).get('gain_raw')
        g1 = '-' if g1 is None else f'{100 * g1:+.1f} %'
        note = c.get('note', '')
        if c.get('physical') is False:
            note = 'not physical, left out of extended.yaml: ' + c.get('reason', '')
        elif c.get('representable') is False:
            note = c.get('reason', '')
        lines.append(f'| {c["effect"]} | yes | {g1} | {c.get("round", "-")} | '
                     f'{100 * c.get("gain", 0):.1f} % | '
                     f'{_fmt(c.get("p_value"), ".2g")} | {_fmt(c.get("p_holm"), ".2g")} | '
                     f'{c.get("blocks_improved", "-")}/{c.get("blocks", "-")} | '
                     f'{"**yes**" if c["significant"] else "no"} | {note} |')
    lines += ['', 'Named effects: gain when added (against the model at that round); the others: '
              'gain against the final model.  An untestable candidate (the data cannot tell '
              'it) is never named.', '']
    lines += [f'**Not named despite a large first-round gain:** {t}' for t in
              candidate_summary(rep)]
    if candidate_summary(rep):
        lines.append('')
    for note in rep.get('notes', []):
        lines += [f'**Note:** {note}', '']
    adj = rep['extended_fit'].get('sigma1_passivity')
    if adj:
        lines += [f'`extended.yaml`: friction.lugre.sigma1 lowered from {adj["from"]:g} to '
                  f'{adj["to"]:g}, below the passivity bound sigma2 Fc / (Fs - Fc) = '
                  f'{adj["bound"]:.4g} of the extended curve (Astrom & Canudas de Wit 2008).', '']
    for name in figure_names:
        if name != 'residual_scan.png':
            lines += [f'![{name}]({name})', '']
    if rep.get('residual_scan'):
        lines += markdown_lines(rep['residual_scan'])
        lines += ['In plain words: a flagged variable is one the remaining error still '
                  'follows, more than chance would give when the error is shifted in time '
                  'against it; it points at an effect outside the candidate list.', '']
    lines += ['## Timing', '', '| stage | s |', '|---|---|']
    lines += [f'| {k} | {v:.2f} |' for k, v in rep['timing'].items()]
    return '\n'.join(lines) + '\n'


def _adequacy_lines(rep):
    """Return the table of how much of the measured friction torque each model explains."""
    ad = rep['adequacy']
    rows = [('held-out R^2 of the friction torque', 'r2', '.3f'),
            ('held-out RMSE / friction level', 'rmse_over_level', '.3f')]
    return (['| model adequacy | base | extended |', '|---|---|---|'] +
            [f'| {label} | {_fmt(ad["base"][k], spec)} | {_fmt(ad["extended"][k], spec)} |'
             for label, k, spec in rows] +
            ['', f'Friction level (the median of abs(measured friction torque)): '
             f'{ad["base"]["friction_level"]:.4g} Nm.', ''])


def _confound_lines(rep):
    """Return the confounded candidate pairs of this recording, with what separates them."""
    out = []
    for c in rep.get('confounds', []):
        a, b = c['effects']
        out += [f'**Confounded:** {a} and {b} (rank correlation of their variables '
                f'{c["rank_correlation"]:+.2f}): this recording cannot tell them apart; '
                f'{c["separate_by"]} would.  Of the two, {a} (a measured cause) is preferred.',
                '']
    return out
