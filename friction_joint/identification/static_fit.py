"""Identification of the static friction model from constant-velocity plateaus (seed V-A).

The paper identifies its model in three steps; this module does the first
two (the third, pre-sliding parameters, lives in
:mod:`friction_joint.identification.presliding` and is called by the command when present):

* **Step 1** -- velocity and temperature: the coefficients of the temperature
  polynomials of F_c, F_s, F_v, v_s and delta_v (eq. 6-7) by least squares
  (eq. 16) over the plateau data points, ``scipy.optimize.least_squares``
  with the trust-region reflective method (the paper's Matlab ``trf``), the
  load terms held fixed.
* **Step 2** -- load: with step 1 fixed, the load coefficients (powers
  1..m of tau_L, eq. 7).

Because every plateau carries some load (the lever's gravity; at high speed a
plateau sweeps the whole revolution), step 1 cannot be run on load-free data
alone: steps 1 and 2 are alternated (step 1 starts with the load terms at
zero) until the load coefficients settle (at most four passes), and a final
joint least-squares pass over all coefficients removes what is left of the
coupling.  Parameter
standard errors come from that final pass: Cov = s^2 (J^T J)^-1 with J the
Jacobian and s^2 the residual variance, mapped linearly to the file's
coefficients.

Parametrisation.  Internally each temperature polynomial of order n is
represented by its values at n + 1 Chebyshev-Lobatto nodes spanning the
recorded temperature range (well conditioned, and bounds on node values keep
F_c, F_s, F_v >= 0, v_s > 0, 0.05 <= delta_v <= 3 where there are data);
load coefficients multiply (tau_L / L)^j with L the largest plateau load.
The model is evaluated with the package's own static curve
(:class:`~friction_joint.models.static.StaticFriction`, batched: one call gives all
finite-difference columns of the Jacobian), so the identified file means
exactly what was fitted.  Load powers above 1 are evaluated at the plateau's
mean load (exact for the linear load terms, an approximation otherwise).

The model structure (which coefficients exist, the list lengths) comes from
the STRUCTURE gear file; ``orders='auto'`` instead chooses per-parameter
polynomial orders by held-out error (:func:`select_orders`).  Data that cannot
determine a coefficient raise :class:`~friction_joint.exceptions.ExcitationError`
naming what to record (:func:`check_excitation`).

Object API::

    ident = StaticIdentifier(load_gear('config/csd25.yaml')).fit(plateaus)
    ident.predict(qd, xi, tau_l)        # static friction torque, Nm
    ident.results                       # rows: parameter, power, value, se
    ident.gear                          # GearParams with the identified coefficients
"""
import dataclasses
import math
import time

import numpy as np
from scipy.optimize import least_squares, nnls

from ..exceptions import ExcitationError, GearConfigError
from ..models.static import PARAMETERS, PackedStatic, StaticFriction

__all__ = ['PARAMS', 'Structure', 'StaticIdentifier', 'check_excitation', 'temperature_groups',
           'distinct_levels', 'cross_validate', 'select_orders']

#: temperature-polynomial parameters, in the order of the packed arrays of :mod:`static`
PARAMS = PARAMETERS                      # ('fc', 'fs', 'fv', 'vs', 'delta_v')
LOWER = {'fc': 0.0, 'fs': 0.0, 'fv': 0.0, 'vs': 1e-6, 'delta_v': 0.05}
UPPER = {'fc': np.inf, 'fs': np.inf, 'fv': np.inf, 'vs': np.inf, 'delta_v': 3.0}
UNITS = {'fc': 'Nm', 'fs': 'Nm', 'fv': 'Nm/(rad/s)^dv', 'vs': 'rad/s', 'delta_v': '1'}

#: temperature-group width (degC): plateaus within this span count as one temperature
GROUP_WIDTH = 1.0
#: fewest plateaus of a temperature group that counts as a measured temperature
MIN_GROUP = 3
#: relative tolerance of "distinct" speeds
SPEED_TOL = 0.05


# ------------------------------------------------------------------ structure ---

