# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint import`` of large logs: memory bounded by the columns, the same result.

The import's allocations are instrumented (numpy reports them to :mod:`tracemalloc`),
never timed: with small blocks and chunks, its peak beyond the start is at most the
columns it keeps plus two scratch columns, and within its own estimate.  The block-wise
steps give value for value what the whole-array numpy expressions gave.
"""
import math
import tracemalloc

import friction_joint.bag.blockwise as blockwise
import friction_joint.bag.consistency as consistency
import friction_joint.bag.importer as importer
from friction_joint.bag.importer import IMPORT_BUDGET, import_logs
import friction_joint.bag.plausible as plausible
import friction_joint.bag.tables as tables
from friction_joint.exceptions import RecordingError
import numpy as np
import pytest

N = 200_000


@pytest.fixture
def small_blocks(monkeypatch):
    """Blocks and chunks small against the logs, so that only n-sized arrays count."""
    monkeypatch.setattr(blockwise, 'BLOCK', 4096)
    monkeypatch.setattr(plausible, 'BLOCK', 4096)
    monkeypatch.setattr(consistency, 'BLOCK', 4096)
    monkeypatch.setattr(tables, 'CHUNK', 1 << 16)
    np.percentile(np.median(np.arange(5.0), overwrite_input=True), 50)   # their lazy imports


def _write(path, t, cols, header):
    np.savetxt(path, np.column_stack([t] + cols), delimiter=',', header=header, comments='',
               fmt='%.10g')
    return str(path)


def _signals(n, rng):
    t = np.arange(n) * 1e-3
    q = np.sin(2 * np.pi * t / 2.0)
    tau = 2.0 * np.sign(np.cos(2 * np.pi * t / 2.0)) + 0.01 * rng.standard_normal(n)
    return t, q, tau


def _peak(func):
    """Return ``func()`` and the peak of traced memory beyond the start (bytes)."""
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        result = func()
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    return result, peak


def _case(tmp_path, case):
    """Return the paths, columns and options of one kind of log (only its file written)."""
    rng = np.random.default_rng(3)
    t, q, tau = _signals(N, rng)
    xi = 25.0 + 1e-3 * (np.arange(N) % 1000)
    jitter = t + rng.uniform(-2e-4, 2e-4, N)
    jitter[0] = 0.0
    head = 'time,pos,tau,temp'
    cols = {'time': ('time', None), 'position': ('pos', None), 'torque': ('tau', None)}
    path = tmp_path / 'log.csv'
    if case == 'on grid':
        return [_write(path, t, [q, tau, xi], head)], dict(cols, temperature=('temp', None)), {}
    if case == 'resampled':
        return ([_write(path, jitter, [q, tau, xi], head)],
                dict(cols, temperature=('temp', None)), {})
    if case == 'pieces':
        t[N // 3:] += 2.0
        return [_write(path, t, [q, tau], 'time,pos,tau')], cols, {}
    if case == 'friction, load, flipped':
        del cols['torque']
        return ([_write(path, jitter, [q, -np.sign(np.cos(t)), 0 * t + 0.5],
                        'time,pos,fric,load')],
                dict(cols, friction=('fric', None), load=('load', None)), {'flip_friction': True})
    if case == 'unwrapped':
        wrapped = np.mod(3e-3 * np.arange(N) + 1.0, 2 * np.pi) - np.pi
        return [_write(path, t, [wrapped, tau], 'time,pos,tau')], cols, {'unwrap': True}
    half = N // 2                                   # two files
    return [_write(path, t[:half], [q[:half], tau[:half]], 'time,pos,tau')] * 2, cols, {}


@pytest.mark.parametrize('case', ['on grid', 'resampled', 'pieces', 'friction, load, flipped',
                                  'unwrapped', 'two files'])
def test_import_memory_is_the_columns_and_two_scratch_columns(tmp_path, small_blocks, case):
    """Peak of the n-sized allocations: the columns kept, 2 scratch columns, the estimate."""
    paths, columns, options = _case(tmp_path, case)
    log, peak = _peak(lambda: import_logs(paths, columns, **options))
    js = log.topics['/joint_states']
    rows = N
    kept = len(columns) + ('velocity' not in columns) + ('friction' in columns
                                                         and 'load' not in columns)
    assert len(js['t']) >= 0.99 * rows
    fixed = 1.5e6                                   # RowLines, chunks, blocks, mapping
    assert peak <= rows * 8 * (kept + 2) + fixed, (case, peak / rows)
    assert peak <= rows * importer._row_bytes(columns) + fixed, (case, peak / rows)


def test_a_1gb_csv_of_four_columns_fits_the_import_budget():
    """23 M rows (a 1 GB CSV of time, position, torque, temperature) are within the budget."""
    columns = {q: ('x', None) for q in ('time', 'position', 'torque', 'temperature')}
    need = 23_000_000 * importer._row_bytes(columns)
    assert need <= IMPORT_BUDGET <= 1.7e9          # + about 0.3 GB fixed: under 2 GB
    assert 40_000_000 * importer._row_bytes(columns) > IMPORT_BUDGET


def test_over_the_budget_refused_at_once_naming_the_size(tmp_path, monkeypatch):
    """Over :data:`IMPORT_BUDGET`: one line with the rows and the memory, nothing decoded."""
    rng = np.random.default_rng(0)
    t, q, tau = _signals(2000, rng)
    path = _write(tmp_path / 'log.csv', t, [q, tau], 'time,pos,tau')
    columns = {'time': ('time', None), 'position': ('pos', None), 'torque': ('tau', None)}
    monkeypatch.setattr(importer, 'IMPORT_BUDGET', 2000 * importer._row_bytes(columns) - 1)

    def no_parse(*args, **kwargs):
        raise AssertionError('decoded although over the budget')

    monkeypatch.setattr(tables.np, 'loadtxt', no_parse)
    with pytest.raises(RecordingError, match=r'log\.csv: 2000 rows need about .* MiB'):
        import_logs([path], columns)


# ----------------------------------------------------- the same values as before ---

def _old_position_rate(t, q):
    """Return the whole-array rate of the plausibility check before it worked in blocks."""
    dt = np.diff(t)
    fd = np.zeros(len(dt))
    ok = dt > 0
    fd[ok] = np.abs(np.diff(q)[ok] / dt[ok])
    both = np.maximum(np.r_[0.0, fd], np.r_[fd, 0.0])
    padded = np.pad(both, plausible.RATE_WINDOW, mode='edge')
    return np.lib.stride_tricks.sliding_window_view(
        padded, 2 * plausible.RATE_WINDOW + 1).max(axis=1)


def _old_implausible(x, reference, factor):
    fin = np.flatnonzero(np.isfinite(x))
    n = len(fin)
    k = max(3, int(math.ceil(1e-3 * n)))
    if n < 2 * k + 1:
        return np.zeros(0, dtype=np.int64), math.nan, math.nan
    v = x[fin]
    med = float(np.median(v))
    dev = np.abs(v - med)
    spread = max(float(np.partition(dev, n - k - 1)[n - k - 1]), 1e-3 * abs(med))
    limit = np.full(n, spread)
    if reference is not None:
        limit = np.maximum(limit, reference[fin])
    bad = np.flatnonzero((dev > factor * limit) & (limit > 0))
    bad = bad[np.argsort(-dev[bad] / limit[bad], kind='stable')]
    return fin[bad], med, spread


def test_plausibility_in_blocks_judges_as_the_whole_arrays(monkeypatch):
    """Median, spread, the worst samples and the position's rate: equal to the old ones."""
    rng = np.random.default_rng(11)
    for trial in range(150):
        monkeypatch.setattr(plausible, 'BLOCK', int(rng.integers(1, 300)))
        n = int(rng.integers(0, 1500))
        t = np.cumsum(rng.uniform(5e-4, 2e-3, n)) + rng.uniform(-5, 1e4)
        q = np.cumsum(rng.normal(0, 1e-3, n))
        qd = rng.normal(0, 1, n)
        if n:
            qd[rng.integers(0, n, 3)] *= rng.choice([1e4, 1e9, -1e12])
            if trial % 4 == 0:
                qd[rng.integers(0, n, 2)] = np.nan
        with np.errstate(all='ignore'):
            ref = _old_position_rate(t - (t[0] if n else 0.0), q) if n else np.zeros(0)
            if n:
                got = np.concatenate([plausible._rate(t, q, a, min(n, a + 97), t[0])
                                      for a in range(0, n, 97)])
                assert np.array_equal(got, ref, equal_nan=True), trial
            old = _old_implausible(qd, ref if n else None, 1e3)
            new = plausible.implausible(qd, ref if n else None, 1e3)
        assert np.array_equal(old[0], new[0]), trial
        assert old[1:] == new[1:] or (math.isnan(old[1]) and math.isnan(new[1])), trial


