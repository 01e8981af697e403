# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Figures and report tables of the classic LuGre experiments (:mod:`.classic`).

:func:`draw_classic` draws the figure of a classic experiment's
:class:`~friction_joint.results.ExperimentResult`; the files
``NAME.png`` and ``NAME.json`` are written by :mod:`friction_joint.jobs.classic`
(the ``classic`` command and the demo).
:func:`summary_markdown` renders a summary as Markdown tables with units, the
set-up beside the results (the ``demo`` report).
"""
import numpy as np

__all__ = ['FIGURES', 'draw_classic', 'summary_markdown']


PLOT_POINTS = 20000   # series are thinned to about this many points per line


def _thin(*arrays):
    """Every k-th sample of equally long arrays, k chosen for ~PLOT_POINTS points."""
    step = max(1, len(arrays[0]) // PLOT_POINTS)
    return [np.asarray(a)[::step] for a in arrays]


def _plot_presliding(fig, res):
    s, m = res.series, res.summary
    t, force, x, friction = _thin(s['t'], s['force'], s['x'], s['friction'])
    ax1, ax2 = fig.subplots(1, 2)
    ax1.plot(t, force, color='C0', label='applied force')
    ax1.set_xlabel('time (s)')
    ax1.set_ylabel('applied force (N)', color='C0')
    ax1b = ax1.twinx()
    ax1b.plot(t, 1e6 * x, color='C1', label='displacement')
    ax1b.set_ylabel('displacement (\u00b5m)', color='C1')
    ax1.set_title('force below $F_s$ and response')
    ax2.plot(1e6 * x, friction, color='C3', label='LuGre')
    xs = np.array([-0.2, 0.2]) * m['force_amplitude'] / m['sigma0']
    ax2.plot(1e6 * xs, m['sigma0'] * xs, 'k--', label='slope $\\sigma_0$ = %.0f N/m' % m['sigma0'])
    ax2.set_xlabel('displacement (\u00b5m)')
    ax2.set_ylabel('friction force (N)')
    ax2.set_title('pre-sliding: stiffness %.0f N/m at zero force' % m['stiffness'])
    ax2.legend(loc='lower right', fontsize='small')
    ax2.grid(True, alpha=0.3)


def _plot_lag(fig, res):
    s, m = res.series, res.summary
    ax = fig.subplots()
    ax.plot(1e3 * s['v_static'], s['friction_static'], 'k--', lw=1, label='steady state')
    for i, w in enumerate(m['omegas']):
        v, f = _thin(s['v'][i], s['friction'][i])
        ax.plot(1e3 * v, f, color=f'C{i}',
                label='$\\omega$ = %g rad/s (width %.3g N)' % (w, m['loop_width'][i]))
    ax.set_xlabel('velocity (mm/s)')
    ax.set_ylabel('friction force (N)')
    ax.set_title('frictional lag: $v(t) = %g + %g\\,\\cos(\\omega t)$ mm/s'
                 % (1e3 * m['v_mean'], 1e3 * m['v_amplitude']))
    ax.legend(fontsize='small')
    ax.grid(True, alpha=0.3)


def _plot_breakaway(fig, res):
    s, m = res.series, res.summary
    ax1, ax2 = fig.subplots(1, 2)
    for i, r in enumerate(m['rates']):
        ax1.plot(*_thin(s['force'][i], s['friction'][i]), lw=1, label='%g N/s' % r)
    ax1.set_xlabel('applied force (N)')
    ax1.set_ylabel('friction force (N)')
    ax1.set_title('force ramps $F = r\\,t$')
    ax1.legend(fontsize='x-small', ncol=2)
    ax1.grid(True, alpha=0.3)
    ok = [i for i, f in enumerate(m['breakaway_force']) if f is not None]
    rates = [m['rates'][i] for i in ok]
    ax2.semilogx(rates, [m['breakaway_force'][i] for i in ok], 'o-', label='friction at peak')
    ax2.semilogx(rates, [m['applied_force_at_breakaway'][i] for i in ok], 's--',
                 label='applied force then')
    ax2.axhline(m['fs'], color='k', lw=0.8, ls=':')
    ax2.axhline(m['fc'], color='k', lw=0.8, ls=':')
    ax2.set_xlabel('force rate (N/s)')
    ax2.set_ylabel('break-away force (N)')
    ax2.set_title('varying break-away force')
    ax2.legend(fontsize='small')
    ax2.grid(True, which='both', alpha=0.3)


def _plot_stick_slip(fig, res):
    s, m = res.series, res.summary
    t, x, y, v, friction = _thin(s['t'], s['x'], s['y'], s['v'], s['friction'])
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(t, x, label='mass $x$')
    ax1.plot(t, y, '--', label='spring end $y = v_p t$')
    ax1.set_ylabel('position (m)')
    ax1.legend(fontsize='small')
    ax1.set_title('stick-slip: period %.4g s' % m['period'] if m['period'] else 'stick-slip')
    ax2.plot(t, friction, color='C3', label='friction force')
    ax2.set_ylabel('friction force (N)', color='C3')
    ax2.set_xlabel('time (s)')
    ax2b = ax2.twinx()
    ax2b.plot(t, v, color='C2', lw=0.8)
    ax2b.set_ylabel('velocity (m/s)', color='C2')
    for t_on in m['slip_onsets']:
        ax2.axvline(t_on, color='k', lw=0.5, ls=':')


def _g(x, digits=3):
    """``x`` to ``digits`` significant digits (whole from 1000 on, thousands spaced); None: –."""
    if x is None:
        return '–'
    if abs(x) >= 1000.0:
        return f'{float(f"{x:.{digits}g}"):,.0f}'.replace(',', '\u2009')
    return f'{x:.{digits}g}'


def _rows(head, rows):
    """Return a Markdown table: ``head``, its separator line, ``rows``."""
    return [head, '|' + '---|' * (head.count('|') - 1)] + rows


def _md_presliding(m):
    um = 1e6
    return _rows('| quantity | value | unit |', [
        f'| applied force amplitude A (below F_s) | {_g(m["force_amplitude"])} | N |',
        f'| bristle stiffness σ0 (parameter) | {_g(m["sigma0"])} | N/m |',
        f'| stiffness measured at zero force (mean of {len(m["stiffness_passages"])} '
        f'passages) | {_g(m["stiffness"], 5)} | N/m |',
        f'| its error against σ0 | {100.0 * m["stiffness_error"]:.2f} | % |',
        f'| stiffness on the first loading from rest | {_g(m["stiffness_virgin"], 5)} | N/m |',
        f'| largest displacement (quasi-static formula) | {_g(um * m["x_max"])} '
        f'({_g(um * m["x_max_quasistatic"])}) | µm |',
        f'| smallest displacement (quasi-static formula) | {_g(um * m["x_min"])} '
        f'({_g(um * m["x_min_quasistatic"])}) | µm |',
        f'| displacement after the cycle, back at zero force | {_g(um * m["x_end"])} | µm |',
        f'| loop closure (second +A hold minus first) | {_g(um * m["loop_closure"])} | µm |',
        f'| largest velocity (never sliding: far below v_s = 1 mm/s) '
        f'| {_g(1e3 * m["v_peak"])} | mm/s |'])


def _md_lag(m):
    head = [f'Imposed velocity v(t) = {1e3 * m["v_mean"]:g} + {1e3 * m["v_amplitude"]:g} '
            'cos(ω t) mm/s; loop width: the largest friction difference between the '
            'decelerating and the accelerating branch at equal velocity; loop area: the '
            'area enclosed in the friction-velocity plane.', '']
    return head + _rows('| ω (rad/s) | loop width (N) | loop area (N mm/s) |', [
        f'| {w:g} | {_g(width)} | {_g(1e3 * area)} |'
        for w, width, area in zip(m['omegas'], m['loop_width'], m['loop_area'], strict=True)])


def _md_breakaway(m):
    head = [f'Force ramps F = r t on the resting mass (F_s = {m["fs"]:g} N, '
            f'F_c = {m["fc"]:g} N); the break-away force is the friction at its stiction '
            'peak, where the mass breaks loose.', '']
    rows = []
    for r, f, fa, tb in zip(m['rates'], m['breakaway_force'],
                            m['applied_force_at_breakaway'], m['time_to_breakaway'], strict=True):
        if f is None:
            rows.append(f'| {r:g} | no peak: friction rises straight to the kinetic level '
                        '| – | – |')
        else:
            rows.append(f'| {r:g} | {f:.3f} | {fa:.3f} | {_g(tb)} |')
    return head + _rows('| force rate r (N/s) | break-away force (N) | applied force then (N) '
                        '| time to break-away (s) |', rows)


def _md_stick_slip(m):
    onsets = m['slip_onsets']
    forces = m.get('spring_force_at_slip') or []
    rows = [f'| spring stiffness k | {_g(m.get("spring_stiffness"))} | N/m |',
            f'| pulling velocity v_p | {_g(m.get("pull_velocity"))} | m/s |',
            f'| slips in the run | {len(onsets)} | |',
            f'| first slip onset | {_g(onsets[0] if onsets else None, 4)} | s |',
            f'| stick-slip period | {_g(m["period"], 4)} | s |']
    if forces:
        rows.append(f'| spring force at slip onset (the static level) | '
                    f'{min(forces):.3f}' + (f'-{max(forces):.3f}' if
                                            f'{min(forces):.3f}' != f'{max(forces):.3f}'
                                            else '') + ' | N |')
    rows += [f'| largest sliding velocity | {_g(m["v_max"])} | m/s |',
             f'| position of the mass at the end | {_g(m["x_end"])} | m |']
    return _rows('| quantity | value | unit |', rows)


_MARKDOWN = {'presliding': _md_presliding, 'lag': _md_lag, 'breakaway': _md_breakaway,
             'stick-slip': _md_stick_slip}


def summary_markdown(name, summary):
    """
    Return the summary of classic experiment ``name`` as Markdown lines (tables with units).

    Parameters
    ----------
    name : str
        ``presliding``, ``lag``, ``breakaway`` or ``stick-slip``.
    summary : dict
        The experiment's ``summary`` (as written to ``NAME.json``).

    Returns
    -------
    list of str
        The set-up in a sentence where it is not in the table, then one
        table with the results and their units.

    """
    return _MARKDOWN[name](summary)


#: experiment name -> (figure function, title)
FIGURES = {
    'presliding': (_plot_presliding, 'Pre-sliding displacement'),
    'lag': (_plot_lag, 'Frictional lag'),
    'breakaway': (_plot_breakaway, 'Varying break-away force'),
    'stick-slip': (_plot_stick_slip, 'Stick-slip motion'),
}


def draw_classic(fig, result):
    """
    Draw the figure of a classic experiment on ``fig``, titled.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The (empty) figure to draw on.
    result : ExperimentResult
        The run; its ``name`` selects the figure in :data:`FIGURES`.

    """
    plot, title = FIGURES[result.name]
    plot(fig, result)
    fig.suptitle(title + ' (LuGre, Canudas de Wit et al. 1995 parameters)')
