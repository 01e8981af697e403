# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Friction model structures for diagnosis, as linear regressions over the bin averages.

Every structure the diagnosis tries is *linear in its coefficients* once a
few nonlinear parameters are fixed, so it is fitted by linear least squares
and its nonlinear parameters by a grid, then by bounded continuous
optimisation between the grid points (variable projection,
:mod:`~friction_joint.diagnosis.refine`):

    tau_r = sum_k fc_k u^k h (1 - E) + sum_k fs_k u^k h E          (Coulomb/Stribeck, eq. 1, 7)
          + sum_j fc_load_j tl^j h (1 - E) + ...                   (load, eq. 7)
          + sum_k fv_k u^k sign(qd) |kappa qd|^delta_v + ...        (viscous, eq. 5)
          + sum_n a_n sin(n c q) + b_n cos(n c q)                  (position ripple)
          + offset + dJ q̈                                          (asymmetry, inertia)
          + a sin q + b cos q                                      (gravity)
            (short stroke: c0 + c1 x + c2 x^2, x = (q - centre) / half stroke)
          + sum_j fc_drift_j P_j(s) h (1 - E)                          (drift)

with E = exp(-|kappa qd / v_s|^delta_s), u the (clipped, centred, scaled)
temperature, tl = |tau_ext|, P_j the shifted Legendre polynomials of the
accumulated travel s (0..1, :func:`accumulated_travel`) and h = sign(qd) for a static model.  For a
pre-sliding model h is the normalised friction state driven by the measured
(filtered) position, g the mean Coulomb level, by the models' own updates
(:mod:`~friction_joint.diagnosis.states`):
LuGre h' = (sigma0 / g) (dq - |dq| h) solved exactly per sample
(:func:`~friction_joint.models.lugre.lugre_update`, eq. 10), GMS
h = sum alpha_i h_i with Maxwell-slip elements h_i clipped to [-1, 1]
(increments k_i dq / (alpha_i g); :func:`~friction_joint.models.gms.gms_update`
with instantaneous slip, eq. 11-12).

Layers
------
A :class:`CandidateStructure` is the paper's static structure plus the terms
the diagnosis adds.  Its static part (the temperature and load polynomial
lengths of F_c, F_v, F_s, the Stribeck flag, a fitted or linear viscous
exponent) is an :class:`~friction_joint.identification.StaticStructure`, the
structure the identification fits (:meth:`CandidateStructure.from_static`,
:meth:`CandidateStructure.static`); the diagnosis adds position ripple, a
direction offset, an inertia error, pre-sliding, drift over travel, a lever
gravity error and the values of the nonlinear parameters (``vs``, ``dv``,
``cyc``, ``ps``).  v_s and delta_v keep the base gear's temperature shapes
(:class:`Context`); the diagnosis fits their level.

Nonlinear parameters and their grids: ``vs`` (Stribeck velocity), ``dv``
(delta_v level), ``cyc`` (ripple fundamental, cycles per output revolution:
2 N first, then N), ``ps`` (pre-sliding model and stiffness).  A structure's
temperature-dependent ``vs``/``delta_v`` polynomials keep their shape; the grid
sets their level.  The grids in physical units derive from the data
(:class:`~friction_joint.diagnosis.data.DiagnosisData` scales), never from
numbers of one gear: ``vs`` spans ``max(1.5 v_stick, P1 / 2)`` to
``0.3 P99`` of the sliding speeds (:data:`N_VS` points, log spaced); the
pre-sliding stiffness is ``g / L`` for pre-sliding lengths L from
:data:`PS_MIN_RESOLUTIONS` position resolutions to :data:`PS_MAX_STROKE` of
the stroke, a factor :data:`PS_STEP` apart (g the mean Coulomb level); the
ripple fundamentals are those that repeat within a piece
(:func:`~friction_joint.diagnosis.ripple.ripple_cycles`).  The refinement
moves every parameter continuously from the best grid point, so a true value
between grid points leaves no systematic residual for another candidate.

