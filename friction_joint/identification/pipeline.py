# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ``identify`` command: recordings -> identified gear file + report (seed Section V-A).

    friction_joint identify RECORDING [RECORDING ...] --model STRUCTURE.yaml --out GEAR.yaml
                            [--orders auto] [--report DIR] [--presliding auto|skip|require]
                            [--joint NAME] [--force]

1. Reads the joint ``--joint`` (default the structure's ``joint_name``) from the
   recordings (rosbag2 directories or ``.mcap`` files; a recording without that
   joint is an error, there is no fallback to another joint) and finds their
   constant-velocity plateaus (:mod:`friction_joint.identification.plateaus`).
2. Steps 1 and 2: the static curve's temperature and load coefficients
   (:class:`~friction_joint.identification.static_fit.StaticIdentifier`), in the structure of
   STRUCTURE.yaml (or with orders chosen by held-out error, ``--orders auto``).
   Plateaus in one direction only are fitted when every recording measured tau_ext
   (``/link_torque``): the curve in that direction, the other one assumed symmetric
   and said so; without the load sensor they are refused, naming what to record
   (docs/identification.md: plateaus in one direction only).
3. Step 3: the pre-sliding parameters of every dynamic model the structure
   has a section for (``friction.lugre``, ``friction.gms``), by pattern search
   on the recordings' slow reversals (:mod:`friction_joint.identification.presliding`).
   ``--presliding auto`` (default) runs it when the module is there and notes
   in the output why it was skipped otherwise (module missing, no slow
   reversals in the data); ``skip`` never runs it; ``require`` makes a
   failure an error.  Skipped: the structure's pre-sliding values are kept.
   A parameter the fit reports as undetermined (flat objective or on a search
   bound, e.g. the LuGre micro-damping sigma1 from slow data) also keeps the
   structure's value, and so does a whole model whose fit misses the measured
   friction torque by more than :data:`MAX_PRESLIDING_ERROR` (10 %) RMS (no
   pre-sliding experiment in the data, or a model that cannot describe the
   gear); the header and report say so.  A failed or rejected step 3 also says
   why in plain words, from the recordings (``why``: e.g. no reversal within
   the pre-sliding range, the smallest swing seen, small commanded reversals
   the joint did not follow) and what to record (``advice``: swings within the
   range the gear gives), on the console, in ``identification.json`` and the
   header (:func:`~friction_joint.identification.presliding.presliding_excitation`).
4. (:func:`friction_joint.jobs.identify.run_identify`, the command's job)
   writes the report directory (default ``GEAR_report/`` next to GEAR.yaml:
   figures after Fig. 3 and 4, ``identification.json``) and GEAR.yaml
   (:func:`~friction_joint.gear.save_gear`): the structure file with the
   identified coefficients, ``joint_name`` the joint identified,
   ``friction.temperature_range`` set to the recorded temperature range, every
   other section kept, and the parameters with their standard errors in the
   header comments.  The two are one set of outputs
   (:class:`~friction_joint.output.OutputSet`): checked before the work (an
   existing one is refused unless ``force``, one that is an input always),
   then published together or not at all, the old set replaced as a whole.

STRUCTURE.yaml's coefficient *values* are not used, only its list lengths
(the model structure), ``delta_s``, ``velocity_scale``, inertia (J qdd) and
lever (tau_ext when a recording has no ``/link_torque``).  A structure file
without a ``delta_v`` key means linear viscous friction: delta_v stays 1.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
import dataclasses
import importlib.util
import os
import time
from typing import Any, cast, TYPE_CHECKING
import warnings

import numpy as np
from numpy.typing import NDArray

from ._arrays import FloatArray
from .plateaus import DETECTION, Detection, find_plateaus, Plateaus
from .report import identification_figures
from .scales import scale_lines
from .static_fit import StaticIdentifier
from .step3 import PreslidingStep
from .stick_slip import stick_slip_summary
from .._filters import zero_phase_derivatives
from ..bag import read_recording, Recording
from ..bag.stamps import BRIDGE_MARGIN, gap_summary, piece_on_grid, split_pieces
from ..exceptions import (ArgumentError, ExcitationError, FrictionJointError, GearConfigError,
                          GearConfigWarning, MissingTopicError, RecordingError,
                          UnitsWarning)
from ..gear import GearParams, load_gear
from ..gear.strict_yaml import read_yaml_document
from ..results import draw_figures, json_clean

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ['IdentificationRun', 'identify_recordings',
           'MAX_PRESLIDING_ERROR', 'BRIDGE_MARGIN']

#: step 3: a pre-sliding fit whose RMS torque error exceeds this fraction of the RMS
#: measured friction torque is rejected (the structure's values are kept)
MAX_PRESLIDING_ERROR = 0.10
#: cut-off (Hz) of the zero-phase derivatives of step 3
CUTOFF = 100.0


class IdentificationRun:
    """
    Everything one identification produced; the parameters are kept as attributes.

    Parameters
    ----------
    identifier : StaticIdentifier
        Steps 1 and 2 (fitted).
    gear : GearParams
        The identified gear (steps 1-2, plus step 3 when it ran).
    recordings : list of Recording
    plateaus : Plateaus
    presliding : PreslidingStep
        Step 3: ``status`` (``'done'``, ``'skipped'``, ``'failed'``), ``reason``,
        per model ``params``, ``stderr``, ``rel_stderr``, ``report``.
    timings : dict
        Seconds per stage.
    gaps : dict or None
        Gaps of the joint-state stamps over the recordings
        (:func:`friction_joint.bag.stamps.gap_summary`: ``bridged``, ``longest_bridged_s``,
        ``longest_bridged_samples``, ``split``, ``bridge_limit_s``, ``rule``).

    """

    def __init__(self, identifier: StaticIdentifier, gear: GearParams, recordings: list[Recording],
                 plateaus: Plateaus, presliding: PreslidingStep, timings: dict[str, float], *,
                 gaps: dict[str, Any] | None = None) -> None:
        self.identifier = identifier
        self.gear = gear
        self.recordings = recordings
        self.plateaus = plateaus
        self.presliding = presliding
        self.timings = timings
        self.gaps = gaps

    def to_dict(self) -> dict[str, Any]:
        """Return :meth:`report` (plain JSON types)."""
        return cast('dict[str, Any]', json_clean(self.report()))

    def plot(self) -> dict[str, Figure]:
        """
        Draw the report's figures (Fig. 3, Fig. 4, residuals, plateaus) in memory.

        The figures of :func:`~friction_joint.identification.report.identification_figures`,
        drawn as the report's PNG files are, but returned, not written.

        Returns
        -------
        dict of str to matplotlib.figure.Figure
            By the report's file name (e.g. ``'fig3a_temperature_curves.png'``).

        """
        return draw_figures(identification_figures(self.identifier, self.recordings,
                                                   self.presliding))

    def report(self) -> dict[str, Any]:
        """Return the ``identification.json`` content."""
        rep = self.identifier.report()
        rep['recordings'] = [{'path': r.path, 'duration_s': r.duration,
                              'samples': len(r.joint_states),
                              'link_torque': r.link_torque is not None}
                             for r in self.recordings]
        rep['plateaus'] = self.plateaus.to_dict()
        rep['presliding'] = self.presliding.to_dict()
        if self.gaps is not None:
            rep['gaps'] = self.gaps
        rep['timings'].update(self.timings)
        return rep


def _declared_friction_keys(path: str) -> set[str] | None:
    """Keys under ``friction`` as written in a gear file (defaults not filled in)."""
    try:
        doc = read_yaml_document(path)        # through the input gate, as load_gear read it
        params = doc['/**']['ros__parameters']
    except (GearConfigError, KeyError, TypeError):
        return None
    if not isinstance(params, dict):
        return None
    keys = set()
    fr = params.get('friction')
    if isinstance(fr, dict):
        keys |= {str(k) for k in fr}
    keys |= {str(k)[len('friction.'):] for k in params if str(k).startswith('friction.')}
    return keys


def _read(path: str | os.PathLike[str], joint_name: str, velocity_from_position: bool = False
          ) -> Recording:
    try:
        return read_recording(path, joint_name=joint_name,
                              velocity_from_position=velocity_from_position)
    except MissingTopicError as exc:
        if exc.topic == '/joint_temperature':
            # the topic is absent: say why it is needed (a bad value is named as it is)
            raise RecordingError(
                f'{exc}: the identification needs the gear housing temperature during the '
                'plateaus (sensor_msgs/Temperature on /joint_temperature); record it with the '
                'joint states') from None
        raise


#: a contiguous piece of a recording as step 3's input arrays (``bridged``: a bool mask)
_Piece = dict[str, NDArray[Any]]


def _presliding_pieces(recording: Recording, gear: GearParams) -> list[_Piece]:
    """
    Contiguous pieces of a recording, on their uniform grids, as pre-sliding input arrays.

    Pieces are cut at long gaps and bridge short ones
    (:func:`friction_joint.bag.stamps.split_pieces`); an irregular piece is resampled
    onto its uniform grid (linear interpolation).  ``bridged`` marks the samples of a
    bridged gap and :data:`BRIDGE_MARGIN` derivative-filter time constants on either
    side: a pre-sliding segment that holds one is left out of the fit.
    """
    js = recording.joint_states
    t = js.t
    if len(t) < 10:
        return []
    cut = split_pieces(t, js.qd)
    out = []
    for a, b in cut.ranges:
        if b - a < 200:
            continue
        steps = cut.bridged[(cut.bridged >= a) & (cut.bridged < b - 1)] - a
        tt, (q, effort), ok = piece_on_grid(t[a:b], (js.q[a:b], js.effort[a:b]), steps,
                                            margin=BRIDGE_MARGIN / CUTOFF)
        dt = float(np.median(np.diff(tt)))
        qd, qdd = zero_phase_derivatives(q, dt, cutoff=CUTOFF)
        if recording.link_torque is not None and len(recording.link_torque) > 1:
            tau_ext = np.interp(tt, recording.link_torque.t, recording.link_torque.tau)
        else:
            tau_ext = gear.lever_torque(q)
        tau_r = effort - tau_ext - gear.inertia * qdd
        out.append({'t': tt, 'q': q, 'qd': qd, 'tau_r': tau_r,
                    'xi': recording.temperature_at(t=tt), 'tau_l': np.abs(tau_ext),
                    'bridged': ~ok})
    return out


def _step3(gear: GearParams, recordings: Sequence[Recording], mode: str,
           progress: Callable[[str], None] | None) -> tuple[GearParams, PreslidingStep]:
    """Pre-sliding parameters (step 3); returns (gear, result)."""
    if mode == 'skip':
        return gear, PreslidingStep('skipped', reason='--presliding skip')
    models = [m for m in ('lugre', 'gms') if getattr(gear.friction, m) is not None]
    if not models:
        return gear, PreslidingStep('skipped', reason='the structure has no friction.lugre or '
                                                      'friction.gms section')
    if importlib.util.find_spec('friction_joint.identification.presliding') is None:
        reason = ('friction_joint.identification.presliding is not available: the pre-sliding '
                  'parameters are kept from the structure file')
        if mode == 'require':
            raise ArgumentError(f'step 3: {reason}')
        return gear, PreslidingStep('skipped', reason=reason)
    from .presliding import fit_presliding
    from .presliding_data import EXPERIMENT_ADVICE, presliding_segments, PreslidingOptions
    fits: dict[str, dict[str, Any]] = {}
    pieces: list[_Piece] = []
    try:
        pieces = [p for r in recordings for p in _presliding_pieces(r, gear)]
        for model in models:
            cols: dict[str, list[FloatArray]] = {k: [] for k in ('t', 'q', 'qd', 'tau_r', 'xi',
                                                                 'tau_l')}
            errors: list[str] = []
            dropped = 0
            for piece in pieces:
                try:
                    segs = presliding_segments(piece['t'], piece['qd'], gear=gear, model=model,
                                               xi=piece['xi'])
                except ExcitationError as exc:
                    errors.append(str(exc))
                    continue
                for seg in segs:
                    if seg.init != 'sliding':
                        continue
                    if piece['bridged'][seg.slice].any():
                        dropped += 1                 # interpolated across a gap: left out
                        continue
                    for k in cols:
                        cols[k].append(piece[k][seg.slice])
            if not cols['t']:
                raise ExcitationError(errors[0] if errors else
                                      'no slow velocity reversals in the recordings: '
                                      + EXPERIMENT_ADVICE)
            if progress:
                progress(f'step 3 ({model}): pattern search on {len(cols["t"])} pre-sliding '
                         f'segments ({sum(len(x) for x in cols["t"])} samples)')
            t0 = time.perf_counter()
            with warnings.catch_warnings():          # kept in fit.report['warnings']
                warnings.simplefilter('ignore', GearConfigWarning)
                fit = fit_presliding(cols['t'], cols['qd'], cols['tau_r'], cols['xi'],
                                     cols['tau_l'], gear, q=cols['q'],
                                     options=PreslidingOptions(model=model))
            scale = float(np.sqrt(np.mean(np.concatenate(cols['tau_r']) ** 2)))
            rel = fit.report['objective_final'] / max(scale, 1e-12)
            if rel > MAX_PRESLIDING_ERROR:
                fits[model] = {
                    'status': 'rejected', 'params': fit.params, 'report': fit.report,
                    'reason': f'the fitted {model} model misses the measured friction torque by '
                              f'{fit.report["objective_final"]:.3g} Nm RMS, {100 * rel:.0f} % of '
                              f'its RMS ({scale:.3g} Nm; accepted up to '
                              f'{100 * MAX_PRESLIDING_ERROR:.0f} %): kept from the structure',
                    'time_s': time.perf_counter() - t0}
                if mode == 'require':
                    why = _explain(fits, pieces, recordings, gear, models)
                    raise ExcitationError(f'step 3: {fits[model]["reason"]}; '
                                          + (f'why: {why.why}; to fit it, {why.advice}'
                                             if why else EXPERIMENT_ADVICE))
                if progress:
                    progress(f'step 3 ({model}): {fits[model]["reason"]}')
                continue
            kept = list(fit.report.get('undetermined', []))
            old = getattr(gear.friction, model)
            sec = getattr(fit.gear.friction, model)
            if model == 'lugre':
                gear = gear.replace({'friction': {'lugre': {
                    'sigma0': old.sigma0 if 'sigma0' in kept else sec.sigma0,
                    'sigma1': old.sigma1 if 'sigma1' in kept else sec.sigma1}}})
            else:
                gear = gear.replace({'friction': {'gms': {
                    'k': list(old.k if 'k_total' in kept else sec.k),
                    'c': old.c if 'c' in kept else sec.c}}})
            structure_values = ({'sigma0': old.sigma0, 'sigma1': old.sigma1} if model == 'lugre'
                                else {'k_total': float(sum(old.k)), 'c': old.c})
            fits[model] = {
                'status': 'done', 'params': fit.params, 'initial': fit.initial,
                'kept_values': {k: structure_values[k] for k in kept if k in structure_values},
                'stderr': fit.stderr, 'rel_stderr': fit.rel_stderr, 'segments': len(cols['t']),
                'segments_across_gaps_left_out': dropped,
                'kept_from_structure': kept, 'report': fit.report,
                'time_s': time.perf_counter() - t0}
            if progress and fit.report.get('warnings'):
                for w in fit.report['warnings']:
                    progress(f'step 3 ({model}): warning: {w}')
            if progress:
                progress(f'step 3 ({model}): ' + ', '.join(
                    f'{k} = {v:.4g} (+-{100 * fit.rel_stderr[k]:.1f} %)'
                    + (' undetermined, kept from the structure' if k in kept else '')
                    for k, v in fit.params.items() if k in fit.rel_stderr)
                    + f'; RMS {fit.report["objective_final"]:.4f} Nm')
    except FrictionJointError as exc:
        if mode == 'require':
            raise
        failed = PreslidingStep(
            'failed', reason=str(exc),
            note='the pre-sliding parameters are kept from the structure file', models=fits)
        why = _explain(fits, pieces, recordings, gear, models)
        return gear, (dataclasses.replace(failed, excitation=why.excitation, why=why.why,
                                          advice=why.advice) if why else failed)
    result = PreslidingStep('done', models=fits)
    if any(r['status'] == 'rejected' for r in fits.values()):
        why = _explain(fits, pieces, recordings, gear, models)
        if why:
            result = dataclasses.replace(result, excitation=why.excitation, why=why.why,
                                         advice=why.advice)
        if progress and result.why:
            progress(f'step 3: why: {result.why}')
            progress(f'step 3: to fit it, {result.advice}')
    return gear, result


@dataclasses.dataclass(frozen=True)
class _Explanation:
    """Why a failed or rejected step 3 did not fit, and what to record."""

    excitation: dict[str, Any]
    why: str
    advice: str


def _explain(fits: Mapping[str, Mapping[str, Any]],
             pieces: Sequence[Mapping[str, NDArray[Any]]], recordings: Sequence[Recording],
             gear: GearParams, models: Sequence[str]) -> _Explanation | None:
    """
    Say why a failed or rejected step 3 did not fit, in plain words, and what to record.

    ``fits`` are the per-model results so far; returns the excitation
    (:func:`~friction_joint.identification.presliding.presliding_excitation`), the why
    and the advice, or None when there is nothing to say (no data).
    """
    from .presliding import presliding_excitation
    if not pieces:
        return None
    commands = [(r.joint_command.t, r.joint_command.q_d, r.joint_states.t, r.joint_states.q)
                for r in recordings if r.joint_command is not None]
    note = presliding_excitation(pieces, gear, models, commands=commands)
    why = note['why']
    if why is None:
        rejected = {m: r for m, r in fits.items() if r.get('status') == 'rejected'}
        bound = sorted({p for r in rejected.values() for p in r['report'].get('at_bound', [])})
        why = (f'the recordings hold {note["small_reversals"]} reversals within the '
               'pre-sliding range, yet the model does not describe the torque there')
        if bound:
            why += (f' with {", ".join(bound)} anywhere within the search bounds (a factor of '
                    "10 or more around the structure's values, where the fit ended): the "
                    "structure's pre-sliding values may be far off, or the gear's behaviour "
                    'lies outside the model')
    return _Explanation(excitation=note, why=why, advice=note['advice'])


def identify_recordings(paths: Sequence[str | os.PathLike[str]], structure: str | GearParams, *,
                        orders: str | dict[str, int] | None = None, joint_name: str | None = None,
                        detection: Detection | None = None, presliding: str = 'auto',
                        progress: Callable[[str], None] | None = None,
                        velocity_from_position: bool = False) -> IdentificationRun:
    """
    Identify a gear from recordings (steps 1-3); the engine of the command.

    Parameters
    ----------
    paths : sequence of str
        Recordings.
    structure : str or GearParams
        The structure gear file (path or loaded).
    orders : None, 'auto' or dict
        See :class:`~friction_joint.identification.static_fit.StaticIdentifier`.
    joint_name : str, optional
        Joint to pick from the recordings (default: the structure's ``joint_name``); a
        recording without it is a :class:`~friction_joint.exceptions.RecordingError`.
        The identified gear is named for it.
    detection : Detection, optional
        Plateau detection thresholds (default
        :data:`friction_joint.identification.plateaus.DETECTION`).
    presliding : {'auto', 'skip', 'require'}
        Step 3 policy (see the module docstring).
    progress : callable, optional
        Called with progress messages.
    velocity_from_position : bool
        Replace the recorded velocity by the position's centred difference
        (:func:`~friction_joint.bag.read_recording`).

    Returns
    -------
    IdentificationRun

    """
    if presliding not in ('auto', 'skip', 'require'):
        raise ArgumentError(f'presliding must be auto, skip or require, got {presliding!r}')
    timings: dict[str, float] = {}
    fixed: tuple[str, ...] = ()
    if isinstance(structure, str):
        structure_path = structure
        structure = load_gear(structure_path)    # a malformed file: GearConfigError first
        keys = _declared_friction_keys(structure_path)
        if keys is not None and 'delta_v' not in keys:
            fixed = ('delta_v',)
    if not paths:
        raise RecordingError('no recordings given')
    if joint_name is not None and joint_name != structure.joint_name:
        structure = structure.replace({'joint_name': joint_name})
    t0 = time.perf_counter()
    recordings, parts = [], []
    for path in paths:
        rec = _read(path, structure.joint_name, velocity_from_position)
        recordings.append(rec)
        part = find_plateaus(rec, structure, options=detection)
        parts.append(part)
        if progress:
            src = 'link torque sensor' if part.torque_source[0] == 'link_torque' else \
                'structure lever model (no /link_torque)'
            progress(f'{path}: {rec.duration:.1f} s, {len(part)} plateaus (tau_ext from {src})')
    plateaus = Plateaus.concatenate(parts)
    gap = (DETECTION if detection is None else detection).gap_factor
    gaps = gap_summary(split_pieces(r.joint_states.t, r.joint_states.qd, gap=gap)
                       for r in recordings)
    if progress and (gaps['bridged'] or gaps['split']):
        progress(f'gaps in the joint-state stamps: {gaps["bridged"]} bridged (longest '
                 f'{1e3 * gaps["longest_bridged_s"]:.1f} ms), {gaps["split"]} split')
    timings['time_read_and_plateaus_s'] = time.perf_counter() - t0
    t0 = time.perf_counter()
    ident = StaticIdentifier(structure, orders=orders, fixed=fixed,
                             progress=progress).fit(plateaus)
    timings['time_steps_1_2_s'] = time.perf_counter() - t0
    for line in scale_lines(ident.gear, structure):
        warnings.warn(line, UnitsWarning, stacklevel=2)
    if progress:
        progress(f'steps 1-2: RMS residual {ident.rms:.4f} Nm over {len(plateaus)} plateaus '
                 f'({timings["time_steps_1_2_s"]:.2f} s)')
        for line in ident.identifiability['lines']:
            progress(f'steps 1-2: {line}')
        val = ident.validation
        if val.get('blocks'):
            worst = max(val['bands'], key=lambda b: b['worst_rel'])
            progress(f'steps 1-2: held out ({val["blocks"]} blocks): RMS {val["rms"]:.4f} Nm; '
                     f'worst {100 * worst["worst_rel"]:.2g} % of the friction torque at '
                     f'{worst["v_low"]:.3g}..{worst["v_high"]:.3g} rad/s')
        slip = stick_slip_summary(plateaus)
        if slip:
            progress(f'stick-slip: {slip}')
    if ident.gear is None:                       # fit() sets it
        raise RuntimeError('steps 1-2 gave no gear')
    t0 = time.perf_counter()
    gear, step3 = _step3(ident.gear, recordings, presliding, progress)
    timings['time_step_3_s'] = time.perf_counter() - t0
    if progress and step3.status != 'done':
        progress(f'step 3 {step3.status}: {step3.reason}')
        if step3.why:
            progress(f'step 3: why: {step3.why}')
            progress(f'step 3: to fit it, {step3.advice}')
    return IdentificationRun(ident, gear, recordings, plateaus, step3, timings, gaps=gaps)
