# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Diagnosis input: recordings -> friction-torque data averaged over short time bins.

For every recording the joint states are split into contiguous pieces at
long gaps in the stamps (:func:`friction_joint.bag.stamps.split_pieces`: a
step longer than ``GAP`` (5) median sample times that is longer than
``BRIDGE_SAMPLES`` (50) median sample times or than ``BRIDGE_FRACTION`` (1/4)
of the motion's time scale P90(|qd|)/P90(|qdd|), e.g. a pause between runs,
which no derivative bridges); shorter gaps (a realtime simulator or logger
that skipped samples) are **bridged**: the piece goes on across them.  The
encoder position is differentiated without phase lag
(:func:`friction_joint._filters.zero_phase_derivatives`), and

    y = tau - tau_ext - J q̈          (the measured friction torque tau_r, eq. 2)

is formed with ``tau_ext`` from ``/link_torque`` (or the base gear's lever
``m g l sin q`` when the recording has none) and J the base inertia.

Measured data are often sampled irregularly (stamps that jitter, a dropped
sample now and then, bridged gaps).  A piece whose stamps lie further than
``REGULAR`` (1 %) of a sample time from a uniform grid is resampled onto the
uniform grid of its median sample time (linear interpolation of position,
torques) before the derivatives are taken; regular pieces are used as they
are.  The samples of a bridged gap, and :data:`BRIDGE_MARGIN` time constants
of the derivative filter (1 / cutoff) on either side, where the interpolated
position makes the acceleration unreliable, are marked (``bridged``) and no
bin that holds one is used.  ``gaps`` counts the bridged gaps (and the
longest) and those that split a recording.

