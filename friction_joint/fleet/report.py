# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The files of ``friction_joint fleet``: ``fleet.json``, ``recordings.csv``, ``report.html``.

``report.html`` is one self-contained page (Markdown rendered by
:func:`~friction_joint.report_html.markdown_to_html`, figures embedded as
``data:`` URIs): the reference point, the fleet summary table (one row per
joint: verdict, onset, rate, p-value, the naive monitor's verdict, failed
recordings), a trend plot per joint (:mod:`~friction_joint.fleet.plots`) and
the failed recordings with their reasons.

Both are opened by people who did not write what they quote, so they are
inert.  In ``report.html`` every text from outside (joint ids, recording and
file paths, the scheduler's address, failure reasons, also those read from
the cache) is escaped (:func:`~friction_joint.report_html.markdown_text`:
shown as written, never markup, a link or an image) and the only images are
the trend plots rendered here (no file is opened).  In ``recordings.csv`` a
text cell (and a metadata column's name) that a spreadsheet would take for a
formula -- one starting with ``=``, ``+``, ``-``, ``@``, a tab or a carriage
return -- is prefixed with a single quote (:func:`csv_cell`, the OWASP rule);
numbers are written as numbers.
"""
import csv
import io

from .plots import trend_figures
from ..output import json_bytes, render_png

__all__ = ['CSV_COLUMNS', 'FORMULA_START', 'csv_cell', 'fleet_files', 'recordings_csv',
           'report_markdown']

CSV_COLUMNS = ('joint', 'time', 'recording', 'status', 'reason', 'reference_friction',
               'reference_friction_se', 'fc_ref', 'fc_ref_se', 'raw_friction',
               'raw_friction_se', 'xi_min', 'xi_max', 'load_min', 'load_max', 'travel',
               'odometer', 'plateaus', 'fitted_terms', 'cached')


#: first characters that make a spreadsheet read a cell as a formula
FORMULA_START = ('=', '+', '-', '@', '\t', '\r')


def _num(v, fmt='.5g'):
    return '' if v is None else format(v, fmt)


def csv_cell(text):
    """
    Return ``text`` for a CSV cell that a spreadsheet shows as text, never runs as a formula.

    A text starting with one of :data:`FORMULA_START` gets a leading single
    quote (the OWASP rule against CSV injection); any other is returned as is.
    """
    text = '' if text is None else str(text)
    return "'" + text if text.startswith(FORMULA_START) else text


def recordings_csv(assessment):
    """Return ``recordings.csv`` (text): one row per manifest entry, metadata columns last."""
    meta = []
    for r in assessment.recordings:
        meta += [k for k in r['metadata'] if k not in meta and k not in CSV_COLUMNS]
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator='\n')
    w.writerow(list(CSV_COLUMNS) + [csv_cell(k) for k in meta])
    for r in assessment.recordings:
        xi = r['xi_range'] or (None, None)
        load = r['load_range'] or (None, None)
        vals = {'xi_min': xi[0], 'xi_max': xi[1], 'load_min': load[0], 'load_max': load[1],
                'fitted_terms': ' '.join(str(t) for t in r['terms'])}
        row = []
        for c in CSV_COLUMNS:
            v = vals[c] if c in vals else r.get(c)
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                row.append(csv_cell(v))
            else:
                row.append(_num(v) if isinstance(v, float) else str(v))
        w.writerow(row + [csv_cell(r['metadata'].get(k, '')) for k in meta])
    return buf.getvalue()


def _cell(text):
    """Return a user's (or any) text for the report's Markdown: shown as written."""
    from ..report_html import markdown_text       # Python-Markdown: loaded for reports only
    return markdown_text(text)


def figure_name(k):
    """Return the name the report's Markdown gives the ``k``-th joint's trend plot."""
    return f'trend-{k}.png'


def report_markdown(assessment, run_info, figures):
    """
    Return the report's Markdown.

    Parameters
    ----------
    assessment : FleetAssessment
        The verdict.
    run_info : dict
        ``manifest``, ``model``, ``computed``, ``cached``, ``workers``, ``scheduler``.
    figures : dict
        Joint -> name of its trend plot in the Markdown.

    """
    a = assessment
    n_rec = len(a.recordings)
    failed = [r for r in a.recordings if r['status'] != 'ok']
    flagged = sorted(j for j, d in a.joints.items() if d['wear'])
    lines = [
        '# Fleet friction report', '',
        f'Manifest {_cell(run_info["manifest"])}, model {_cell(run_info["model"])}: '
        f'{len(a.joints)} joints, {n_rec} recordings ({n_rec - len(failed)} analysed, '
        f'{len(failed)} failed; {run_info["computed"]} computed on {run_info["workers"]} '
        f'workers ({_cell(run_info["scheduler"])}), {run_info["cached"]} from the cache).', '',
        f'Reference point: temperature {a.xi_ref:.2f} degC, speed '
        + ('none (no recording analysed)' if a.v_ref is None else f'{a.v_ref:.3g} rad/s') + ', '
        'no load (the fleet medians). *Reference friction* is the identified static curve '
        'there; the *raw mean friction* is the mean |friction torque| of the plateaus, '
        'uncompensated. Extra standard deviation over the fleet: '
        f'{a.extra_sd["reference"]:.3g} N m (reference), {a.extra_sd["raw"]:.3g} N m (raw).',
        '', f'**Wearing joints: {", ".join(_cell(j) for j in flagged) if flagged else "none"}.**',
        '',
        '## Summary', '',
        '| joint | wear | onset | rate (N m/day) | rate (N m/krad) | p-value | naive monitor '
        '| recordings | failed |',
        '|---|---|---|---|---|---|---|---|---|']
    for j in sorted(a.joints):
        d = a.joints[j]
        ev = d['evidence']
        rate = d['rate'] or {}
        naive = ev.get('raw_mean_friction')
        lines.append('| ' + ' | '.join(_cell(c) for c in (
            j, 'yes' if d['wear'] else 'no', d['onset'] or '',
            f'{rate["per_day"]:.3g} ± {rate["per_day_se"]:.2g}' if rate else '',
            f'{1e3 * rate["per_travel"]:.3g} ± {1e3 * rate["per_travel_se"]:.2g}'
            if rate else '',
            f'{ev["p_value"]:.3g}' if 'p_value' in ev else ev.get('note', ''),
            '' if naive is None else ('wear' if naive['wear'] else 'no wear')
            + f' (p = {naive["p_value"]:.3g})',
            d['recordings'], d['failed'])) + ' |')
    lines += ['', '## Trends', '']
    for j in sorted(a.joints):
        lines += [f'### {_cell(j)}', '', f'![trend plot]({figures[j]})', '']
    if failed:
        lines += ['## Failed recordings', '', '| joint | time | recording | reason |',
                  '|---|---|---|---|']
        for r in failed:
            lines.append(f'| {_cell(r["joint"])} | {_cell(r["time"])} | '
                         f'{_cell(r["recording"])} | {_cell(r["reason"])} |')
        lines.append('')
    return '\n'.join(lines) + '\n'


def fleet_files(assessment, run_info):
    """
    Return ``[(name, bytes)]`` of the output directory.

    ``fleet.json`` (:meth:`FleetAssessment.to_dict` plus ``run``), ``recordings.csv``,
    ``report.html`` (its only images the trend plots rendered here: no file is read).
    """
    from ..report_html import markdown_to_html
    names, images = {}, {}
    for k, (j, (draw, size)) in enumerate(trend_figures(assessment).items()):
        names[j] = figure_name(k)
        images[names[j]] = render_png(draw, size)
    md = report_markdown(assessment, run_info, names)
    doc = assessment.to_dict()
    doc['run'] = dict(run_info)
    return [('fleet.json', json_bytes(doc)),
            ('recordings.csv', recordings_csv(assessment).encode('utf-8')),
            ('report.html', markdown_to_html(md, images=images,
                                             title='Fleet friction report').encode('utf-8'))]
