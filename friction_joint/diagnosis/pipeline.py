# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Diagnosis: what a base friction model gets wrong, and which missing effects explain it.

    friction_joint diagnose RECORDING [RECORDING ...] --model BASE.yaml --out DIR

Method
------
1. **Data** (:mod:`friction_joint.diagnosis.data`): the measured friction
   torque ``y = tau - tau_ext - J q̈`` averaged over 10 ms bins while the joint
   slides; K = 10 contiguous time blocks for cross-validation.
   Which candidates the data can tell is decided first
   (:mod:`friction_joint.diagnosis.testability`); an untestable candidate is
   reported with its reason, never named, and does not stop the run, which
   fails only when no candidate is testable or nothing slides.
2. **Base fit**: BASE's structure (polynomial lengths, Stribeck term, delta_v,
   ripple, pre-sliding model) is refitted to the data by linear least squares
   with grids over its few nonlinear parameters (:mod:`friction_joint.diagnosis.structures`);
   every fit is bounded to F_c, F_s, F_v >= 0 over the data's temperature and
   load range.
3. **Candidates** (:mod:`friction_joint.diagnosis.candidates`): every effect
   of :data:`EFFECTS` extends the current
   structure (``thermal``: temperature orders of F_c and F_v (and F_s) + 1;
   ``load``: load orders + 1; ``position_ripple``: 3 harmonics of 2 N, else N,
   cycles per output turn; ``nonlinear_viscous``: free delta_v;
   ``stribeck``: F_s and v_s; ``presliding``: LuGre or GMS friction state
   instead of sign(qd); ``inertia``: J refitted; ``asymmetry``: constant
   ``friction.offset``; ``drift``: the Coulomb term times 2 shifted Legendre
   polynomials of the accumulated travel, 0..1; ``gravity``: a sin q + b cos q
   (over a stroke too short for it, an offset, a slope and a curvature in q),
   :mod:`friction_joint.diagnosis.gravity`).  Each extended structure is fitted on K - 1 blocks
   and predicts the held-out block (its nonlinear parameter chosen on the
   training blocks only).
4. **Significance** -- the criterion (:mod:`friction_joint.diagnosis.criterion`):
   for candidate c against the current model m the per-block statistic
   ``d_k = log(MSE_m,k / MSE_c,k)`` of the held-out mean squared torque
   errors over K contiguous blocks (K from the amount of data, 10..20; a floor
   of (1 % of the friction level)^2 added to both, so that blocks both predict
   to a sliver of the level are near ties) is
   tested with the one-sided Wilcoxon signed-rank test (robust to one bad
   block); the p-values of a round are Holm-Bonferroni adjusted; a candidate
   is significant when its adjusted p-value is below :data:`ALPHA` (0.05) AND
   it matters in practice: its gain -- the relative reduction of the pooled
   held-out torque RMSE, ``1 - RMSE_c / RMSE_m`` -- is at least
   :data:`MIN_GAIN` (3 %), or the RMS torque it explains held out,
   ``sqrt(MSE_m - MSE_c)``, is at least :data:`MIN_EXPLAINED` (1 %) of the
   friction level with a gain of at least a quarter of :data:`MIN_GAIN` (other
   errors, e.g. a lagging temperature sensor, must not hide an effect of
   physical size).  Candidates
   whose variables are one in the recording (temperature rising with the
   travel: ``thermal`` and ``drift``; a one-way sweep: position and travel)
   are reported as confounded, with the rank correlation and the recording
   that would separate them; of two significant confounded candidates the
   measured cause is added first.
5. **Greedy**: the significant candidate with the largest gain is added, the
   extended structure becomes the current one and the remaining candidates
   are tested again, until none is significant.  So two missing effects are
   both found, and a candidate that only looked good by confounding with the
   added effect drops out.
6. **Velocity**: the base and the final model are simulated open loop
   (:class:`~friction_joint.models.joint.Joint`) from the measured state over
   0.5 s windows of held-out blocks, driven by the measured drive torque,
   temperature and external torque; velocity RMSE against the zero-phase
   differentiated encoder.
7. **Extended model**: the final structure fitted on all data; an extension
   that still cannot be fitted physically (the gear file check fails) is left
   out of ``extended.yaml`` -- walking back over the greedy sequence -- and its
   candidate entry says ``"physical": false`` with the reason; the report is
   always written (:func:`~friction_joint.diagnosis.fitted_gear.extended_model`).
   A named effect the gear file has no key for (:data:`UNREPRESENTABLE`:
   ``drift``) is left out of ``extended.yaml`` (fitted without it, the other
   effects kept), reported ``"representable": false`` with the reason and in
   ``notes``; ``diagnosed`` gives the fit and held-out RMSE with it.
