# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The structure of a static friction model and the checks that data can determine it.

A :class:`StaticStructure` says which coefficients a static model has (the
list lengths of a gear file, docs/interfaces.md: gear parameter files); :func:`check_excitation`
names what to record when plateaus cannot determine one of them.

It is the one description of a static structure: the diagnosis's model
structure (:class:`~friction_joint.diagnosis.CandidateStructure`) is this
static structure plus the terms the diagnosis adds (position ripple, offset,
inertia, pre-sliding, drift, gravity and nonlinear parameter values), built
with ``CandidateStructure.from_static`` and read back with its ``static``.
"""
from __future__ import annotations

from collections.abc import Iterable
import dataclasses
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ._arrays import IntArray
from ..exceptions import ExcitationError, GearConfigError
from ..models.static import PARAMETERS

if TYPE_CHECKING:
    from .plateaus import Plateaus
    from ..gear import FrictionParams, GearParams

__all__ = ['LOWER', 'UPPER', 'PARAMETER_UNITS', 'GROUP_WIDTH', 'MIN_GROUP', 'SPEED_TOL',
           'StaticStructure', 'temperature_groups', 'distinct_levels', 'group_table',
           'check_excitation', 'carry_structure', 'temperature_levels', 'load_levels',
           'external_torque_measured', 'one_direction_note']

#: temperature-polynomial parameters, in the order of the packed arrays of :mod:`static`
LOWER = {'fc': 0.0, 'fs': 0.0, 'fv': 0.0, 'vs': 1e-6, 'delta_v': 0.05}
UPPER = {'fc': np.inf, 'fs': np.inf, 'fv': np.inf, 'vs': np.inf, 'delta_v': 3.0}
PARAMETER_UNITS = {'fc': 'Nm', 'fs': 'Nm', 'fv': 'Nm/(rad/s)^dv', 'vs': 'rad/s', 'delta_v': '1',
                   'delta_s': '1', 'fs_ratio': '1', 'lever_error': '1', 'sensor_lag': 's'}

#: temperature-group width (degC): plateaus within this span count as one temperature
GROUP_WIDTH = 1.0
#: fewest plateaus of a temperature group that counts as a measured temperature
MIN_GROUP = 3
#: relative tolerance of "distinct" speeds
SPEED_TOL = 0.05


# ------------------------------------------------------------------ structure ---

@dataclasses.dataclass(frozen=True)
class StaticStructure:
    """
    Which coefficients a static model has (the model structure).

    See docs/interfaces.md, gear parameter files.

    Attributes
    ----------
    orders : dict
        Parameter -> temperature polynomial order (list length - 1) of every fitted
        parameter of :data:`PARAMETERS`.
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

    orders: dict[str, int]
    load_orders: dict[str, int]
    fixed: dict[str, list[float]]
    stribeck: bool
    delta_s: float = 2.0
    velocity_scale: float = 1.0

    @classmethod
    def from_gear(cls, gear: GearParams, *, fixed: Iterable[str] = ()) -> StaticStructure:
        """
        Return the structure of a gear file.

        Parameters
        ----------
        gear : GearParams
            The gear file (loaded).
        fixed : iterable of str
            Parameters of :data:`PARAMETERS` kept at the file's values (e.g. ``delta_v``
            when the file has no ``delta_v`` key: linear viscous friction).

        Returns
        -------
        StaticStructure

        """
        f = gear.friction
        stribeck = f.fs is not None
        orders, fix, load = {}, {}, {}
        for p in PARAMETERS:
            coef = getattr(f, p)
            if coef is None:
                continue
            if p in fixed:
                fix[p] = list(coef)
            else:
                orders[p] = len(coef) - 1
            load[p] = len(getattr(f, p + '_load'))
        unknown = set(fixed) - set(PARAMETERS)
        if unknown:
            raise GearConfigError(f'cannot fix {", ".join(sorted(unknown))}: not a static '
                                  f'curve parameter ({", ".join(PARAMETERS)})')
        return cls(orders, load, fix, stribeck, f.delta_s, f.velocity_scale)

    def with_orders(self, *, orders: dict[str, int] | None = None,
                    load_orders: dict[str, int] | None = None) -> StaticStructure:
        """
        Return a copy with some orders changed.

        Parameters
        ----------
        orders : dict, optional
            Parameter -> new temperature polynomial order.
        load_orders : dict, optional
            Parameter -> new load polynomial order.

        Returns
        -------
        StaticStructure

        """
        o = dict(self.orders)
        o.update(orders or {})
        lo = dict(self.load_orders)
        lo.update(load_orders or {})
        return dataclasses.replace(self, orders=o, load_orders=lo)

    def length(self, p: str) -> int:
        """
        Return the length of a parameter's temperature polynomial (0: not in the model).

        Parameters
        ----------
        p : str
            A parameter of :data:`PARAMETERS`.

        Returns
        -------
        int
            Its order + 1 when fitted, the length of its list when fixed.

        """
        if p in self.orders:
            return self.orders[p] + 1
        return len(self.fixed.get(p, ()))

    @property
    def params(self) -> list[str]:
        """Fitted temperature parameters, in :data:`PARAMETERS` order."""
        return [p for p in PARAMETERS if p in self.orders]

    @property
    def load_params(self) -> list[str]:
        return [p for p in PARAMETERS if self.load_orders.get(p, 0) > 0]

    def describe(self) -> str:
        """
        Say in words what is fitted, e.g. ``fc linear in temperature, fv constant, ...``.

        The list lengths of the gear file's keys follow in brackets
        (``fc: [2]`` = 2 coefficients).
        """
        shape = {1: 'constant', 2: 'linear in temperature', 3: 'quadratic in temperature'}
        parts = [f'{p} {shape.get(self.orders[p] + 1, f"degree {self.orders[p]} in temperature")}'
                 for p in self.params]
        parts += [f'{p} kept from the structure file' for p in self.fixed]
        parts += [f'{p} x load up to |tau_L|^{self.load_orders[p]}' for p in self.load_params]
        lengths = [f'{p}: [{self.orders[p] + 1}]' for p in self.params]
        lengths += [f'{p}_load: [{self.load_orders[p]}]' for p in self.load_params]
        return ', '.join(parts) + f' ({", ".join(lengths)})'


