# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Figures of the fleet report (drawn from a :class:`~friction_joint.fleet.assess.FleetAssessment`).

:func:`trend_figure` returns ``draw(fig)`` for one joint, :func:`trend_figures`
``{joint: (draw, size)}`` for all of them (the report's figures, and
:meth:`FleetRun.plot <friction_joint.jobs.runs.FleetRun.plot>`): the reference
friction with its standard errors (left axis) beside the raw mean friction
of the plateaus (same axis, what an uncompensated monitor sees), the
recording's temperature on a second axis, the fitted hinge and the onset
marked when the joint is flagged.
"""
import datetime
import re

import numpy as np

__all__ = ['TREND_SIZE', 'plain_text', 'trend_figure', 'trend_figures']

#: figure size (inches) of a trend plot
TREND_SIZE = (8.0, 4.2)


def plain_text(text):
    """
    Return ``text`` for a matplotlib label, shown as written (never mathtext).

    A joint id with ``$`` signs would otherwise be parsed as TeX math (and a
    malformed one fails the whole report); every ``$`` is escaped, control
    characters (tabs, line breaks) become blanks.
    """
    return re.sub(r'[\x00-\x1f\x7f]', ' ', str(text)).replace('$', r'\$')


def _dates(start, days):
    return [start + datetime.timedelta(days=float(d)) for d in days]


def trend_figure(joint, verdict, xi_ref, v_ref):
    """
    Return ``draw(fig)`` of one joint's trend plot.

    Parameters
    ----------
    joint : str
        The joint's id (the title).
    verdict : dict
        The joint's entry of :attr:`FleetAssessment.joints` (with ``series``).
    xi_ref, v_ref : float
        The reference point, named in the legend.

    """
    s = verdict['series']
    pts = s['points']
    joint = plain_text(joint)

    def draw(fig):
        ax = fig.add_subplot(111)
        if not pts:
            ax.text(0.5, 0.5, f'{joint}: no analysed recording', ha='center',
                    transform=ax.transAxes)
            return
        days = np.array([p['days'] for p in pts])
        when = _dates(s['start'], days)
        ref = np.array([p['reference'] for p in pts])
        se = np.array([p['reference_se'] for p in pts])
        raw = np.array([p['raw'] for p in pts])
        ax.errorbar(when, ref, yerr=se, fmt='o-', ms=3, lw=1, capsize=2, color='C0',
                    label=f'reference friction ({v_ref:.2g} rad/s, {xi_ref:.1f} degC, '
                          'no load)')
        ax.plot(when, raw, 's--', ms=3, lw=0.8, color='C1',
                label='raw mean friction (uncompensated)')
        ev = verdict.get('evidence', {})
        if verdict.get('wear') and ev.get('onset_day') is not None:
            onset = s['start'] + datetime.timedelta(days=ev['onset_day'])
            ax.axvline(onset, color='C3', lw=1.2, label=f'wear onset {onset:%Y-%m-%d %H:%M}')
            lo, hi = ev.get('onset_range', (ev['onset_day'], ev['onset_day']))
            ax.axvspan(s['start'] + datetime.timedelta(days=lo),
                       s['start'] + datetime.timedelta(days=hi), color='C3', alpha=0.12)
            if ev.get('axis') == 'time':
                fit = ev['level'] + ev['rate_per_day'] * np.clip(days - ev['onset_day'], 0.0,
                                                                 None)
            else:
                travel = np.array([p['travel'] for p in pts])
                fit = ev['level'] + ev['rate_per_travel'] * np.clip(
                    travel - ev['onset_travel'], 0.0, None)
            ax.plot(when, fit, '-', color='C3', lw=1, label=f'hinge fit (over {ev["axis"]})')
        ax.set_ylabel('friction torque (N m)')
        title = f'{joint}: ' + ('WEAR' if verdict.get('wear') else 'no wear')
        if ev.get('p_value') is not None:
            title += f' (p = {ev["p_value"]:.3g})'
        ax.set_title(title)
        ax2 = ax.twinx()
        xi = [p['xi'] for p in pts]
        ax2.plot(when, xi, '^:', ms=3, lw=0.6, color='C2', label='temperature')
        ax2.set_ylabel('housing temperature (degC)', color='C2')
        lines = ax.get_legend_handles_labels()
        lines2 = ax2.get_legend_handles_labels()
        fig.autofmt_xdate()
        ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=7, loc='upper center',
                  bbox_to_anchor=(0.5, -0.3), ncol=3, frameon=False)
    return draw


def trend_figures(assessment):
    """
    Return ``{joint: (draw(fig), TREND_SIZE)}`` of every joint's trend plot.

    Parameters
    ----------
    assessment : FleetAssessment
        The fleet's verdict (its joints and reference point).

    Returns
    -------
    dict
        By joint id, in the order of ``assessment.joints``.

    """
    return {j: (trend_figure(j, d, assessment.xi_ref, assessment.v_ref), TREND_SIZE)
            for j, d in assessment.joints.items()}
