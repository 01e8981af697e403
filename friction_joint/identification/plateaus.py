# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Constant-velocity plateaus of a recording: the data points of the static friction fit.

The seed paper identifies the static friction curve from "constant velocity
points" at constant temperatures (Section V-A).  :func:`find_plateaus` finds
such segments automatically in a recording, from the measured velocity only,
and reduces each to one data point: mean velocity, friction torque, housing
temperature and load, each with a standard error.

Detection (:data:`DETECTION` holds the thresholds)
--------------------------------------------------
1. The joint states are cut into contiguous pieces at long time gaps and
   averaged over blocks of ``block`` seconds (25 ms).  A step of more than
   ``gap_factor`` median sample periods is a gap; a short one is bridged
   (:func:`friction_joint.bag.stamps.split_pieces`: at most 50 sample
   periods and a quarter of the motion's time scale P90(|qd|)/P90(|qdd|)):
   the piece is resampled onto its uniform grid (linear interpolation) and
   the samples of the gap, and ``gap_factor`` sample periods on either side
   (where the interpolated velocity spoils qdd), are left out of the plateau
   means; a longer gap cuts the piece.
2. A block is *steady* if its mean speed is at least ``v_floor`` and the
   velocity changes across it by less than ``rel_slope`` of its speed per
   second plus ``abs_slope`` (ramps, reversals and oscillations fail this).
3. Consecutive steady blocks of one sign form a candidate; it is cut where a
   block mean leaves the candidate's running median by more than
   ``rel_tol`` of the speed plus ``abs_tol`` (a slow drift of the velocity
   is not a plateau).
4. Transients are excluded: ``trim`` seconds are dropped at both ends, and
   leading blocks whose friction torque still differs from the plateau's
   settled level (median of its second half) by more than ``settle_tol`` of
   that level (plus three noise standard deviations) are dropped too (at low
   speed the friction torque keeps building up after the velocity has
   settled).  What remains must last ``min_duration`` seconds.

Per plateau
-----------
* ``qd``: outlier-robust mean velocity (samples further than
  ``clip_mad`` median absolute deviations from the median are left out).
* ``tau_r``: friction torque tau_r = effort - tau_ext - J qdd (docs/interfaces.md,
  Interfaces: sign convention), same robust mean.  tau_ext is the ``/link_torque`` sensor when
  the recording has it, else the lever gravity m g l sin(q - angle_offset) of the STRUCTURE
  gear file (no contact torque); J is the structure's inertia and qdd the
  derivative of the measured velocity.
* ``xi``: mean housing temperature (zero-order hold of ``/joint_temperature``).
* ``load``: mean tau_L = |tau_ext| (link torque smoothed over 10 ms first, so
  sensor noise does not bias the magnitude), and the means of tau_L^2,
  tau_L^3 (``load_moments``).
* standard errors ``*_se`` by batch means: the window is cut into up to ten
  batches and the spread of the batch means gives the standard error, which
  keeps correlated noise (filtering, ripple) from looking like independent
  samples.
"""
from __future__ import annotations

from collections.abc import Iterable
import dataclasses
import math
from typing import Any, cast, TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._arrays import FloatArray, IntArray
from .stick_slip import position_resolution, stick_slip_scan, stuck_and_slipped
from ..bag import check_samples, check_values
from ..bag.stamps import piece_on_grid, split_pieces
from ..exceptions import ExcitationError, RecordingError

if TYPE_CHECKING:
    from ..bag import Recording
    from ..gear import GearParams

__all__ = ['DETECTION', 'Detection', 'NOISE_SIGMAS', 'Plateaus', 'find_plateaus',
           'plateaus_from_arrays']


@dataclasses.dataclass(frozen=True)
class Detection:
    """The plateau detection thresholds (module docstring); change them with ``replace``."""

    block: float = 0.025       # s, averaging block
    gap_factor: float = 5.0    # a time step larger than this many median steps is a gap
    v_floor: float = 2e-3      # rad/s, slowest plateau speed
    rel_slope: float = 1.0     # 1/s: |dv/dt| <= rel_slope |v| + abs_slope within a steady block
    abs_slope: float = 0.02    # rad/s^2
    rel_tol: float = 0.04      # block means within rel_tol |v| + abs_tol of the running median
    abs_tol: float = 5e-4      # rad/s
    trim: float = 0.05         # s dropped at both ends
    settle_tol: float = 0.01   # leading blocks off the settled friction by more are dropped
    min_duration: float = 0.2  # s, shortest plateau kept
    min_samples: int = 50      # fewest samples in a plateau
    clip_mad: float = 5.0      # outlier clipping of the robust means, in MADs
    batches: int = 10          # batch means for the standard errors
    load_smooth: float = 0.01  # s, smoothing of the link torque before |.|


#: detection thresholds (see the module docstring)
DETECTION = Detection()

#: detection tolerances include this many robust standard deviations of the data's own noise
NOISE_SIGMAS = 4.0

_FIELDS = ('qd', 'qd_se', 'tau_r', 'tau_r_se', 'xi', 'xi_se', 'xi_spread', 'load', 'load_se',
           'load2', 'load3', 'tau_ext', 'q', 't0', 't1', 'n', 'source', 'xi_rate')


@dataclasses.dataclass(frozen=True)
class Plateaus:
    """
    Constant-velocity plateaus, one entry per plateau in each array.

    Attributes
    ----------
    qd, qd_se : ndarray
        Mean velocity and its standard error (rad/s).
    tau_r, tau_r_se : ndarray
        Mean friction torque effort - tau_ext - J qdd and its standard error (Nm).
    xi, xi_se, xi_spread : ndarray
        Mean housing temperature, its standard error and max - min over the plateau (degC).
    load, load_se : ndarray
        Mean load tau_L = |tau_ext| and its standard error (Nm).
    load2, load3 : ndarray
        Means of tau_L^2 and tau_L^3 over the plateau.
    tau_ext : ndarray
        Mean signed tau_ext (Nm).
    q : ndarray
        Mean position (rad).
    t0, t1 : ndarray
        Start and end of the window used (s, recording time).
    n : ndarray of int
        Samples used.
    source : ndarray of int
        Index into ``sources``.
    xi_rate : ndarray
        Rate of change of the measured temperature around the plateau (degC/s; a line
        through the readings over the plateau and half its length, or the time of five
        sensor steps at the recording's mean rate, either side): a lagging sensor reads
        low by lag x rate.
    sources : tuple of str
        The recordings the plateaus come from.
    torque_source : tuple of str
        Per source: ``'link_torque'`` or ``'lever_model'`` (where tau_ext came from).
    stick_slip : tuple of dict
        Constant-speed commands the joint did not follow steadily (it stuck and slipped):
        ``source`` (index into ``sources``), ``t0``, ``t1`` (s), ``speed`` (mean speed from
        the position, rad/s), ``stuck`` (fraction of the window the position did not
        move).  Left out of the plateaus
        (:func:`~friction_joint.identification.stick_slip.stick_slip_summary` says it in
        words).

    """

    qd: FloatArray
    qd_se: FloatArray
    tau_r: FloatArray
    tau_r_se: FloatArray
    xi: FloatArray
    xi_se: FloatArray
    xi_spread: FloatArray
    load: FloatArray
    load_se: FloatArray
    load2: FloatArray
    load3: FloatArray
    tau_ext: FloatArray
    q: FloatArray
    t0: FloatArray
    t1: FloatArray
    n: IntArray
    source: IntArray
    xi_rate: FloatArray
    sources: tuple[str, ...] = ()
    torque_source: tuple[str, ...] = ()
    stick_slip: tuple[dict[str, float], ...] = ()

    def __len__(self) -> int:
        return len(self.qd)

    @classmethod
    def empty(cls, *, sources: Iterable[str] = (),
              torque_source: Iterable[str] = ()) -> Plateaus:
        """
        Return no plateaus.

        Parameters
        ----------
        sources : iterable of str
            The recordings looked at.
        torque_source : iterable of str
            Per source, where tau_ext came from.

        Returns
        -------
        Plateaus

        """
        columns: dict[str, Any] = {f: np.zeros(0, dtype=int if f in ('n', 'source') else float)
                                   for f in _FIELDS}
        return cls(**columns, sources=tuple(sources),
                   torque_source=tuple(torque_source))

    @classmethod
    def from_arrays(cls, qd: ArrayLike, tau_r: ArrayLike, xi: ArrayLike, *, load: ArrayLike = 0.0,
                    **extra: ArrayLike | tuple[str, ...]) -> Plateaus:
        """
        Build plateaus from plain arrays (e.g. hand-made or from another tool).

        Parameters
        ----------
        qd, tau_r, xi : array_like
            Velocity (rad/s), friction torque (Nm), temperature (degC), broadcast to one
            length.
        load : array_like
            tau_L (Nm).
        **extra : array_like or tuple of str
            Other fields by name; default 0 (``load2``/``load3``: load^2, load^3).

        Returns
        -------
        Plateaus

        """
        qd = np.atleast_1d(np.asarray(qd, dtype=float))
        n = len(qd)

        def col(x: ArrayLike | None, default: ArrayLike = 0.0) -> FloatArray:
            return np.broadcast_to(np.asarray(default if x is None else x, dtype=float),
                                   (n,)).copy()
        load = col(load)
        data: dict[str, Any] = {
            f: col(extra.pop(f, None)) for f in _FIELDS
            if f not in ('qd', 'tau_r', 'xi', 'load', 'load2', 'load3', 'n', 'source')}
        data['load2'] = col(extra.pop('load2', None), load ** 2)
        data['load3'] = col(extra.pop('load3', None), load ** 3)
        sources = cast('tuple[str, ...]', extra.pop('sources', ('arrays',)))
        torque_source = cast('tuple[str, ...]',
                             extra.pop('torque_source', ('given',) * len(sources)))
        src = np.broadcast_to(np.asarray(extra.pop('source', 0), dtype=int), (n,)).copy()
        nn = np.broadcast_to(np.asarray(extra.pop('n', 1), dtype=int), (n,)).copy()
        if extra:
            raise TypeError(f'unknown plateau field(s): {", ".join(sorted(extra))}')
        return cls(qd=qd, tau_r=col(tau_r), xi=col(xi), load=load, n=nn, source=src,
                   sources=tuple(sources), torque_source=tuple(torque_source), **data)

    def select(self, mask: ArrayLike) -> Plateaus:
        """
        Return the plateaus where ``mask`` is set.

        Parameters
        ----------
        mask : array_like
            Bool array or indices.

        Returns
        -------
        Plateaus

        """
        return dataclasses.replace(self, **{f: getattr(self, f)[mask] for f in _FIELDS})

    @staticmethod
    def concatenate(parts: Iterable[Plateaus]) -> Plateaus:
        """
        Join plateau sets (``source`` indices are renumbered).

        Parameters
        ----------
        parts : iterable of Plateaus
            The sets.

        Returns
        -------
        Plateaus

        """
        parts = list(parts)
        if not parts:
            return Plateaus.empty()
        cols: dict[str, list[NDArray[Any]]] = {f: [] for f in _FIELDS}
        sources: list[str] = []
        stick: list[dict[str, float]] = []
        for p in parts:
            for f in _FIELDS:
                cols[f].append(getattr(p, f) + (len(sources) if f == 'source' else 0))
            stick += [dict(x, source=x['source'] + len(sources)) for x in p.stick_slip]
            sources += list(p.sources)
        columns: dict[str, Any] = {f: np.concatenate(v) for f, v in cols.items()}
        return Plateaus(**columns,
                        sources=tuple(sources),
                        torque_source=tuple(s for p in parts for s in p.torque_source),
                        stick_slip=tuple(stick))

    def to_dict(self) -> dict[str, list[Any]]:
        """Return plain lists (JSON)."""
        out: dict[str, list[Any]] = {f: getattr(self, f).tolist() for f in _FIELDS}
        out['sources'] = list(self.sources)
        out['torque_source'] = list(self.torque_source)
        out['stick_slip'] = [dict(x) for x in self.stick_slip]
        return out


def _moving_average(x: FloatArray, m: int) -> FloatArray:
    """Centred moving average over m samples (shorter at the ends)."""
    if m <= 1:
        return x.copy()
    c: FloatArray = np.concatenate(([0.0], np.cumsum(x)))
    n = len(x)
    i = np.arange(n)
    lo = np.clip(i - m // 2, 0, n)
    hi = np.clip(i - m // 2 + m, 0, n)
    return (c[hi] - c[lo]) / (hi - lo)


def _robust_mean(x: FloatArray, clip: float) -> float:
    """Mean of the samples within ``clip`` MADs of the median."""
    med = np.median(x)
    mad = np.median(np.abs(x - med))
    if mad > 0:
        x = x[np.abs(x - med) <= clip * 1.4826 * mad]
    return float(np.mean(x))


def _batch_se(x: FloatArray, batches: float) -> float:
    """Return the standard error of the mean of x by batch means."""
    k = int(min(batches, len(x) // 10))
    if k < 2:
        return float(np.std(x) / math.sqrt(max(len(x), 1)))
    means = np.array([b.mean() for b in np.array_split(x, k)])
    return float(np.std(means, ddof=1) / math.sqrt(k))


def _rate(t: FloatArray, x: FloatArray, i0: int, i1: int, half: int
          ) -> float:
    """Slope of x over [i0, i1) and ``half`` samples either side (0 where x is flat)."""
    h = max((i1 - i0) // 2, half)
    a, b = max(0, i0 - h), min(len(t), i1 + h)
    tt, xx = t[a:b], x[a:b]
    if b - a < 3 or np.ptp(xx) == 0.0:
        return 0.0
    tc = tt - tt.mean()
    return float(np.dot(tc, xx - xx.mean()) / np.dot(tc, tc))


def _segments(t: FloatArray, qd: FloatArray, tau_r: FloatArray,
              opt: Detection) -> list[tuple[int, int]]:
    """Index ranges [i0, i1) of plateaus in one contiguous piece."""
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 1.0
    m = max(2, int(round(opt.block / dt)))
    nb = len(t) // m
    if nb < 2:
        return []
    vb = qd[:nb * m].reshape(nb, m)
    mean = vb.mean(axis=1)
    half = m // 2
    slope = (vb[:, half:].mean(axis=1) - vb[:, :half].mean(axis=1)) / (0.5 * m * dt)
    speed = np.abs(mean)
    # the tolerances grow with the recording's own noise of a block mean and of a block
    # slope (robust spreads over the piece: a coarse encoder or a slow logger makes the
    # velocity of a block noisier than any fixed tolerance)
    # (second differences: a ramp's steady change of the velocity is not noise)
    noise_b = 1.4826 * float(np.median(np.abs(np.diff(mean, 2)))) / math.sqrt(6.0) \
        if nb > 3 else 0.0
    noise_s = 1.4826 * float(np.median(np.abs(np.diff(slope)))) / math.sqrt(2.0) \
        if nb > 2 else 0.0
    abs_tol = opt.abs_tol + NOISE_SIGMAS * noise_b
    steady = ((speed >= opt.v_floor)
              & (np.abs(slope) <= opt.rel_slope * speed + opt.abs_slope
                 + NOISE_SIGMAS * noise_s))
    sign = np.sign(mean)
    out = []
    j = 0
    while j < nb:
        if not steady[j]:
            j += 1
            continue
        k = j
        vals = [mean[j]]
        while k + 1 < nb and steady[k + 1] and sign[k + 1] == sign[j]:
            ref = float(np.median(vals))
            if abs(mean[k + 1] - ref) > opt.rel_tol * abs(ref) + abs_tol:
                break
            k += 1
            vals.append(mean[k])
        out.append((j, k + 1))
        j = k + 1
    segs = []
    # blocks to trim: a sample time a few ulps off (stamps read as float seconds) must not
    # tip the count over an integer
    trim = int(math.ceil(opt.trim / (m * dt) - 1e-6))
    for b0, b1 in out:
        b0, b1 = b0 + trim, b1 - trim
        if b1 - b0 < 2:
            continue
        # friction settling: drop leading blocks off the settled level
        tb = tau_r[b0 * m:b1 * m].reshape(b1 - b0, m).mean(axis=1)
        second = tb[(b1 - b0) // 2:]
        level = float(np.median(second))
        noise = float(1.4826 * np.median(np.abs(second - level))) if len(second) > 2 else 0.0
        tol = opt.settle_tol * abs(level) + 3.0 * noise
        off = np.abs(tb - level) > tol
        first_ok = int(np.argmin(off)) if not off.all() else len(tb)
        b0 += first_ok
        i0, i1 = b0 * m, b1 * m
        if i1 - i0 >= opt.min_samples and (i1 - i0) * dt >= opt.min_duration:
            segs.append((i0, i1))
    return segs


def plateaus_from_arrays(t: ArrayLike, q: ArrayLike, qd: ArrayLike, effort: ArrayLike,
                         xi: ArrayLike, tau_ext: ArrayLike, *, inertia: float,
                         options: Detection | None = None, source: str = 'arrays',
                         torque_source: str = 'given', check: bool = True,
                         qd_command: ArrayLike | None = None) -> Plateaus:
    """
    Find plateaus in sampled arrays (the engine of :func:`find_plateaus`).

    Parameters
    ----------
    t, q, qd, effort : array_like
        Joint-state samples: time (s), position (rad), velocity (rad/s), drive torque (Nm).
    xi : array_like
        Housing temperature at the sample times (degC).
    tau_ext : array_like
        External torque at the sample times (Nm), signed as in docs/interfaces.md: sign convention.
    inertia : float
        J (kg m^2) for the J qdd term.
    options : Detection, optional
        The thresholds (default :data:`DETECTION`).
    source : str
        Name of the data in error messages and in the plateaus' ``sources``.
    torque_source : str
        Where tau_ext came from (e.g. ``'link_torque'`` or ``'lever_model'``), kept as
        the plateaus' ``torque_source``.
    check : bool
        Reject absurd samples (:func:`friction_joint.bag.check_samples`: a value millions
        of robust spreads off, a velocity the position does not show) before fitting.
    qd_command : array_like, optional
        Commanded velocity at the sample times (``/joint_command`` ``qd_d``): where it
        is constant and the joint did not follow it steadily (stuck and slipped), the
        window is reported in ``stick_slip``.

    Returns
    -------
    Plateaus

    Raises
    ------
    ExcitationError
        Arrays of different lengths, NaN/inf.
    RecordingError
        An absurd sample (named with ``source``, the field and its time).

    """
    opt = DETECTION if options is None else options
    t, q, qd, effort, xi, tau_ext = (np.asarray(a, dtype=float) for a in
                                     (t, q, qd, effort, xi, tau_ext))
    n = len(t)
    for name, a in (('q', q), ('qd', qd), ('effort', effort), ('xi', xi), ('tau_ext', tau_ext)):
        if len(a) != n:
            raise ExcitationError(f'{name} has {len(a)} samples, t has {n}')
        if not np.all(np.isfinite(a)):
            raise ExcitationError(f'{source}: {name} contains NaN or inf')
    if check:
        check_samples(source, t, {'q': q, 'qd': qd, 'effort': effort, 'xi': xi,
                                  'tau_ext': tau_ext}, position=('q', 'qd'))
    if n < 3:
        return Plateaus.empty(sources=(source,), torque_source=(torque_source,))
    # time relative to the first sample before any differencing: epoch seconds in float64
    # are quantised to about 0.24 us, a visible fraction of a 1 kHz sample time
    t_first = float(t[0])
    t = t - t_first
    has_command = qd_command is not None
    command = (np.broadcast_to(np.asarray(qd_command, dtype=float), (n,)) if has_command
               else np.zeros(n))
    cut = split_pieces(t, qd, gap=opt.gap_factor)
    rows: list[tuple[float, ...]] = []
    stick: list[dict[str, float]] = []
    for a, b in cut.ranges:
        if b - a < 10:
            continue
        steps = cut.bridged[(cut.bridged >= a) & (cut.bridged < b - 1)] - a
        tt, (qq, vv, ee, xx, te, cc), ok = piece_on_grid(
            t[a:b], [x[a:b] for x in (q, qd, effort, xi, tau_ext, command)], steps,
            margin=opt.gap_factor * cut.dt)
        qdd = np.gradient(_moving_average(vv, 5), tt)
        tau_r = ee - te - inertia * qdd
        dt = float(np.median(np.diff(tt)))
        tl = np.abs(_moving_average(te, max(1, int(round(opt.load_smooth / dt)))))
        tick = position_resolution(qq)
        # the temperature's rate around a plateau: over at least ten of the sensor's steps
        # at the piece's mean rate (a quantised sensor's rate over a few seconds is noise)
        steps = np.abs(np.diff(xx))
        q_step = float(steps[steps > 0].min()) if np.any(steps > 0) else 0.0
        mean_rate = abs(float(xx[-1] - xx[0])) / max(float(tt[-1] - tt[0]), 1e-12)
        rate_half = (int(5.0 * q_step / mean_rate / dt) if mean_rate > 0 and q_step > 0
                     else 0)
        segs = _segments(tt, vv, tau_r, opt)
        scan = stick_slip_scan(tt, qq, cc if has_command else None, tick, segs,
                               dataclasses.asdict(opt))
        for w0, w1, window in scan:
            stick.append(dict(window, source=0, t0=float(tt[w0]) + t_first,
                              t1=float(tt[w1 - 1]) + t_first))
        for i0, i1 in segs:
            sl = np.arange(i0, i1)[ok[i0:i1]]
            if len(sl) < opt.min_samples:
                continue
            slip = stuck_and_slipped(tt[i0:i1], qq[i0:i1], tick)
            if slip is not None:
                stick.append(dict(slip, source=0, t0=float(tt[i0]) + t_first,
                                  t1=float(tt[i1 - 1]) + t_first))
                continue
            x = xx[sl]
            lo = tl[sl]
            v_mean = _robust_mean(vv[sl], opt.clip_mad)
            v_pos = (qq[i1 - 1] - qq[i0]) / (tt[i1 - 1] - tt[i0])
            if abs(v_mean - v_pos) > 0.05 * abs(v_pos) + 2.0 * tick / (tt[i1 - 1] - tt[i0]):
                # a velocity column too coarse for this speed (single encoder ticks as
                # spikes): the position's travel gives the mean speed
                v_mean = float(v_pos)
            rows.append((
                v_mean, _batch_se(vv[sl], opt.batches),
                _robust_mean(tau_r[sl], opt.clip_mad), _batch_se(tau_r[sl], opt.batches),
                float(x.mean()), _batch_se(x, opt.batches), float(x.max() - x.min()),
                float(lo.mean()), _batch_se(lo, opt.batches),
                float(np.mean(lo ** 2)), float(np.mean(lo ** 3)),
                float(te[sl].mean()), float(qq[sl].mean()),
                float(tt[i0]) + t_first, float(tt[i1 - 1]) + t_first, len(sl), 0,
                _rate(tt, xx, i0, i1, rate_half)))
    if not rows:
        return dataclasses.replace(Plateaus.empty(sources=(source,),
                                                  torque_source=(torque_source,)),
                                   stick_slip=tuple(stick))
    cols = list(zip(*rows, strict=True))
    data: dict[str, Any] = {f: np.array(c, dtype=int if f in ('n', 'source') else float)
                            for f, c in zip(_FIELDS, cols, strict=True)}
    return Plateaus(**data, sources=(source,), torque_source=(torque_source,),
                    stick_slip=tuple(stick))


def find_plateaus(recording: Recording, structure: GearParams, *,
                  options: Detection | None = None) -> Plateaus:
    """
    Find the constant-velocity plateaus of one recording.

    Parameters
    ----------
    recording : Recording
        From :func:`friction_joint.bag.read_recording`.
    structure : GearParams
        The structure gear file: its inertia (J qdd) and, when the recording has
        no ``/link_torque``, its lever (tau_ext = m g l sin(q - angle_offset)).
    options : Detection, optional
        The thresholds (default :data:`DETECTION`).

    Returns
    -------
    Plateaus
        Possibly empty; :class:`~friction_joint.identification.static_fit.StaticIdentifier`
        says what is missing.

    Raises
    ------
    RecordingError
        The recording has no temperature samples, or an absurd sample
        (:func:`friction_joint.bag.check_values`, naming the file, topic, field and time).

    """
    check_values(recording)
    js = recording.joint_states
    if recording.temperature is None or len(recording.temperature) == 0:
        raise RecordingError(f'{recording.path}: no /joint_temperature samples: the '
                             'identification needs the gear housing temperature')
    xi = recording.temperature_at(t=js.t)
    if recording.link_torque is not None and len(recording.link_torque) > 1:
        lt = recording.link_torque
        tau_ext = np.interp(js.t, lt.t, lt.tau)
        tsrc = 'link_torque'
    else:
        tau_ext = structure.lever_torque(js.q)
        tsrc = 'lever_model'
    command = None
    jc = recording.joint_command
    if jc is not None and len(jc.t) > 1 and len(jc.qd_d) == len(jc.t) and \
            np.all(np.isfinite(jc.qd_d)):
        command = np.interp(js.t, jc.t, jc.qd_d)
    return plateaus_from_arrays(js.t, js.q, js.qd, js.effort, xi, tau_ext,
                                inertia=structure.inertia, options=options,
                                source=recording.path, torque_source=tsrc, check=False,
                                qd_command=command)