8. **Adequacy**: the report opens with how much of the measured friction
   torque the base and the extended model explain (held-out R^2, RMSE against
   the friction level); a model that leaves a residual comparable to the
   friction level "does not explain the data", and the headline points at the
   largest structure of the residual scan.  Headline, findings, next steps and
   the adequacy table are worded from one verdict
   (:func:`~friction_joint.diagnosis.criterion.verdict`, built once here).
9. **Residual scan** (:mod:`friction_joint.diagnosis.scan`): the held-out
   residual of the diagnosed model against time, position (periodogram),
   velocity, acceleration, temperature rate and dwell time, each with a
   held-out explained variance and a permutation p-value.

Outputs: ``report.json`` (named causes, candidate table, baseline/extended
held-out RMSE, per-round tables, timing), ``extended.yaml`` (a gear file of
the final model fitted on all data, loadable by every node), ``report.md``
and figures; all written atomically (:mod:`friction_joint.output`).
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
import dataclasses
import os
import time
from typing import Any, TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from . import criterion as cr
from . import structures as dm
from .candidates import base_structure, extend
from .core import DiagnosisCore, ExtendedModel, VelocitySim
from .crossval import fit_all
from .data import BIN, load_data
from .fitted_gear import extended_model
from .gravity import gravity_untestable, linear_device, POSE_CAVEAT, pose_frame
from .greedy import (ALPHA, fit_base, greedy_round, MAX_ROUNDS, MIN_EXPLAINED, MIN_GAIN, Search,
                     Setup)
from .next_step import identify_refusal
from .report import figure_drawers
from .result import DataSummary, DiagnosisResult, Gaps, Scales, Timing
from .scan import residual_scan
from .testability import untestable
from .velocity import fold_gears, simulate_windows, WINDOW
from .verdicts import (Adequacy, CandidateVerdict, CriterionInfo, DiagnosedModel, Fit,
                       IdentifyCheck, ModelScore, ScanRow)
from ..effects import EFFECTS, UNREPRESENTABLE
from ..exceptions import ExcitationError, GearConfigError
from ..results import draw_figures

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .crossval import CVResult
    from .data import DiagnosisData
    from ..gear import GearParams

__all__ = ['EFFECTS', 'UNREPRESENTABLE', 'ALPHA', 'MIN_GAIN', 'MIN_EXPLAINED', 'WINDOW',
           'Diagnosis', 'diagnose', 'base_structure', 'extend']

Say = Callable[[str], None]
Array = npt.NDArray[np.float64]


@dataclasses.dataclass(frozen=True)
class Diagnosis(DiagnosisCore):
    """
    Everything a diagnosis found (see :func:`diagnose`).

    The fields of :class:`~friction_joint.diagnosis.core.DiagnosisCore` and the verdict.

    Attributes
    ----------
    result : DiagnosisResult
        The ``report.json`` content, typed: named causes, candidate verdicts,
        adequacy, rounds, data, timing (its ``to_dict()`` is ``report.json``).
    gear : GearParams
        The extended gear (the base when nothing was added).
    data : DiagnosisData
        The data.
    base : GearParams
        The base gear, as given.
    ctx : Context
        The design context.
    base_cv, final_cv : CVResult
        Cross-validation of the base and the final structure.
    velocity : VelocitySim
        Open-loop velocity of held-out windows.
    fits : tuple of RoundFit
        The models of each greedy round.
    scan : dict or None
        The residual scan (:func:`~friction_joint.diagnosis.scan.residual_scan`).
    verdict : Verdict or None
        The one story of the report (:func:`~friction_joint.diagnosis.criterion.verdict`,
        built once from ``result``): headline, findings, next steps and the adequacy
        table are worded from it.  None: built from ``result`` when asked.

    """

    verdict: cr.Verdict | None = None

    def plot(self) -> dict[str, Figure]:
        """
        Draw the report's figures (torque, velocity, causes, gains, confounds, scan) in memory.

        The figures of :func:`~friction_joint.diagnosis.report.figure_drawers`,
        drawn as ``diagnose`` writes them, but returned, not written.

        Returns
        -------
        dict of str to matplotlib.figure.Figure
            By the report's file name (e.g. ``'torque.png'``).

        """
        return draw_figures(figure_drawers(self))