@dataclasses.dataclass(frozen=True)
class Structure:
    """Which coefficients a static model has (the model structure, CONTRACT section 4).

    Attributes
    ----------
    orders : dict
        Parameter -> temperature polynomial order (list length - 1) of every fitted
        parameter of :data:`PARAMS`.
    load_orders : dict
        Parameter -> load polynomial order m (powers 1..m; 0 = no load term).
    fixed : dict
        Parameter -> coefficient list kept as is (not fitted), e.g. ``delta_v: [1.0]``
        for a linear viscous model.
    stribeck : bool
        The model has F_s and v_s.
    delta_s, velocity_scale : float
        Kept from the structure file.
    """

    orders: dict
    load_orders: dict
    fixed: dict
    stribeck: bool
    delta_s: float = 2.0
    velocity_scale: float = 1.0

    @classmethod
    def from_gear(cls, gear, fixed=()):
        """The structure of a gear file.

        Parameters
        ----------
        gear : GearParams
        fixed : iterable of str
            Parameters of :data:`PARAMS` kept at the file's values (e.g. ``delta_v``
            when the file has no ``delta_v`` key: linear viscous friction).
        """
        f = gear.friction
        stribeck = f.fs is not None
        orders, fix, load = {}, {}, {}
        for p in PARAMS:
            coef = getattr(f, p)
            if coef is None:
                continue
            if p in fixed:
                fix[p] = list(coef)
            else:
                orders[p] = len(coef) - 1
            load[p] = len(getattr(f, p + '_load'))
        unknown = set(fixed) - set(PARAMS)
        if unknown:
            raise GearConfigError(f'cannot fix {", ".join(sorted(unknown))}: not a static '
                                  f'curve parameter ({", ".join(PARAMS)})')
        return cls(orders, load, fix, stribeck, f.delta_s, f.velocity_scale)

    def with_orders(self, orders=None, load_orders=None):
        """A copy with some orders changed."""
        o = dict(self.orders)
        o.update(orders or {})
        lo = dict(self.load_orders)
        lo.update(load_orders or {})
        return dataclasses.replace(self, orders=o, load_orders=lo)

    @property
    def params(self):
        """Fitted temperature parameters, in :data:`PARAMS` order."""
        return [p for p in PARAMS if p in self.orders]

    @property
    def load_params(self):
        return [p for p in PARAMS if self.load_orders.get(p, 0) > 0]

    def describe(self):
        """``fc: [3], fv: [3], ..., fc_load: [1]`` (list lengths)."""
        parts = [f'{p}: [{self.orders[p] + 1}]' for p in self.params]
        parts += [f'{p}: fixed' for p in self.fixed]
        parts += [f'{p}_load: [{self.load_orders[p]}]' for p in self.load_params]
        return ', '.join(parts)


# ------------------------------------------------------------- data checks ---

def temperature_groups(xi, width=GROUP_WIDTH):
    """Group labels of temperatures: sorted, a new group when the span would exceed ``width``."""
    xi = np.asarray(xi, dtype=float)
    labels = np.zeros(len(xi), dtype=int)
    if len(xi) == 0:
        return labels
    order = np.argsort(xi)
    g, start = 0, xi[order[0]]
    for i in order:
        if xi[i] - start > width:
            g += 1
            start = xi[i]
        labels[i] = g
    return labels


def distinct_levels(x, rel=SPEED_TOL, absolute=0.0):
    """Number of distinct values of x (sorted values closer than rel |x| + absolute merge)."""
    x = np.sort(np.abs(np.asarray(x, dtype=float)))
    if len(x) == 0:
        return 0
    count, ref = 1, x[0]
    for v in x[1:]:
        if v - ref > rel * ref + absolute:
            count += 1
            ref = v
    return count


def _group_table(plateaus):
    labels = temperature_groups(plateaus.xi)
    groups = []
    for g in range(labels.max() + 1 if len(labels) else 0):
        m = labels == g
        if m.sum() >= MIN_GROUP:
            groups.append((float(plateaus.xi[m].mean()), int(m.sum())))
    return labels, groups


def check_excitation(plateaus, structure):
    """Raise :class:`ExcitationError` if the plateaus cannot determine the structure's coefficients.

    Checks: plateaus exist; both directions; enough plateaus for the number of
    coefficients; distinct temperatures for each temperature order; low-speed
    plateaus for the Stribeck parameters; a velocity range for delta_v and F_v;
    distinct loads for each load order.  The message says what to record.
    """
    src = ', '.join(plateaus.sources) or 'the data'
    n = len(plateaus)
    if n == 0:
        raise ExcitationError(
            f'{src}: no constant-velocity plateaus found: the identification needs segments '
            'of constant velocity (at least 0.2 s each, both directions, speeds from about '
            '0.01 rad/s up to the highest operating speed, e.g. '
            '"friction_joint experiment identification"); the recording has none')
    pos, neg = int(np.sum(plateaus.qd > 0)), int(np.sum(plateaus.qd < 0))
    if min(pos, neg) < 2:
        have, miss = ('positive', 'negative') if neg < 2 else ('negative', 'positive')
        raise ExcitationError(
            f'{src}: the {n} plateaus all have {have} velocity ({pos} positive, {neg} negative): '
            f'record plateaus in both directions (also {miss} velocities); with one direction '
            'friction cannot be told from a torque offset or a gravity error')
    lo, hi = float(plateaus.xi.min()), float(plateaus.xi.max())
    _, groups = _group_table(plateaus)
    temps = ', '.join(f'{x:.1f}' for x, _ in groups) or 'none'
    for p, order in structure.orders.items():
        if order >= 1 and len(groups) < order + 1:
            coeffs = ', '.join(f'c{i}' for i in range(max(1, len(groups))))
            raise ExcitationError(
                f'the recording covers xi = {lo:.1f}..{hi:.1f} degC: a temperature polynomial '
                f'of order {order} for {p} needs plateaus at >= {order + 1} distinct '
                f'temperatures (found {len(groups)}: {temps} degC, groups of >= {MIN_GROUP} '
                f'plateaus {GROUP_WIDTH:g} degC wide); record at more temperatures or use '
                f'{p}: [{coeffs}]')
    speed = np.abs(plateaus.qd)
    vmin, vmax = float(speed.min()), float(speed.max())
    nspeeds = distinct_levels(speed)
    if structure.stribeck and ('fs' in structure.orders or 'vs' in structure.orders):
        low = distinct_levels(speed[speed <= 10.0 * vmin])
        if vmax < 30.0 * vmin or low < 3:
            raise ExcitationError(
                f'plateau speeds span {vmin:.3g}..{vmax:.3g} rad/s ({nspeeds} distinct, {low} '
                'within a decade of the slowest): the Stribeck parameters fs and vs need '
                'plateaus at low speed (at least 3 distinct speeds in the lowest decade, '
                'reaching down to 1/30 of the highest speed, e.g. 0.01 rad/s); record slower '
                'plateaus or drop fs/vs from the structure')
    if 'delta_v' in structure.orders and (vmax < 10.0 * vmin or nspeeds < 4):
        raise ExcitationError(
            f'plateau speeds span {vmin:.3g}..{vmax:.3g} rad/s ({nspeeds} distinct): the '
            'viscous exponent delta_v needs plateaus over at least a decade of speed '
            '(>= 4 distinct speeds); record a wider velocity range or fix delta_v')
    for p in structure.load_params:
        m = structure.load_orders[p]
        loads = plateaus.load
        span = float(loads.max() - loads.min())
        levels = distinct_levels(loads, rel=0.0, absolute=max(0.5, 0.1 * span))
        if span < 1.0 or levels < m + 1:
            raise ExcitationError(
                f'the plateaus\' loads span tau_L = {loads.min():.2f}..{loads.max():.2f} Nm '
                f'({levels} distinct levels): the load polynomial of order {m} for {p}_load '
                f'needs plateaus at >= {m + 1} clearly different loads (at least 1 Nm apart, '
                'e.g. the lever at different angles); record with varying load or use '
                f'{p}_load: []')
    npar = sum(o + 1 for o in structure.orders.values()) + sum(structure.load_orders.values())
    if n < npar + 2:
        raise ExcitationError(
            f'{n} plateaus for {npar} coefficients: record more plateaus (at least {npar + 2}; '
            'the paper used 34 per temperature series)')


