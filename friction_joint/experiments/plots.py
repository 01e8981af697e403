# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
Figures of the test-bed experiments, drawn from their results (``ExperimentResult``).

The experiment functions compute; this module draws.  :data:`TESTBED_FIGURES`
maps an experiment name to its figures (file name -> ``(draw(fig, data), (width,
height))``); :func:`experiment_figures` binds them to one result for
:func:`friction_joint.output.result_files`.  The paper's numbers drawn as
reference lines and bands come from :data:`~friction_joint.paper.PAPER`.
Every figure shares the style helpers here: one line style per model
(:data:`STYLES`), a zoom inset (:func:`zoom_inset`) and the paper's figure
number in the title (:func:`paper_suptitle`).
"""
import math

import numpy as np

from ._basics import json_key, MODEL_LABELS, MODELS, reversal_window
from ..paper import PAPER

__all__ = ['STYLES', 'COLORS', 'SETTLING_LABEL', 'grid_on', 'paper_suptitle', 'add_headroom',
           'zoom_inset', 'TESTBED_FIGURES', 'experiment_figures']


def grid_on(ax):
    """Draw a light grid on ``ax``."""
    ax.grid(True, alpha=0.3)


#: line style per model (matplotlib keyword arguments) in every figure: LuGre
#: solid under GMS dashed stay apart where the two curves coincide; the
#: measured / true signal is black and thicker, drawn first (underneath)
STYLES = {'none': {'color': 'C3', 'linestyle': '-', 'linewidth': 1.0},
          'lugre': {'color': 'C0', 'linestyle': '-', 'linewidth': 1.4},
          'gms': {'color': 'C2', 'linestyle': '--', 'linewidth': 1.4},
          'measured': {'color': 'k', 'linestyle': '-', 'linewidth': 2.0},
          'truth': {'color': 'k', 'linestyle': '-', 'linewidth': 2.0}}
COLORS = {k: v['color'] for k, v in STYLES.items()}

#: label of the shaded settling interval at the start of a run
SETTLING_LABEL = 'settling, not evaluated'


def paper_suptitle(fig, number, what, truth_model):
    """Figure title naming the seed paper's figure ``number`` and the hardware's friction."""
    name = {'lugre': 'LuGre', 'gms': 'GMS'}.get(truth_model, truth_model)
    fig.suptitle(f'Fig. {number} (reproduced): {what}, hardware with {name} friction',
                 fontsize='large', fontweight='bold')


def add_headroom(ax, frac, data=None, margin=0.05):
    """
    Raise the top of the y axis so that the data fill the lower ``1 - frac`` of ``ax``.

    ``data``: arrays whose range (plus ``margin``) sets the y axis first
    instead of the current limits, e.g. the evaluated part of the curves.
    """
    if data is not None:
        lo = min(float(np.min(d)) for d in data)
        hi = max(float(np.max(d)) for d in data)
        pad = margin * (hi - lo) if hi > lo else 1.0
        lo, hi = lo - pad, hi + pad
    else:
        lo, hi = ax.get_ylim()
    ax.set_ylim(lo, hi + frac / (1.0 - frac) * (hi - lo))


def zoom_inset(ax, window, curves, *, scale_by=None, width=0.42, height=0.36, margin=0.08,
               title='zoom'):
    """
    Inset axes on ``ax`` zooming on the time ``window``: ``(inset, legend corner)``.

    ``curves`` is a sequence of ``(t, y, style)`` drawn again in the inset
    (``style``: matplotlib keyword arguments, any ``label`` dropped); the
    y range covers the curves whose indices are in ``scale_by`` (all by
    default) over the window.  The inset sits in the top corner away from the
    window (call :func:`add_headroom` first to keep the curves below it) and
    the zoomed region is marked on ``ax``.  Returns the inset axes and
    ``'upper left'`` or ``'upper right'``, the other top corner, for the
    legend of ``ax``.
    """
    t0, t1 = window
    x_lo, x_hi = ax.get_xlim()
    centre = (0.5 * (t0 + t1) - x_lo) / max(x_hi - x_lo, 1e-12)
    left = centre > 0.5
    x = 0.01 if left else 0.99 - width
    inset = ax.inset_axes([x, 0.95 - height, width, height])
    lo, hi = math.inf, -math.inf
    for i, (t, y, style) in enumerate(curves):
        t, y = np.asarray(t), np.asarray(y)
        k0 = max(int(np.searchsorted(t, t0)) - 1, 0)
        k1 = int(np.searchsorted(t, t1, side='right')) + 1
        inset.plot(t[k0:k1], y[k0:k1], **{k: v for k, v in style.items() if k != 'label'})
        if (scale_by is None or i in scale_by) and k1 > k0:
            lo, hi = min(lo, float(np.min(y[k0:k1]))), max(hi, float(np.max(y[k0:k1])))
    if math.isfinite(lo) and math.isfinite(hi):
        pad = margin * (hi - lo) if hi > lo else max(abs(hi), 1.0) * margin
        inset.set_ylim(lo - pad, hi + pad)
    inset.set_xlim(t0, t1)
    inset.tick_params(labelsize='x-small')
    if left:                # tick labels inside ax, not over its own y tick labels
        inset.yaxis.tick_right()
    inset.set_title(title, fontsize='x-small', pad=2)
    inset.set_facecolor('white')
    grid_on(inset)
    ax.indicate_inset_zoom(inset, edgecolor='0.4')
    return inset, ('upper right' if left else 'upper left')


# ---------------------------------------------------------------- figures ---

def _chirp(fig, res):
    """Fig. 5: commanded torque, velocity and friction, measured against the models."""
    summary = res.summary
    models = tuple(summary['velocity_rmse'])
    series = [(amp, res.series[json_key(amp)]['t'], res.series[json_key(amp)]['command'],
               res.series[json_key(amp)]['measured'], res.series[json_key(amp)]['models'])
              for amp in summary['amplitudes']]
    axes = fig.subplots(3, len(series), sharex='col', squeeze=False,
                        gridspec_kw={'height_ratios': [1.0, 1.6, 1.2]})
    letters = 'abcdef'
    for j, (amp, t, cmd, meas, sims) in enumerate(series):
        tag = 'low' if j == 0 else 'high'
        a0, a1, a2 = axes[:, j]
        key = json_key(amp)
        p = [f'({letters[3 * j + i]}) ' if len(series) == 2 else '' for i in range(3)]
        a0.plot(t, cmd, color='C1', lw=2.2, label='commanded')
        a0.plot(t, meas['effort'], color='k', lw=0.7, ls='--',
                label='applied (measured effort)')
        a0.set_ylabel('motor torque (Nm)')
        a0.set_title(f'{p[0]}{tag} amplitude: {amp:g} Nm chirp, '
                     f'{summary["f0_hz"]:g}-{summary["f1_hz"]:g} Hz: commanded and applied torque',
                     fontsize='medium')
        curves = [(t, meas['qd'], dict(STYLES['measured'], label='measured'))]
        for m in models:
            curves.append((t, sims[m].qd, dict(
                STYLES[m], label=(f'{MODEL_LABELS[m]} (RMSE '
                                  f'{summary["velocity_rmse"][m][key]:.3f} rad/s)'))))
        for tt, y, style in curves:
            a1.plot(tt, y, **style)
        a1.set_ylabel('velocity (rad/s)')
        a1.set_title(f'{p[1]}velocity: measured and simulated (open loop, same effort '
                     'and temperature)', fontsize='medium')
        loc1 = 'upper left'
        window = reversal_window(t, meas['qd'], 0.2)
        if window is not None:
            add_headroom(a1, 0.42)
            _, loc1 = zoom_inset(a1, window, curves, width=0.4, height=0.36,
                                 title='zoom: break-away at the first velocity reversal')
        a2.plot(t, meas['tau_r'], **STYLES['truth'], label='true friction (incl. ripple)')
        for m in models:
            a2.plot(t, sims[m].tau_r, **STYLES[m], label=MODEL_LABELS[m])
        a2.set_ylabel('friction torque (Nm)')
        a2.set_title(f'{p[2]}friction torque: true and estimated by the models',
                     fontsize='medium')
        a2.set_xlabel('time (s)')
        for ax, loc in ((a0, 'upper left'), (a1, loc1), (a2, 'upper left')):
            ax.legend(fontsize='x-small', loc=loc)
            grid_on(ax)
    paper_suptitle(fig, 5, 'open-loop chirp excitation, low (left) and high (right) '
                           'amplitude', res.truth_model)


def _compensation_setup(res):
    """Return the summary, the error traces, temperature and amplitude keys, settling (s)."""
    summary = res.summary
    return (summary, res.series['error'], [json_key(x) for x in summary['temperatures']],
            [json_key(a) for a in summary['amplitudes']], summary['settle_s'])


def _compensation_errors(fig, res):
    """Fig. 6: the position error over time per temperature and amplitude, with a zoom."""
    summary, traces, temps, amps, settle = _compensation_setup(res)
    axes = fig.subplots(len(amps), len(temps), sharex=True, squeeze=False)
    for i, ak in enumerate(amps):
        speed = 'low' if i == 0 else 'high'
        for j, tk in enumerate(temps):
            ax = axes[i, j]
            curves = []
            for kind in MODELS:
                t, e = traces[(tk, ak, kind)]
                pct = summary['max_error_pct'][kind][tk][ak]
                curves.append((t, 1e3 * e, dict(STYLES[kind],
                                                label=f'{MODEL_LABELS[kind]} (max {pct:.1f} %)')))
            for t, y, style in curves:
                ax.plot(t, y, **style)
            ax.axvspan(0.0, settle, color='0.85', lw=0, label=SETTLING_LABEL)
            ax.set_title(f'{speed} velocity: $q_d = {ak}\\,\\sin({summary["omega"]:g}t)$ rad '
                         f'(peak {summary["peak_velocity"][ak]:.1f} rad/s), {tk} \u00b0C',
                         fontsize='medium')
            if j == 0:
                ax.set_ylabel('position error $q_d - q$ (mrad)')
            if i == len(amps) - 1:
                ax.set_xlabel('time since the start of tracking (s)')
            t = curves[0][0]
            add_headroom(ax, 0.45, [y[t >= settle] for _, y, _ in curves])
            zoom = summary['zoom'][tk][ak]
            _, loc = zoom_inset(ax, zoom['window_s'], curves, scale_by=(1, 2), width=0.46,
                                height=0.36,
                                title=f'zoom: largest {MODEL_LABELS[zoom["model"]]} error '
                                      f'(t = {zoom["time_s"]:.2f} s)')
            ax.legend(fontsize='x-small', loc=loc)
            grid_on(ax)
    paper_suptitle(fig, 6, 'position error of the friction compensation, low (top) and '
                           'high (bottom) velocity', summary['truth_model'])


def _compensation_bars(fig, res):
    """Fig. 7: the maximum tracking errors (and RMSE) as bars beside the paper's numbers."""
    summary, _, temps, amps, _ = _compensation_setup(res)
    ax = fig.subplots()
    cases = [(tk, ak) for ak in amps for tk in temps]
    x = np.arange(len(cases))
    w = 0.27
    low = [k for k, (_, ak) in enumerate(cases) if ak == amps[0]]
    x0, x1 = low[0] - 0.45, low[-1] + 0.45
    lo, hi = PAPER['uncompensated_band'].value
    ax.fill_between([x0, x1], lo, hi, color='C3', alpha=0.12, lw=0,
                    label=f'paper, no compensation: {lo:g}-{hi:g} %')
    for kind in ('lugre', 'gms'):
        v = PAPER['compensated_' + kind].value
        ax.plot([x0, x1], [v, v], color=STYLES[kind]['color'], ls=':', lw=1.6,
                label=f'paper, {MODEL_LABELS[kind]}: {v:g} %')
    for i, kind in enumerate(MODELS):
        mx = [summary['max_error_pct'][kind][tk][ak] for tk, ak in cases]
        rm = [100.0 * summary['rmse'][kind][tk][ak] / float(ak) for tk, ak in cases]
        pos = x + (i - 1) * w
        ax.bar(pos, mx, w * 0.9, color=STYLES[kind]['color'], alpha=0.75,
               hatch='//' if kind == 'gms' else None, edgecolor='white', lw=0,
               label=f'{MODEL_LABELS[kind]}: max error')
        ax.bar(pos, rm, w * 0.22, color='k',
               label='RMSE (thin bars)' if i == len(MODELS) - 1 else None)
        for p_, v_ in zip(pos, mx, strict=True):
            ax.annotate(f'{v_:.1f}', (p_, v_), xytext=(0, 3), textcoords='offset points',
                        ha='center', va='bottom', fontsize='small',
                        bbox={'facecolor': 'white', 'edgecolor': 'none', 'alpha': 0.7,
                              'pad': 0.5})
    split = len(low) - 0.5
    ax.axvline(split, color='0.5', lw=0.8)
    top = ax.get_ylim()[1] * 1.12
    ax.set_ylim(0.0, top)
    for xs, ak, ha in ((split - 0.1, amps[0], 'right'), (split + 0.1, amps[-1], 'left')):
        speed = 'low' if ak == amps[0] else 'high'
        ax.text(xs, 0.98 * top, f'{speed} velocity (a = {ak} rad, peak '
                f'{summary["peak_velocity"][ak]:.1f} rad/s) \u2192' if ha == 'left' else
                f'\u2190 {speed} velocity (a = {ak} rad, peak '
                f'{summary["peak_velocity"][ak]:.1f} rad/s)',
                ha=ha, va='top', fontsize='small', color='0.3')
    ax.set_xticks(x)
    ax.set_xticklabels([f'{tk} \u00b0C\na = {ak} rad' for tk, ak in cases])
    ax.set_ylabel('position error (% of amplitude a)')
    ax.set_title('thick bars: max $|q_d - q|$, thin bars: RMSE, both in % of a '
                 f'(friction feed-forward driven by the {summary["ff_velocity"]} velocity)',
                 fontsize='medium')
    ax.legend(fontsize='small', loc='center right')
    grid_on(ax)
    paper_suptitle(fig, 7, 'maximum tracking error', summary['truth_model'])