def diagnose(paths: Sequence[str | os.PathLike[str]], base: GearParams, *,
             effects: Sequence[str] = EFFECTS, joint_name: str | None = None,
             progress: Callable[[str], None] | None = None,
             velocity_from_position: bool = False) -> Diagnosis:
    """
    Diagnose ``base`` against recordings.

    Parameters
    ----------
    paths : sequence of str
        Recordings: rosbag2 directories or ``.mcap`` files.
    base : GearParams
        The base model (gear file) to diagnose.
    effects : sequence of str
        Candidate effects to test (default all of :data:`EFFECTS`).
    joint_name : str, optional
        Joint to read (default: the gear's joint name if present, else the first).
    progress : callable, optional
        Called with progress messages.
    velocity_from_position : bool
        Replace the recorded velocity by the position's centred difference.

    Returns
    -------
    Diagnosis

    Raises
    ------
    RecordingError
        Unreadable or bad recordings.
    ExcitationError
        Nothing slides, or no candidate of ``effects`` is testable on the data.
    GearConfigError
        An unknown effect.

    """
    unknown = [e for e in effects if e not in EFFECTS]
    if unknown:
        raise GearConfigError(f'unknown effect(s) {", ".join(unknown)}; '
                              f'known: {", ".join(EFFECTS)}')
    setup = _read(paths, base, effects, joint_name, progress or _quiet, velocity_from_position)
    search = fit_base(setup)
    t0 = time.perf_counter()
    for rnd in range(1, MAX_ROUNDS + 1):
        if not greedy_round(rnd, setup, search):
            break
    setup.timing = dataclasses.replace(setup.timing, candidates_s=time.perf_counter() - t0)
    return _conclude(setup, search, velocity_from_position)


def _quiet(message: str) -> None:
    """Say nothing."""


def _read(paths: Sequence[str | os.PathLike[str]], base: GearParams, effects: Sequence[str],
          joint_name: str | None, say: Say, velocity_from_position: bool) -> Setup:
    """Read the data, cut the blocks, and decide which candidates it can test."""
    t0 = time.perf_counter()
    data = load_data(paths, base, joint_name=joint_name,
                     velocity_from_position=velocity_from_position)
    cr.reblock(data, cr.n_blocks(data.n_bins))
    ctx = dm.Context(base, data)
    if base.friction.model != 'static':
        ctx.ps_models = (base.friction.model,)
    read_s = time.perf_counter() - t0
    temp = (f'xi {data.xi.min():.2f}..{data.xi.max():.2f} degC' if data.has_temperature
            else 'no temperature logged')
    say(f'read {len(paths)} recording(s): {data.n_bins} sliding bins of {1e3 * BIN:.0f} ms, '
        f'{temp} ({read_s:.2f} s)')
    why = untestable(data, base.gear_ratio, effects)
    pose_note = None
    if 'gravity' in effects:
        linear = linear_device(paths)
        reason = gravity_untestable(data, dm.design(base_structure(base), ctx)[0],
                                    linear=linear)
        if reason and not linear:       # too short for the sine: a smooth pose-dependent load
            ctx.pose = pose_frame(data)
            pose_note = f'gravity: {POSE_CAVEAT} ({reason})'
        elif reason:
            why['gravity'] = reason
    testable = [e for e in effects if e not in why]
    if not testable:
        raise ExcitationError('no candidate effect is testable on these recordings: ' + '; '.join(
            f'{k}: {v}' for k, v in why.items()))
    if why:
        say('untestable: ' + '; '.join(f'{k}: {v}' for k, v in why.items()))
    return Setup(paths, base, effects, joint_name, say, data, ctx, why, testable, pose_note,
                 Timing(read_s=read_s))


