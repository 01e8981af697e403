# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

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

from collections.abc import Callable, Sequence
import dataclasses
from functools import partial
import math
from typing import Any, TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from .criterion import effect_variables, verdict as verdict_of
from .findings import candidate_summary, data_ranges, finding_lines, next_step_lines
from .scan_report import draw_scan, markdown_lines, SCAN_SIZE, table_cell
from .structures import accumulated_travel
from ..results import render_png

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .core import DiagnosisCore, VelocitySim
    from .data import DiagnosisData
    from .result import DiagnosisResult, Gaps
    from .verdicts import Confound, CriterionInfo, Round

Array = npt.NDArray[np.float64]
#: a figure's drawing function, its size (inches) and whether it is cut tight
Drawer = tuple[Callable[['Figure'], None], tuple[float, float]] | \
    tuple[Callable[['Figure'], None], tuple[float, float], bool]

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

#: effects whose variable is the sliding speed: drawn only at or above the sliding threshold
SPEED_AXES = ('nonlinear_viscous', 'stribeck')

#: confound variable -> axis label (criterion.effect_variables)
CONFOUND_AXES = {'thermal': 'housing temperature xi (degC)',
                 'drift': 'accumulated travel (fraction of the total)',
                 'gravity': 'output angle q (rad)',
                 'position_ripple': 'output angle q (rad)', 'load': 'load |tau_ext| (Nm)'}


def _travel_since_reversal(data: DiagnosisData) -> Array:
    qf = data.qf
    s = np.sign(np.diff(qf, prepend=qf[0]))
    nz = np.flatnonzero(s)
    rev = np.zeros(len(qf), dtype=np.int64)
    if len(nz) > 1:
        change = nz[1:][s[nz[1:]] != s[nz[:-1]]]
        rev[change] = change
    rev = np.maximum.accumulate(rev)
    return data.average(np.abs(qf - qf[np.maximum(rev - 1, 0)]))