# --------------------------------------------------------------- the model ---

class _Layout:
    """Parameter vector <-> coefficient arrays of the static curve."""

    def __init__(self, structure, t_range, load_ref):
        self.s = structure
        lo, hi = t_range
        self.t_range = (float(lo), float(hi))
        self.load_ref = float(load_ref)
        self.blocks = []            # (name, kind, slice)
        self.maps = {}              # name -> matrix theta_block -> coefficients
        self.nodes = {}
        i = 0
        for p in structure.params:
            n = structure.orders[p]
            nodes = self._nodes(n)
            self.nodes[p] = nodes
            self.maps[p] = np.linalg.inv(np.vander(nodes, n + 1, increasing=True))
            self.blocks.append((p, 'temp', slice(i, i + n + 1)))
            i += n + 1
        for p in structure.load_params:
            m = structure.load_orders[p]
            self.maps[p + '_load'] = np.diag(self.load_ref ** -np.arange(1.0, m + 1))
            self.blocks.append((p + '_load', 'load', slice(i, i + m)))
            i += m
        self.size = i
        self.nt = max([structure.orders[p] + 1 for p in structure.params]
                      + [len(c) for c in structure.fixed.values()] + [1])
        self.nl = max([structure.load_orders.get(p, 0) for p in PARAMS] + [1])

    def _nodes(self, n):
        lo, hi = self.t_range
        if n == 0:
            return np.array([0.5 * (lo + hi)])
        k = np.arange(n + 1)
        return 0.5 * (lo + hi) - 0.5 * (hi - lo) * np.cos(np.pi * k / n)

    def mask(self, kind):
        m = np.zeros(self.size, dtype=bool)
        for _, k, sl in self.blocks:
            if k == kind:
                m[sl] = True
        return m

    def bounds(self):
        lo = np.full(self.size, -np.inf)
        hi = np.full(self.size, np.inf)
        for name, kind, sl in self.blocks:
            if kind == 'temp':
                lo[sl], hi[sl] = LOWER[name], UPPER[name]
        return lo, hi

    def coefficients(self, theta):
        """Name -> coefficient array (file convention: powers of xi, powers of tau_L)."""
        return {name: self.maps[name] @ theta[sl] for name, _, sl in self.blocks}

    def transform(self):
        """Matrix A with coefficients = A theta (blocks in layout order)."""
        a = np.zeros((self.size, self.size))
        for name, _, sl in self.blocks:
            a[sl, sl] = self.maps[name]
        return a

    def packed(self, thetas):
        """PackedStatic of a batch of parameter vectors (B, size)."""
        thetas = np.atleast_2d(thetas)
        b = thetas.shape[0]
        temp = np.zeros((b, 5, self.nt))
        load = np.zeros((b, 5, self.nl))
        idx = {p: i for i, p in enumerate(PARAMS)}
        for p, c in self.s.fixed.items():
            temp[:, idx[p], :len(c)] = c
        for name, kind, sl in self.blocks:
            coef = thetas[:, sl] @ self.maps[name].T
            if kind == 'temp':
                temp[:, idx[name], :coef.shape[1]] = coef
            else:
                load[:, idx[name[:-5]], :coef.shape[1]] = coef
        if not self.s.stribeck:                 # no Stribeck: Fs = Fc, vs irrelevant
            temp[:, idx['fs']] = temp[:, idx['fc']]
            load[:, idx['fs']] = load[:, idx['fc']]
            temp[:, idx['vs'], 0] = 1.0
        ones = np.ones(b)
        return PackedStatic(temp, load, self.s.delta_s * ones, self.s.velocity_scale * ones,
                            -1e9 * ones, 1e9 * ones)

    def torque(self, thetas, qd, xi, load):
        """(B, N) static friction torque of a batch of parameter vectors."""
        return StaticFriction.from_packed(self.packed(thetas)).torque(qd, xi, load)