Physical fits
-------------
Every least-squares fit is bounded
(:func:`~friction_joint.diagnosis.physical.solve_physical`): F_c, F_s and F_v
(with their load terms) must be >= 0 on a grid over the temperature range the
fit is valid on (the data's, clipped to the base's) and over the data's load
range.  The unconstrained solution is kept when it satisfies this; otherwise
the quadratic problem is solved with the inequalities (SLSQP).  v_s > 0 and
delta_v in [0.3, 1.7] hold by their grids and the refinement's bounds.
"""
from __future__ import annotations

from collections.abc import Sequence
import dataclasses
import math
from typing import Any, TYPE_CHECKING

import numpy as np

from .ripple import ripple_cycles
from .states import accumulated_travel, presliding_state
from ..identification.static_structure import StaticStructure

if TYPE_CHECKING:
    from numpy.typing import ArrayLike, NDArray

    from .data import DiagnosisData
    from ..gear import GearParams

#: a design column's name: (coefficient kind, power or index)
Column = tuple[str, int]

__all__ = ['CandidateStructure', 'design', 'column_groups', 'grid_of',
           'coefficients', 'presliding_state', 'fit_range', 'drift_basis', 'DRIFT_ORDER',
           'accumulated_travel', 'ripple_cycles', 'Context', 'Column']

#: floats the context's cache of design column groups holds at most
CACHE_FLOATS = 10_000_000
#: points of the Stribeck velocity grid
N_VS = 15
DV_GRID = np.array([0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.0, 1.05, 1.1, 1.2, 1.35, 1.5, 1.7])
#: shortest pre-sliding length of the grid, in position resolutions
PS_MIN_RESOLUTIONS = 2.0
#: longest pre-sliding length of the grid, as a fraction of the stroke
PS_MAX_STROKE = 0.25
#: ratio of neighbouring pre-sliding lengths of the grid
PS_STEP = 2.0
#: temperature points of the physical constraints
N_CONSTRAINT = 9
RIPPLE_HARMONICS = 3
#: basis functions of the travel-dependent Coulomb level of ``drift``
DRIFT_ORDER = 2
GMS_RATIOS = np.array([0.6, 0.25, 0.1, 0.05])


@dataclasses.dataclass(frozen=True)
class CandidateStructure:
    """
    A model structure: polynomial lengths, flags and nonlinear parameter values.

    Attributes
    ----------
    nfc, nfv, nfs : int
        Lengths of the temperature polynomials of F_c, F_v, F_s (``nfs`` 0: no Stribeck).
    nfc_load, nfv_load, nfs_load : int
        Lengths of their load polynomials.
    dv_free : bool
        The viscous exponent delta_v is fitted (else 1).
    ripple : int
        Position-ripple harmonics.
    offset, inertia, presliding : bool
        Direction offset, an inertia error and pre-sliding (LuGre or GMS) are modelled.
    drift : int
        Order of the drift over accumulated travel.
    gravity : bool
        A lever gravity error is modelled.
    vs, dv, cyc : float
        Nonlinear parameters: v_s (rad/s), delta_v, ripple cycles per turn.
    ps : tuple
        Pre-sliding ``(model, stiffness)``.

    """

    nfc: int = 1
    nfv: int = 1
    nfs: int = 0
    nfc_load: int = 0
    nfv_load: int = 0
    nfs_load: int = 0
    dv_free: bool = False
    ripple: int = 0
    offset: bool = False
    inertia: bool = False
    presliding: bool = False
    drift: int = 0
    gravity: bool = False
    # nonlinear parameter values
    vs: float = 0.05
    dv: float = 1.0
    cyc: float = 160.0
    ps: tuple[str, float] = ('lugre', 2e4)

    @classmethod
    def from_static(cls, static: StaticStructure,
                    **terms: Any) -> CandidateStructure:
        """
        Return the structure of a static structure plus the terms the diagnosis adds.

        Parameters
        ----------
        static : StaticStructure
            The static part: F_c, F_v and F_s temperature and load polynomial lengths
            (F_s only with ``stribeck``), delta_v fitted (its level, ``dv_free``) or
            fixed at ``[1.0]`` (linear viscous).  The orders of v_s and delta_v do not
            enter: the diagnosis keeps the base gear's temperature shapes.
        **terms : float, bool or tuple
            The other fields: ``ripple``, ``offset``, ``inertia``, ``presliding``,
            ``drift``, ``gravity`` and the nonlinear values ``vs``, ``dv``, ``cyc``, ``ps``.

        Returns
        -------
        CandidateStructure

        Raises
        ------
        ValueError
            A term names a field of the static part, or ``static`` fixes F_c, F_v,
            F_s or a delta_v other than ``[1.0]`` (the diagnosis fits them).

        """
        fixed = [p for p in static.fixed if p != 'delta_v' or list(static.fixed[p]) != [1.0]]
        if fixed:
            raise ValueError(f'the diagnosis fits {", ".join(fixed)}: cannot keep it fixed')
        loads = static.load_orders
        own: dict[str, Any]
        own = {'nfc': static.length('fc'), 'nfv': static.length('fv'),
               'nfs': static.length('fs') if static.stribeck else 0,
               'nfc_load': loads.get('fc', 0), 'nfv_load': loads.get('fv', 0),
               'nfs_load': loads.get('fs', 0) if static.stribeck else 0,
               'dv_free': 'delta_v' in static.orders}
        clash = sorted(set(own) & set(terms))
        if clash:
            raise ValueError(f'{", ".join(clash)}: part of the static structure')
        return cls(**own, **terms)

    def static(self, *, base: StaticStructure | None = None) -> StaticStructure:
        """
        Return the static part as the structure of the gear file a fit of it writes.

        Parameters
        ----------
        base : StaticStructure, optional
            The base gear's structure: the orders of v_s and delta_v (whose
            temperature shapes the diagnosis keeps and scales), their load orders,
            delta_s and the velocity scale.  Without it: order 0, no load terms,
            the defaults.

        Returns
        -------
        StaticStructure
            ``CandidateStructure.from_static(s.static(), ...)`` gives back ``s``.

        """
        orders, load = {}, {}
        for p, n, n_load in (('fc', self.nfc, self.nfc_load), ('fv', self.nfv, self.nfv_load),
                             ('fs', self.nfs, self.nfs_load)):
            if n:
                orders[p], load[p] = n - 1, n_load
        shapes = ('vs', 'delta_v') if self.nfs else ('delta_v',)
        for p in shapes:
            orders[p] = base.length(p) - 1 if base is not None and base.length(p) else 0
            load[p] = base.load_orders.get(p, 0) if base is not None else 0
        fixed = {}
        if not self.dv_free:
            fixed['delta_v'] = [1.0]
            del orders['delta_v']
        extra = {} if base is None else {'delta_s': base.delta_s,
                                         'velocity_scale': base.velocity_scale}
        return StaticStructure(orders, load, fixed, bool(self.nfs), **extra)

    def with_(self, **kw: Any) -> CandidateStructure:
        """
        Return a copy with some fields changed.

        Parameters
        ----------
        **kw : float, bool or tuple
            Field name -> new value.

        Returns
        -------
        CandidateStructure

        """
        return dataclasses.replace(self, **kw)


class Context:
    """What the design matrix needs besides the data: base polynomial shapes and scales."""

    def __init__(self, gear: GearParams, data: DiagnosisData) -> None:
        f = gear.friction
        self.kappa = f.velocity_scale
        self.ds = f.delta_s
        self.lo, self.hi = f.temperature_range
        x = np.clip(data.xi, self.lo, self.hi)
        self.xc = float(np.mean(x))
        self.xs = max(float(np.std(x)), 0.5)
        self.u = (x - self.xc) / self.xs
        level = getattr(data, 'friction_level', 1.0)
        self.ts = max(float(np.mean(data.tl)), 0.05 * level)
        self.vl = data.tl / self.ts
        self.range = fit_range(gear, data)
        self.u_grid = (np.linspace(*self.range, N_CONSTRAINT) - self.xc) / self.xs
        self.vl_max = float(np.max(self.vl)) if len(self.vl) else 0.0
        sliding = np.abs(data.average(data.qd))
        v_stick = getattr(data, 'v_stick', 2e-3)
        lo_v = max(1.5 * v_stick, 0.5 * float(np.percentile(sliding, 1)))
        hi_v = max(0.3 * float(np.percentile(sliding, 99)), 2.0 * lo_v)
        self.vs_grid = np.geomspace(lo_v, hi_v, N_VS)
        res = getattr(data, 'resolution', 0.0) or 1e-7
        stroke = getattr(data, 'stroke', 0.0) or 1.0
        l_lo = PS_MIN_RESOLUTIONS * res
        l_hi = max(PS_MAX_STROKE * stroke, 2.0 * l_lo)
        n_ps = int(min(40, math.ceil(math.log(l_hi / l_lo) / math.log(PS_STEP)) + 1))
        self.ps_lengths = np.geomspace(l_lo, l_hi, n_ps)
        self.gear_ratio = gear.gear_ratio
        self.ripple_cycles = ripple_cycles(data, gear.gear_ratio)
        poly = np.polynomial.polynomial.polyval
        self.vs_shape = ((poly(x, f.vs) / poly(self.xc, f.vs))
                         if f.vs is not None and len(f.vs) > 1 else np.ones_like(x))
        self.vs_shape = np.maximum(self.vs_shape, 1e-3)
        self.vs_coef = f.vs
        dvp = f.delta_v
        self.dv_shift = (poly(x, dvp) - poly(self.xc, dvp)) if len(dvp) > 1 else np.zeros_like(x)
        self.dv_coef = dvp
        ratios = np.asarray(f.gms.k, float) if f.gms is not None else GMS_RATIOS
        self.gms_ratios = ratios / ratios.sum()
        self.gms_alpha = np.asarray(f.gms.alpha, float) if f.gms is not None else \
            np.full(len(ratios), 1.0 / len(ratios))
        self.g_nom = level
        #: ``(centre, half stroke)`` (rad): ``gravity`` is a smooth pose-dependent load about
        #: the stroke's centre (the stroke too short for a lever's sine); None: the sine
        self.pose: tuple[float, float] | None = None
        self.ps_models: tuple[str, ...] = ('lugre', 'gms')
        self.data = data
        self.dv_grid = DV_GRID
        self._travel: NDArray[np.float64] | None = None
        self.columns: dict[CandidateStructure, tuple[NDArray[np.float64], list[Column]]] = {}
        self._cached = 0

    @property
    def travel(self) -> NDArray[np.float64]:
        """Return the accumulated travel as a fraction of its total, 0..1, at full rate."""
        if self._travel is None:
            self._travel = accumulated_travel(self.data)
        return self._travel


def drift_basis(x: ArrayLike, order: int) -> list[NDArray[np.float64]]:
    """Shifted Legendre polynomials 1..``order`` of ``x`` in 0..1 (list of arrays)."""
    z = 2.0 * np.asarray(x, float) - 1.0
    return [np.polynomial.legendre.legval(z, np.eye(order + 1)[j]) for j in range(1, order + 1)]


#: the fields of each column group of :func:`design`, and their values when a group is left out
_GROUPS: tuple[dict[str, Any], ...] = (
    {'nfc': 0, 'nfc_load': 0, 'drift': 0, 'nfs': 0, 'nfs_load': 0, 'vs': 0.0,
     'presliding': False, 'ps': None},                             # Coulomb/Stribeck/drift
    {'nfv': 0, 'nfv_load': 0, 'dv': 1.0},                          # viscous
    {'ripple': 0, 'cyc': 0.0},                                     # ripple
    {'offset': False, 'gravity': False, 'inertia': False})         # the others


def column_groups(s: CandidateStructure) -> list[CandidateStructure]:
    """
    Return the column groups of ``s``'s design, each a structure with only those columns.

    Coulomb/Stribeck/drift (on ``vs``, ``ps``), viscous (on ``dv``), ripple (on
    ``cyc``), and offset/gravity/inertia, in the design's order: a change of
    one nonlinear parameter changes one group only.  A group is ``s`` with the
    other groups' fields cleared (and the unused parameters of its own).
    """
    out = []
    for i, own in enumerate(_GROUPS):
        if not any(getattr(s, f) for f in own if f not in ('vs', 'ps', 'dv', 'cyc')):
            continue
        clear = {f: v for j, g in enumerate(_GROUPS) if j != i for f, v in g.items()}
        clear['dv_free'] = False
        if i == 0:
            clear.update({} if s.nfs else {'vs': 0.0}, **({} if s.presliding else {'ps': None}))
        out.append(s.with_(**clear))
    return out


def design(s: CandidateStructure, ctx: Context) -> tuple[NDArray[np.float64], list[Column]]:
    """
    Bin-averaged design matrix (n_bins, p) and column names of structure ``s``.

    Assembled from its :func:`column_groups`, each computed once per context
    (cached, up to :data:`CACHE_FLOATS` floats).
    """
    xs, names = [], []
    for g in column_groups(s):
        hit = ctx.columns.get(g)
        if hit is None:
            hit = _columns(g, ctx)
            if ctx._cached + hit[0].size > CACHE_FLOATS:
                ctx.columns.clear()
                ctx._cached = 0
            ctx.columns[g] = hit
            ctx._cached += hit[0].size
        xs.append(hit[0])
        names.extend(hit[1])
    if len(set(names)) < len(names):
        raise ValueError(f'a column in two groups of the design: {names}')
    x = np.hstack(xs) if xs else np.empty((len(ctx.data.y), 0))
    return x, names


def _columns(s: CandidateStructure, ctx: Context) -> tuple[NDArray[np.float64], list[Column]]:
    """Bin-averaged columns and names of ``s`` (computed)."""
    d = ctx.data
    v = ctx.kappa * d.qd
    sgn = np.sign(d.qd)
    cols: list[NDArray[np.float64]] = []
    names: list[Column] = []

    def terms(base: NDArray[np.float64], name: str, n_temp: int, n_load: int) -> None:
        # polynomial in the temperature variable u (powers 0..) and the load vl (powers 1..)
        for k in range(n_temp):
            cols.append(base * ctx.u ** k)
            names.append((name, k))
        for m in range(1, n_load + 1):
            cols.append(base * ctx.vl ** m)
            names.append((name + '_load', m))

    if s.nfc or s.nfc_load or s.drift or s.nfs or s.nfs_load:
        h = presliding_state(ctx, s.ps) if s.presliding else sgn
        if s.nfs:
            vs = s.vs * ctx.kappa * ctx.vs_shape
            e: NDArray[np.float64] | float = np.exp(-np.abs(v / vs) ** ctx.ds)
        else:
            e = 0.0
        terms(h * (1.0 - e), 'fc', s.nfc, s.nfc_load)
        if s.drift:
            for j, phi in enumerate(drift_basis(ctx.travel, s.drift), 1):
                cols.append(h * (1.0 - e) * phi)
                names.append(('fc_drift', j))
        if s.nfs:
            terms(h * e, 'fs', s.nfs, s.nfs_load)
    if s.nfv or s.nfv_load:
        dv = s.dv + ctx.dv_shift
        terms(sgn * np.abs(v) ** np.maximum(dv, 0.05), 'fv', s.nfv, s.nfv_load)
    if s.ripple:
        s1, c1 = np.sin(s.cyc * d.qf), np.cos(s.cyc * d.qf)
        sn, cn = s1, c1
        for n in range(1, s.ripple + 1):
            if n > 1:           # sin/cos of n c q by the angle-addition recurrence
                sn, cn = sn * c1 + cn * s1, cn * c1 - sn * s1
            cols.extend((sn, cn))
            names.extend((('ripple_sin', n), ('ripple_cos', n)))
    if s.offset:
        cols.append(np.ones_like(v))
        names.append(('offset', 0))
    if s.gravity and ctx.pose is not None:     # short stroke: a smooth pose-dependent load
        x = (d.qf - ctx.pose[0]) / ctx.pose[1]
        for k in range(0 if not s.offset else 1, 3):
            cols.append(x ** k)
            names.append(('pose', k))
    elif s.gravity:                    # a direction-independent m g l sin(q - q0)
        cols.extend((np.sin(d.qf), np.cos(d.qf)))
        names.extend((('gravity_sin', 0), ('gravity_cos', 0)))
    if s.inertia:
        cols.append(d.qdd)
        names.append(('inertia', 0))
    x = np.column_stack([d.average(c) for c in cols])
    return x, names


def grid_of(s: CandidateStructure, new: str | None, ctx: Context) -> list[CandidateStructure]:
    """Grid of structures over the nonlinear parameter named in ``new`` (None: no grid)."""
    if new is None:
        return [s]
    if new == 'vs':
        return [s.with_(vs=float(v)) for v in ctx.vs_grid]
    if new == 'dv':
        return [s.with_(dv=float(v)) for v in DV_GRID]
    if new == 'cyc':           # none repeats within a piece: the structure's own
        return [s.with_(cyc=float(c)) for c in ctx.ripple_cycles] or [s]
    if new == 'ps':
        return [s.with_(ps=(m, float(ctx.g_nom / length))) for m in ctx.ps_models
                for length in ctx.ps_lengths[::-1]]
    raise ValueError(new)


def fit_range(gear: GearParams, data: DiagnosisData) -> tuple[float, float]:
    """
    Temperature range (degC) an extended model is valid on.

    The data's range (rounded outward to 0.1 degC), clipped to the base's
    ``friction.temperature_range``; the base's range when the data have no span.
    """
    lo, hi = gear.friction.temperature_range
    xlo, xhi = float(np.min(data.xi)), float(np.max(data.xi))
    nlo, nhi = max(lo, math.floor(xlo * 10) / 10), min(hi, math.ceil(xhi * 10) / 10)
    return (nlo, nhi) if nhi > nlo else (lo, hi)


def _raw_poly(c: Sequence[float], xc: float, xs: float) -> list[float]:
    """Coefficients in u = (x - xc)/xs -> coefficients in x."""
    p = np.polynomial.Polynomial(c)(np.polynomial.Polynomial([-xc / xs, 1.0 / xs]))
    out = np.zeros(len(c))
    out[:len(p.coef)] = p.coef
    return [float(v) for v in out]


def coefficients(s: CandidateStructure, beta: NDArray[np.float64], names: Sequence[Column],
                 ctx: Context) -> dict[str, Any]:
    """Gear-file coefficient lists and extras from a fitted structure."""
    by: dict[str, dict[int, float]] = {}
    for (kind, i), val in zip(names, beta, strict=True):
        by.setdefault(kind, {})[i] = float(val)

    def temp(kind: str, n: int) -> list[float] | None:
        return _raw_poly([by[kind][i] for i in range(n)], ctx.xc, ctx.xs) if n else None

    def load(kind: str, n: int) -> list[float]:
        return [by[kind][j] / ctx.ts ** j for j in range(1, n + 1)]

    out: dict[str, Any]
    out = {'fc': temp('fc', s.nfc), 'fv': temp('fv', s.nfv),
           'fc_load': load('fc_load', s.nfc_load), 'fv_load': load('fv_load', s.nfv_load)}
    if s.nfs:
        out['fs'] = temp('fs', s.nfs)
        out['fs_load'] = load('fs_load', s.nfs_load)
        if ctx.vs_coef is not None and len(ctx.vs_coef) > 1:
            scale = s.vs * ctx.kappa / np.polynomial.polynomial.polyval(ctx.xc, ctx.vs_coef)
            out['vs'] = [float(c * scale) for c in ctx.vs_coef]
        else:
            out['vs'] = [s.vs * ctx.kappa]
        out['velocity_scale'] = float(ctx.kappa)           # vs is in velocity_scale x rad/s
    if s.dv_free or s.dv != 1.0:
        dvc: list[Any] = list(ctx.dv_coef)
        dvc[0] += s.dv - np.polynomial.polynomial.polyval(ctx.xc, ctx.dv_coef)
        out['delta_v'] = [float(v) for v in dvc]
    if s.ripple:
        amp: list[float] = []
        ph: list[float] = []
        for n in range(1, s.ripple + 1):
            a, b = by['ripple_sin'][n], by['ripple_cos'][n]
            amp.append(math.hypot(a, b))
            ph.append(math.atan2(b, a))
        out['position_ripple'] = {'cycles_per_rev': s.cyc, 'amplitude': amp, 'phase': ph}
    if s.offset:
        out['offset'] = by['offset'][0]
    if s.inertia:
        out['d_inertia'] = by['inertia'][0]
    if s.gravity and 'pose' in by:     # Nm per power of rad about the stroke's centre
        if ctx.pose is None:                # set whenever a pose term is fitted
            raise AssertionError('a pose term without the frame of its stroke')
        c, h = ctx.pose
        out['gravity'] = {'pose': {'center': float(c), 'coefficients': [
            by['pose'].get(k, 0.0) / h ** k for k in range(3)]}}
    elif s.gravity:
        out['gravity'] = {'sin': by['gravity_sin'][0], 'cos': by['gravity_cos'][0]}
    if s.presliding:
        out['presliding'] = {'model': s.ps[0], 'stiffness': s.ps[1]}
    if s.drift:
        out['drift'] = {'basis': 'shifted Legendre polynomials 1..n of the accumulated travel '
                                 'as a fraction of its total, times the Coulomb term',
                        'fc_drift': [by['fc_drift'][j] for j in range(1, s.drift + 1)]}
    return out
