# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The residual scan's figure and table (:func:`.scan.residual_scan` computes the scan).

:func:`draw_scan` draws the residual against each scanned variable with its
binned means, and the position periodogram with its strongest period;
:func:`scan_png` renders it; :func:`markdown_lines` gives the report's table.
"""
from __future__ import annotations

from collections.abc import Iterable
from typing import Any, TYPE_CHECKING

import numpy as np

from .scan import (BUFFER, COLLINEAR, N_PERM, N_QUANT, quantile_cells, SCAN_ALPHA,
                   SCAN_MIN_EXPLAINED)
from ..results import render_png

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from numpy.typing import NDArray

__all__ = ['draw_scan', 'scan_png', 'markdown_lines', 'table_cell', 'MAX_POINTS', 'SCAN_SIZE']

#: size of the residual-scan figure, inches
SCAN_SIZE = (12, 7)


#: scatter points per panel of the figure at most (evenly spaced in time)
MAX_POINTS = 1500
#: axis labels of the scanned variables
_LABELS = {'time': 'sliding time (s)', 'position': 'cycles per rad (1 / period)',
           'velocity': 'velocity qd (rad/s)', 'acceleration': 'acceleration qdd (rad/s^2)',
           'temperature_rate': 'temperature rate d xi/dt (degC/s)',
           'dwell': 'dwell time before the breakaway (s)'}


def table_cell(text: object) -> str:
    r"""
    Return computed or user text as one Markdown table cell: pipes escaped, one line.

    A ``|`` in a cell (``|tau_ext|``, ``|qd|``) would end the cell and cut the
    rest of the row in every renderer; ``\|`` shows it as written.
    """
    return ' '.join(str(text).replace('\\|', '|').replace('|', '\\|').split())


def _binned_means(x: NDArray[np.float64], r: NDArray[np.float64]
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    key, n_cells = quantile_cells(x)
    cnt = np.bincount(key, minlength=n_cells)
    ok = cnt > 0
    xm = np.bincount(key, weights=x, minlength=n_cells)[ok] / cnt[ok]
    return xm, np.bincount(key, weights=r, minlength=n_cells)[ok] / cnt[ok]


def scan_png(scan: dict[str, Any], size: tuple[float, float] = SCAN_SIZE,
             dpi: float = 100) -> bytes:
    """Return the PNG bytes of the residual-scan figure (:func:`draw_scan`)."""
    return render_png(lambda fig: draw_scan(fig, scan), size, dpi=dpi, tight=False)


def _title(entry: dict[str, Any]) -> str:
    if entry['p_value'] is None:
        return f'{entry["variable"]}: untestable'
    return (f'{entry["variable"]}: explained {100 * entry["explained"]:.1f} %, '
            f'p {entry["p_value"]:.3g}')


def draw_scan(fig: Figure, scan: dict[str, Any]) -> None:
    """Draw the residual scan (:func:`residual_scan`'s result) on a matplotlib figure."""
    ax = fig.subplots(2, 3).ravel()
    for a in ax[len(scan['table']):]:
        a.set_axis_off()
    for a, entry in zip(ax, scan['table'], strict=False):
        name = entry['variable']
        pdata = scan['plot'].get(name)
        a.locator_params(nbins=4)
        a.tick_params(labelsize=7)
        if pdata is None:
            a.text(0.5, 0.5, entry['note'][:60], ha='center', va='center', fontsize=8,
                   transform=a.transAxes)
            a.set_xticks([])
            a.set_yticks([])
            a.set_title(name, fontsize=9)
            continue
        if 'periods' in pdata:
            a.set_xlabel(_LABELS['position'], fontsize=8)
            a.plot(1.0 / pdata['periods'], pdata['power'] / max(pdata['power'].max(), 1e-300),
                   '-', color='C0', lw=0.8)
            a.axvline(1.0 / pdata['period'], color='C3', ls=':', lw=1)
            a.set_ylabel('periodogram of the residual (of its peak)', fontsize=8)
        else:
            first = entry.get('group', [name])[0]
            a.set_xlabel(_LABELS.get(first, first), fontsize=8)
            pick = np.unique(np.linspace(0, len(pdata['x']) - 1, MAX_POINTS).astype(int))
            a.plot(pdata['x'][pick], pdata['r'][pick], '.', ms=1.0, color='0.6')
            xm, rm = _binned_means(pdata['x'], pdata['r'])
            a.plot(xm, rm, 'o-', color='C3', lw=1.5, ms=3)
            a.set_ylabel('held-out residual (Nm)', fontsize=8)
        a.set_title(_title(entry), fontsize=9 if len(name) < 30 else 7,
                    color='C3' if entry['flagged'] else 'k')
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.08, top=0.95, wspace=0.3, hspace=0.35)


def markdown_lines(table: Iterable[dict[str, Any]]) -> list[str]:
    """Lines of the residual-scan section of ``report.md``."""
    lines = ['## Residual scan', '',
             'The held-out residual of the diagnosed model (all named effects) against '
             'variables no candidate has to cover.  *explained*: the fraction of the held-out '
             f'residual variance a smooth fit on the variable explains (at least {N_QUANT} '
             'quantile bins, for position a sine at the strongest period; fitted on the blocks '
             'farther from the held-out one than the residual is correlated, at least '
             f'{BUFFER + 1} blocks away); *p*: permutation test '
             f"over {N_PERM} random orders of the residual's cross-validation blocks (the "
             'period search repeated in each); *untestable*: the recording cannot tell the '
             'variable from a drift of the residual, or has too few blocks.  Variables '
             f'collinear in the recording (|rank correlation| > {COLLINEAR:g}) are one entry '
             f'(a ~ b).  *flagged*: p < {SCAN_ALPHA:g} and explained >= '
             f'{100 * SCAN_MIN_EXPLAINED:.1f} % -- an effect outside the candidate list may be '
             'there.', '',
             '| variable | explained | p | flagged | note |', '|---|---|---|---|---|']
    for e in table:
        ex = '-' if e['explained'] is None else f'{100 * e["explained"]:.1f} %'
        p = (('untestable' if e.get('untestable') else '-') if e['p_value'] is None
             else f'{e["p_value"]:.3g}')
        lines.append(f'| {table_cell(e["variable"])} | {ex} | {p} | '
                     f'{"**yes**" if e["flagged"] else "no"} | {table_cell(e["note"])} |')
    return lines + ['', '![residual_scan.png](residual_scan.png)', '']