class _Problem:
    """Least-squares residuals of the plateau data for a layout."""

    def __init__(self, layout, plateaus):
        self.layout = layout
        self.qd = plateaus.qd.astype(float)
        self.xi = plateaus.xi.astype(float)
        self.load = plateaus.load.astype(float)
        self.y = plateaus.tau_r.astype(float)
        self.nfev = 0

    def residual_batch(self, thetas):
        self.nfev += len(np.atleast_2d(thetas))
        return self.layout.torque(thetas, self.qd, self.xi, self.load) - self.y

    def solve(self, theta0, free, max_nfev=200):
        """Minimise over the entries of theta marked ``free``.

        Returns ``(theta, result of scipy.optimize.least_squares)``.
        """
        theta0 = np.asarray(theta0, dtype=float).copy()
        idx = np.flatnonzero(free)
        lo, hi = self.layout.bounds()
        lo, hi = lo[idx], hi[idx]
        with np.errstate(invalid='ignore'):
            pad_lo = np.where(np.isfinite(lo), lo + 1e-9 * (1 + np.abs(lo)), -np.inf)
            pad_hi = np.where(np.isfinite(hi), hi - 1e-9 * (1 + np.abs(hi)), np.inf)
        x0 = np.clip(theta0[idx], pad_lo, pad_hi)

        def full(x):
            th = np.broadcast_to(theta0, (np.atleast_2d(x).shape[0], theta0.size)).copy()
            th[:, idx] = np.atleast_2d(x)
            return th

        def fun(x):
            return self.residual_batch(full(x))[0]

        def jac(x):
            h = 1e-6 * np.maximum(np.abs(x), 0.1)
            xs = np.concatenate([x + np.diag(h), x - np.diag(h)])
            r = self.residual_batch(full(xs))
            k = len(x)
            return ((r[:k] - r[k:]) / (2.0 * h[:, None])).T

        res = least_squares(fun, x0, jac=jac, bounds=(lo, hi), method='trf', x_scale='jac',
                            max_nfev=max_nfev, ftol=1e-12, xtol=1e-12, gtol=1e-12)
        theta = theta0.copy()
        theta[idx] = res.x
        return theta, res

    def jacobian(self, theta, free=None):
        free = np.ones(theta.size, dtype=bool) if free is None else free
        idx = np.flatnonzero(free)
        h = 1e-6 * np.maximum(np.abs(theta[idx]), 0.1)
        th = np.repeat(theta[None, :], 2 * len(idx), axis=0)
        for j, i in enumerate(idx):
            th[j, i] += h[j]
            th[len(idx) + j, i] -= h[j]
        r = self.residual_batch(th)
        k = len(idx)
        return ((r[:k] - r[k:]) / (2.0 * h[:, None])).T


# ---------------------------------------------------- initial single-temperature fit ---

def _single_init(structure, plateaus, load_part=None):
    """Order-0 curve (fc, fs, fv, vs, delta_v) of pooled plateaus by variable projection.

    For each (vs, delta_v) on a grid the curve is linear in (fc, fs, fv): those come
    from non-negative least squares; the best grid point is returned.
    """
    kappa = structure.velocity_scale
    x = kappa * np.abs(plateaus.qd)
    y = np.sign(plateaus.qd) * plateaus.tau_r
    if load_part is not None:
        y = y - load_part
    dv_fixed = structure.fixed.get('delta_v')
    dvs = [float(dv_fixed[0])] if dv_fixed is not None else np.linspace(0.1, 1.6, 31)
    vss = (np.geomspace(max(x.min(), 1e-6) * 0.3, x.max(), 30) if structure.stribeck
           else [1.0])
    ds = structure.delta_s
    best = None
    for vs in vss:
        e = np.exp(-(x / vs) ** ds) if structure.stribeck else np.zeros_like(x)
        for dv in dvs:
            cols = [1.0 - e, e, x ** dv] if structure.stribeck else [np.ones_like(x), x ** dv]
            a = np.column_stack(cols)
            coef, rn = nnls(a, y)
            if best is None or rn < best[0]:
                best = (rn, vs, dv, coef)
    _, vs, dv, coef = best
    if structure.stribeck:
        fc, fs, fv = coef
    else:
        (fc, fv), fs = coef, coef[0]
    return {'fc': fc, 'fs': fs, 'fv': fv, 'vs': vs, 'delta_v': dv}


def _theta_from_values(layout, values, load=None):
    """theta with every temperature node of parameter p at values[p] (scalar or callable)."""
    theta = np.zeros(layout.size)
    for name, kind, sl in layout.blocks:
        if kind == 'temp':
            v = values[name]
            nodes = layout.nodes[name]
            theta[sl] = v(nodes) if callable(v) else v
            theta[sl] = np.clip(theta[sl], LOWER[name] + 1e-6, UPPER[name] - 1e-6)
        elif load is not None and name in load:
            theta[sl] = load[name]
    return theta