def _conclude(setup: Setup, search: Search, velocity_from_position: bool) -> Diagnosis:
    """Fit the extended model, simulate, scan the residual and put the result together."""
    t0 = time.perf_counter()
    sequence = [f.structure for f in search.fits]
    if not sequence or sequence[-1] is not search.cur:
        sequence.append(search.cur)
    # the gear file has no key for some effects: extended.yaml is fitted without them
    ext = ExtendedModel.from_dict(extended_model(
        setup.base, [s.with_(drift=0) for s in sequence], setup.ctx, setup.y))
    final_cv = search.cur_cv
    if ext.structure != search.cur:
        final_cv = (search.base_cv if ext.structure == search.base_struct
                    else setup.cv(ext.structure))
    setup.timing = dataclasses.replace(setup.timing, extended_fit_s=time.perf_counter() - t0)
    t0 = time.perf_counter()
    vb_sim, meas, folds = simulate_windows(setup.data, *fold_gears(
        setup.base, search.base_cv, setup.ctx, setup.data))
    ve_sim = vb_sim
    if ext.kept > 0:
        ve_sim = simulate_windows(setup.data, *fold_gears(setup.base, final_cv, setup.ctx,
                                                          setup.data))[0]
    setup.timing = dataclasses.replace(setup.timing, velocity_sim_s=time.perf_counter() - t0)
    t0 = time.perf_counter()
    scan = residual_scan(setup.data, setup.y - search.cur_cv.pred, progress=setup.say)
    setup.timing = dataclasses.replace(setup.timing,
                                       residual_scan_s=time.perf_counter() - t0)
    velocity = VelocitySim(vb_sim, ve_sim, meas, folds)
    result = _result(setup, search, ext, final_cv, velocity, scan['table'],
                     velocity_from_position)
    verdict = cr.verdict(result)
    return Diagnosis(dataclasses.replace(result, headline=verdict.headline), ext.gear,
                     setup.data, setup.base, setup.ctx, search.base_cv, final_cv,
                     velocity, tuple(search.fits), scan, verdict)


def _result(setup: Setup, search: Search, ext: ExtendedModel, final_cv: CVResult,
            velocity: VelocitySim, scan_table: Sequence[Mapping[str, Any]],
            velocity_from_position: bool) -> DiagnosisResult:
    """Return the typed ``report.json`` content (without its headline)."""
    data, ctx, y, named = setup.data, setup.ctx, setup.y, search.named
    kept = max(ext.kept, 0)
    level = data.friction_level
    written = [e for e in named[:kept] if e not in UNREPRESENTABLE]
    identify = diagnosed = None
    if kept and written:
        refusal = identify_refusal(setup.paths, ext.gear, setup.joint_name)   # must run next
        identify = IdentifyCheck(refusal is None, refusal)
    if ext.structure != search.cur:
        diagnosed = DiagnosedModel(tuple(named), search.cur_cv.rmse, dm.coefficients(
            search.cur, *_refit(search.cur, ctx, y)))
    return DiagnosisResult(
        named_causes=tuple(named),
        candidates=_candidates(setup, search, ext),
        baseline=ModelScore(search.base_cv.rmse, _vrmse(velocity.base, velocity.measured)),
        extended=ModelScore(final_cv.rmse, _vrmse(velocity.extended, velocity.measured)),
        criterion=_criterion(data.n_blocks),
        adequacy=Adequacy(Fit.from_dict(cr.adequacy(y, search.base_cv.pred, level)),
                          Fit.from_dict(cr.adequacy(y, final_cv.pred, level))),
        confounds=tuple(search.pairs),
        rounds=tuple(search.rounds),
        data=_data_summary(data, velocity, velocity_from_position),
        base_fit=dm.coefficients(search.base_struct, *_refit(search.base_struct, ctx, y)),
        extended_fit=ext.fit, extended_effects=tuple(written),
        residual_scan=tuple(ScanRow.from_dict(r) for r in scan_table),
        untestable=dict(setup.why), notes=tuple(_notes(setup, search, ext, final_cv)),
        timing=setup.timing, identify=identify, diagnosed=diagnosed)


def _vrmse(sim: Array, meas: Array) -> float | None:
    return float(np.sqrt(np.mean((sim - meas) ** 2))) if sim.size else None


def _criterion(blocks: int) -> CriterionInfo:
    """Return the criterion in words and numbers."""
    return CriterionInfo(
        statistic='d_k = log(MSE_current,k / MSE_candidate,k) of held-out torque MSE per '
                  'contiguous time block k',
        test='one-sided Wilcoxon signed-rank test of the d_k over the blocks (H0: the '
             'candidate does not predict held-out blocks better; robust to one bad block)',
        multiplicity='Holm-Bonferroni over the candidates of each greedy round',
        alpha=ALPHA, min_gain=MIN_GAIN, min_explained=MIN_EXPLAINED, blocks=blocks,
        gain='1 - RMSE_candidate / RMSE_current, pooled held-out torque RMSE',
        selection='greedy: add the significant candidate with the largest gain (of '
                  'confounded significant candidates the measured cause first), refit, '
                  'test the rest again until none is significant',
        confound_rank_correlation=cr.CONFOUND_RHO)