# ------------------------------------------------------------- data checks ---

def temperature_groups(xi: ArrayLike, width: float = GROUP_WIDTH) -> IntArray:
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


def distinct_levels(x: ArrayLike, rel: float = SPEED_TOL, absolute: float = 0.0) -> int:
    """
    Return the number of distinct values of x.

    Sorted values closer than rel |x| + absolute merge.
    """
    x = np.sort(np.abs(np.asarray(x, dtype=float)))
    if len(x) == 0:
        return 0
    count, ref = 1, x[0]
    for v in x[1:]:
        if v - ref > rel * ref + absolute:
            count += 1
            ref = v
    return count


def group_table(plateaus: Plateaus) -> tuple[IntArray, list[tuple[float, int]]]:
    labels = temperature_groups(plateaus.xi)
    groups = []
    for g in range(labels.max() + 1 if len(labels) else 0):
        m = labels == g
        if m.sum() >= MIN_GROUP:
            groups.append((float(plateaus.xi[m].mean()), int(m.sum())))
    return labels, groups


def temperature_levels(plateaus: Plateaus) -> tuple[int, float]:
    """
    Return the number of distinct plateau temperatures and the width that merges them.

    Temperatures closer than four times the plateaus' median temperature standard error
    (their own noise; at least 1e-3 degC) count once: a temperature that only rises
    gives many levels, a constant one gives one.
    """
    if not len(plateaus):
        return 0, 0.0
    width = max(4.0 * float(np.median(plateaus.xi_se)), 1e-3)
    return distinct_levels(plateaus.xi, rel=0.0, absolute=width), width


def load_levels(plateaus: Plateaus) -> int:
    """
    Return the number of distinct plateau loads.

    Loads closer than four times the plateaus' median load standard error, or than 5 %
    of the largest load, count once.
    """
    if not len(plateaus):
        return 0
    loads = plateaus.load
    width = max(4.0 * float(np.median(plateaus.load_se)), 0.05 * float(np.max(loads)), 1e-9)
    return distinct_levels(loads, rel=0.0, absolute=width)


def external_torque_measured(plateaus: Plateaus) -> bool:
    """
    Return whether every plateau's tau_ext was measured by a load sensor (``/link_torque``).

    Parameters
    ----------
    plateaus : Plateaus
        The data (their ``torque_source`` per recording).

    Returns
    -------
    bool
        False when any recording's tau_ext came from the structure's lever model (or
        was given from elsewhere), or there are no sources.

    """
    src = plateaus.torque_source
    return bool(src) and all(s == 'link_torque' for s in src)


def _directions(plateaus: Plateaus) -> tuple[int, int]:
    """Return (positive, negative) plateau counts."""
    return int(np.sum(plateaus.qd > 0)), int(np.sum(plateaus.qd < 0))