Bins
----
Models are compared on averages over :data:`BIN` (10 ms) bins of the 1 kHz
samples.  Averaging is linear, so a model linear in its coefficients fits
the averaged data with the averaged regressors *exactly* as it fits the raw
samples, at a tenth of the cost and with a tenth of the noise per point.
A bin is used only when the joint slides throughout it: every sample has
``|qd| >= v_stick``, with a margin of :data:`STICK_MARGIN` around
stick phases, and :data:`EDGE` (0.1 s) away from the ends of a piece (where
the zero-phase filter's edge effects spoil the acceleration).  While a joint
sticks its friction torque is whatever balances the applied torque (Karnopp),
which no friction *curve* predicts; leaving those samples out keeps every
candidate model on the same footing.

Scales taken from the data
--------------------------
No threshold is in rad/s, Nm or Nm/rad: every one derives from the data
(so a device 100 times slower or weaker is treated alike):

* ``resolution`` (rad): the position resolution, the larger of the smallest
  nonzero encoder step and the (robust) width of the encoder noise
  ``sqrt(12) * 1.4826 * median|q - q_filtered|`` (filtered at the highest cutoff);
* ``cutoff`` (Hz): the derivative filter's cutoff, at most
  :data:`MAX_CUTOFF` (100 Hz) and :data:`MAX_CUTOFF_RATE` of the sample
  rate, lowered in steps of sqrt(2) (at most :data:`CUTOFF_STEPS`) until
  the quantisation noise of the bin-averaged acceleration (a position error
  uniform over one ``resolution``, white) is at most :data:`ACC_NOISE` of the
  motion's (RMS of the bin-averaged acceleration, noise taken out): a coarse
  encoder's steps would otherwise put a noise ``J q̈`` in ``y`` correlated
  with the acceleration regressor (a spurious ``inertia``); a fine encoder
  keeps the highest cutoff;
* ``quantisation_noise`` (rad/s): the velocity noise a position error
  uniform over one ``resolution`` gives through the zero-phase derivative,
  ``resolution / sqrt(12)`` times the noise gain of the derivative filter
  (the root sum of squares of its impulse response, about
  ``1.37 cutoff`` at a cutoff of a tenth of the sample rate), i.e.
  ``0.40 resolution * cutoff``: the noise of a moving joint whose encoder
  steps are uncorrelated from sample to sample;
* ``standstill_noise`` (rad/s): the velocity noise measured where the joint
  stands still, the robust standard deviation ``1.4826 MAD`` of ``qd`` over
  the samples whose filtered position moves less than one ``resolution``
  within :data:`STILL_WINDOW` derivative-filter time constants (1 / cutoff)
  around them (0 when fewer than :data:`MIN_STILL` samples stand still: a
  recording that never stands still has the quantisation model alone);
* ``velocity_noise`` (rad/s): the larger of the two, the noise as it is
  (no margin: a pure quantiser standing still shows none, a moving one
  the quantisation noise; dither or vibration shows at standstill);
* ``v_stick`` (rad/s): the sliding threshold, the larger of
  :data:`V_NOISE` (3) times ``velocity_noise`` and :data:`V_STICK_FRACTION`
  of the 99th percentile of ``|qd|`` (the floor the data prove).  A
  threshold at the measured noise, not at a multiple of the quantisation
  step, keeps the transitions after velocity reversals of a coarse encoder
  in the data, where pre-sliding acts: a reversal costs the samples below
  ``v_stick`` and :data:`STICK_MARGIN` around them, a few ms at the
  accelerations of a servo;
* ``friction_level`` (Nm): the median of ``|y|`` over the sliding bins;
* ``stroke`` (rad): the largest position range of a piece.

A recording without ``/joint_temperature`` has no temperature signal
(``has_temperature`` False): its ``xi`` is the middle of the base gear's
``friction.temperature_range`` and ``thermal`` cannot be tested.

Cross-validation blocks
-----------------------
The used bins are split into :data:`N_BLOCKS` contiguous time blocks of
equal size (over all recordings, in the order given).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import dataclasses
import math
import os
from typing import Any, cast, TYPE_CHECKING, TypedDict

import numpy as np

from .criterion import reblock
from .._filters import zero_phase_derivatives
from ..bag import read_recording
from ..bag.stamps import BRIDGE_MARGIN, gap_summary, piece_on_grid, split_pieces, uniform_grid
from ..exceptions import ExcitationError, PreslidingDataError, RecordingError

if TYPE_CHECKING:
    from numpy.typing import NDArray

    from ..bag import Recording
    from ..bag.stamps import Pieces
    from ..gear import GearParams

    class _Piece(TypedDict):
        """A contiguous piece of one recording, as recorded."""

        rec: Recording
        dt: float
        steps: NDArray[np.int64]
        t: NDArray[np.float64]
        q: NDArray[np.float64]
        effort: NDArray[np.float64]

    #: a piece on its uniform grid: t, q, effort and the bridged mask
    _OnGrid = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                    NDArray[np.bool_]]

__all__ = ['BIN', 'V_STICK_FRACTION', 'V_NOISE', 'STICK_MARGIN', 'STILL_WINDOW', 'MIN_STILL',
           'N_BLOCKS', 'MAX_STEP', 'DiagnosisData', 'load_data', 'derivative_noise_gain']

#: bin length (s) over which samples are averaged
BIN = 0.01
#: |qd| below this fraction of its 99th percentile counts as sticking (2 mrad/s on the CSD-25)
V_STICK_FRACTION = 7e-4
#: ... or below this many standard deviations of the measured velocity noise
V_NOISE = 3.0
#: highest cutoff (Hz) of the zero-phase derivative, and as a fraction of the sample rate
MAX_CUTOFF = 100.0
MAX_CUTOFF_RATE = 0.2
#: quantisation noise allowed in the bin-averaged acceleration, relative to the motion's
ACC_NOISE = 0.2
#: the cutoff is lowered in steps of sqrt(2), at most this many (a factor 8 at 6)
CUTOFF_STEPS = 6
#: margin (s) around sticking samples also left out
STICK_MARGIN = 0.005
#: window (derivative-filter time constants 1 / cutoff) over which a still joint moves < resolution
STILL_WINDOW = 10.0
#: fewest standing-still samples from which the standstill velocity noise is measured
MIN_STILL = 200
#: number of contiguous cross-validation blocks
N_BLOCKS = 10
#: shortest contiguous piece of a recording used (s)
MIN_PIECE = 1.0
#: samples this close (s) to the start or end of a piece are not used (filter edge effects)
EDGE = 0.1
#: longest sample time (s) diagnosed: 10 samples in an open-loop window
#: (:data:`~friction_joint.diagnosis.velocity.WINDOW`, 0.5 s) and a derivative cut-off of at
#: least 4 Hz (:data:`MAX_CUTOFF_RATE` of the rate); a 33 Hz tribometer is diagnosed, a log
#: in ms read as s (a sample time of 1 s) is refused
MAX_STEP = 0.05


