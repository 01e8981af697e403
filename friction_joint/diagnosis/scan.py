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
Open residual scan: the final model's held-out residual against variables no candidate covers.

The candidates of :data:`~friction_joint.diagnosis.pipeline.EFFECTS` are a
closed list; the scan points at an effect outside it even when it cannot be
named.  The residual is the held-out residual of the diagnosed model (all
named effects) per 10 ms bin, against:

* ``time``: sliding time (bin order over all recordings);
* ``position``: a periodogram of the residual over position, periods from
  twice the median travel of a bin (shorter periods are averaged out within
  a bin) to the stroke: the strongest period is reported;
* ``velocity`` and ``acceleration`` (signed);
* ``temperature_rate``: d xi / dt (smoothed over :data:`RATE_WINDOW` s);
* ``dwell``: the time the joint stood still before the breakaway, for the
  first :data:`BREAKAWAY_BINS` bins after every breakaway (the residual
  times sign(qd) there).

Significance, the same for every variable: ``explained`` is the fraction of
the residual's held-out variance explained by a smooth fit on the variable
-- the residual's mean over :data:`N_QUANT` quantile bins of the variable
(for ``position``: a sine at the strongest period), fitted on K - 1 of the
contiguous cross-validation blocks and scored on the held-out one, against
the training mean.  The ``p_value`` is that of a permutation test with
:data:`N_PERM` circular shifts of the residual against the variables (at
least a tenth of the data apart): a shift keeps the residual's own time
correlation, which a free permutation would destroy and so overstate the
significance.  For ``position`` the statistic is the periodogram's largest
peak, searched again in every shift, so the search over periods is paid
for.  A variable the data do not have (no temperature signal, too few
breakaways) gets a ``note`` and no figure.
"""
import numpy as np

from .data import BIN

__all__ = ['N_PERM', 'N_QUANT', 'SCAN_ALPHA', 'SCAN_MIN_EXPLAINED', 'BREAKAWAY_BINS',
           'RATE_WINDOW', 'residual_scan', 'draw_scan', 'scan_png', 'markdown_lines',
           'position_periodogram']

#: circular shifts of the permutation test
N_PERM = 199
#: quantile bins of the smooth fit
N_QUANT = 8
#: a variable is ``flagged`` when its p-value is below this ...
SCAN_ALPHA = 0.01
#: ... and it explains at least this fraction of the held-out residual variance (the
#: variance counterpart of the criterion's 3 % minimum RMSE gain: 1 - 0.97 ** 2)
SCAN_MIN_EXPLAINED = 1.0 - (1.0 - 0.03) ** 2
#: bins after a breakaway whose residual is scanned against the dwell time
BREAKAWAY_BINS = 5
#: window (s) of the temperature-rate smoothing
RATE_WINDOW = 10.0
#: fewest bins a variable needs to be scanned
MIN_BINS = 50
#: zero padding of the position periodogram
PAD = 8
#: most position cells of the periodogram
MAX_CELLS = 2 ** 15
#: fixed seed of the circular shifts (the scan is reproducible)
SEED = 20260101


def _shifted(r, rng):
    """Rows: ``r`` and :data:`N_PERM` circular shifts of it."""
    n = len(r)
    lo = max(1, n // 10)
    offs = rng.integers(lo, max(lo + 1, n - lo), N_PERM)
    idx = (np.arange(n)[None, :] - offs[:, None]) % n
    return np.vstack([r[None, :], r[idx]])


def _explained(rows, key, block, k, n_cells):
    """Held-out explained variance of cell means (cell ``key``) per row of ``rows``."""
    n = rows.shape[1]
    cnt = np.bincount(block * n_cells + key, minlength=k * n_cells).reshape(k, n_cells)
    tc = cnt.sum(0)[None, :] - cnt
    nb = np.bincount(block, minlength=k)
    out = np.empty(rows.shape[0])
    for i, r in enumerate(rows):
        s = np.bincount(block * n_cells + key, weights=r, minlength=k * n_cells)
        s = s.reshape(k, n_cells)
        sb = s.sum(1)
        tm = (sb.sum() - sb) / np.maximum(n - nb, 1)          # training mean per fold
        ts = s.sum(0)[None, :] - s
        cm = np.where(tc > 0, ts / np.maximum(tc, 1), tm[:, None])
        sse = np.sum((r - cm[block, key]) ** 2)
        sst = np.sum((r - tm[block]) ** 2)
        out[i] = 1.0 - sse / sst if sst > 0 else 0.0
    return out


def _quantile_cells(x):
    edges = np.unique(np.quantile(x, np.linspace(0, 1, N_QUANT + 1)[1:-1]))
    return np.searchsorted(edges, x, side='right'), len(edges) + 1


def _scan_variable(name, x, r, block, k, rng):
    """Table entry and plot data of one variable (quantile-bin smooth fit)."""
    if len(x) < MIN_BINS:
        return {'variable': name, 'explained': None, 'p_value': None,
                'note': f'only {len(x)} bins (at least {MIN_BINS} needed)'}, None
    key, n_cells = _quantile_cells(x)
    if n_cells < 2:
        return {'variable': name, 'explained': None, 'p_value': None,
                'note': 'the variable does not vary'}, None
    stat = _explained(_shifted(r, rng), key, block, k, n_cells)
    p = float((1 + np.count_nonzero(stat[1:] >= stat[0])) / (1 + N_PERM))
    return ({'variable': name, 'explained': float(stat[0]), 'p_value': p, 'note': ''},
            {'x': x, 'r': r})


def position_periodogram(q, rows, p_min, p_max):
    """Return periods and |FFT|^2 (per row) of residuals ``rows`` on a uniform grid of ``q``."""
    span = float(np.ptp(q))
    cell = max(p_min / 4.0, span / MAX_CELLS)
    idx = np.minimum(((q - q.min()) / cell).astype(np.int64), int(span / cell))
    n_cells = int(idx.max()) + 1
    cnt = np.bincount(idx, minlength=n_cells)
    w = 1.0 / np.sqrt(np.maximum(cnt, 1))
    grid = np.stack([np.bincount(idx, weights=r - r.mean(), minlength=n_cells) * w
                     for r in rows])
    nfft = 1 << int(np.ceil(np.log2(PAD * n_cells)))
    power = np.abs(np.fft.rfft(grid, nfft, axis=1)) ** 2
    f = np.fft.rfftfreq(nfft, d=cell)
    band = (f >= 1.0 / p_max) & (f <= 1.0 / p_min)
    return 1.0 / f[band], power[:, band] / n_cells


def _sine_explained(q, r, period, block, k):
    """Held-out explained variance of a sine and a constant at ``period`` (K - 1 blocks fit)."""
    x = np.column_stack([np.ones_like(q), np.sin(2 * np.pi * q / period),
                         np.cos(2 * np.pi * q / period)])
    g = np.stack([x[block == i].T @ x[block == i] for i in range(k)])
    b = np.stack([x[block == i].T @ r[block == i] for i in range(k)])
    sse = sst = 0.0
    for i in range(k):
        m = block == i
        beta = np.linalg.lstsq(g.sum(0) - g[i], b.sum(0) - b[i], rcond=None)[0]
        sse += float(np.sum((r[m] - x[m] @ beta) ** 2))
        sst += float(np.sum((r[m] - np.mean(r[~m])) ** 2))
    return 1.0 - sse / sst if sst > 0 else 0.0


def _scan_position(data, r, rows, block, k):
    q = data.average(data.q)
    travel = float(np.median(np.abs(data.average(data.qd)))) * BIN
    p_min = max(2.0 * travel, 2.0 * data.resolution)
    p_max = float(min(data.stroke or np.ptp(q), np.ptp(q)))
    if not p_max > 2.0 * p_min:
        return {'variable': 'position', 'explained': None, 'p_value': None,
                'note': f'the stroke {p_max:.4g} rad is too short for periods above '
                        f'{p_min:.4g} rad'}, None
    periods, power = position_periodogram(q, rows, p_min, p_max)
    j = int(np.argmax(power[0]))
    peak = power.max(axis=1)
    p = float((1 + np.count_nonzero(peak[1:] >= peak[0])) / (1 + N_PERM))
    period = float(periods[j])
    entry = {'variable': 'position', 'explained': _sine_explained(q, r, period, block, k),
             'p_value': p, 'period': period,
             'note': f'strongest period {period:.4g} rad of {p_min:.3g}..{p_max:.3g} rad'}
    return entry, {'x': q, 'r': r, 'periods': periods, 'power': power[0], 'period': period}


def _temperature_rate(data):
    rate = np.zeros(len(data.t))
    for p in np.unique(data.piece):
        m = np.flatnonzero(data.piece == p)
        dt = data.dt[m[0]]
        n = max(1, int(round(RATE_WINDOW / dt)))
        xi = data.xi[m]
        c = np.cumsum(np.r_[0.0, xi])
        lo = np.clip(np.arange(len(m)) - n // 2, 0, len(m))
        hi = np.clip(np.arange(len(m)) + n // 2 + 1, 0, len(m))
        sm = (c[hi] - c[lo]) / (hi - lo)
        rate[m] = np.gradient(sm, dt) if len(m) > 1 else 0.0
    return rate


def _dwell(data):
    """Per bin: dwell time before the breakaway, and whether it is a first bin after one."""
    stick = np.abs(data.qd) < data.v_stick
    n = len(stick)
    new_piece = np.r_[True, data.piece[1:] != data.piece[:-1]]
    prev = np.r_[False, stick[:-1]] & ~new_piece
    start = stick & ~prev                                   # first sample of a stick run
    end = ~stick & prev                                     # first sliding sample after one
    ar = np.arange(n)
    last_start = np.maximum.accumulate(np.where(start, ar, -1))
    piece_start = np.maximum.accumulate(np.where(new_piece, ar, 0))
    last_end = np.maximum.accumulate(np.where(end, ar, -1))
    has = (last_end >= piece_start) & (last_end >= 0)
    dwell_at_end = np.zeros(n)
    e = np.flatnonzero(end)
    dwell_at_end[e] = data.t[e] - data.t[last_start[e]]
    dwell = np.where(has, dwell_at_end[np.maximum(last_end, 0)], np.nan)
    ep = data.average(np.where(has, last_end, -1).astype(float))
    dw = data.average(np.nan_to_num(dwell, nan=0.0))
    first = np.r_[True, ep[1:] != ep[:-1]]
    rank = np.arange(len(ep)) - np.maximum.accumulate(np.where(first, np.arange(len(ep)), 0))
    sel = (ep >= 0) & (rank < BREAKAWAY_BINS)
    return dw, sel


def residual_scan(data, r):
    """
    Scan the residual ``r`` (per bin) against the variables of the module docstring.

    Parameters
    ----------
    data : DiagnosisData
        The diagnosis data.
    r : ndarray
        Held-out residual of the final model per bin (Nm).

    Returns
    -------
    dict
        ``table``: list of ``{variable, explained, p_value, note, flagged}``
        (``position`` also has ``period``, rad); ``plot``: variable -> plot data (None for a
        variable with a note only).

    """
    rng = np.random.default_rng(SEED)
    block, k = data.block, data.n_blocks
    table, plot = [], {}
    rows = _shifted(r, rng)

    def add(entry, pdata):
        table.append(entry)
        plot[entry['variable']] = pdata

    add(*_scan_variable('time', np.arange(len(r)) * BIN, r, block, k, rng))
    add(*_scan_position(data, r, rows, block, k))
    add(*_scan_variable('velocity', data.average(data.qd), r, block, k, rng))
    add(*_scan_variable('acceleration', data.average(data.qdd), r, block, k, rng))
    if data.has_temperature:
        add(*_scan_variable('temperature_rate', data.average(_temperature_rate(data)),
                            r, block, k, rng))
    else:
        add({'variable': 'temperature_rate', 'explained': None, 'p_value': None,
             'note': 'no temperature signal in the recordings'}, None)
    dw, sel = _dwell(data)
    sgn = np.sign(data.average(data.qd))
    entry, pdata = _scan_variable('dwell', dw[sel], (r * sgn)[sel], block[sel], k, rng)
    if entry['explained'] is not None:
        entry['note'] = (f'{int(sel.sum())} bins within {BREAKAWAY_BINS} bins after a '
                         'breakaway; residual x sign(qd)')
    else:
        entry['note'] = f'{entry["note"]} after a breakaway'
    add(entry, pdata)
    for e in table:
        e['flagged'] = bool(e['p_value'] is not None and e['p_value'] < SCAN_ALPHA
                            and e['explained'] >= SCAN_MIN_EXPLAINED)
    return {'table': table, 'plot': plot}


#: scatter points per panel of the figure at most (evenly spaced in time)
MAX_POINTS = 1500
#: axis labels of the scanned variables
LABELS = {'time': 'sliding time (s)', 'position': 'cycles per rad (1 / period)',
          'velocity': 'velocity qd (rad/s)', 'acceleration': 'acceleration qdd (rad/s^2)',
          'temperature_rate': 'temperature rate d xi/dt (degC/s)',
          'dwell': 'dwell time before the breakaway (s)'}


def _binned_means(x, r):
    key, n_cells = _quantile_cells(x)
    cnt = np.bincount(key, minlength=n_cells)
    ok = cnt > 0
    xm = np.bincount(key, weights=x, minlength=n_cells)[ok] / cnt[ok]
    return xm, np.bincount(key, weights=r, minlength=n_cells)[ok] / cnt[ok]


def scan_png(scan, size=(12, 7), dpi=100):
    """Return the PNG bytes of the residual-scan figure (:func:`draw_scan`)."""
    import io
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fig = Figure(figsize=size)
    FigureCanvasAgg(fig)
    draw_scan(fig, scan)
    buf = io.BytesIO()
    fig.savefig(buf, format='png', dpi=dpi)
    return buf.getvalue()


def draw_scan(fig, scan):
    """Draw the residual scan (:func:`residual_scan`'s result) on a matplotlib figure."""
    ax = fig.subplots(2, 3).ravel()
    for a, entry in zip(ax, scan['table']):
        name = entry['variable']
        pdata = scan['plot'].get(name)
        a.set_xlabel(LABELS[name], fontsize=8)
        a.locator_params(nbins=4)
        a.tick_params(labelsize=7)
        if pdata is None:
            a.text(0.5, 0.5, entry['note'][:60], ha='center', va='center', fontsize=8,
                   transform=a.transAxes)
            a.set_xticks([])
            a.set_yticks([])
            a.set_title(name, fontsize=9)
            continue
        if name == 'position':
            a.plot(1.0 / pdata['periods'], pdata['power'] / max(pdata['power'].max(), 1e-300),
                   '-', color='C0', lw=0.8)
            a.axvline(1.0 / pdata['period'], color='C3', ls=':', lw=1)
            a.set_ylabel('periodogram of the residual (of its peak)', fontsize=8)
        else:
            pick = np.unique(np.linspace(0, len(pdata['x']) - 1, MAX_POINTS).astype(int))
            a.plot(pdata['x'][pick], pdata['r'][pick], '.', ms=1.0, color='0.6')
            xm, rm = _binned_means(pdata['x'], pdata['r'])
            a.plot(xm, rm, 'o-', color='C3', lw=1.5, ms=3)
            a.set_ylabel('held-out residual (Nm)', fontsize=8)
        a.set_title(f'{name}: explained {100 * entry["explained"]:.1f} %, '
                    f'p {entry["p_value"]:.3g}', fontsize=9,
                    color='C3' if entry['flagged'] else 'k')
    fig.subplots_adjust(left=0.07, right=0.98, bottom=0.08, top=0.95, wspace=0.3, hspace=0.35)


def markdown_lines(table):
    """Lines of the residual-scan section of ``report.md``."""
    lines = ['## Residual scan', '',
             'The held-out residual of the diagnosed model (all named effects) against '
             'variables no candidate has to cover.  *explained*: the fraction of the held-out '
             f'residual variance a smooth fit on the variable explains ({N_QUANT} quantile '
             'bins, for position a sine at the strongest period; fitted on the other blocks); '
             f'*p*: permutation test over {N_PERM} circular shifts of the residual (the period '
             'search repeated in each).  *flagged*: p < '
             f'{SCAN_ALPHA:g} and explained >= {100 * SCAN_MIN_EXPLAINED:.1f} % -- an effect '
             'outside the candidate list may be there.', '',
             '| variable | explained | p | flagged | note |', '|---|---|---|---|---|']
    for e in table:
        ex = '-' if e['explained'] is None else f'{100 * e["explained"]:.1f} %'
        p = '-' if e['p_value'] is None else f'{e["p_value"]:.3g}'
        lines.append(f'| {e["variable"]} | {ex} | {p} | {"**yes**" if e["flagged"] else "no"} '
                     f'| {e["note"]} |')
    return lines + ['', '![residual_scan.png](residual_scan.png)', '']