def one_direction_note(plateaus: Plateaus) -> dict[str, str] | None:
    """
    Say what one-direction plateaus leave unidentified, or None when both directions are there.

    With the external torque measured, plateaus in one direction pin the static curve in
    that direction (F_c, F_v, delta_v, the Stribeck dip where slow plateaus reach it, the
    temperature and load terms the ranges carry); the other direction is the same curve
    mirrored, assumed, not measured, and an offset of the drive torque (effort) would sit
    in F_c unseen (two directions would show it as an asymmetry).

    Parameters
    ----------
    plateaus : Plateaus
        The data.

    Returns
    -------
    dict or None
        ``{'why', 'kept', 'advice', 'measured', 'assumed'}`` (``measured``/``assumed``:
        ``'positive'`` or ``'negative'``), the form of
        :func:`carry_structure`'s notes.

    """
    pos, neg = _directions(plateaus)
    if not len(plateaus) or min(pos, neg) >= 2:
        return None
    have, miss = ('positive', 'negative') if pos >= neg else ('negative', 'positive')
    return {
        'why': f'the {len(plateaus)} plateaus are all {have} velocity ({pos} positive, {neg} '
               'negative) with tau_ext measured (/link_torque): the curve is identified in the '
               f'{have} direction only, and an offset of the drive torque would sit in F_c '
               'unseen',
        'kept': f'the {miss} direction assumed symmetric (the {have} curve mirrored, '
                'F(-v) = -F(v)), not measured',
        'advice': f'record plateaus at {miss} velocities too to identify it and check the '
                  'symmetry',
        'measured': have, 'assumed': miss}


def check_excitation(plateaus: Plateaus, structure: StaticStructure, *,
                     stribeck: bool = True, temperature: bool = True,
                     load: bool = True, one_direction: bool = False) -> None:
    """
    Raise :class:`ExcitationError` if the plateaus cannot determine the structure's coefficients.

    Checks: plateaus exist; both directions (or one, see ``one_direction``); enough
    plateaus for the number of coefficients; distinct temperatures for each temperature
    order; low-speed plateaus for the Stribeck parameters; a velocity range for delta_v
    and F_v; distinct loads for each load order.  The message says what to record.

    Parameters
    ----------
    plateaus : Plateaus
        The data.
    structure : StaticStructure
        The model structure.
    stribeck, temperature, load : bool
        Check the low-speed plateaus of the Stribeck parameters, the temperature groups
        of the temperature orders (:data:`MIN_GROUP` plateaus within :data:`GROUP_WIDTH`
        degC per group: the fleet's rule for a day's recording) and the load spread of
        the load orders.  ``identify`` turns them off: it lowers what the data cannot
        carry and says so (:func:`carry_structure`, scaled with the data) and decides the
        Stribeck parameters from the residual's profile over v_s.
    one_direction : bool
        Accept plateaus in one direction when every recording measured tau_ext
        (:func:`external_torque_measured`; ``identify`` does, saying what is assumed:
        :func:`one_direction_note`).  Otherwise, or without the load sensor, one
        direction is refused, the message naming what to record: both directions, or
        the external torque with a load sensor.

    """
    src = ', '.join(plateaus.sources) or 'the data'
    n = len(plateaus)
    if n == 0:
        raise ExcitationError(
            f'{src}: no constant-velocity plateaus found: the identification needs segments '
            'of constant velocity (at least 0.2 s each, both directions, speeds from about '
            '0.01 rad/s up to the highest operating speed, e.g. '
            '"friction_joint experiment identification"); the recording has none')
    pos, neg = _directions(plateaus)
    if min(pos, neg) < 2 and not (one_direction and external_torque_measured(plateaus)):
        have, miss = ('positive', 'negative') if neg < 2 else ('negative', 'positive')
        if one_direction:
            raise ExcitationError(
                f'{src}: the {n} plateaus all have {have} velocity ({pos} positive, {neg} '
                f'negative) and tau_ext comes from the lever model (no /link_torque): record '
                f'plateaus in both directions (also {miss} velocities), or record the external '
                'torque with a load sensor on /link_torque; with one direction and no load '
                'sensor friction cannot be told from a torque offset or a gravity error')
        raise ExcitationError(
            f'{src}: the {n} plateaus all have {have} velocity ({pos} positive, {neg} negative): '
            f'record plateaus in both directions (also {miss} velocities); with one direction '
            'friction cannot be told from a torque offset or a gravity error')
    lo, hi = float(plateaus.xi.min()), float(plateaus.xi.max())
    _, groups = group_table(plateaus)
    temps = ', '.join(f'{x:.1f}' for x, _ in groups) or 'none'
    for p, order in structure.orders.items():
        if temperature and order >= 1 and len(groups) < order + 1:
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
    if stribeck and structure.stribeck and ('fs' in structure.orders
                                            or 'vs' in structure.orders):
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
    for p in structure.load_params if load else ():
        m = structure.load_orders[p]
        loads = plateaus.load
        span = float(loads.max() - loads.min())
        levels = distinct_levels(loads, rel=0.0, absolute=max(0.5, 0.1 * span))
        if span < 1.0 or levels < m + 1:
            raise ExcitationError(
                f"the plateaus' loads span tau_L = {loads.min():.2f}..{loads.max():.2f} Nm "
                f'({levels} distinct levels): the load polynomial of order {m} for {p}_load '
                f'needs plateaus at >= {m + 1} clearly different loads (at least 1 Nm apart, '
                'e.g. the lever at different angles); record with varying load or use '
                f'{p}_load: []')
    npar = sum(o + 1 for o in structure.orders.values()) + sum(structure.load_orders.values())
    if n < npar + 2:
        raise ExcitationError(
            f'{n} plateaus for {npar} coefficients: record more plateaus (at least {npar + 2}; '
            'the paper used 34 per temperature series)')