@dataclasses.dataclass
class DiagnosisData:
    """
    Full-rate samples and bin averages of one or more recordings.

    Attributes
    ----------
    t, q, qf, qd, qdd, effort, tau_ext, xi, tl : ndarray
        Full-rate arrays (all pieces concatenated): time, position (encoder), zero-phase
        filtered position, velocity, acceleration, drive torque, external torque,
        temperature, load (= |tau_ext|).
    piece, dt, bin_of, block_of : ndarray
        Per sample: piece index, step, bin index (-1 if unused), CV block (by time).
    y, count, t_bin, block : ndarray
        Bin arrays (used bins only): mean friction torque with the base inertia, samples,
        mean time, CV block.
    n_blocks : int
        Number of CV blocks.
    inertia, mgl_sim : float
        The base gear's inertia and the lever's m g l the torque was corrected with.
    link_torque : bool
        tau_ext is measured (``/link_torque``), not the lever model.
    recordings : list of Recording
        The recordings read.
    has_temperature : bool
        Every recording has ``/joint_temperature``.
    v_stick, resolution, friction_level, stroke : float
        Scales (module docstring): rad/s, rad, Nm, rad.
    bridged : ndarray of bool or None
        Sample in or next to a bridged gap of the stamps (interpolated, never in a bin).
    gaps : dict or None
        The gaps of the stamps (:func:`friction_joint.bag.stamps.gap_summary`: bridged,
        longest bridged, split).
    velocity_noise, quantisation_noise, standstill_noise : float
        Velocity noise (rad/s, standard deviations): the larger of the encoder step
        through the derivative filter and the noise where the joint stands still (0
        when it never does).
    standstill_fraction : float
        Fraction of the samples at standstill.
    cutoff : float
        The derivative filter's cut-off (Hz, the highest over the pieces).

    """

    t: NDArray[np.float64]
    q: NDArray[np.float64]
    qf: NDArray[np.float64]
    qd: NDArray[np.float64]
    qdd: NDArray[np.float64]
    effort: NDArray[np.float64]
    tau_ext: NDArray[np.float64]
    xi: NDArray[np.float64]
    tl: NDArray[np.float64]
    piece: NDArray[np.int64]
    dt: NDArray[np.float64]
    bin_of: NDArray[np.int64]
    block_of: NDArray[np.int64]
    y: NDArray[np.float64]
    count: NDArray[np.float64]
    t_bin: NDArray[np.float64]
    block: NDArray[np.int64]
    n_blocks: int
    inertia: float
    mgl_sim: float
    link_torque: bool
    recordings: list[Recording]
    has_temperature: bool = True
    v_stick: float = 2e-3
    resolution: float = 0.0
    friction_level: float = 1.0
    stroke: float = 0.0
    bridged: NDArray[np.bool_] | None = None
    gaps: dict[str, Any] | None = None
    velocity_noise: float = 0.0
    quantisation_noise: float = 0.0
    standstill_noise: float = 0.0
    standstill_fraction: float = 0.0
    cutoff: float = 0.0

    @property
    def n_bins(self) -> int:
        return len(self.y)

    def average(self, f: NDArray[np.float64]) -> NDArray[np.float64]:
        """
        Return the bin averages (used bins) of a full-rate array.

        Parameters
        ----------
        f : ndarray
            A full-rate array.

        Returns
        -------
        ndarray

        """
        sel = self.bin_of >= 0
        out: NDArray[np.float64] = np.bincount(self.bin_of[sel], weights=f[sel],
                                               minlength=self.n_bins) / self.count
        return out