def _estimation(fig, res):
    """Fig. 8: applied and estimated external torque, the error with a zoom, the motion."""
    summary, r = res.summary, res.series
    bnd = PAPER['estimation_max'].value
    a0, a1, a2 = fig.subplots(3, 1, sharex=True, gridspec_kw={'height_ratios': [3, 3, 1.3]})
    t = r['t']
    settle_s = summary['settle_s']
    a0.plot(t, r['tau_link'], color='0.6', lw=0.5, label='link torque sensor')
    a0.plot(t, r['tau_ext'], **STYLES['truth'], label=r'applied $\tau_{ext}$ (true)')
    for kind in MODELS:
        a0.plot(t, r['estimates'][kind], **STYLES[kind], label=f'estimate, {MODEL_LABELS[kind]}')
    a0.set_ylabel('external torque (Nm)')
    ctrl = MODEL_LABELS[summary['controller_friction']]
    a0.set_title(f'disturbance observer eq. 15, $\\beta$ = {summary["beta"]:g} rad/s, gravity '
                 f'as unknown load; controller eq. 17 with {ctrl} feed-forward',
                 fontsize='medium')
    curves = []
    for kind in MODELS:
        label = (f'{MODEL_LABELS[kind]} (RMS {summary["rms_error"][kind]:.2f} Nm, '
                 f'{summary["rms_error_pct"][kind]:.1f} %)')
        curves.append((t, r['estimates'][kind] - r['tau_ext'],
                       dict(STYLES[kind], label=label)))
    for tt, y, style in curves:
        a1.plot(tt, y, **style)
    bound = {'color': 'k', 'linestyle': ':', 'linewidth': 1.0}
    a1.axhline(bnd, **bound, label=f'paper: error < {bnd:g} Nm')
    a1.axhline(-bnd, **bound)
    a1.set_ylabel(r'error $\hat\tau_{ext} - \tau_{ext}$ (Nm)')
    a1.set_title('estimation error against the true external torque', fontsize='medium')
    add_headroom(a1, 0.45)
    zoom = summary['zoom']
    inset, loc1 = zoom_inset(a1, zoom['window_s'], curves, scale_by=(1, 2), width=0.4,
                             height=0.38,
                             title=f'zoom: the largest LuGre/GMS error, '
                                   f'{zoom["max_error"]:.2f} Nm ({MODEL_LABELS[zoom["model"]]}) '
                                   f'at t = {zoom["time_s"]:.2f} s')
    inset.axhline(bnd, **bound)
    inset.axhline(-bnd, **bound)
    a2.plot(t, r['q'], color='C4', lw=0.9, label='position (rad)')
    a2.plot(t, r['qd'], color='C5', lw=0.7, label='velocity (rad/s)')
    a2.set_ylabel('q (rad), $\\dot q$ (rad/s)')
    a2.set_xlabel('time (s)')
    for ax, loc in ((a0, 'upper right'), (a1, loc1), (a2, 'upper right')):
        ax.axvspan(0.0, settle_s, color='0.85', lw=0, label=SETTLING_LABEL)
        ax.legend(fontsize='x-small', loc=loc, ncol=2)
        grid_on(ax)
    paper_suptitle(fig, 8, 'external torque estimation', summary['truth_model'])