def carry_structure(plateaus: Plateaus, structure: StaticStructure, *,
                    prior: FrictionParams | None = None
                    ) -> tuple[StaticStructure, dict[str, dict[str, str]]]:
    """
    Lower what the plateaus cannot carry, and say so, instead of refusing the fit.

    * a temperature order above what the distinct temperatures carry (order + 1
      groups of :data:`MIN_GROUP` plateaus :data:`GROUP_WIDTH` degC wide) is lowered;
    * delta_v over less than a decade of speed, or fewer than 4 distinct speeds, is
      kept from the structure file (``prior``);
    * a load order above what the distinct loads carry is dropped.

    Parameters
    ----------
    plateaus : Plateaus
        The data.
    structure : StaticStructure
        The structure asked for.
    prior : FrictionParams, optional
        The structure file's friction section (values kept for delta_v).

    Returns
    -------
    structure : StaticStructure
        What the data can carry.
    notes : dict
        Name (``'fc temperature order'``, ``'delta_v'``, ``'fc_load'``, ...) ->
        ``{'why', 'kept', 'advice'}`` in plain words.

    """
    notes: dict[str, dict[str, str]] = {}
    if not len(plateaus):
        return structure, notes
    orders = dict(structure.orders)
    fixed = dict(structure.fixed)
    load_orders = dict(structure.load_orders)
    lo, hi = float(plateaus.xi.min()), float(plateaus.xi.max())
    # distinct temperatures: further apart than the plateaus' own temperature noise (a
    # temperature that only rises gives many; a constant one gives one)
    levels, width = temperature_levels(plateaus)
    for p, order in structure.orders.items():
        if order >= 1 and levels < order + 1:
            new = max(levels - 1, 0)
            orders[p] = new
            notes[f'{p} temperature order'] = {
                'why': f'{p} of order {order} in temperature needs plateaus at {order + 1} '
                       f'distinct temperatures; the recordings hold {levels} (xi {lo:.2f}..'
                       f'{hi:.2f} degC, temperatures within {width:.2g} degC counted once)',
                'kept': f'fitted to order {new}',
                'advice': f'record plateaus at {order + 1} or more temperatures'}
    speed = np.abs(plateaus.qd)
    vmin, vmax = float(speed.min()), float(speed.max())
    nspeeds = distinct_levels(speed)
    if 'delta_v' in orders and (vmax < 10.0 * vmin or nspeeds < 4):
        value = list(getattr(prior, 'delta_v', None) or [1.0])
        orders.pop('delta_v')
        fixed['delta_v'] = value
        notes['delta_v'] = {
            'why': f'plateau speeds span {vmin:.3g}..{vmax:.3g} rad/s ({nspeeds} distinct): '
                   'the viscous exponent needs a decade of speed and 4 distinct speeds',
            'kept': f'delta_v = {value} from the structure file',
            'advice': 'record plateaus over at least a decade of speed'}
    for p in list(structure.load_params):
        m = structure.load_orders[p]
        loads = plateaus.load
        levels = load_levels(plateaus)
        if levels < m + 1:
            load_orders[p] = 0
            notes[f'{p}_load'] = {
                'why': f"the plateaus' loads span tau_L = {loads.min():.2f}..{loads.max():.2f} "
                       f'Nm ({levels} distinct levels); a load polynomial of order {m} needs '
                       f'{m + 1} clearly different loads',
                'kept': f'{p}_load not fitted (no load dependence)',
                'advice': 'record with varying load (e.g. the lever at different angles)'}
    return dataclasses.replace(structure, orders=orders, fixed=fixed,
                               load_orders=load_orders), notes