def _pieces(t: NDArray[np.float64], qd: NDArray[np.float64],
            path: str) -> tuple[list[tuple[int, int]], Pieces]:
    """Pieces of at least MIN_PIECE s (cut at long gaps, short ones bridged) and the cut."""
    if len(t) > 1 and not np.median(np.diff(t)) > 0:
        raise RecordingError(f'{path}: /joint_states: stamps do not increase')
    cut = split_pieces(t, qd)
    return [(a, b) for a, b in cut.ranges
            if b - a >= 2 and t[b - 1] - t[a] >= MIN_PIECE], cut


def load_data(paths: Sequence[str | os.PathLike[str]], gear: GearParams, *,
              joint_name: str | None = None, n_blocks: int = N_BLOCKS,
              progress: Callable[[str], None] | None = None,
              velocity_from_position: bool = False) -> DiagnosisData:
    """
    Read recordings into :class:`DiagnosisData`.

    Parameters
    ----------
    paths : sequence of str
        rosbag2 directories or ``.mcap`` files.
    gear : GearParams
        The base gear (inertia, lever when there is no ``/link_torque``).
    joint_name : str, optional
        Joint to read (default: the gear's joint name; a recording without it is an
        error naming the joints it has).
    n_blocks : int, optional
        Number of contiguous cross-validation blocks (default :data:`N_BLOCKS`).
    progress : callable, optional
        Progress callback (currently not called).
    velocity_from_position : bool
        Replace the recorded velocity by the position's centred difference
        (:func:`~friction_joint.bag.read_recording`).

    Returns
    -------
    DiagnosisData

    Raises
    ------
    RecordingError
        Unreadable or corrupt recording, missing topic or joint, NaN, time stamps that go
        backwards, absurd values (from :func:`read_recording`, naming the file).
    ExcitationError
        Too little sliding motion to fit and cross-validate a model.

    """
    if not paths:
        raise RecordingError('no recordings given')
    joint = gear.joint_name if joint_name is None else joint_name
    recs = [read_recording(path, joint_name=joint, velocity_from_position=velocity_from_position)
            for path in paths]
    cols: dict[str, list[NDArray[Any]]]
    cols = {k: [] for k in ('t', 'q', 'qf', 'qd', 'qdd', 'effort', 'tau_ext', 'xi', 'dt',
                            'piece', 'cutoff', 'bridged')}
    have_link = all(r.link_torque is not None and len(r.link_torque) > 1 for r in recs)
    have_temp = all(_temperature(r) is not None for r in recs)
    xi_none = float(np.mean(gear.friction.temperature_range))
    cuts: list[Pieces] = []
    raw: list[_Piece] = []
    for rec in recs:
        js = rec.joint_states
        pieces, cut = _pieces(js.t, js.qd, rec.path)
        cuts.append(cut)
        if not pieces:
            raise ExcitationError(
                f'{rec.path}: no contiguous stretch of /joint_states of at least {MIN_PIECE:g} s '
                f'(recording {rec.duration:.2f} s long; {cut.split} gaps too long to bridge, '
                f'longer than {cut.limit:.3g} s, {len(cut.bridged)} bridged)')
        for a, b in pieces:
            dt, _ = uniform_grid(js.t[a:b])
            _check_step(rec.path, js.t[a] - js.t[0], dt)
            steps = cut.bridged[(cut.bridged >= a) & (cut.bridged < b - 1)] - a
            raw.append({'rec': rec, 'dt': dt, 'steps': steps,
                        't': js.t[a:b], 'q': js.q[a:b], 'effort': js.effort[a:b]})
    # position resolution at the highest cutoff, then the cutoff the encoder allows
    top = [_on_grid(r, _max_cutoff(r['dt'])) + (r['dt'],) for r in raw]
    res, stroke = _resolution(top)
    scale = _cutoff_scale(top, res)
    for n_piece, r in enumerate(raw):
        rec, dt = r['rec'], r['dt']
        cutoff = scale * _max_cutoff(dt)
        t, q, effort, bridged = _on_grid(r, cutoff)
        try:
            qd, qdd = zero_phase_derivatives(q, dt, cutoff=cutoff)
        except PreslidingDataError as exc:
            raise ExcitationError(f'{rec.path}: {exc}') from None
        qf = _lowpass(q, dt, cutoff)
        link = rec.link_torque
        if have_link and link is not None:      # have_link: every recording has one
            te = np.interp(t, link.t, link.tau)
        else:
            te = gear.lever_torque(q)
        xi = (rec.temperature_at(t=t) if _temperature(rec) is not None
              else np.full(len(t), xi_none))
        for k, v in (('t', t), ('q', q), ('qf', qf), ('qd', qd), ('qdd', qdd),
                     ('effort', effort), ('tau_ext', te), ('xi', xi),
                     ('dt', np.full(len(t), dt)), ('piece', np.full(len(t), n_piece)),
                     ('cutoff', np.full(len(t), cutoff)), ('bridged', bridged)):
            cols[k].append(v)
    n_piece = len(raw)
    c = {k: np.concatenate(v) for k, v in cols.items()}
    n = len(c['t'])
    sc = _scales(c, n_piece, res)
    sc.update(resolution=res, stroke=stroke, cutoff=float(np.max(c['cutoff'])))
    v_stick = sc['v_stick']
    # bins: per piece, consecutive samples, BIN long
    bin_raw = np.full(n, -1, dtype=np.int64)
    nb_total = 0
    stick = np.abs(c['qd']) < v_stick
    for p in range(n_piece):
        idx = np.flatnonzero(c['piece'] == p)
        dt = c['dt'][idx[0]]
        m = max(1, int(round(BIN / dt)))
        nb = len(idx) // m
        if nb == 0:
            continue
        st = stick[idx] | c['bridged'][idx]
        edge = int(round(EDGE / dt))
        st[:edge] = True
        st[len(st) - edge:] = True
        margin = int(round(STICK_MARGIN / dt))
        if margin > 0 and st.any():
            st = np.convolve(st.astype(float), np.ones(2 * margin + 1), mode='same') > 0
        ok = ~st[:nb * m].reshape(nb, m).any(axis=1)
        ids = np.full(nb, -1, dtype=np.int64)
        ids[ok] = nb_total + np.arange(int(ok.sum()))
        nb_total += int(ok.sum())
        bin_raw[idx[:nb * m]] = np.repeat(ids, m)
    if nb_total < 20 * n_blocks:
        raise ExcitationError(
            f'too little sliding motion to diagnose: {nb_total * BIN:.1f} s of the recordings '
            f'have the joint sliding (|qd| >= {v_stick:.3g} rad/s, the larger of '
            f'{V_STICK_FRACTION:g} x the 99th percentile of |qd| and {V_NOISE:g} x the velocity '
            f'noise {sc["velocity_noise"]:.3g} rad/s), at least {20 * n_blocks * BIN:.0f} s '
            f'are needed ({n_blocks} '
            'cross-validation blocks)')
    sel = bin_raw >= 0
    count: NDArray[np.float64] = np.bincount(bin_raw[sel], minlength=nb_total).astype(float)

    def avg(f: NDArray[np.float64]) -> NDArray[np.float64]:
        sums = np.bincount(bin_raw[sel], weights=f[sel], minlength=nb_total)
        return cast('NDArray[np.float64]', sums) / count

    inertia = gear.inertia
    y = avg(c['effort'] - c['tau_ext'] - inertia * c['qdd'])
    t_bin = avg(c['t'])
    data = DiagnosisData(
        t=c['t'], q=c['q'], qf=c['qf'], qd=c['qd'], qdd=c['qdd'], effort=c['effort'],
        tau_ext=c['tau_ext'], xi=c['xi'], tl=np.abs(c['tau_ext']), piece=c['piece'],
        dt=c['dt'], bin_of=bin_raw, block_of=np.zeros(0, np.int64), y=y, count=count, t_bin=t_bin,
        block=np.zeros(0, np.int64), n_blocks=n_blocks, inertia=inertia,
        mgl_sim=0.0 if have_link else gear.mgl, link_torque=have_link, recordings=recs,
        has_temperature=have_temp, v_stick=v_stick, resolution=sc['resolution'],
        friction_level=max(float(np.median(np.abs(y))), 1e-12), stroke=sc['stroke'],
        bridged=c['bridged'], gaps=gap_summary(cuts), velocity_noise=sc['velocity_noise'],
        quantisation_noise=sc['quantisation_noise'], standstill_noise=sc['standstill_noise'],
        standstill_fraction=sc['standstill_fraction'], cutoff=sc['cutoff'])
    reblock(data, n_blocks)
    return data


