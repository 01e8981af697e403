# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Figures of an identification, after the seed paper's Fig. 3 and Fig. 4.

:func:`identification_figures` returns ``{file name: (draw, size)}`` for
:func:`friction_joint.output.result_files` (the report files) and for
:func:`friction_joint.results.draw_figures` (matplotlib figures in memory,
:meth:`IdentificationRun.plot <friction_joint.identification.pipeline.IdentificationRun.plot>`):

* ``fig3a_temperature_curves.png`` -- per temperature group: the plateau
  data (markers, load effect removed with the identified load terms) and
  the static curve fitted to that group alone (lines), Fig. 3 (a).
* ``fig3b_parameters.png`` -- each curve parameter against temperature:
  per-group fits (markers with standard errors) and the identified
  polynomial (line) over the recorded range, Fig. 3 (b); the caption says
  what the markers are (each group's order-0 fit after moving its plateaus
  to the group's mean temperature) and that their error bars are statistical.
* ``fig3c_model.png`` -- the temperature-dependent model (eq. 6-7, one
  set of coefficients) at each group's temperature against the same data,
  Fig. 3 (c).
* ``fig4_load.png`` -- load dependency: (a) friction caused by the load
  (data minus the zero-load model) against tau_L with the model lines at a
  few speeds; (b) friction at one constant velocity against load (data
  moved to that velocity and a reference temperature with the model), Fig. 4.
* ``residuals.png`` -- residuals against velocity, temperature and load.
* ``plateaus.png`` -- the measured velocity of the first recording with the
  detected plateau windows shaded (check of the detection).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import os
import re
import textwrap
from typing import Any, TYPE_CHECKING

import numpy as np

from ._arrays import BoolArray, FloatArray
from ..models.static import StaticFriction

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .plateaus import Plateaus
    from .static_fit import StaticIdentifier
    from .step3 import PreslidingStep
    from ..bag import Recording
    from ..gear import GearParams

    #: file name -> (draw(fig), (width, height))
    _Figures = dict[str, tuple[Callable[[Figure], None], tuple[float, float]]]

__all__ = ['against_truth_markdown', 'identification_figures']

_LABELS = {'fc': r'$F_c$ (Nm)', 'fs': r'$F_s$ (Nm)', 'fv': r'$F_v$ (Nm/(rad/s)$^{\delta_v}$)',
           'vs': r'$v_s$ (rad/s, $\kappa\dot q$)', 'delta_v': r'$\delta_v$'}


#: caption of Fig. 3 (b): what the markers are and why they may differ from the polynomials
_FIG3B_NOTE = (
    'Markers: each temperature block fitted alone with constant parameters, error bars its '
    'statistical standard errors only. The gear warms by up to {drift:.2f} K within a block '
    'while the velocity plateaus run; each plateau is first moved to the block’s mean '
    'temperature with the identified model, else the constant-parameter fit would take the '
    'drift for a velocity dependence and trade the correlated parameters against each other. '
    'Lines: the polynomials, fitted jointly to all plateaus at their own temperatures (with the '
    'load terms).')


def _grid(ax: Axes) -> None:
    ax.grid(True, which='both', alpha=0.3)


def _speeds(plateaus: Plateaus) -> FloatArray:
    s = np.abs(plateaus.qd)
    return np.geomspace(max(s.min() * 0.7, 1e-4), s.max() * 1.3, 200)


def _colors(n: int) -> list[tuple[float, float, float, float]]:
    import matplotlib
    cmap = matplotlib.colormaps['coolwarm']
    return [cmap(x) for x in (np.linspace(0.0, 1.0, n) if n > 1 else [0.0])]


def _zero_load_data(ident: StaticIdentifier) -> FloatArray:
    """|tau_r| with the identified load effect removed (sign-folded), per plateau."""
    p = ident.plateaus
    with_load = ident.predict(p.qd, p.xi, p.load)
    no_load = ident.predict(p.qd, p.xi, 0.0)
    y: FloatArray = np.sign(p.qd) * (p.tau_r - (with_load - no_load))
    return y


def _group_masks(ident: StaticIdentifier) -> list[BoolArray]:
    """Plateau masks of the fitted temperature groups."""
    xi = ident.plateaus.xi
    return [(xi >= g['xi_min'] - 1e-9) & (xi <= g['xi_max'] + 1e-9) for g in ident.group_fits]


def identification_figures(ident: StaticIdentifier, recordings: Sequence[Recording | None] = (),
                           presliding: PreslidingStep | None = None) -> _Figures:
    """
    Figures of a fitted :class:`~friction_joint.identification.static_fit.StaticIdentifier`.

    Parameters
    ----------
    ident : StaticIdentifier
        After ``fit``.
    recordings : sequence of Recording, optional
        For ``plateaus.png`` (the first one is drawn).
    presliding : PreslidingStep, optional
        Step-3 results (not drawn; reserved).

    Returns
    -------
    dict
        ``{file name: (draw(fig), (width, height))}``.

    """
    gear = ident.gear
    if gear is None:
        raise RuntimeError('call fit() first')
    p = ident.plateaus
    y0 = _zero_load_data(ident)
    v = _speeds(p)
    kappa = gear.friction.velocity_scale
    masks = _group_masks(ident)
    colors = _colors(max(len(masks), 1))
    sf = StaticFriction(gear.friction)

    def group_curve(g: dict[str, Any]) -> FloatArray:
        """Return the static curve of one group's own order-0 fit, zero load."""
        f = gear.friction
        vals = g['values']
        fs = vals.get('fs')
        changes = {p_: [vals[p_]] for p_ in vals}
        import dataclasses
        fr = dataclasses.replace(
            f, fc=tuple(changes['fc']), fv=tuple(changes['fv']),
            fs=tuple(changes['fs']) if fs is not None else f.fs,
            vs=tuple(changes['vs']) if 'vs' in changes else f.vs,
            delta_v=tuple(changes['delta_v']) if 'delta_v' in changes else f.delta_v,
            temperature_range=(-1e3, 1e3))
        return StaticFriction(fr).torque(v, g['xi'], 0.0)

    def scatter_groups(ax: Axes) -> None:
        for m, c, _g in zip(masks, colors, ident.group_fits, strict=False):
            pos = m & (p.qd > 0)
            neg = m & (p.qd < 0)
            ax.plot(np.abs(p.qd[pos]), y0[pos], '^', color=c, ms=4, mfc='none')
            ax.plot(np.abs(p.qd[neg]), y0[neg], 'v', color=c, ms=4, mfc='none')
        rest = np.ones(len(p), dtype=bool)
        for m in masks:
            rest &= ~m
        if rest.any():
            ax.plot(np.abs(p.qd[rest]), y0[rest], 'x', color='0.5', ms=4,
                    label='plateaus outside the temperature groups')

    def finish(ax: Axes, title: str) -> None:
        ax.set_xscale('log')
        ax.set_xlabel(r'velocity $|\dot q|$ (rad/s, output)')
        ax.set_ylabel(r'friction torque $|\tau_r|$ at zero load (Nm)')
        ax.set_title(title)
        ax.legend(fontsize='x-small', loc='upper left')
        _grid(ax)

    def draw3a(fig: Figure) -> None:
        ax = fig.subplots()
        scatter_groups(ax)
        for g, c in zip(ident.group_fits, colors, strict=False):
            ax.plot(v, group_curve(g), color=c, lw=1.3,
                    label=f'{g["xi"]:.1f} degC: fit of this temperature alone '
                          f'({g["plateaus"]} plateaus, RMS {g["rms"]:.3f} Nm)')
        ax.plot([], [], 'k^', mfc='none', label='plateaus, positive velocity')
        ax.plot([], [], 'kv', mfc='none', label='plateaus, negative velocity')
        finish(ax, '(a) static friction curves identified at single temperatures')

    def draw3c(fig: Figure) -> None:
        ax = fig.subplots()
        scatter_groups(ax)
        for g, c in zip(ident.group_fits, colors, strict=False):
            ax.plot(v, sf.torque(v, g['xi'], 0.0), color=c, lw=1.3,
                    label=f'model at {g["xi"]:.1f} degC')
        if not ident.group_fits:
            for x in np.linspace(p.xi.min(), p.xi.max(), 3):
                ax.plot(v, sf.torque(v, x, 0.0), lw=1.3, label=f'model at {x:.1f} degC')
        finish(ax, f'(c) temperature-dependent model (eq. 6-7), RMS residual {ident.rms:.3f} Nm '
                   f'over {len(p)} plateaus')

    def draw3b(fig: Figure) -> None:
        names = [n for n in ('fc', 'fs', 'fv', 'vs', 'delta_v')
                 if n in ident.structure.orders or n in ident.structure.fixed]
        caption = 0.2 if ident.group_fits else 0.01
        grid = fig.add_gridspec(2, len(names), height_ratios=(1.0, caption))
        axes = [fig.add_subplot(grid[0, i]) for i in range(len(names))]
        lo, hi = gear.friction.temperature_range
        xs = np.linspace(lo, hi, 100)
        pars = sf.parameters(xs, 0.0)
        for ax, n in zip(axes, names, strict=True):
            order = ident.structure.orders.get(n)
            lab = 'fixed' if order is None else f'polynomial of order {order}'
            ax.plot(xs, pars[n], 'k-', lw=1.3, label=lab)
            gx = [g['xi'] for g in ident.group_fits if n in g['values']]
            gy = [g['values'][n] for g in ident.group_fits if n in g['values']]
            ge = [g['se'][n] for g in ident.group_fits if n in g['values']]
            for x, y, e, c in zip(gx, gy, ge, colors, strict=False):
                ax.errorbar([x], [y], yerr=[e], fmt='o', color=c, ms=5, capsize=3)
            if gx:
                ax.plot([], [], 'o', color='0.4', label='single-temperature fits')
            ax.set_xlabel('temperature (degC)')
            ax.set_title(_LABELS[n])
            ax.legend(fontsize='x-small')
            _grid(ax)
        fig.suptitle('(b) curve parameters against temperature (velocities in units of '
                     f'{kappa:g} x output rad/s)')
        note = fig.add_subplot(grid[1, :])
        note.axis('off')
        if ident.group_fits:
            drift = max(g['xi_max'] - g['xi_min'] for g in ident.group_fits)
            note.text(0.5, 0.5, textwrap.fill(_FIG3B_NOTE.format(drift=drift), 190),
                      ha='center', va='center', fontsize='small', transform=note.transAxes)

    def draw4(fig: Figure) -> None:
        a0, a1 = fig.subplots(1, 2)
        dl = np.sign(p.qd) * p.tau_r - np.sign(p.qd) * sf.torque(p.qd, p.xi, 0.0)
        sc = a0.scatter(p.load, dl, c=np.log10(np.abs(p.qd)), cmap='viridis', s=14)
        cb = fig.colorbar(sc, ax=a0)
        cb.set_label(r'$\log_{10}|\dot q|$ (rad/s)')
        tl = np.linspace(0.0, max(p.load.max(), 1e-3) * 1.05, 50)
        xm = float(np.mean(p.xi))
        for vv in np.geomspace(np.abs(p.qd).min(), np.abs(p.qd).max(), 3):
            a0.plot(tl, sf.torque(vv, xm, tl) - sf.torque(vv, xm, 0.0), lw=1.2,
                    label=f'model, {vv:.3g} rad/s, {xm:.1f} degC')
        a0.set_xlabel(r'load $\tau_L = |\tau_{ext}|$ (Nm)')
        a0.set_ylabel('friction caused by the load (Nm)')
        a0.set_title('(a) load-dependent part: data minus the zero-load model')
        a0.legend(fontsize='x-small')
        _grid(a0)
        # constant velocity: the speed level where the model's load effect over the
        # level's load spread is largest
        speeds = np.abs(p.qd)
        order = np.argsort(speeds)
        best, best_effect = order[:1], -1.0
        i = 0
        while i < len(order):
            j = i
            while j + 1 < len(order) and speeds[order[j + 1]] <= speeds[order[i]] * 1.05:
                j += 1
            idx = order[i:j + 1]
            if len(idx) >= 3:
                vv = float(np.median(speeds[idx]))
                effect = abs(float(np.ravel(sf.torque(vv, xm, p.load[idx].max())
                                            - sf.torque(vv, xm, p.load[idx].min()))[0]))
                if effect > best_effect:
                    best, best_effect = idx, effect
            i = j + 1
        vref = float(np.median(speeds[best]))
        xref = float(np.mean(p.xi))
        moved = (np.sign(p.qd[best]) * p.tau_r[best]
                 - sf.torque(speeds[best], p.xi[best], p.load[best])
                 + sf.torque(vref, xref, p.load[best]))
        a1.plot(p.load[best], moved, 'o', color='C0', ms=5,
                label=f'plateaus at {vref:.3g} rad/s (moved to {xref:.1f} degC)')
        a1.plot(tl, sf.torque(vref, xref, tl), 'k-', lw=1.3, label='model')
        a1.set_xlabel(r'load $\tau_L$ (Nm)')
        a1.set_ylabel(r'friction torque $|\tau_r|$ (Nm)')
        a1.set_title(f'(b) load dependency at constant velocity {vref:.3g} rad/s')
        a1.legend(fontsize='x-small')
        _grid(a1)

    def draw_res(fig: Figure) -> None:
        axes = fig.subplots(1, 3, sharey=True)
        r = ident.residuals
        for ax, x, lab, log in ((axes[0], np.abs(p.qd), r'$|\dot q|$ (rad/s)', True),
                                (axes[1], p.xi, 'temperature (degC)', False),
                                (axes[2], p.load, r'load $\tau_L$ (Nm)', False)):
            ax.errorbar(x, r, yerr=p.tau_r_se, fmt='.', color='C0', ms=4, elinewidth=0.6)
            ax.axhline(0.0, color='k', lw=0.8)
            if log:
                ax.set_xscale('log')
            ax.set_xlabel(lab)
            _grid(ax)
        axes[0].set_ylabel('residual model - data (Nm)')
        fig.suptitle(f'residuals of the identified model (RMS {ident.rms:.4f} Nm; error bars: '
                     'plateau standard errors)')

    figures: _Figures = {
        'fig3a_temperature_curves.png': (draw3a, (10, 6.5)),
        'fig3b_parameters.png': (draw3b, (16, 5.4)),
        'fig3c_model.png': (draw3c, (10, 6.5)),
        'fig4_load.png': (draw4, (14, 5.5)),
        'residuals.png': (draw_res, (14, 4.5)),
    }
    recs = [r for r in recordings if r is not None]
    if recs:
        rec = recs[0]

        def draw_plateaus(fig: Figure) -> None:
            ax = fig.subplots()
            js = rec.joint_states
            step = max(1, len(js.t) // 200000)
            ax.plot(js.t[::step], js.qd[::step], color='k', lw=0.5, label='measured velocity')
            src = p.source == 0
            for k, (a, b) in enumerate(zip(p.t0[src], p.t1[src], strict=True)):
                ax.axvspan(a, b, color='C2', alpha=0.35, lw=0,
                           label='detected plateau windows' if k == 0 else None)
            ax.set_yscale('symlog', linthresh=0.01)
            ax.set_xlabel('time (s)')
            ax.set_ylabel('velocity (rad/s, symlog)')
            name = os.path.basename(os.path.normpath(rec.path))   # no temporary directory
            ax.set_title(f'plateau detection in {name} ({int(src.sum())} plateaus)')
            ax.legend(fontsize='small', loc='upper right')
            _grid(ax)

        figures['plateaus.png'] = (draw_plateaus, (16, 5))
    return figures


#: static-curve parameters compared with the truth: name, symbol, unit
CURVE = (('fc', 'F_c', 'Nm'), ('fs', 'F_s', 'Nm'), ('fv', 'F_v', 'Nm/(rad/s)^δv'),
         ('vs', 'v_s', 'rad/s (motor side)'), ('delta_v', 'δ_v', '–'))


def _err(found: float, true: float) -> str:
    return '–' if not true else f'{100.0 * (found / true - 1.0):+.1f} %'


def _num(x: float) -> str:
    """``x`` to 4 significant digits; whole and with spaced thousands from 1000 on."""
    if abs(x) >= 1000.0:
        return f'{x:,.0f}'.replace(',', '\u2009')
    return f'{x:.4g}'


def against_truth_markdown(ident: GearParams, truth: GearParams, header: Sequence[str] = (),
                           temperatures: Sequence[float] = ()) -> list[str]:
    """
    Return Markdown lines: the identified parameters against the truth gear of the recording.

    Parameters
    ----------
    ident, truth : GearParams
        The identified gear and the simulated hardware the recording came from.
    header : sequence of str
        The identified file's comment lines (a parameter "written, kept from the
        structure" there has no error: the data did not determine it).
    temperatures : sequence of float
        Where the temperature polynomials are compared (those inside the
        identified temperature range; its middle if none is).

    Returns
    -------
    list of str
        A sentence and a table with units: the static-curve parameters at
        each temperature, the load coefficients, the static friction torque
        at a few velocities, the pre-sliding parameters; relative errors
        identified / truth - 1.

    """
    lo, hi = ident.friction.temperature_range
    temps = [x for x in temperatures if lo <= x <= hi] or [0.5 * (lo + hi)]
    xs = np.array(temps, dtype=float)
    found, true = (StaticFriction(g.friction).parameters(xs, 0.0) for g in (ident, truth))
    rows = []
    for key, sym, unit in CURVE:
        constant = max(len(getattr(g.friction, key) or ()) for g in (ident, truth)) <= 1
        for i, x in enumerate(xs[:1] if constant else xs):
            where = 'every temperature' if constant else f'{x:g} °C'
            f, t = float(found[key][i]), float(true[key][i])
            rows.append(f'| {sym}, {where} | {unit} | {_num(f)} | {_num(t)} | {_err(f, t)} |')
    for key, sym in (('fc_load', 'F_c'), ('fv_load', 'F_v')):
        fl, tl = (tuple(getattr(g.friction, key) or ()) for g in (ident, truth))
        for j in range(max(len(fl), len(tl))):
            f = fl[j] if j < len(fl) else 0.0
            t = tl[j] if j < len(tl) else 0.0
            power, unit = ('', 'Nm per Nm of load') if j == 0 else (f'^{j + 1}', f'Nm/Nm^{j + 1}')
            rows.append(f'| {sym} load coefficient of τ_L{power} | {unit} | {_num(f)} | '
                        f'{_num(t)} | {_err(f, t)} |')
    xm = float(xs[len(xs) // 2])
    for qd, load in ((0.01, 0.0), (0.1, 0.0), (1.0, 0.0), (1.0, truth.mgl)):
        f, t = (float(np.ravel(StaticFriction(g.friction).torque(qd, xm, load))[0])
                for g in (ident, truth))
        rows.append(f'| static friction torque at {qd:g} rad/s (output), {xm:g} °C, load '
                    f'{load:.3g} Nm | Nm | {_num(f)} | {_num(t)} | {_err(f, t)} |')
    kept = ' '.join(ln for ln in header if 'kept from the structure' in ln)
    lugre_hw = truth.friction.model == 'lugre'
    for model, key, sym, unit in (('lugre', 'sigma0', 'σ0', 'Nm/rad'),
                                  ('lugre', 'sigma1', 'σ1', 'Nm s/rad'),
                                  ('gms', 'k', 'GMS Σk_i', 'Nm/rad'), ('gms', 'c', 'GMS C',
                                                                       'Nm/s')):
        a, b = getattr(ident.friction, model), getattr(truth.friction, model)
        if a is None or b is None:
            continue
        f, t = (float(np.sum(getattr(p, key))) for p in (a, b))
        if model != truth.friction.model:
            err = (f'– (the hardware has {"LuGre" if lugre_hw else "GMS"} friction: these '
                   'are fitted to it, not to this truth)')
        elif re.search(rf'\b{key} = \S+ written, kept from the structure', kept):
            err = '– (undetermined by the data: the structure file’s value is written)'
        else:
            err = _err(f, t)
        rows.append(f'| {sym} | {unit} | {_num(f)} | {_num(t)} | {err} |')
    return ['The identified parameters against the simulated truth '
            f'(`{os.path.basename(truth.source or "truth")}`) that produced the recording; the '
            'temperature polynomials are compared by their values at '
            + ', '.join(f'{x:g} °C' for x in xs) + ', and the static curve itself at a few '
            'velocities (error: identified / truth − 1):', '',
            '| parameter | unit | identified | truth | error |', '|---|---|---|---|---|'] \
        + rows + ['']