# ------------------------------------------------------------------ fitting ---

def _fit(structure, plateaus, t_range, load_ref, theta0=None, stepwise=True, progress=None,
         max_iterations=4, tol=1e-3):
    """Fit one structure; returns (layout, theta, info)."""
    layout = _Layout(structure, t_range, load_ref)
    prob = _Problem(layout, plateaus)
    info = {'steps': []}
    tmask, lmask = layout.mask('temp'), layout.mask('load')
    if theta0 is None:
        init = _single_init(structure, plateaus)
        theta = _theta_from_values(layout, init)
        info['init'] = init
    else:
        theta = theta0.copy()
    if not stepwise or not lmask.any():
        t = time.perf_counter()
        theta, res = prob.solve(theta, np.ones(layout.size, dtype=bool))
        info['steps'].append({'step': 'joint' if lmask.any() else 1, 'cost': 2 * res.cost,
                              'nfev': int(res.nfev), 'time_s': time.perf_counter() - t})
        return layout, theta, prob, info
    prev = theta[lmask].copy()
    for it in range(max_iterations):
        for step, mask, label in ((1, tmask, 'step 1 (velocity, temperature)'),
                                  (2, lmask, 'step 2 (load)')):
            t = time.perf_counter()
            theta, res = prob.solve(theta, mask)
            info['steps'].append({'step': step, 'iteration': it, 'cost': 2 * res.cost,
                                  'nfev': int(res.nfev), 'time_s': time.perf_counter() - t})
            if progress:
                progress(f'  {label}, pass {it + 1}: RMS '
                         f'{math.sqrt(2 * res.cost / len(prob.y)):.4f} Nm')
        change = np.max(np.abs(theta[lmask] - prev) / np.maximum(np.abs(theta[lmask]), 1e-3))
        prev = theta[lmask].copy()
        if change < tol:
            break
    t = time.perf_counter()
    theta, res = prob.solve(theta, np.ones(layout.size, dtype=bool))
    info['steps'].append({'step': 'joint', 'cost': 2 * res.cost, 'nfev': int(res.nfev),
                          'time_s': time.perf_counter() - t})
    if progress:
        rms = math.sqrt(2 * res.cost / len(prob.y))
        progress(f'  joint refinement of steps 1+2: RMS {rms:.4f} Nm')
    return layout, theta, prob, info


def _covariance(prob, theta):
    """Covariance of theta: s^2 (J^T J)^-1 (pseudo-inverse if singular), and s^2."""
    jac = prob.jacobian(theta)
    r = prob.residual_batch(theta)[0]
    dof = max(len(r) - theta.size, 1)
    s2 = float(r @ r) / dof
    cov = s2 * np.linalg.pinv(jac.T @ jac)
    return cov, s2


def _t_range(plateaus):
    lo, hi = float(plateaus.xi.min()), float(plateaus.xi.max())
    if hi - lo < 0.2:
        c = 0.5 * (lo + hi)
        lo, hi = c - 0.1, c + 0.1
    return lo, hi


def _load_ref(plateaus):
    return max(float(np.max(plateaus.load)) if len(plateaus) else 0.0, 1.0)


def _folds(n, k, seed=0):
    perm = np.random.default_rng(seed).permutation(n)
    return [perm[i::k] for i in range(k)]


def cross_validate(plateaus, structure, folds=5, theta_full=None, seed=0):
    """Held-out RMS (Nm) of a structure by k-fold cross-validation over plateaus.

    Each fold is left out in turn, the structure refitted (all coefficients at
    once, started from ``theta_full`` when given) on the rest, and the left-out
    plateaus predicted.

    Returns
    -------
    float
    """
    t_range, load_ref = _t_range(plateaus), _load_ref(plateaus)
    if theta_full is None:
        _, theta_full, _, _ = _fit(structure, plateaus, t_range, load_ref, stepwise=False)
    sq, count = 0.0, 0
    n = len(plateaus)
    for test in _folds(n, min(folds, n), seed):
        train = np.ones(n, dtype=bool)
        train[test] = False
        _, th, _, _ = _fit(structure, plateaus.select(train), t_range, load_ref,
                           theta0=theta_full, stepwise=False)
        held = plateaus.select(test)
        r = _Layout(structure, t_range, load_ref).torque(th, held.qd, held.xi, held.load)[0] \
            - held.tau_r
        sq += float(r @ r)
        count += len(r)
    return math.sqrt(sq / max(count, 1))