def _check_step(path: str, start: float, dt: float) -> None:
    """Raise unless the sample time ``dt`` (s) of a piece is one the method resolves."""
    if not dt <= MAX_STEP:
        raise RecordingError(
            f'{path}: /joint_states: a sample time of {dt:.6g} s (the piece from t = '
            f'{start:.6g} s); diagnose needs at most {MAX_STEP:g} s (10 samples in its '
            f'0.5 s open-loop windows): stamps in other units than s? (import: --time '
            'COL:ms)')


def _temperature(rec: Recording) -> Any:
    """Return the recording's ``/joint_temperature`` series, None when it has none."""
    temp = getattr(rec, 'temperature', None)
    if temp is None or len(getattr(temp, 't', ())) == 0:
        return None
    return temp


def derivative_noise_gain(dt: float, cutoff: float) -> float:
    """
    Return the white-noise gain (1/s) of the zero-phase derivative filter.

    The root sum of squares of the impulse response of
    :func:`friction_joint._filters.zero_phase_derivatives` (velocity): a position
    noise of standard deviation s, white from sample to sample, gives a velocity noise
    of standard deviation ``s * gain`` (about ``1.37 cutoff`` at a cutoff of a tenth
    of the sample rate).
    """
    return _noise_gains(dt, cutoff)[0]