def test_blockwise_steps_equal_numpy(monkeypatch):
    """Gradient, unwrap, interpolation and the friction sign: numpy's values, exactly."""
    rng = np.random.default_rng(5)
    for trial in range(120):
        monkeypatch.setattr(blockwise, 'BLOCK', int(rng.integers(1, 60)))
        n = int(rng.integers(2, 500))
        x = (np.arange(n) * 0.25 + 3.0 if trial % 3 == 0
             else np.cumsum(rng.uniform(1e-4, 2e-3, n)))
        f = np.cumsum(rng.normal(0, 1, n))
        out = np.empty(n)
        assert np.array_equal(blockwise.gradient(f, x, out), np.gradient(f, x)), trial
        p = np.mod(np.cumsum(rng.normal(0, 2, n)), 2 * np.pi) - np.pi
        p[rng.integers(0, n)] = np.pi
        assert np.array_equal(blockwise.unwrap(p.copy()), np.unwrap(p)), trial
        grid = np.linspace(x[0], x[-1] + 1e-3, int(rng.integers(2, 400)))
        out = np.empty(len(grid))
        assert np.array_equal(blockwise.interp(out, grid, x, f), np.interp(grid, x, f)), trial
        qd = rng.normal(0, 1, n) * (rng.random(n) < 0.7)
        fr = rng.normal(0, 1, n)
        aq = np.abs(qd)
        moving = (aq > 0.1 * np.percentile(aq, 99)) & (fr != 0)
        old = (float(np.mean(np.sign(fr[moving]) != np.sign(qd[moving])))
               if moving.any() else None)
        assert blockwise.opposed_fraction(qd, fr) == old, trial