def select_orders(plateaus, structure, max_order=2, max_load_order=2, threshold=0.05, folds=5,
                  progress=None):
    """Choose per-parameter polynomial orders by held-out error (``--orders auto``).

    Greedy forward selection: start with every parameter constant in temperature
    and no load terms; in each round raise, one at a time, the temperature order
    of each parameter (up to ``max_order``) and the load order of fc and fv (up
    to ``max_load_order``), skipping what the data cannot determine
    (:func:`check_excitation`), and keep the raise with the lowest k-fold
    held-out RMS if it lowers the RMS by at least ``threshold`` (5 %).  Then
    a backward pass lowers, one at a time, any order whose removal costs less
    than ``threshold`` of held-out RMS (an order raised early may have become
    unnecessary).  Lower orders are preferred unless clearly better.

    Returns
    -------
    structure : Structure
        The chosen orders.
    trace : list of dict
        Every candidate tried: ``orders``, ``load_orders``, ``cv_rms``, ``accepted``.
    """
    cur = structure.with_orders({p: 0 for p in structure.params},
                                {p: 0 for p in PARAMS})
    check_excitation(plateaus, cur)
    t_range, load_ref = _t_range(plateaus), _load_ref(plateaus)
    _, th, _, _ = _fit(cur, plateaus, t_range, load_ref, stepwise=False)
    best = cross_validate(plateaus, cur, folds, th)
    trace = [{'orders': dict(cur.orders), 'load_orders': dict(cur.load_orders), 'cv_rms': best,
              'accepted': True}]
    if progress:
        progress(f'orders auto: all constant, no load terms: held-out RMS {best:.4f} Nm')

    def score(cands, label):
        """Held-out RMS of each candidate the data can determine; logged in ``trace``."""
        results = []
        for cand in cands:
            try:
                check_excitation(plateaus, cand)
            except ExcitationError:
                continue
            _, th, _, _ = _fit(cand, plateaus, t_range, load_ref, stepwise=False)
            cv = cross_validate(plateaus, cand, folds, th)
            results.append((cv, cand))
            trace.append({'orders': dict(cand.orders), 'load_orders': dict(cand.load_orders),
                          'cv_rms': cv, 'accepted': False})
            if progress:
                progress(f'orders auto: {label} {cand.describe()}: held-out RMS {cv:.4f} Nm')
        return results

    while True:
        cands = []
        for p in cur.params:
            if cur.orders[p] < max_order:
                cands.append(cur.with_orders({p: cur.orders[p] + 1}))
        for p in ('fc', 'fv'):
            if p in cur.orders and cur.load_orders.get(p, 0) < max_load_order:
                cands.append(cur.with_orders(load_orders={p: cur.load_orders.get(p, 0) + 1}))
        results = score(cands, 'try')
        if not results:
            break
        cv, cand = min(results, key=lambda r: r[0])
        if cv > (1.0 - threshold) * best:
            break
        best, cur = cv, cand
        for t in trace:
            if t['orders'] == cand.orders and t['load_orders'] == cand.load_orders:
                t['accepted'] = True
        if progress:
            progress(f'orders auto: keep {cur.describe()} ({cv:.4f} Nm)')
    # backward pass: drop an order again where the higher one is not clearly better
    while True:
        cands = [cur.with_orders({p: cur.orders[p] - 1}) for p in cur.params if cur.orders[p] > 0]
        cands += [cur.with_orders(load_orders={p: cur.load_orders[p] - 1})
                  for p in cur.load_params]
        results = score(cands, 'try without one order:')
        if not results:
            break
        cv, cand = min(results, key=lambda r: r[0])
        if (1.0 - threshold) * cv > best:
            break
        best, cur = min(best, cv), cand
        trace[-len(results) + [r[1] for r in results].index(cand)]['accepted'] = True
        if progress:
            progress(f'orders auto: drop to {cur.describe()} ({cv:.4f} Nm)')
    return cur, trace


# ---------------------------------------------------------------- identifier ---

