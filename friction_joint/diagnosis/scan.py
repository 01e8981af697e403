# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

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
* ``temperature_rate``: d xi / dt (smoothed over :data:`TEMPERATURE_RATE_WINDOW` s);
* ``dwell``: the time the joint stood still before the breakaway, for the
  first :data:`BREAKAWAY_BINS` bins after every breakaway (the residual
  times sign(qd) there).

Held-out fit.  ``explained`` is the fraction of the residual's held-out
variance explained by a smooth fit on the variable -- the residual's mean
over quantile cells of the variable (at least :data:`N_QUANT`, and no fewer
than the cross-validation blocks); for ``position`` a sine at the strongest
period of the training blocks' periodogram -- fitted on the contiguous
cross-validation blocks that are neither the held-out block nor one of its
neighbours on either side (at least :data:`BUFFER`, and as many as the
residual's autocorrelation takes to fall below :data:`CORR_FLOOR`), scored on
the held-out block against the training mean.  Leaving the neighbours out
keeps the residual's own slow correlation (a drift, slowly varying noise)
from passing for a dependence: a block is only predicted from stretches of
the recording away from it in time.  Bins whose cell no training block
visits are predicted by the training mean.

Null.  The ``p_value`` is that of a permutation test with :data:`N_PERM`
random orders of block-long contiguous pieces of the residual (cut at the
block boundaries moved by a random offset) against the variables: the null
keeps the residual's correlation within a piece (a free permutation would
destroy it and overstate the significance), and together with the held-out
fit away from the neighbours it stays meaningful when the variable is
monotone or periodic in time, where a circular shift of a drifting residual
is not.  The period search of ``position`` is repeated in every
fold of every permutation, so the search is paid for.

Untestable.  A variable whose value ranges are each visited in one stretch
of the recording only (``time`` always; position and velocity of a one-way
sweep) cannot be told from a drift of the residual: when fewer than
:data:`MIN_COVERAGE` of the bins lie in a cell some training block visits,
the entry is ``untestable`` (its reason, no p-value).  So is every variable
of data with fewer than :data:`MIN_UNITS` blocks (too few orders for a
p-value below the level), and a variable the data do not have (no
temperature signal, too few breakaways).