def _variable(effect: str, data: DiagnosisData,
              diag: DiagnosisCore) -> tuple[Array, Array | float, bool]:
    sgn = np.sign(data.average(data.qd))
    if effect == 'thermal':          # F_c and F_v terms: the residual's sign follows qd
        return data.average(data.xi), sgn, False
    if effect == 'load':
        return data.average(data.tl), sgn, False
    if effect == 'position_ripple':
        cyc = diag.result.extended_fit.get('position_ripple', {}).get(
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


def _binned(x: Array, r: Array, n: int = 30, log: bool = False) -> tuple[Array, Array]:
    lo, hi = float(np.percentile(x, 1)), float(np.percentile(x, 99))
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


def figures(diag: DiagnosisCore) -> list[tuple[str, bytes]]:
    """
    Return ``[(file name, png bytes), ...]`` of a diagnosis (:func:`figure_drawers` rendered).

    Parameters
    ----------
    diag : DiagnosisCore
        The diagnosis.

    Returns
    -------
    list of (str, bytes)

    """
    return [(name, render_png(spec[0], spec[1], tight=spec[2] if len(spec) > 2 else True))
            for name, spec in figure_drawers(diag).items()]


def _draw_torque(fig: Figure, tb: Array, y: Array, pb: Array, pe: Array,
                 rmse: tuple[float, float]) -> None:
    """Draw the measured friction torque, both models' held-out predictions and residuals."""
    ax = fig.subplots(2, 1, sharex=True)
    # models as larger pale points underneath, the measurement on top stays visible
    ax[0].plot(tb, pb, '.', ms=4.0, color='C3', alpha=0.35, label='base model (held out)')
    ax[0].plot(tb, pe, '.', ms=4.0, color='C0', alpha=0.35, label='extended model (held out)')
    ax[0].plot(tb, y, '.', ms=1.2, color='k', zorder=3, label='measured tau - tau_ext - J qdd')
    ax[0].set_ylabel('friction torque (Nm)')
    ax[0].legend(loc='upper right', fontsize=8, markerscale=6)
    ax[1].plot(tb, y - pb, '.', ms=1.5, color='C3', label=f'base: RMSE {rmse[0]:.4f} Nm')
    ax[1].plot(tb, y - pe, '.', ms=1.5, color='C0', label=f'extended: RMSE {rmse[1]:.4f} Nm')
    ax[1].set_ylabel('residual (Nm)')
    ax[1].set_xlabel('time (s), 10 ms bin averages while sliding')
    ax[1].legend(loc='upper right', fontsize=8, markerscale=6)


def _draw_velocity(fig: Figure, vel: VelocitySim,
                   rmse: tuple[float | None, float | None]) -> None:
    """Draw the measured and both models' open-loop velocities over a few held-out windows."""
    ax = fig.subplots(1, 1)
    nw = vel.measured.shape[0]
    pick = np.unique(np.linspace(0, nw - 1, min(nw, 6)).astype(int))
    n = vel.measured.shape[1]
    for j, w in enumerate(pick):
        x = j * (n + 50) + np.arange(n)
        ax.plot(x, vel.measured[w], color='k', lw=1, label='measured' if j == 0 else None)
        ax.plot(x, vel.base[w], color='C3', lw=1,
                label='base, open loop' if j == 0 else None)
        ax.plot(x, vel.extended[w], color='C0', lw=1, ls='--',
                label='extended, open loop' if j == 0 else None)
    ax.set_xlabel('samples (held-out windows side by side)')
    ax.set_ylabel('velocity (rad/s)')
    ax.set_title(f'open-loop simulation from measured states: velocity RMSE base '
                 f'{rmse[0]:.4g}, extended {rmse[1]:.4g} rad/s', fontsize=9)
    ax.legend(fontsize=8)


@dataclasses.dataclass(frozen=True)
class _Cause:
    """
    What :func:`_draw_cause` draws of one named effect.

    ``effect``, ``x`` (its variable per bin), ``sign`` (the residual's factor),
    ``log`` (log x axis), ``before`` and ``after`` (held-out residuals), ``gain``
    and ``p_holm`` (its verdict's), ``v_stick`` (the sliding threshold of a speed
    axis, or None): only the bins at or above it are drawn, the threshold marked.
    """

    effect: str
    x: Array
    sign: Array | float
    log: bool
    before: Array
    after: Array
    gain: float
    p_holm: float
    v_stick: float | None


def _draw_cause(fig: Figure, cause: _Cause) -> None:
    """Draw one named effect's residual before and after it was added."""
    x, sgn, before, after = cause.x, cause.sign, cause.before, cause.after
    eff, v_stick = cause.effect, cause.v_stick
    if v_stick is not None:
        keep = x >= v_stick
        x, before, after = x[keep], before[keep], after[keep]
        sgn = sgn[keep] if isinstance(sgn, np.ndarray) and np.ndim(sgn) else sgn
    ax = fig.subplots(1, 1)
    ax.plot(x, before * sgn, '.', ms=1.5, color='C3', alpha=0.4,
            label='residual before (held out)')
    ax.plot(x, after * sgn, '.', ms=1.5, color='C0', alpha=0.4, label=f'after adding {eff}')
    for r, c in ((before, 'C3'), (after, 'C0')) if x.size else ():
        bx, bm = _binned(x, r * sgn, log=cause.log)
        ax.plot(bx, bm, '-', color=c, lw=2)
    if v_stick is not None:
        ax.axvline(v_stick, color='k', ls=':', lw=1,
                   label=f'sliding threshold {v_stick:.3g} rad/s')
    if cause.log:
        ax.set_xscale('log')
    ax.set_xlabel(CAUSE_VARIABLES[eff])
    ax.set_ylabel('torque residual (Nm)')
    ax.set_title(f'{eff}: held-out gain {100 * cause.gain:.1f} %, '
                 f'p (Holm) {cause.p_holm:.2g}', fontsize=9)
    ax.legend(fontsize=8, markerscale=6)


def _draw_gains(fig: Figure, rounds: Sequence[Round], effects: Sequence[str],
                named: Sequence[str], criterion: CriterionInfo) -> None:
    """Draw every candidate's held-out gain in every greedy round (hatched: not significant)."""
    ax = fig.subplots(1, 1)
    nr = len(rounds)
    w = 0.8 / max(nr, 1)
    for i, r in enumerate(rounds):
        g = {c.effect: 0.0 if c.gain_raw is None else c.gain_raw for c in r.candidates}
        sig = {c.effect for c in r.candidates if c.significant}
        vals = [100 * g.get(e, np.nan) for e in effects]
        x = np.arange(len(effects)) + i * w
        against = ('against the base model' if i == 0 else
                   'after adding ' + ', '.join(named[:i]))
        bars = ax.bar(x, vals, w, color=f'C{i}', label=f'round {r.round}: {against}')
        for e, b in zip(effects, bars, strict=True):
            if e not in sig:            # not significant: hatched, pale
                b.set_alpha(0.45)
                b.set_hatch('//')
        for e, xx, v in zip(effects, x, vals, strict=True):
            if e in sig and math.isfinite(v):
                ax.annotate('named' if e in named else 'significant', (xx, v),
                            ha='center', va='bottom', fontsize=7)
    ax.axhline(100 * criterion.min_gain, color='k', ls=':', lw=1,
               label='minimum gain (named only if also significant)')
    ax.bar([np.nan], [np.nan], color='0.7', hatch='//', alpha=0.45,
           label=f'hatched: not significant (p (Holm) >= {criterion.alpha:g})')
    ax.set_xticks(np.arange(len(effects)) + 0.4 - w / 2)
    ax.set_xticklabels(effects, rotation=30, ha='right')
    ax.set_ylabel('held-out torque RMSE reduction (%)')
    ax.set_title('gain of each candidate per round; the table gives the last round for '
                 'effects not named', fontsize=9)
    ax.set_ylim(max(-20, ax.get_ylim()[0]), 100)
    ax.legend(fontsize=7)


def _draw_confound(fig: Figure, pair: Confound, xa: Array, xb: Array) -> None:
    """Draw the variables of two confounded candidates against each other."""
    a, b = pair.effects
    ax = fig.subplots(1, 1)
    ax.plot(xb, xa, '.', ms=1.5, color='k')
    ax.set_xlabel(CONFOUND_AXES[b])
    ax.set_ylabel(CONFOUND_AXES[a])
    ax.set_title(f'{a} and {b} confounded in this recording:\nrank correlation '
                 f'{pair.rank_correlation:+.2f} over the sliding bins', fontsize=9)


def _causes(diag: DiagnosisCore) -> dict[str, _Cause]:
    """
    Return ``{effect: cause}`` of the named effects, what :func:`_draw_cause` draws.

    Each ``cause`` holds the effect's own verdict's held-out ``gain`` and ``p_holm``
    and its residuals at the round it was added.
    """
    data, result = diag.data, diag.result
    rounds = {f.round: f for f in diag.fits}
    out = {}
    for eff in result.named_causes:
        entry = result.candidate(eff)
        assert entry is not None and entry.round is not None, f'{eff} named without a round'
        rnd = rounds[entry.round]
        x, sgn, log = _variable(eff, data, diag)
        out[eff] = _Cause(eff, x, sgn, log, before=data.y - rnd.cur_cv.pred,
                          after=data.y - rnd.cv[eff].pred, gain=float(entry.gain),
                          p_holm=float('nan' if entry.p_holm is None else entry.p_holm),
                          v_stick=(float(result.data.scales.v_stick)
                                   if eff in SPEED_AXES else None))
    return out


def figure_drawers(diag: DiagnosisCore) -> dict[str, Drawer]:
    """
    Return ``{file name: (draw, size[, tight])}`` of a diagnosis's figures.

    For :func:`figures` (the report's PNG files) and
    :func:`friction_joint.results.draw_figures` (:meth:`Diagnosis.plot
    <friction_joint.diagnosis.pipeline.Diagnosis.plot>`).  Every drawing function
    takes what it draws as arguments (bound here with :func:`functools.partial`).

    Parameters
    ----------
    diag : DiagnosisCore
        The diagnosis.

    Returns
    -------
    dict of str to tuple

    """
    data, result = diag.data, diag.result
    rmse = (result.baseline.torque_rmse, result.extended.torque_rmse)
    out: dict[str, Drawer] = {
        'torque.png': (partial(_draw_torque, tb=data.t_bin, y=data.y, pb=diag.base_cv.pred,
                               pe=diag.final_cv.pred, rmse=rmse), (10, 6.5))}
    vel = diag.velocity
    if vel.measured.size:
        vrmse = (result.baseline.velocity_rmse, result.extended.velocity_rmse)
        out['velocity.png'] = (partial(_draw_velocity, vel=vel, rmse=vrmse), (10, 4))
    for eff, cause in _causes(diag).items():
        out[f'cause_{eff}.png'] = (partial(_draw_cause, cause=cause), (7, 4.5))
    out['gains.png'] = (partial(_draw_gains, rounds=result.rounds,
                                effects=[c.effect for c in result.candidates],
                                named=list(result.named_causes), criterion=result.criterion),
                        (8, 4.5))
    variables = effect_variables(data, diag.ctx.travel) if result.confounds else {}
    for pair in result.confounds:
        a, b = pair.effects
        out[f'confound_{a}_{b}.png'] = (partial(_draw_confound, pair=pair, xa=variables[a],
                                                xb=variables[b]), (6, 4.5))
    if diag.scan is not None:
        out['residual_scan.png'] = (partial(draw_scan, scan=diag.scan), SCAN_SIZE, False)
    return out


def _fmt(v: float | int | None, spec: str = '.3g') -> str:
    return '-' if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, spec)


