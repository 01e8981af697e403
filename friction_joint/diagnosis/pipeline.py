# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

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
   polynomials of the accumulated travel, 0..1; ``gravity``: a sin q + b cos q,
   :mod:`friction_joint.diagnosis.gravity`).  Each extended structure is fitted on K - 1 blocks
   and predicts the held-out block (its nonlinear parameter chosen on the
   training blocks only).
4. **Significance** -- the criterion (:mod:`friction_joint.diagnosis.criterion`):
   for candidate c against the current model m the per-block statistic
   ``d_k = log(MSE_m,k / MSE_c,k)`` of the held-out mean squared torque
   errors over K contiguous blocks (K from the amount of data, 10..20) is
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
   always written (:func:`~friction_joint.diagnosis.gears.extended_model`).
   A named effect the gear file has no key for (:data:`UNREPRESENTABLE`:
   ``drift``) is left out of ``extended.yaml`` (fitted without it, the other
   effects kept), reported ``"representable": false`` with the reason and in
   ``notes``; ``diagnosed`` gives the fit and held-out RMSE with it.
8. **Adequacy**: the report opens with how much of the measured friction
   torque the base and the extended model explain (held-out R^2, RMSE against
   the friction level); a model that leaves a residual comparable to the
   friction level "does not explain the data", and the headline points at the
   largest structure of the residual scan.
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

from collections.abc import Callable, Sequence
import dataclasses
import os
import time
from typing import TYPE_CHECKING

import numpy as np

from . import criterion as cr
from . import structures as dm
from .candidates import base_structure, extend
from .crossval import cross_validate_structures, fit_all
from .data import BIN, load_data
from .gears import extended_model
from .gravity import gravity_untestable, linear_device
from .report import figure_drawers
from .scan import residual_scan
from .testability import inertia_noise_gain, untestable
from .velocity import fold_gears, simulate_windows, WINDOW
from ..effects import EFFECTS, UNREPRESENTABLE
from ..exceptions import ExcitationError, GearConfigError
from ..results import draw_figures, json_clean

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .crossval import CVResult
    from .data import DiagnosisData
    from ..gear import GearParams

__all__ = ['EFFECTS', 'UNREPRESENTABLE', 'ALPHA', 'MIN_GAIN', 'MIN_EXPLAINED', 'WINDOW',
           'Diagnosis', 'diagnose', 'base_structure', 'extend']

#: family-wise significance level (Holm over the candidates of a round)
ALPHA = 0.05
#: minimum relative reduction of the held-out torque RMSE to name a cause
MIN_GAIN = 0.03
#: ... or the least RMS torque it explains held out, as a fraction of the friction level
MIN_EXPLAINED = 0.01
#: contiguous position bands of the ripple's check across the travel
POSITION_BANDS = 4
#: greedy rounds at most
MAX_ROUNDS = 8


def _nl_params(s):
    out = []
    if s.nfs:
        out.append('vs')
    if s.dv_free:
        out.append('dv')
    if s.ripple:
        out.append('cyc')
    if s.presliding:
        out.append('ps')
    return out


def _g_nom(ctx, s, beta, names):
    g = 0.0
    for (kind, i), b in zip(names, beta):
        if kind == 'fc':
            g += b * float(np.mean(ctx.u ** i))
        elif kind == 'fc_load':
            g += b * float(np.mean(ctx.vl ** i))
    return max(g, 0.05 * ctx.data.friction_level)


def _refine(s, ctx, y):
    """Nonlinear parameters of ``s`` by grid on all data (one coordinate sweep)."""
    for p in _nl_params(s):
        s, beta, names, _ = fit_all(dm.grid_of(s, p, ctx), ctx, y)
    s, beta, names, pred = fit_all([s], ctx, y)
    return s, beta, names, pred