def _max_cutoff(dt: float) -> float:
    """Return the highest cutoff (Hz) of the zero-phase derivative at sample time ``dt``."""
    return min(MAX_CUTOFF, MAX_CUTOFF_RATE / dt)


def _on_grid(r: _Piece, cutoff: float) -> _OnGrid:
    """Piece ``r`` on its uniform grid: t, q, effort and the bridged mask for ``cutoff``."""
    t, (q, effort), ok = piece_on_grid(r['t'], (r['q'], r['effort']), r['steps'],
                                       margin=BRIDGE_MARGIN / cutoff)
    return t, q, effort, ~ok


def _lowpass(q: NDArray[np.float64], dt: float, cutoff: float) -> NDArray[np.float64]:
    """Zero-phase Butterworth low-pass of the position (the derivative filter's)."""
    from scipy import signal

    bb, aa = signal.butter(2, cutoff, fs=1.0 / dt)
    out: NDArray[np.float64] = signal.filtfilt(bb, aa, q)
    return out


def _resolution(pieces: Sequence[tuple[NDArray[np.float64], NDArray[np.float64],
                                       NDArray[np.float64], NDArray[np.bool_], float]]
                ) -> tuple[float, float]:
    """Position resolution and stroke of pieces ``(t, q, effort, bridged, dt)`` (docstring)."""
    steps, widths, stroke = [], [], 0.0
    for _, q, _, bridged, dt in pieces:
        dq = np.abs(np.diff(q))
        real = ~bridged
        pos = dq[(dq > 0) & real[1:] & real[:-1]]       # encoder steps, not interpolated ones
        if len(pos):
            steps.append(float(pos.min()))
        if len(q) > 12:
            widths.append(float(np.median(np.abs(q - _lowpass(q, dt, _max_cutoff(dt))))))
        stroke = max(stroke, float(np.ptp(q)))
    res = max(min(steps) if steps else 0.0,
              math.sqrt(12.0) * 1.4826 * max(widths) if widths else 0.0)
    return max(res, 1e-12 * max(stroke, 1.0)), stroke