def _data_summary(data: DiagnosisData, velocity: VelocitySim,
                  velocity_from_position: bool) -> DataSummary:
    """Return what was read: recordings, bins, temperature range, torque source, scales."""
    gaps = getattr(data, 'gaps', None)
    return DataSummary(
        recordings=tuple(r.path for r in data.recordings), bins=data.n_bins, bin_s=BIN,
        sliding_s=data.n_bins * BIN, xi_range=(float(data.xi.min()), float(data.xi.max())),
        torque_source=('link_torque' if data.link_torque else
                       'lever model' if data.mgl_sim > 0 else 'none'),
        velocity_windows=int(velocity.measured.shape[0]), window_s=WINDOW,
        has_temperature=bool(data.has_temperature),
        scales=Scales(v_stick=data.v_stick, resolution=data.resolution,
                      friction_level=data.friction_level, stroke=data.stroke,
                      velocity_noise=getattr(data, 'velocity_noise', None),
                      quantisation_noise=getattr(data, 'quantisation_noise', None),
                      standstill_noise=getattr(data, 'standstill_noise', None),
                      standstill_fraction=getattr(data, 'standstill_fraction', None),
                      cutoff=getattr(data, 'cutoff', None)),
        velocity_from_position=bool(velocity_from_position),
        gaps=None if gaps is None else Gaps.from_dict(gaps))


def _notes(setup: Setup, search: Search, ext: ExtendedModel,
           final_cv: CVResult) -> list[str]:
    """Return the report's notes: what extended.yaml leaves out or carries differently."""
    named, kept = search.named, max(ext.kept, 0)
    notes = []
    if ext.kept < 0:
        notes.append(f'extended.yaml is the base file as given: {ext.reason}')
    elif kept < len(named):
        notes.append(f'extended.yaml leaves out {", ".join(named[kept:])}: {ext.reason}')
    for e in named:
        if e in UNREPRESENTABLE:
            notes.append(f'{e} is {UNREPRESENTABLE[e]}; the model with it has a held-out torque '
                         f'RMSE of {search.cur_cv.rmse:.4g} Nm, extended.yaml '
                         f'{final_cv.rmse:.4g} Nm')
    gravity = ext.fit.get('gravity')
    if gravity is not None and gravity.get('pose') is not None:
        pose = gravity.get('pose')
        notes.append(f'{setup.pose_note}; extended.yaml carries it as lever.pose_torque = '
                     f'{[float(f"{c:.4g}") for c in pose.get("pose_torque")]} (Nm, Nm/rad, '
                     f'Nm/rad^2) about lever.pose_center = {pose.get("center"):.4g} rad')
    elif gravity is not None:
        lever = gravity.get('lever', {})
        nan = float('nan')
        notes.append('gravity: extended.yaml corrects the lever section to m g l = '
                     f'{lever.get("mgl", nan):.4g} Nm at angle_offset '
                     f'{lever.get("angle_offset", nan):.4g} rad (base '
                     f'{lever.get("mgl_base", nan):.4g} Nm at '
                     f'{lever.get("angle_offset_base", nan):.4g} rad)' +
                     ('; the recordings carry /link_torque, so the term stands for a '
                      'position-dependent torque the link side does not measure'
                      if setup.data.link_torque else ''))
    return notes


def _candidates(setup: Setup, search: Search,
                ext: ExtendedModel) -> tuple[CandidateVerdict, ...]:
    """Candidate table of the report: one entry per effect, testable or not."""
    kept = max(ext.kept, 0)
    physical = {e: i < kept for i, e in enumerate(search.named)}
    out = []
    for eff in setup.effects:
        if eff in setup.why:
            entry = CandidateVerdict(eff, testable=False, reason=setup.why[eff], gain=0.0,
                                     significant=False)
        else:
            entry = dataclasses.replace(
                search.added.get(eff) or search.last.get(eff) or CandidateVerdict(eff),
                testable=True, significant=eff in search.named)
        if eff in search.named:
            entry = dataclasses.replace(entry, physical=bool(physical[eff]))
            if not physical[eff]:
                entry = dataclasses.replace(entry, reason=ext.reason)
            elif eff in UNREPRESENTABLE:
                entry = dataclasses.replace(entry, representable=False,
                                            reason=UNREPRESENTABLE[eff])
        if eff == 'gravity' and setup.pose_note:
            entry = dataclasses.replace(entry, form='pose', caveat=POSE_CAVEAT)
        out.append(entry)
    return tuple(out)


def _refit(s: dm.CandidateStructure, ctx: dm.Context,
           y: Array) -> tuple[Array, list[tuple[str, int]], dm.Context]:
    _, beta, names, _ = fit_all([s], ctx, y)
    return beta, names, ctx