def _gap_lines(gaps: Gaps | None) -> list[str]:
    """Sentence on the gaps of the stamps (bridged, split), empty when there are none."""
    if not gaps or not (gaps.bridged or gaps.split):
        return []
    text = f'Gaps in the /joint_states stamps: {gaps.bridged} bridged'
    if gaps.bridged:
        text += (f' (the longest {1e3 * gaps.longest_bridged_s:.1f} ms, '
                 f'{gaps.longest_bridged_samples:.1f} sample times; interpolated, the samples '
                 'around them left out of the fits)')
    return [text + f', {gaps.split} too long to bridge (pieces cut there).  '
            f'Rule: {gaps.rule}.', '']


def _logged_unit_lines(lines: Sequence[str] | None) -> list[str]:
    """Return the key numbers in the units of the import (empty: not imported, or in SI)."""
    if not lines:
        return []
    return (['In the units the recordings were imported in (SI in brackets):', '']
            + [f'- {line}' for line in lines] + [''])


def markdown(diag: DiagnosisCore, figure_names: Sequence[str], model_path: Any,
             out_dir: str | None = None) -> str:
    """
    Return the ``report.md`` text: findings and next steps first, then the details.

    Parameters
    ----------
    diag : DiagnosisCore
        The diagnosis.
    figure_names : sequence of str
        The figures' file names, in the order they are shown.
    model_path : str or os.PathLike
        The base gear file, as given.
    out_dir : str, optional
        The result directory, as given (None: ``DIR`` in the commands suggested).

    Returns
    -------
    str

    """
    result = diag.result
    verdict = verdict_of(result)
    crit, data = result.criterion, result.data
    xi = data.xi_range
    temp = 'no temperature signal'
    if data.has_temperature:
        temp = f'temperature {xi[0]:.2f}..{xi[1]:.2f} degC'
    lines = ['# Friction model diagnosis', '',
             *finding_lines(verdict, result, data_ranges(diag) if verdict.named else None),
             *next_step_lines(verdict, result, out_dir, data.recordings),
             '## Data', '',
             f'Base model: `{model_path}`  ',
             'Recordings: ' + ', '.join(f'`{p}`' for p in data.recordings), '',
             f'{data.sliding_s:.1f} s of sliding data (10 ms bins), '
             f'{temp}, sliding above {data.scales.v_stick:.3g} rad/s, '
             f'{_torque_source(data.torque_source)}.', '',
             *_gap_lines(data.gaps),
             *[f'`{c.recording}`: {c.text}.  ' for c in data.torque_from_current or ()],
             *_logged_unit_lines(data.in_logged_units),
             '## Result', '',
             f'**{verdict.headline}**', '', *verdict.adequacy_lines(), *_confound_lines(result),
             '| held-out | base | extended |', '|---|---|---|',
             f'| torque RMSE (Nm) | {_fmt(result.baseline.torque_rmse, ".4f")} | '
             f'{_fmt(result.extended.torque_rmse, ".4f")} |',
             f'| velocity RMSE, {data.window_s:g} s open-loop windows (rad/s) | '
             f'{_fmt(result.baseline.velocity_rmse, ".4g")} | '
             f'{_fmt(result.extended.velocity_rmse, ".4g")} |', '',
             *_criterion_lines(crit), *_candidate_lines(result)]
    for note in result.notes:
        lines += [f'**Note:** {note}', '']
    adj = result.extended_fit.get('sigma1_passivity')
    if adj:
        lines += [f'`extended.yaml`: friction.lugre.sigma1 lowered from {adj["from"]:g} to '
                  f'{adj["to"]:g}, below the passivity bound sigma2 Fc / (Fs - Fc) = '
                  f'{adj["bound"]:.4g} of the extended curve (Astrom & Canudas de Wit 2008).', '']
    for name in figure_names:
        if name != 'residual_scan.png':
            lines += [f'![{name}]({name})', '']
    if result.residual_scan:
        lines += markdown_lines([r.to_dict() for r in result.residual_scan])
        lines += ['In plain words: a flagged variable is one the remaining error still '
                  'follows, more than chance would give when the error is shifted in time '
                  'against it; it points at an effect outside the candidate list.', '']
    lines += ['## Timing', '', '| stage | s |', '|---|---|']
    lines += [f'| {k} | {v:.2f} |' for k, v in result.timing.stages()]
    return '\n'.join(lines) + '\n'