def _noise_gains(dt: float, cutoff: float) -> tuple[float, float]:
    """White-noise gains of the zero-phase velocity and of its bin-averaged acceleration."""
    half = int(math.ceil(40.0 / (cutoff * dt))) + 10
    x = np.zeros(2 * half + 1)
    x[half] = 1.0
    qd, qdd = zero_phase_derivatives(x, dt, cutoff=cutoff)
    m = max(1, int(round(BIN / dt)))
    acc = np.convolve(qdd, np.full(m, 1.0 / m))
    return float(np.sqrt(np.sum(qd ** 2))), float(np.sqrt(np.sum(acc ** 2)))


def _cutoff_scale(pieces: Sequence[tuple[NDArray[np.float64], NDArray[np.float64],
                                         NDArray[np.float64], NDArray[np.bool_], float]],
                  res: float) -> float:
    """
    Factor (<= 1) on the highest derivative cutoff that the encoder's resolution allows.

    The largest of ``2 ** (-k / 2)``, k = 0 .. :data:`CUTOFF_STEPS`, at which the
    quantisation noise of the bin-averaged acceleration is at most
    :data:`ACC_NOISE` of the acceleration the motion has (the RMS of the
    bin-averaged measured acceleration, its noise taken out); the smallest when none.
    """
    scales = 2.0 ** (-0.5 * np.arange(CUTOFF_STEPS + 1))
    for f in scales:
        noise2 = signal2 = 0.0
        for _, q, _, bridged, dt in pieces:
            cutoff = f * _max_cutoff(dt)
            m = max(1, int(round(BIN / dt)))
            if len(q) <= 12 + m:
                continue
            _, qdd = zero_phase_derivatives(q, dt, cutoff=cutoff)
            acc = np.convolve(qdd, np.full(m, 1.0 / m), mode='valid')
            acc = acc[~bridged[:len(acc)]]
            noise2 += len(acc) * (res / math.sqrt(12.0) * _noise_gains(dt, cutoff)[1]) ** 2
            signal2 += float(np.sum(acc ** 2))
        if noise2 <= ACC_NOISE ** 2 * max(signal2 - noise2, 0.0):
            return float(f)
    return float(scales[-1])


def _standstill(c: dict[str, NDArray[Any]], m: NDArray[np.bool_],
                res: float) -> NDArray[np.bool_]:
    """Mark the samples of piece mask ``m`` whose filtered position moves < ``res`` nearby."""
    from scipy.ndimage import maximum_filter1d, minimum_filter1d

    qf = c['qf'][m]
    cutoff, dt = float(c['cutoff'][m][0]), float(c['dt'][m][0])
    w = max(3, int(round(STILL_WINDOW / (cutoff * dt))))
    still: NDArray[np.bool_] = (maximum_filter1d(qf, w) - minimum_filter1d(qf, w)) < res
    still &= ~c['bridged'][m]
    edge = int(round(EDGE / dt))
    still[:edge] = False
    still[len(still) - edge:] = False
    return still


def _scales(c: dict[str, NDArray[Any]], n_piece: int, res: float) -> dict[str, float]:
    """
    Velocity noise and sliding threshold from the samples (module docstring).

    Returns a dict with ``quantisation_noise``, ``standstill_noise``,
    ``standstill_fraction``, ``velocity_noise`` and ``v_stick``.
    """
    masks = [c['piece'] == p for p in range(n_piece)]
    # the encoder step seen through the derivative filter (white quantisation error)
    q_noise = max(res / math.sqrt(12.0)
                  * derivative_noise_gain(float(c['dt'][m][0]), float(c['cutoff'][m][0]))
                  for m in masks)
    # the velocity noise where the joint stands still
    still = np.concatenate([_standstill(c, m, res) for m in masks])
    s_noise = 0.0
    if int(still.sum()) >= MIN_STILL:
        v = c['qd'][still]
        s_noise = 1.4826 * float(np.median(np.abs(v - np.median(v))))
    v_noise = max(q_noise, s_noise)
    aq = np.abs(c['qd'])
    v_stick = max(V_STICK_FRACTION * float(np.percentile(aq, 99)), V_NOISE * v_noise)
    return {'quantisation_noise': q_noise,
            'standstill_noise': s_noise, 'standstill_fraction': float(np.mean(still)),
            'velocity_noise': v_noise, 'v_stick': v_stick}