def _gain_sweep(fig, res):
    """Maximum tracking error against the design inertia of the gains, the paper's band."""
    summary = res.summary
    models = tuple(summary['max_error_pct'])
    grid, table = summary['design_inertia'], summary['max_error_pct']
    temps, amp = summary['temperatures'], summary['amplitude']
    ax = fig.subplots()
    lo, hi = PAPER['uncompensated_band'].value
    ax.axhspan(lo, hi, color='0.85', label=f'paper, no compensation: {lo:g}-{hi:g} %')
    for kind in models:
        for xi, mark in zip(temps, ('o', 's'), strict=False):
            style = dict(STYLES[kind])
            style['linestyle'] = '-' if xi == temps[0] else '--'
            ax.plot(grid, table[kind][json_key(xi)], marker=mark, ms=4,
                    label=f'{"no friction model" if kind == "none" else "LuGre"}, '
                          f'{xi:g} \u00b0C', **style)
    for name, j in summary['presets'].items():
        ax.axvline(j, color='k', ls=':', lw=0.9)
        ax.text(j, ax.get_ylim()[1] * 0.95, f' preset {name}\n {j:.3g} kg m$^2$',
                fontsize='x-small', va='top')
    ax.set_xscale('log')
    ax.set_xlabel('design inertia of the PD gains (kg m$^2$); plant inertia '
                  f'{summary["truth_inertia"]:g} kg m$^2$')
    ax.set_ylabel(f'max tracking error (% of a = {amp:g} rad)')
    fig.suptitle("Where the paper's Fig. 7 regime lies: uncompensated error vs the gains' "
                 f'design inertia (hardware: {summary["truth_model"]})')
    ax.legend(fontsize='small')
    grid_on(ax)


#: experiment name -> {file name: (draw(fig, data), (width, height) in inches)}
TESTBED_FIGURES = {
    'chirp': {'chirp.png': (_chirp, (15, 13))},
    'compensation': {'compensation_error.png': (_compensation_errors, (16, 9.5)),
                     'compensation_bars.png': (_compensation_bars, (13, 7))},
    'estimation': {'estimation.png': (_estimation, (13, 12))},
    'gain_sweep': {'gain_sweep.png': (_gain_sweep, (10, 6))},
}


def experiment_figures(data):
    """
    Return the figures of one experiment run, for :func:`~friction_joint.output.result_files`.

    Parameters
    ----------
    data : ExperimentResult
        The run; its ``name`` selects the figures in :data:`TESTBED_FIGURES` (none
        for a name without an entry).

    Returns
    -------
    dict
        File name -> ``(draw(fig), (width, height))``.

    """
    def bind(draw):
        return lambda fig: draw(fig, data)
    return {name: (bind(draw), size)
            for name, (draw, size) in TESTBED_FIGURES.get(data.name, {}).items()}