class StaticIdentifier:
    """Identify the static friction model (steps 1 and 2 of seed Section V-A).

    Parameters
    ----------
    structure : GearParams
        The STRUCTURE gear file: which coefficients exist (list lengths), delta_s,
        velocity_scale, inertia and lever; its coefficient values are not used.
    orders : None, 'auto' or dict
        None: the structure's orders.  'auto': chosen by held-out error
        (:func:`select_orders`).  A dict ``{'fc': 2, 'fc_load': 1, ...}`` overrides
        individual orders.
    fixed : iterable of str
        Parameters kept at the structure's values (e.g. ``('delta_v',)``).
    progress : callable, optional
        ``progress(message)`` for long fits.

    Attributes (after :meth:`fit`)
    -------------------------------
    gear : GearParams
        The structure with the identified coefficients and
        ``temperature_range`` set to the recorded temperature range.
    coefficients, standard_errors : dict
        Parameter (``fc``, ``fc_load``, ...) -> list in the file's convention.
    results : list of dict
        One row per coefficient: ``parameter``, ``power``, ``value``, ``se``, ``unit``.
    rms : float
        RMS residual over the plateaus (Nm).
    group_fits : list of dict
        Order-0 fits per temperature group (markers of Fig. 3 b).
    info : dict
        Steps, iterations, timings, node values, order selection trace.
    """

    def __init__(self, structure, orders=None, fixed=(), progress=None):
        self.structure_gear = structure
        self.base = Structure.from_gear(structure, fixed)
        self.orders = orders
        self.progress = progress
        self.gear = None

    # -- fitting
    def _structure(self, plateaus):
        if self.orders == 'auto':
            s, trace = select_orders(plateaus, self.base, progress=self.progress)
            self.info['order_selection'] = trace
            return s
        if isinstance(self.orders, dict):
            temp = {k: int(v) for k, v in self.orders.items() if not k.endswith('_load')}
            load = {k[:-5]: int(v) for k, v in self.orders.items() if k.endswith('_load')}
            bad = [k for k in temp if k not in self.base.orders] + \
                  [k for k in load if k not in PARAMS]
            if bad:
                raise GearConfigError(f'orders: unknown or absent parameter(s) {", ".join(bad)}')
            return self.base.with_orders(temp, load)
        if self.orders is not None:
            raise GearConfigError(f"orders must be None, 'auto' or a dict, got {self.orders!r}")
        return self.base

    def fit(self, plateaus):
        """Fit the plateaus (a :class:`~friction_joint.identification.plateaus.Plateaus`); returns self.

        Raises
        ------
        ExcitationError
            The plateaus cannot determine a coefficient of the structure.
        """
        t_start = time.perf_counter()
        self.info = {}
        t0 = time.perf_counter()
        if self.orders == 'auto':
            check_excitation(plateaus, self.base.with_orders({p: 0 for p in self.base.params},
                                                             {p: 0 for p in PARAMS}))
        s = self._structure(plateaus)
        self.info['time_order_selection_s'] = time.perf_counter() - t0
        check_excitation(plateaus, s)
        self.structure = s
        self.plateaus = plateaus
        t_range, load_ref = _t_range(plateaus), _load_ref(plateaus)
        if self.progress:
            self.progress(f'fitting {s.describe()} to {len(plateaus)} plateaus '
                          f'(xi {t_range[0]:.1f}..{t_range[1]:.1f} degC)')
        t0 = time.perf_counter()
        theta0 = self._initial(s, plateaus, t_range, load_ref)
        layout, theta, prob, info = _fit(s, plateaus, t_range, load_ref, theta0=theta0,
                                         progress=self.progress)
        self.info['time_fit_s'] = time.perf_counter() - t0
        self.info.update(info)
        self.layout, self.theta = layout, theta
        cov, s2 = _covariance(prob, theta)
        a = layout.transform()
        cov_c = a @ cov @ a.T
        se_all = np.sqrt(np.clip(np.diag(cov_c), 0.0, None))
        coefs = layout.coefficients(theta)
        self.coefficients = {k: [float(x) for x in v] for k, v in coefs.items()}
        self.standard_errors = {name: [float(x) for x in se_all[sl]]
                                for name, _, sl in layout.blocks}
        node_se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
        self.info['nodes'] = {name: {'xi': layout.nodes[name].tolist(),
                                     'value': theta[sl].tolist(), 'se': node_se[sl].tolist()}
                              for name, kind, sl in layout.blocks if kind == 'temp'}
        self.info['residual_variance'] = s2
        self.info['temperature_range'] = list(t_range)
        self.info['load_ref'] = load_ref
        self.info['nfev'] = prob.nfev
        r = prob.residual_batch(theta)[0]
        self.residuals = r
        self.rms = float(np.sqrt(np.mean(r ** 2)))
        self.gear = self._gear(coefs, t_range)
        t0 = time.perf_counter()
        self.group_fits = self._group_fits(plateaus, load_ref)
        self.info['time_group_fits_s'] = time.perf_counter() - t0
        self.info['time_identifier_s'] = time.perf_counter() - t_start
        return self

    def _initial(self, s, plateaus, t_range, load_ref):
        """Start values: per-temperature-group order-0 fits, polynomials through them."""
        layout = _Layout(s, t_range, load_ref)
        pooled = _single_init(s, plateaus)
        labels, groups = _group_table(plateaus)
        vals = []
        single = s.with_orders({p: 0 for p in s.params}, {p: 0 for p in PARAMS})
        for g in range(labels.max() + 1):
            m = labels == g
            sub = plateaus.select(m)
            if m.sum() < 8 or distinct_levels(sub.qd) < 4 or min(np.sum(sub.qd > 0),
                                                                   np.sum(sub.qd < 0)) < 1:
                continue
            lay1 = _Layout(single, _t_range(sub), 1.0)
            th = _theta_from_values(lay1, pooled)
            th, _ = _Problem(lay1, sub).solve(th, np.ones(lay1.size, dtype=bool))
            vals.append((float(sub.xi.mean()), lay1.coefficients(th)))
        values = {}
        for p in s.params:
            n = s.orders[p]
            if len(vals) >= n + 1 and n > 0:
                x = np.array([v[0] for v in vals])
                y = np.array([v[1][p][0] for v in vals])
                c = np.polynomial.polynomial.polyfit(x, y, n)
                values[p] = (lambda c_: lambda xi: np.polynomial.polynomial.polyval(xi, c_))(c)
            elif vals:
                values[p] = float(np.median([v[1][p][0] for v in vals]))
            else:
                values[p] = pooled[p]
        return _theta_from_values(layout, values)

    def _gear(self, coefs, t_range):
        fr = {p: [float(x) for x in c] for p, c in coefs.items()}
        for p in self.base.load_orders:              # load terms dropped by auto orders
            key = p + '_load'
            if key not in fr and self.base.load_orders.get(p, 0) > 0:
                fr[key] = []
        lo = math.floor(t_range[0] * 10.0) / 10.0
        hi = math.ceil(t_range[1] * 10.0) / 10.0
        fr['temperature_range'] = [lo, hi]
        try:
            return self.structure_gear.replace({'friction': fr})
        except GearConfigError as exc:
            raise ExcitationError(
                f'the identified coefficients are not physical over the recorded temperature '
                f'range {lo}..{hi} degC ({exc}); the data do not pin the polynomial down: '
                'lower its order or record at more temperatures') from None

    def _group_fits(self, plateaus, load_ref):
        """Order-0 fits per temperature group with the identified load terms (Fig. 3 b)."""
        labels, _ = _group_table(plateaus)
        out = []
        single = self.structure.with_orders({p: 0 for p in self.structure.params})
        for g in range(labels.max() + 1 if len(labels) else 0):
            m = labels == g
            sub = plateaus.select(m)
            if m.sum() < 8 or distinct_levels(sub.qd) < 4 or min(np.sum(sub.qd > 0),
                                                                   np.sum(sub.qd < 0)) < 1:
                continue
            lay = _Layout(single, _t_range(sub), load_ref)
            th = np.zeros(lay.size)
            main = {name: sl for name, _, sl in self.layout.blocks}
            at = self.predict_parameters(float(sub.xi.mean()))
            for name, kind, sl in lay.blocks:
                th[sl] = float(at[name][0]) if kind == 'temp' else self.theta[main[name]]
            free = lay.mask('temp')
            prob = _Problem(lay, sub)
            try:
                th, res = prob.solve(th, free)
                cov, _ = _covariance(prob, th)
                se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
            except (ValueError, np.linalg.LinAlgError):
                continue
            entry = {'xi': float(sub.xi.mean()), 'xi_min': float(sub.xi.min()),
                     'xi_max': float(sub.xi.max()), 'plateaus': int(m.sum()),
                     'rms': float(np.sqrt(2 * res.cost / len(sub))), 'values': {}, 'se': {}}
            for name, kind, sl in lay.blocks:
                if kind == 'temp':
                    entry['values'][name] = float(th[sl][0])
                    entry['se'][name] = float(se[sl][0])
            out.append(entry)
        return out

    # -- results
    def _need_fit(self):
        if self.gear is None:
            raise RuntimeError('call fit() first')

    def predict(self, qd, xi, tau_l=0.0):
        """Static friction torque (Nm) of the identified model (xi clipped to its range)."""
        self._need_fit()
        return StaticFriction(self.gear.friction).torque(qd, xi, tau_l)

    def predict_parameters(self, xi, tau_l=0.0):
        """Evaluated curve parameters (fc, fs, fv, vs, delta_v) at xi, tau_l."""
        self._need_fit()
        return StaticFriction(self.gear.friction).parameters(np.atleast_1d(xi), tau_l)

    @property
    def results(self):
        """One row per identified coefficient: parameter, power, value, se, unit."""
        self._need_fit()
        rows = []
        for name, vals in self.coefficients.items():
            load = name.endswith('_load')
            base = name[:-5] if load else name
            for i, (v, e) in enumerate(zip(vals, self.standard_errors[name])):
                power = i + 1 if load else i
                var = 'tau_L' if load else 'xi'
                unit = UNITS[base] + (f'/Nm^{power}' if load else
                                      (f'/degC^{power}' if power else ''))
                rows.append({'parameter': name, 'power': f'{var}^{power}', 'value': v,
                             'se': e, 'unit': unit})
        for name, vals in self.structure.fixed.items():
            for i, v in enumerate(vals):
                rows.append({'parameter': name, 'power': f'xi^{i}', 'value': float(v),
                             'se': None, 'unit': 'fixed'})
        return rows

    def results_table(self):
        """The :attr:`results` as aligned text."""
        lines = [f'{"parameter":<14}{"power":<9}{"value":>14}{"std. error":>14}  unit']
        for r in self.results:
            se = '(fixed)' if r['se'] is None else f'{r["se"]:.4g}'
            lines.append(f'{r["parameter"]:<14}{r["power"]:<9}{r["value"]:>14.6g}{se:>14}  '
                         f'{r["unit"]}')
        return '\n'.join(lines)

    def report(self):
        """JSON-able summary: parameters, standard errors, RMS, plateaus, timings."""
        self._need_fit()
        step_rms = {}
        for st in self.info.get('steps', []):
            step_rms[str(st['step'])] = math.sqrt(st['cost'] / len(self.plateaus))
        return {
            'structure': {'orders': self.structure.orders,
                          'load_orders': {p: o for p, o in self.structure.load_orders.items()},
                          'fixed': self.structure.fixed, 'stribeck': self.structure.stribeck,
                          'delta_s': self.structure.delta_s,
                          'velocity_scale': self.structure.velocity_scale},
            'orders_mode': 'auto' if self.orders == 'auto' else
                           ('given' if self.orders else 'structure'),
            'parameters': self.coefficients,
            'standard_errors': self.standard_errors,
            'fixed': self.structure.fixed,
            'results': self.results,
            'rms_residual': self.rms,
            'rms_by_step': step_rms,
            'max_abs_residual': float(np.max(np.abs(self.residuals))),
            'plateau_count': len(self.plateaus),
            'temperature_range': self.info['temperature_range'],
            'load_range': [float(self.plateaus.load.min()), float(self.plateaus.load.max())],
            'speed_range': [float(np.abs(self.plateaus.qd).min()),
                            float(np.abs(self.plateaus.qd).max())],
            'temperature_groups': self.group_fits,
            'nodes': self.info['nodes'],
            'steps': self.info['steps'],
            'order_selection': self.info.get('order_selection'),
            'timings': {k: v for k, v in self.info.items() if k.startswith('time_')},
        }