Collinear variables.  ``time``, ``position``, ``velocity``, ``acceleration``
(and ``temperature_rate``) whose rank correlation over the bins exceeds
:data:`COLLINEAR` in magnitude are one entry (``'time ~ position ~
velocity'``, its members in ``group``), tested once: by the fit on position
(the richest: any period) when position is in the group and testable, else
by the first testable member's.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any, cast, TYPE_CHECKING, TypedDict

import numpy as np

from .data import BIN, DiagnosisData

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

__all__ = ['N_PERM', 'N_QUANT', 'SCAN_ALPHA', 'SCAN_MIN_EXPLAINED', 'BREAKAWAY_BINS',
           'TEMPERATURE_RATE_WINDOW', 'BUFFER', 'CORR_FLOOR', 'MIN_UNITS', 'MIN_COVERAGE',
           'COLLINEAR', 'residual_scan', 'position_periodogram', 'quantile_cells']

#: random block orders of the permutation test
N_PERM = 199
#: fewest quantile cells of the smooth fit
N_QUANT = 8
#: a variable is ``flagged`` when its p-value is below this ...
SCAN_ALPHA = 0.01
#: ... and it explains at least this fraction of the held-out residual variance (the
#: variance counterpart of the criterion's 3 % minimum RMSE gain: 1 - 0.97 ** 2)
SCAN_MIN_EXPLAINED = 1.0 - (1.0 - 0.03) ** 2
#: fewest blocks on either side of the held-out block left out of its training set ...
BUFFER = 1
#: ... and more while the residual's autocorrelation at that many blocks is above this
CORR_FLOOR = 0.05
#: fewest cross-validation blocks (exchangeable units) for a p-value (6! = 720 orders)
MIN_UNITS = 6
#: fewest fraction of the bins whose cell a training block visits for a variable to be tested
MIN_COVERAGE = 0.5
#: |rank correlation| over the bins above which variables are one collinear entry
COLLINEAR = 0.95
#: bins after a breakaway whose residual is scanned against the dwell time
BREAKAWAY_BINS = 5
#: window (s) of the temperature-rate smoothing
TEMPERATURE_RATE_WINDOW = 10.0
#: fewest bins a variable needs to be scanned
MIN_BINS = 50
#: zero padding of the position periodogram
PAD = 8
#: most position cells of the periodogram
MAX_CELLS = 2 ** 15
#: longest FFT of the per-fold period search (the padding is reduced beyond it)
MAX_FFT = 2 ** 16
#: fixed seed of the block orders (the scan is reproducible)
SEED = 20260101
#: note of a collinear group
COLLINEAR_NOTE = ('collinear in this recording: a recording that moves them independently '
                  'would separate them')


class _Folds(TypedDict):
    """Cross-validation folds of the scan (:func:`_folds`)."""

    block: NDArray[np.int64]        # block of every bin
    k: int                          # number of blocks
    h: int                          # blocks left out on either side of the held-out one
    corr_s: float                   # correlation time of the residual (s)
    m: NDArray[np.float64]          # training matrix (row i: fold i's training blocks)


class _Scanned(TypedDict):
    """One variable's scan: statistic per row (or why none), note, plot data, table extras."""

    stat: NDArray[np.float64] | None
    reason: str
    note: str
    plot: dict[str, Any] | None
    extra: dict[str, Any]


def _folds(r: NDArray[np.float64], block: NDArray[np.int64], k: int) -> _Folds:
    """Cross-validation folds: blocks, buffer and training matrix (row i: fold i's blocks)."""
    r0 = r - r.mean()
    n = len(r0)
    f = np.fft.rfft(r0, 2 * n)
    acf = np.fft.irfft(np.abs(f) ** 2)[:n]
    below = np.flatnonzero(acf <= CORR_FLOOR * acf[0]) if acf[0] > 0 else np.array([0])
    lag = int(below[0]) if len(below) else n
    size = max(1, int(np.min(np.bincount(block, minlength=k))))
    h = max(BUFFER, int(np.ceil(lag / size)))
    i = np.arange(k)
    return {'block': block, 'k': k, 'h': h, 'corr_s': lag * BIN,
            'm': (np.abs(i[:, None] - i[None, :]) > h).astype(float)}


def _permuted(r: NDArray[np.float64], block: NDArray[np.int64], k: int,
              rng: np.random.Generator) -> NDArray[np.float64]:
    """
    Rows: ``r`` and :data:`N_PERM` copies cut into ``k`` contiguous pieces put in random order.

    The cuts are the block boundaries moved by a random offset (one per copy, circular), so
    a residual tied to a motion that repeats with the blocks does not stay tied to it.
    """
    order = np.argsort(block, kind='stable')
    rs = r[order]
    n = len(rs)
    edges = np.r_[0, np.cumsum(np.bincount(block, minlength=k))]
    rows = np.empty((N_PERM + 1, n))
    rows[0] = r
    for i in range(1, N_PERM + 1):
        rolled = np.roll(rs, -int(rng.integers(0, max(n, 1))))
        parts = [rolled[a:b] for a, b in zip(edges[:-1], edges[1:], strict=True)]
        rows[i, order] = np.concatenate([parts[j] for j in rng.permutation(k)])
    return rows


def quantile_cells(x: NDArray[np.float64],
                   n_quant: int = N_QUANT) -> tuple[NDArray[np.int64], int]:
    """Return each value's cell among ``n_quant`` quantile cells of ``x``, and the cell count."""
    edges = np.unique(np.quantile(x, np.linspace(0, 1, n_quant + 1)[1:-1]))
    return np.searchsorted(edges, x, side='right'), len(edges) + 1


def _coverage(key: NDArray[np.int64], n_cells: int, block: NDArray[np.int64], k: int,
              m: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Training counts per fold and cell, and whether each bin's cell has training bins."""
    cnt = np.bincount(block * n_cells + key, minlength=k * n_cells).reshape(k, n_cells)
    tc = m @ cnt
    return tc, tc[block, key] > 0


def _explained(rows: NDArray[np.float64], key: NDArray[np.int64], block: NDArray[np.int64],
               k: int, n_cells: int, m: NDArray[np.float64]) -> NDArray[np.float64]:
    """Held-out explained variance of cell means (cell ``key``) per row of ``rows``."""
    nr, n = rows.shape
    tc, _ = _coverage(key, n_cells, block, k, m)
    tn = np.maximum(m @ np.bincount(block, minlength=k), 1)
    flat = (np.arange(nr)[:, None] * (k * n_cells) + (block * n_cells + key)[None, :]).ravel()
    s = np.bincount(flat, weights=rows.ravel(), minlength=nr * k * n_cells)
    ts = np.einsum('ij,rjc->ric', m, s.reshape(nr, k, n_cells))
    tm = ts.sum(axis=2) / tn
    cm = np.where(tc[None] > 0, ts / np.maximum(tc, 1)[None], tm[:, :, None])
    sse = np.sum((rows - cm[:, block, key]) ** 2, axis=1)
    sst = np.sum((rows - tm[:, block]) ** 2, axis=1)
    return np.where(sst > 0, 1.0 - sse / np.where(sst > 0, sst, 1.0), 0.0)


def _monotone_reason(cov: float, cv: _Folds) -> str:
    return (f'untestable: only {100 * cov:.0f} % of the bins have their value range visited '
            f'again more than {cv["h"]} block(s) away (the residual is correlated over '
            f'{cv["corr_s"]:.3g} s): a dependence on the variable cannot be told from a drift '
            'of the residual')


def _result(stat: NDArray[np.float64] | None = None, reason: str = '', note: str = '',
            plot: dict[str, Any] | None = None, extra: dict[str, Any] | None = None) -> _Scanned:
    return {'stat': stat, 'reason': reason, 'note': note, 'plot': plot, 'extra': extra or {}}


def _scan_variable(x: NDArray[np.float64], rows: NDArray[np.float64], cv: _Folds) -> _Scanned:
    """Statistic per row of one variable (quantile-cell smooth fit), or why there is none."""
    if len(x) < MIN_BINS:
        return _result(reason=f'only {len(x)} bins (at least {MIN_BINS} needed)')
    block, k, m = cv['block'], cv['k'], cv['m']
    key, n_cells = quantile_cells(x, max(N_QUANT, k))
    if n_cells < 2:
        return _result(reason='the variable does not vary')
    plot = {'x': x, 'r': rows[0]}
    if k < MIN_UNITS:
        return _result(reason=_units_reason(k), plot=plot)
    cov = float(_coverage(key, n_cells, block, k, m)[1].mean())
    if cov < MIN_COVERAGE:
        return _result(reason=_monotone_reason(cov, cv), plot=plot)
    return _result(_explained(rows, key, block, k, n_cells, m), plot=plot)


def _units_reason(k: int) -> str:
    return (f'untestable: only {k} cross-validation blocks, at least {MIN_UNITS} are needed for '
            'a block-permutation p-value below the level')


def _grid(q: NDArray[np.float64], p_min: float
          ) -> tuple[NDArray[np.int64], int, float, NDArray[np.float64]]:
    """Position cells of the periodogram: index per bin, count, width and weights."""
    span = float(np.ptp(q))
    cell = max(p_min / 4.0, span / MAX_CELLS)
    idx = np.minimum(((q - q.min()) / cell).astype(np.int64), int(span / cell))
    n_cells = int(idx.max()) + 1
    w = 1.0 / np.sqrt(np.maximum(np.bincount(idx, minlength=n_cells), 1))
    return idx, n_cells, cell, w


def position_periodogram(q: NDArray[np.float64], rows: Sequence[NDArray[np.float64]],
                         p_min: float, p_max: float
                         ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return periods and |FFT|^2 (per row) of residuals ``rows`` on a uniform grid of ``q``."""
    idx, n_cells, cell, w = _grid(q, p_min)
    grid = np.stack([np.bincount(idx, weights=r - r.mean(), minlength=n_cells) * w
                     for r in rows])
    nfft = 1 << int(np.ceil(np.log2(PAD * n_cells)))
    power = np.abs(np.fft.rfft(grid, nfft, axis=1)) ** 2
    f = np.fft.rfftfreq(nfft, d=cell)
    band = (f >= 1.0 / p_max) & (f <= 1.0 / p_min)
    return cast('NDArray[np.float64]', 1.0 / f[band]), power[:, band] / n_cells


def _fold_periods(q: NDArray[np.float64], rows: NDArray[np.float64], cv: _Folds,
                  p_range: tuple[float, float]) -> NDArray[np.float64] | None:
    """Strongest period of the training blocks' periodogram, per row and fold."""
    block, k, h = cv['block'], cv['k'], cv['h']
    idx, n_cells, cell, w = _grid(q, p_range[0])
    nfft = max(min(1 << int(np.ceil(np.log2(PAD * n_cells))), MAX_FFT),
               1 << int(np.ceil(np.log2(n_cells))))
    f = np.fft.rfftfreq(nfft, d=cell)
    band = (f >= 1.0 / p_range[1]) & (f <= 1.0 / p_range[0])
    if not band.any():
        return None
    periods = 1.0 / f[band]
    key = block * n_cells + idx

    lo, hi = np.flatnonzero(band)[[0, -1]]
    near = np.clip(np.arange(k)[:, None] + np.array([[-h, h + 1]]), 0, k)

    def training(v: NDArray[Any]) -> NDArray[Any]:
        """Per fold: the sum over all blocks minus that over the held-out one and its buffer."""
        c = np.concatenate([np.zeros((1,) + v.shape[1:], v.dtype), np.cumsum(v, axis=0)])
        out: NDArray[Any] = c[-1][None] - (c[near[:, 1]] - c[near[:, 0]])
        return out

    def spectra(v: NDArray[np.float64]) -> NDArray[np.complex128]:
        g = np.bincount(key, weights=v * w[idx], minlength=k * n_cells).reshape(k, n_cells)
        return training(np.fft.rfft(g, nfft, axis=1)[:, lo:hi + 1])

    f1 = spectra(np.ones(len(q)))
    tn = np.maximum(training(np.bincount(block, minlength=k).astype(float)), 1)
    out = np.empty((rows.shape[0], k))
    for i, r in enumerate(rows):
        mean = training(np.bincount(block, weights=r, minlength=k)) / tn
        power = np.abs(spectra(r) - mean[:, None] * f1) ** 2
        out[i] = periods[np.argmax(power, axis=1)]
    return out


def _sine_explained(q: NDArray[np.float64], rows: NDArray[np.float64], cv: _Folds,
                    periods: NDArray[np.float64], covered: NDArray[np.bool_]
                    ) -> NDArray[np.float64]:
    """Held-out explained variance of a sine at each row's and fold's period (training fit)."""
    nr, block, m = rows.shape[0], cv['block'], cv['m']
    sse, sst = np.zeros(nr), np.zeros(nr)
    for i in range(m.shape[0]):
        test, train = block == i, m[i][block] > 0
        if not test.any() or not train.any():
            continue
        tm = rows[:, train].mean(axis=1)
        sst += np.sum((rows[:, test] - tm[:, None]) ** 2, axis=1)
        for period in np.unique(periods[:, i]):
            sel = periods[:, i] == period
            ph = 2 * np.pi * q / period
            x = np.column_stack([np.ones_like(q), np.sin(ph), np.cos(ph)])
            g = x[train].T @ x[train]
            g += 1e-12 * np.trace(g) * np.eye(3)
            beta = np.linalg.solve(g, x[train].T @ rows[sel][:, train].T)
            pred = np.where(covered[test][None, :], (x[test] @ beta).T, tm[sel][:, None])
            sse[sel] += np.sum((rows[sel][:, test] - pred) ** 2, axis=1)
    return np.where(sst > 0, 1.0 - sse / np.where(sst > 0, sst, 1.0), 0.0)


def _scan_position(data: DiagnosisData, rows: NDArray[np.float64], cv: _Folds) -> _Scanned:
    q, r = data.average(data.q), rows[0]
    travel = float(np.median(np.abs(data.average(data.qd)))) * BIN
    p_min = max(2.0 * travel, 2.0 * data.resolution)
    p_max = float(min(data.stroke or np.ptp(q), np.ptp(q)))
    if not p_max > 2.0 * p_min:
        return _result(reason=f'the stroke {p_max:.4g} rad is too short for periods above '
                              f'{p_min:.4g} rad')
    periods, power = position_periodogram(q, r[None], p_min, p_max)
    period = float(periods[int(np.argmax(power[0]))])
    note = f'strongest period {period:.4g} rad of {p_min:.3g}..{p_max:.3g} rad'
    plot = {'x': q, 'r': r, 'periods': periods, 'power': power[0], 'period': period}
    out = _result(note=note, plot=plot, extra={'period': period})
    block, k, m = cv['block'], cv['k'], cv['m']
    key, n_cells = quantile_cells(q, max(N_QUANT, k))
    if len(q) < MIN_BINS:
        out['reason'] = f'only {len(q)} bins (at least {MIN_BINS} needed)'
    elif k < MIN_UNITS:
        out['reason'] = _units_reason(k)
    else:
        covered = _coverage(key, n_cells, block, k, m)[1]
        if covered.mean() < MIN_COVERAGE:
            out['reason'] = _monotone_reason(float(covered.mean()), cv)
            return out
        fold_periods = _fold_periods(q, rows, cv, (p_min, p_max))
        if fold_periods is None:
            out['reason'] = 'no period of the position grid in the band'
        else:
            out['stat'] = _sine_explained(q, rows, cv, fold_periods, covered)
    return out


def _ranks(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Return the ranks of ``x``, ties averaged."""
    _, inv, cnt = np.unique(x, return_inverse=True, return_counts=True)
    return ((np.cumsum(cnt) - cnt) + (cnt - 1) / 2.0)[inv.ravel()]


def _collinear(xs: Mapping[str, NDArray[np.float64]]) -> list[list[str]]:
    """Return groups (name lists, in order) of variables with |rank correlation| > COLLINEAR."""
    names = list(xs)
    with np.errstate(invalid='ignore', divide='ignore'):
        c = np.nan_to_num(np.corrcoef(np.stack([_ranks(xs[n]) for n in names])))
    label = list(range(len(names)))
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            if abs(c[i, j]) > COLLINEAR and label[j] != label[i]:
                old = label[j]
                label = [label[i] if lab == old else lab for lab in label]
    return [[n for n, lab in zip(names, label, strict=True) if lab == g]
            for g in dict.fromkeys(label)]


def _combine(group: Sequence[str], results: Sequence[_Scanned]
             ) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """Table entry and plot data of a group of variables, tested once (position or the first)."""
    entry: dict[str, Any] = {'variable': ' ~ '.join(group), 'explained': None, 'p_value': None,
                             'note': '', 'untestable': ''}
    for res in results:
        entry.update(res['extra'])
    test = [res for res in results if res['stat'] is not None]
    if test:
        best = next((res for name, res in zip(group, results, strict=True)
                     if name == 'position' and res['stat'] is not None), test[0])
        stat = best['stat']
        if stat is None:                # best is one of test
            raise AssertionError('a tested variable without its statistic')
        entry['explained'] = float(stat[0])
        entry['p_value'] = float((1 + np.count_nonzero(stat[1:] >= stat[0])) / len(stat))
        entry['note'] = best['note']
        pdata = best['plot']
    else:
        reason = next((res['reason'] for res in results if res['reason']), 'untestable')
        entry['note'] = entry['untestable'] = reason
        pdata = next((res['plot'] for res in results if res['plot'] is not None), None)
    if len(group) > 1:
        entry['group'] = list(group)
        entry['note'] = f'{COLLINEAR_NOTE}; {entry["note"]}' if entry['note'] else COLLINEAR_NOTE
    return entry, pdata


def _temperature_rate(data: DiagnosisData) -> NDArray[np.float64]:
    rate = np.zeros(len(data.t))
    for p in np.unique(data.piece):
        m = np.flatnonzero(data.piece == p)
        dt = data.dt[m[0]]
        n = max(1, int(round(TEMPERATURE_RATE_WINDOW / dt)))
        xi = data.xi[m]
        c = np.cumsum(np.r_[0.0, xi])
        lo = np.clip(np.arange(len(m)) - n // 2, 0, len(m))
        hi = np.clip(np.arange(len(m)) + n // 2 + 1, 0, len(m))
        sm = (c[hi] - c[lo]) / (hi - lo)
        rate[m] = np.gradient(sm, dt) if len(m) > 1 else 0.0
    return rate


def _dwell(data: DiagnosisData) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
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


def residual_scan(data: DiagnosisData, r: ArrayLike, *,
                  progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """
    Scan the residual ``r`` (per bin) against the variables of the module docstring.

    Parameters
    ----------
    data : DiagnosisData
        The diagnosis data.
    r : ndarray
        Held-out residual of the final model per bin (Nm).
    progress : callable, optional
        Called with a line before each variable's permutation test (the scan takes
        tens of seconds on long recordings).

    Returns
    -------
    dict
        ``table``: list of ``{variable, explained, p_value, note, flagged, untestable}``
        (``untestable``: the reason there is no p-value, '' when there is one; ``position``
        also has ``period``, rad; a collinear entry has ``group``, its variables, and is
        named after them joined by ' ~ '); ``plot``: variable -> plot data (None for a
        variable the data do not have).

    """
    rng = np.random.default_rng(SEED)
    r = np.asarray(r, dtype=float)
    block, k = data.block, data.n_blocks
    rows = _permuted(r, block, k, rng)
    cv = _folds(r, block, k)
    table: list[dict[str, Any]] = []
    plot: dict[str, dict[str, Any] | None] = {}

    def add(entry: dict[str, Any], pdata: dict[str, Any] | None) -> None:
        table.append(entry)
        plot[entry['variable']] = pdata

    xs: dict[str, NDArray[np.float64]] = {
        'time': np.arange(len(r), dtype=float) * BIN, 'position': data.average(data.q),
        'velocity': data.average(data.qd), 'acceleration': data.average(data.qdd)}
    if data.has_temperature:
        xs['temperature_rate'] = data.average(_temperature_rate(data))
    say = progress or (lambda message: None)
    res: dict[str, _Scanned] = {}
    for i, (name, x) in enumerate(xs.items()):
        say(f'residual scan: {name} ({i + 1} of {len(xs) + 1}, {N_PERM} permutations)')
        res[name] = (_scan_position(data, rows, cv) if name == 'position'
                     else _scan_variable(x, rows, cv))
    for group in _collinear(xs):
        add(*_combine(group, [res[name] for name in group]))
    if not data.has_temperature:
        add(*_combine(['temperature_rate'],
                      [_result(reason='no temperature signal in the recordings')]))
    say(f'residual scan: dwell after a breakaway ({len(xs) + 1} of {len(xs) + 1})')
    dw, sel = _dwell(data)
    sgn = np.sign(data.average(data.qd))
    rd = (r * sgn)[sel]
    out = _scan_variable(dw[sel], _permuted(rd, block[sel], k, rng), {**cv, 'block': block[sel]})
    entry, pdata = _combine(['dwell'], [out])
    if out['reason'].startswith('only'):
        entry['note'] = entry['untestable'] = f'{out["reason"]} after a breakaway'
    else:
        entry['note'] = (f'{int(sel.sum())} bins within {BREAKAWAY_BINS} bins after a '
                         f'breakaway; residual x sign(qd); {out["reason"]}').rstrip('; ')
    add(entry, pdata)
    for e in table:
        e['flagged'] = bool(e['p_value'] is not None and e['p_value'] < SCAN_ALPHA
                            and e['explained'] >= SCAN_MIN_EXPLAINED)
    return {'table': table, 'plot': plot}
