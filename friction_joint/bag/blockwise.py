# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Column operations of :mod:`~friction_joint.bag.importer` done a block at a time.

Each gives, value for value, what the whole-array numpy expression named in its
docstring gives, with temporaries of :data:`BLOCK` samples instead of the
length of the column (an import of tens of millions of rows keeps only its
columns).
"""
import numpy as np

__all__ = ['BLOCK', 'spans', 'first_where', 'step', 'gradient', 'grid', 'off_grid', 'interp',
           'increasing_ns', 'opposed_fraction', 'unwrap']

#: samples per block
BLOCK = 1 << 18


def spans(n, overlap=0, block=None):
    """Yield ``(a, b)`` covering ``range(n - overlap)`` in blocks (``b + overlap <= n``)."""
    block = block or BLOCK
    for a in range(0, max(0, n - overlap), block):
        yield a, min(n - overlap, a + block)


def first_where(n, test, overlap=0):
    """Return the first ``a + i`` with ``test(a, b)[i]`` true over the blocks (None: none)."""
    for a, b in spans(n, overlap):
        hit = np.flatnonzero(test(a, b))
        if len(hit):
            return a + int(hit[0])
    return None


def step(x):
    """Return ``x[1] - x[0]`` if every difference of ``x`` equals it, else None (np.gradient)."""
    first = x[1] - x[0]
    for a, b in spans(len(x), 1):
        if not (np.diff(x[a:b + 1]) == first).all():
            return None
    return first


def gradient(f, x, out):
    """Write the gradient of ``f`` over ``x`` (``len(f) >= 2``) into ``out``, as numpy's."""
    n = len(f)
    h = step(x)
    for a, b in spans(n - 1):
        a = max(a, 1)                               # interior samples a..b-1
        if a >= b:
            continue
        if h is not None:
            out[a:b] = (f[a + 1:b + 1] - f[a - 1:b - 1]) / (2. * h)
            continue
        dx = np.diff(x[a - 1:b + 1])
        dx1, dx2 = dx[:-1], dx[1:]
        c1 = -(dx2) / (dx1 * (dx1 + dx2))
        c2 = (dx2 - dx1) / (dx1 * dx2)
        c3 = dx1 / (dx2 * (dx1 + dx2))
        out[a:b] = c1 * f[a - 1:b - 1] + c2 * f[a:b] + c3 * f[a + 1:b + 1]
    out[0] = (f[1] - f[0]) / (h if h is not None else x[1] - x[0])
    out[n - 1] = (f[n - 1] - f[n - 2]) / (h if h is not None else x[n - 1] - x[n - 2])
    return out


def grid(a, b, dt, t0):
    """Return samples ``a:b`` of the grid ``np.arange(m, dtype=float) * dt + t0``."""
    g = np.arange(a, b, dtype=float)
    g *= dt
    g += t0
    return g


def off_grid(t, dt):
    """Return ``max |t - grid|`` with the grid of ``dt`` from ``t[0]`` (same length)."""
    worst = 0.0
    for a, b in spans(len(t)):
        d = t[a:b] - grid(a, b, dt, t[0])
        worst = max(worst, float(np.abs(d, out=d).max()))
    return worst


def interp(out, times, t, v):
    """Write ``v`` at ``t`` interpolated linearly at ``times`` into ``out``, as numpy does."""
    for a, b in spans(len(times)):
        out[a:b] = np.interp(times[a:b], t, v)
    return out


def increasing_ns(t, ns):
    """Return whether ``np.round(t * ns)`` increases strictly."""
    for a, b in spans(len(t), 1):
        r = np.round(t[a:b + 1] * ns)
        if not np.all(r[1:] > r[:-1]):
            return False
    return True


def opposed_fraction(qd, friction):
    """
    Return the fraction of the sliding samples where ``friction`` opposes ``qd``.

    Sliding: ``|qd|`` above a tenth of its 99th percentile, ``friction != 0``; None when
    no sample slides.  Memory: one copy of ``|qd|`` (the percentile, found in place).
    """
    aq = np.abs(qd)
    limit = 0.1 * np.percentile(aq, 99, overwrite_input=True)
    del aq
    moving = opposed = 0
    for a, b in spans(len(qd)):
        v, f = qd[a:b], friction[a:b]
        slide = np.abs(v) > limit
        slide &= f != 0
        moving += int(np.count_nonzero(slide))
        opposed += int(np.count_nonzero(np.sign(f[slide]) != np.sign(v[slide])))
    return None if moving == 0 else float(np.float64(opposed) / moving)


def unwrap(p):
    """Unwrap the angle ``p`` (rad) in place, value for value as numpy's unwrap."""
    period = 2 * np.pi
    high = period / 2
    low = -high
    carry, start = None, p[0] if len(p) else None
    for a, b in spans(len(p), 1):
        seg = p[a:b + 1].copy()
        seg[0] = start                              # p[a] before it was unwrapped
        start = p[b]
        dd = np.diff(seg)
        mod = np.mod(dd - low, period) + low
        np.copyto(mod, high, where=(mod == low) & (dd > 0))
        mod -= dd
        np.copyto(mod, 0, where=abs(dd) < high)
        if carry is not None:
            mod[0] += carry                         # the running sum goes on
        np.cumsum(mod, out=mod)
        carry = mod[-1]
        p[a + 1:b + 1] = seg[1:] + mod
    return p