@dataclasses.dataclass
class Diagnosis:
    """
    Everything a diagnosis found (see :func:`diagnose`).

    Attributes
    ----------
    report : dict
        The ``report.json`` content.
    gear, data : GearParams, DiagnosisData
        The extended gear (the base when nothing was added) and the data.
    base, ctx : CandidateStructure, Context
        The base structure and the design context.
    rounds : list of dict
        The greedy rounds.
    base_cv, final_cv : CVResult
        Cross-validation of the base and the final structure.
    velocity, scan : dict
        Open-loop velocity of held-out windows; the residual scan
        (:func:`~friction_joint.diagnosis.scan.residual_scan`, or None).

    """

    report: dict
    gear: GearParams
    data: DiagnosisData
    base: dm.CandidateStructure
    ctx: dm.Context
    rounds: list[dict]
    base_cv: CVResult
    final_cv: CVResult
    velocity: dict
    scan: dict | None = None

    def to_dict(self) -> dict:
        """Return the report (``report.json`` content, plain JSON types)."""
        return json_clean(self.report)

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


def diagnose(paths: Sequence[str | os.PathLike], base: GearParams, *,
             effects: Sequence[str] = EFFECTS, joint_name: str | None = None,
             progress: Callable[[str], None] | None = None) -> Diagnosis:
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
    say = progress or (lambda m: None)
    timing = {}
    t0 = time.perf_counter()
    unknown = [e for e in effects if e not in EFFECTS]
    if unknown:
        raise GearConfigError(f'unknown effect(s) {", ".join(unknown)}; '
                              f'known: {", ".join(EFFECTS)}')
    data = load_data(paths, base, joint_name=joint_name)
    cr.reblock(data, cr.n_blocks(data.n_bins))
    ctx = dm.Context(base, data)
    if base.friction.model != 'static':
        ctx.ps_models = (base.friction.model,)
    timing['read_s'] = time.perf_counter() - t0
    say(f'read {len(paths)} recording(s): {data.n_bins} sliding bins of {1e3 * BIN:.0f} ms, '
        f'xi {data.xi.min():.2f}..{data.xi.max():.2f} degC ({timing["read_s"]:.2f} s)')
    why = untestable(data, base.gear_ratio, effects)
    if 'gravity' in effects:
        reason = gravity_untestable(data, dm.design(base_structure(base), ctx)[0],
                                    linear=linear_device(paths))
        if reason:
            why['gravity'] = reason
    testable = [e for e in effects if e not in why]
    if not testable:
        raise ExcitationError('no candidate effect is testable on these recordings: ' + '; '.join(
            f'{k}: {v}' for k, v in why.items()))
    if why:
        say('untestable: ' + '; '.join(f'{k}: {v}' for k, v in why.items()))

    t0 = time.perf_counter()
    y, block, k = data.y, data.block, data.n_blocks
    cur = base_structure(base)
    cur, beta, names, _ = _refine(cur, ctx, y)
    ctx.g_nom = _g_nom(ctx, cur, beta, names)
    base_cv = _cv(cur, None, ctx, y, block, k)
    base_struct = cur
    if 'inertia' in testable:
        spurious = inertia_noise_gain(data, base_cv.rmse ** 2)
        if spurious >= 0.5 * MIN_GAIN:
            why['inertia'] = (f'the encoder quantisation alone would let a refitted J gain '
                              f'{100 * spurious:.1f} % held out (errors in the acceleration '
                              f'regressor): a finer encoder or a lower noise is needed')
            testable.remove('inertia')
    timing['base_fit_s'] = time.perf_counter() - t0
    say(f'base: held-out torque RMSE {base_cv.rmse:.4f} Nm ({timing["base_fit_s"]:.2f} s)')

    t0 = time.perf_counter()
    pairs = cr.confounds(cr.effect_variables(data, ctx.travel), testable)
    rounds, named, added_entries = [], [], {}
    cur_cv = base_cv
    last_table = {}
    for rnd in range(1, MAX_ROUNDS + 1):
        table, cvs = {}, {}
        for eff in testable:
            if eff in named:
                continue
            ext = extend(cur, eff)
            if ext is None:
                table[eff] = {'effect': eff, 'applicable': False, 'gain': 0.0,
                              'significant': False, 'p_value': 1.0,
                              'note': 'already in the model structure'}
                continue
            s_new, param = ext
            cv = _cv(s_new, param, ctx, y, block, k)
            cvs[eff] = cv
            table[eff] = dict({'effect': eff, 'applicable': True}, **cr.compare(cur_cv, cv))
            _confound_entry(table[eff], pairs)
        tested = [e for e in table if table[e]['applicable']]
        adj = cr.holm([table[e]['p_value'] for e in tested]) if tested else []
        for e, pa in zip(tested, adj):
            table[e]['p_holm'] = float(pa)
            table[e]['significant'] = bool(pa < ALPHA and cr.relevant(
                table[e]['gain_raw'], table[e]['explained_torque'], data.friction_level,
                MIN_GAIN, MIN_EXPLAINED))
            table[e]['round'] = rnd
        for e in tested:            # one variable with a named effect: not told apart from it
            other = [n for n in named if n in table[e].get('confounded_with', {})]
            if table[e]['significant'] and other:
                table[e]['significant'] = False
                table[e]['note'] = (f'confounded with the named {other[0]} in this recording: '
                                    'not told apart from it')
        if table.get('position_ripple', {}).get('significant'):
            _ripple_across_travel(table['position_ripple'], cur, ctx, y)
        sig = [e for e in tested if table[e]['significant']]
        rounds.append({'round': rnd, 'model_rmse': cur_cv.rmse, 'candidates': table,
                       'cv': cvs, 'cur_cv': cur_cv, 'structure': cur})
        against = 'the base model' if not named else 'the model with ' + ', '.join(named)
        say(f'round {rnd} (held-out gain against {against}; * significant): ' + ', '.join(
            f'{e} {100 * table[e]["gain_raw"]:+.1f} %{"*" if table[e]["significant"] else ""} '
            f'(p_holm {table[e].get("p_holm", 1):.2g})' for e in tested))
        last_table = table
        if not sig:
            break
        best = cr.prefer(sig, table, pairs)
        if best != max(sig, key=lambda e: table[e]['gain_raw']):
            table[best]['note'] = ('preferred to the confounded ' + ', '.join(
                e for e in sig if e != best and e in table[best].get('confounded_with', {}))
                + ': the measured cause first')
        named.append(best)
        added_entries[best] = table[best]
        s_new, param = extend(cur, best)
        cur, beta, names, _ = _refine(s_new, ctx, y)
        cur_cv = _cv(cur, None, ctx, y, block, k)
        say(f'  added {best}: held-out torque RMSE {cur_cv.rmse:.4f} Nm')
    timing['candidates_s'] = time.perf_counter() - t0

    t0 = time.perf_counter()
    sequence = [r['structure'] for r in rounds]
    if not sequence or sequence[-1] is not cur:
        sequence.append(cur)
    diag_cv = cur_cv
    # the gear file has no key for some effects: extended.yaml is fitted without them
    ext = extended_model(base, [s.with_(drift=0) for s in sequence], ctx, y)
    gear, final, coef = ext['gear'], ext['structure'], ext['coef']
    kept = max(ext['kept'], 0)
    physical = {e: i < kept for i, e in enumerate(named)}
    if final != cur:
        cur_cv = base_cv if final == base_struct else _cv(final, None, ctx, y, block, k)
    timing['extended_fit_s'] = time.perf_counter() - t0

    t0 = time.perf_counter()
    vb_sim, meas, folds = simulate_windows(data, *fold_gears(base, base_cv, ctx, data))
    if kept:
        ve_sim, _, _ = simulate_windows(data, *fold_gears(base, cur_cv, ctx, data))
    else:
        ve_sim = vb_sim
    timing['velocity_sim_s'] = time.perf_counter() - t0

    def vrmse(sim):
        return float(np.sqrt(np.mean((sim - meas) ** 2))) if sim.size else None

    candidates = _candidates(effects, why, named, added_entries, last_table, physical,
                             ext['reason'])
    notes = []
    if ext['kept'] < 0:
        notes.append('extended.yaml is the base file as given: ' + ext['reason'])
    elif kept < len(named):
        notes.append(f'extended.yaml leaves out {", ".join(named[kept:])}: ' + ext['reason'])
    for e in named:
        if e in UNREPRESENTABLE:
            notes.append(f'{e} is {UNREPRESENTABLE[e]}; the model with it has a held-out torque '
                         f'RMSE of {diag_cv.rmse:.4g} Nm, extended.yaml {cur_cv.rmse:.4g} Nm')
    if 'gravity' in coef:
        lever = coef['gravity'].get('lever', {})
        notes.append('gravity: extended.yaml corrects the lever section to m g l = '
                     f'{lever.get("mgl", float("nan")):.4g} Nm at angle_offset '
                     f'{lever.get("angle_offset", float("nan")):.4g} rad (base '
                     f'{lever.get("mgl_base", float("nan")):.4g} Nm at '
                     f'{lever.get("angle_offset_base", float("nan")):.4g} rad)' +
                     ('; the recordings carry /link_torque, so the term stands for a '
                      'position-dependent torque the link side does not measure'
                      if data.link_torque else ''))
    t0 = time.perf_counter()
    scan = residual_scan(data, y - diag_cv.pred)
    timing['residual_scan_s'] = time.perf_counter() - t0
    level = data.friction_level
    adequacy = {'base': cr.adequacy(y, base_cv.pred, level),
                'extended': cr.adequacy(y, cur_cv.pred, level)}
    report = {
        'named_causes': named,
        'candidates': candidates,
        'baseline': {'torque_rmse': base_cv.rmse, 'velocity_rmse': vrmse(vb_sim)},
        'extended': {'torque_rmse': cur_cv.rmse, 'velocity_rmse': vrmse(ve_sim)},
        'criterion': {
            'statistic': 'd_k = log(MSE_current,k / MSE_candidate,k) of held-out torque MSE per '
                         'contiguous time block k',
            'test': 'one-sided Wilcoxon signed-rank test of the d_k over the blocks (H0: the '
                    'candidate does not predict held-out blocks better; robust to one bad '
                    'block)',
            'multiplicity': 'Holm-Bonferroni over the candidates of each greedy round',
            'alpha': ALPHA, 'min_gain': MIN_GAIN, 'min_explained': MIN_EXPLAINED,
            'blocks': k,
            'gain': '1 - RMSE_candidate / RMSE_current, pooled held-out torque RMSE',
            'selection': 'greedy: add the significant candidate with the largest gain (of '
                         'confounded significant candidates the measured cause first), refit, '
                         'test the rest again until none is significant',
            'confound_rank_correlation': cr.CONFOUND_RHO},
        'adequacy': adequacy,
        'confounds': pairs,
        'rounds': [{'round': r['round'], 'model_torque_rmse': r['model_rmse'],
                    'candidates': list(r['candidates'].values())} for r in rounds],
        'data': {'recordings': [r.path for r in data.recordings], 'bins': data.n_bins,
                 'bin_s': BIN, 'sliding_s': data.n_bins * BIN,
                 'xi_range': [float(data.xi.min()), float(data.xi.max())],
                 'torque_source': 'link_torque' if data.link_torque else 'lever model',
                 'velocity_windows': int(meas.shape[0]), 'window_s': WINDOW,
                 'has_temperature': bool(data.has_temperature),
                 'scales': {'v_stick': data.v_stick, 'resolution': data.resolution,
                            'friction_level': data.friction_level, 'stroke': data.stroke,
                            **{k: getattr(data, k, None) for k in (
                                'velocity_noise', 'quantisation_noise', 'standstill_noise',
                                'standstill_fraction', 'cutoff')}}},
        'base_fit': dm.coefficients(base_struct, *_refit(base_struct, ctx, y)),
        'extended_fit': coef,
        'extended_effects': [e for e in named[:kept] if e not in UNREPRESENTABLE],
        'residual_scan': scan['table'],
        'untestable': dict(why),
        'notes': notes,
        'timing': timing,
    }
    if final != cur:
        report['diagnosed'] = {'effects': list(named), 'torque_rmse': diag_cv.rmse,
                               'fit': dm.coefficients(cur, *_refit(cur, ctx, y))}
    report['headline'] = cr.headline(report)
    vel = {'base': vb_sim, 'extended': ve_sim, 'measured': meas, 'folds': folds}
    return Diagnosis(report, gear, data, base, ctx, rounds, base_cv, cur_cv, vel, scan)


