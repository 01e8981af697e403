#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Peak memory and wall time of ``friction_joint import`` on a large CSV log.

    .venv/bin/python benchmarks/bench_import_memory.py               # 1000 MB CSV
    .venv/bin/python benchmarks/bench_import_memory.py --size-mb 250
    .venv/bin/python benchmarks/bench_import_memory.py --keep /tmp/big.csv   # reuse the file

What it does
------------
1. Writes a CSV log of about ``--size-mb`` MB into a temporary directory (not
   timed): ``Time [s],Position [rad],Torque [Nm],Temperature [degC]``, 1 kHz,
   about 44 bytes a row (a 1000 MB file has about 23 million rows).
2. Baseline, in this process: reads the same file's bytes in 8 MiB chunks
   (what any reader must at least do) and times it.
3. Runs ``python -m friction_joint import LOG --out REC ...`` as a subprocess
   (the only child of this process) and reports its wall time and its peak
   resident memory (``resource.getrusage(RUSAGE_CHILDREN).ru_maxrss``).

Target: a 1000 MB CSV imported (exit 0) with a peak RSS under 2 GB (measured
1.29 GB); a larger log is refused at once with one line (exit 2) by the
import's budget (``friction_joint.bag.importer.IMPORT_BUDGET``).  To measure
another checkout of the code, run this script from that checkout's directory
(``python -m`` puts the current directory first on the path).  The last line
is always

    size_mb=<s> rows=<n> status=<rc> import_s=<t> peak_rss_mb=<m> rss_per_file_size=<r>
    read_s=<b> time_vs_read=<q>
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

__all__ = ['write_csv', 'main']

ROW = 44
_CHUNK = 200_000


def write_csv(path, size_mb):
    """Write a CSV log of about ``size_mb`` MB (1 kHz); return its number of rows."""
    n = int(size_mb * 1e6 / ROW)
    rng = np.random.default_rng(1)
    period = 10_000
    k = np.arange(period)
    q = np.sin(2 * np.pi * k / 2000.0)
    tau = 2.0 * np.sign(np.cos(2 * np.pi * k / 2000.0)) + 0.01 * rng.standard_normal(period)
    tails = [f',{a:.8f},{b:.8f},{25 + 0.001 * (i % 1000):.4f}\n'
             for i, (a, b) in enumerate(zip(q, tau, strict=True))]
    with open(path, 'w') as fh:
        fh.write('Time [s],Position [rad],Torque [Nm],Temperature [degC]\n')
        for a in range(0, n, _CHUNK):
            b = min(n, a + _CHUNK)
            fh.write(''.join(f'{i / 1000:.6f}{tails[i % period]}' for i in range(a, b)))
    return n


def _read_baseline(path):
    t0 = time.perf_counter()
    with open(path, 'rb') as fh:
        while fh.read(8 << 20):
            pass
    return time.perf_counter() - t0


def main(argv=None):
    """Run the benchmark; print the figures."""
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[1])
    ap.add_argument('--size-mb', type=float, default=1000.0)
    ap.add_argument('--keep', default=None, metavar='CSV',
                    help='write the log here (reused if it exists) instead of a temporary file')
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix='bench_import_') as tmp:
        log = args.keep or os.path.join(tmp, 'log.csv')
        t0 = time.perf_counter()
        if not (args.keep and os.path.exists(log)):
            write_csv(log, args.size_mb)
        gen = time.perf_counter() - t0
        size = os.path.getsize(log)
        with open(log, 'rb') as fh:
            rows = sum(chunk.count(b'\n') for chunk in iter(lambda: fh.read(8 << 20), b'')) - 1
        print(f'log {log}: {size / 1e6:.0f} MB, {rows} rows (written in {gen:.1f} s)')
        read_s = min(_read_baseline(log) for _ in range(2))
        cmd = [sys.executable, '-m', 'friction_joint', 'import', log, '--out',
               os.path.join(tmp, 'rec'), '--time', 'Time [s]', '--position', 'Position [rad]',
               '--torque', 'Torque [Nm]', '--temperature', 'Temperature [degC]', '--quiet']
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024   # KiB on Linux
        for line in (proc.stdout + proc.stderr).strip().splitlines()[-3:]:
            print(f'  | {line}')
        rec = os.path.join(tmp, 'rec')
        if os.path.isdir(rec):
            out = sum(os.path.getsize(os.path.join(rec, f)) for f in os.listdir(rec))
            print(f'recording: {out / 1e6:.0f} MB')
    print(f'size_mb={size / 1e6:.0f} rows={rows} status={proc.returncode} import_s={wall:.1f} '
          f'peak_rss_mb={peak / 1e6:.0f} rss_per_file_size={peak / size:.2f} '
          f'read_s={read_s:.2f} time_vs_read={wall / max(read_s, 1e-9):.0f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