def _criterion_lines(crit: CriterionInfo) -> list[str]:
    """Return the criterion section in words."""
    return ['## Criterion', '',
            'In plain words: an effect is named only when adding it to the model predicts '
            'the torque of data the fit has not seen better, in most time blocks and by '
            'enough to matter.', '',
            f'{crit.blocks} contiguous time blocks; every model is fitted on the other blocks '
            'and predicts the held-out one.  Per block the statistic is '
            f'{crit.statistic} (d_k > 0: the candidate predicted block k better); '
            f'{crit.test}; {crit.multiplicity} (testing several candidates at once '
            'makes a lucky one likely; the correction raises each p-value accordingly).  '
            f'A candidate is significant when its adjusted p-value is below {crit.alpha} and '
            f'its gain ({crit.gain}) is at least {100 * crit.min_gain:.0f} % or the '
            f'RMS torque it explains held out is at least '
            f'{100 * crit.min_explained:.0f} % of the friction level.  '
            f'Selection: {crit.selection}.', '']


def _candidate_lines(result: DiagnosisResult) -> list[str]:
    """Return the candidate table with its legend and the not-named sentences."""
    lines = ['## Candidates', '',
             '*gain*: how much smaller the held-out torque error gets with the effect added '
             '(*round 1*: against the base model; *gain*: in the round given, against the model '
             'at that round).  *p*: the chance of an improvement this consistent over the '
             'blocks if the effect were not there; *p (Holm)*: the same corrected for the '
             'number of candidates tested; *blocks improved*: in how many of the time blocks '
             'the candidate predicted better.', '',
             '| effect | testable | gain round 1 | round | gain | p | p (Holm) | '
             'blocks improved | significant | note |',
             '|---|---|---|---|---|---|---|---|---|---|']
    first = {c.effect: c for c in result.rounds[0].candidates} if result.rounds else {}
    for c in result.candidates:
        if c.testable is False:
            lines.append(f'| {c.effect} | no | - | - | - | - | - | - | no | '
                         f'{table_cell(c.reason or "")} |')
            continue
        f = first.get(c.effect)
        g1 = '-' if f is None or f.gain_raw is None else f'{100 * f.gain_raw:+.1f} %'
        note = c.note or ''
        if c.physical is False:
            note = 'not physical, left out of extended.yaml: ' + (c.reason or '')
        elif c.representable is False:
            note = c.reason or ''
        lines.append(f'| {c.effect} | yes | {g1} | {_dash(c.round)} | '
                     f'{100 * c.gain:.1f} % | '
                     f'{_fmt(c.p_value, ".2g")} | {_fmt(c.p_holm, ".2g")} | '
                     f'{_dash(c.blocks_improved)}/{_dash(c.blocks)} | '
                     f'{"**yes**" if c.significant else "no"} | {table_cell(note)} |')
    lines += ['', 'Named effects: gain when added (against the model at that round); the others: '
              'gain against the final model.  An untestable candidate (the data cannot tell '
              'it) is never named.', '']
    summary = candidate_summary(result)
    lines += [f'**Not named despite a large first-round gain:** {t}' for t in summary]
    if summary:
        lines.append('')
    return lines


def _dash(n: int | None) -> str:
    return '-' if n is None else str(n)


def _torque_source(source: str) -> str:
    """Return where the external torque came from, in words."""
    if source == 'none':
        return ('no external torque: the gear file has no lever and the recordings no '
                '/link_torque')
    return f'external torque from the {source}'


def _confound_lines(result: DiagnosisResult) -> list[str]:
    """Return the confounded candidate pairs of this recording, with what separates them."""
    out = []
    for c in result.confounds:
        a, b = c.effects
        out += [f'**Confounded:** {a} and {b} (rank correlation of their variables '
                f'{c.rank_correlation:+.2f}): this recording cannot tell them apart; '
                f'{c.separate_by} would.  Of the two, {a} (a measured cause) is preferred.',
                '']
    return out