def _candidates(effects, why, named, added, last, physical, reason):
    """Candidate table of the report: one entry per effect, testable or not."""
    out = []
    for eff in effects:
        if eff in why:
            out.append({'effect': eff, 'testable': False, 'reason': why[eff], 'gain': 0.0,
                        'significant': False})
            continue
        entry = dict(added.get(eff) or last.get(eff) or
                     {'effect': eff, 'gain': 0.0, 'significant': False})
        entry['testable'] = True
        entry['significant'] = eff in named
        if eff in named:
            entry['physical'] = bool(physical[eff])
            if not physical[eff]:
                entry['reason'] = reason
            elif eff in UNREPRESENTABLE:
                entry['representable'] = False
                entry['reason'] = UNREPRESENTABLE[eff]
        out.append(entry)
    return out


def _ripple_across_travel(entry, cur, ctx, y):
    """
    Keep a significant ripple only if it also predicts positions its fit has not seen.

    A ripple repeats along the travel: fitted on all but one of
    :data:`POSITION_BANDS` contiguous position bands, it predicts the held-out
    band.  Harmonics fitted to a slow, non-periodic position dependence do not:
    they gain on time blocks (which all cover the stroke) but not across the
    travel.  The ripple (its period chosen on the training bands) must gain at
    least :data:`MIN_GAIN` there too, or explain :data:`MIN_EXPLAINED` of the
    friction level.
    """
    q = ctx.data.average(ctx.data.q)
    edges = np.quantile(q, np.linspace(0.0, 1.0, POSITION_BANDS + 1)[1:-1])
    band = np.searchsorted(edges, q)
    s_new, param = extend(cur, 'position_ripple')
    base = _cv(cur, None, ctx, y, band, POSITION_BANDS)
    cand = _cv(s_new, param, ctx, y, band, POSITION_BANDS)
    gain = 1.0 - cand.rmse / base.rmse
    entry['position_bands_gain'] = float(gain)
    if not cr.relevant(gain, cr.explained_torque(base.rmse, cand.rmse),
                       ctx.data.friction_level, MIN_GAIN, MIN_EXPLAINED):
        entry['significant'] = False
        entry['note'] = (f'not periodic across the travel: fitted on {POSITION_BANDS - 1} of '
                         f'{POSITION_BANDS} position bands it gains {100 * gain:.1f} % on the '
                         'held-out band (a slow position dependence, see the residual scan)')


def _confound_entry(entry, pairs):
    """Add to a candidate's entry the candidates it is confounded with in this recording."""
    found = {}
    for pair in pairs:
        if entry['effect'] in pair['effects']:
            other = next(e for e in pair['effects'] if e != entry['effect'])
            found[other] = {'rank_correlation': pair['rank_correlation'],
                            'separate_by': pair['separate_by']}
    if found:
        entry['confounded_with'] = found


def _refit(s, ctx, y):
    _, beta, names, _ = fit_all([s], ctx, y)
    return beta, names, ctx


def _cv(s, param, ctx, y, block, k):
    return cross_validate_structures(dm.grid_of(s, param, ctx), ctx, y, block, k)
