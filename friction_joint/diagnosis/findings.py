# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Plain-language findings of a diagnosis: what is wrong, in physical units, and what to do next.

Every number is computed from the fitted model with all named effects
(the result's ``diagnosed.fit`` when it differs from ``extended.yaml``, else its
``extended_fit``), the base fit and the data's ranges (temperature,
sliding speed, load, position, accumulated travel); nothing is hard-coded for a
gear.  A change over a range is given against the value at the lower end of
the range, and the sentence says so.  One
sentence generator per effect kind (:data:`SENTENCES`), a generic
one for any other.  The text only words what the diagnosis computed: no number
of the diagnosis and no named effect is changed here.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
import math
import os
from typing import Any, TYPE_CHECKING

import numpy as np

from .result import DataRanges
from .testability import DRIFT_STROKES, MIN_DIRECTION, MIN_REVERSALS, MIN_XI_SPAN, SPEED_RATIO
from ..bag.provenance import import_mapping, ImportedUnits
from ..bag.units import SI

if TYPE_CHECKING:
    from .core import DiagnosisCore
    from .criterion import Verdict
    from .result import DiagnosisResult
    from .verdicts import CandidateVerdict

#: the fitted coefficients (:func:`~friction_joint.diagnosis.structures.coefficients`)
Coefficients = Mapping[str, Any]

__all__ = ['logged_unit_lines', 'data_ranges', 'effect_finding', 'finding_lines',
           'next_step_lines', 'candidate_summary', 'RECORD_ADVICE', 'SENTENCES']

#: effect -> what to record so that an untestable candidate can be tested (plain words); the
#: limits are the testability rules' own (:mod:`~friction_joint.diagnosis.testability`)
RECORD_ADVICE = {
    'thermal': 'record /joint_temperature while the housing temperature changes by several '
               f'degC (at least {MIN_XI_SPAN:g} degC while sliding; runs at several '
               'temperatures, e.g. cold and warmed up)',
    'load': 'record runs under different loads (payload, lever angle) with the load measured '
            '(/link_torque from a load sensor, or a lever model in the gear file)',
    'position_ripple': 'move over a longer travel, several tooth periods, visiting all of '
                       'each period',
    'nonlinear_viscous': f'slide at speeds spanning at least a factor {SPEED_RATIO:g}, slow '
                         'ones included',
    'stribeck': f'slide at speeds spanning at least a factor {SPEED_RATIO:g}, including very '
                'slow ones just above breakaway',
    'presliding': f'include velocity reversals (small back-and-forth motions, at least '
                  f'{MIN_REVERSALS})',
    'inertia': 'accelerate harder (faster changes of speed), or use a finer encoder',
    'asymmetry': f'move in both directions (at least {100 * MIN_DIRECTION:g} % of the time '
                 'each way)',
    'drift': f'record longer runs (an accumulated travel of at least {DRIFT_STROKES:g} strokes)',
    'gravity': 'travel over a larger angle on a rotary joint',
}


def _pct(x: float) -> str:
    return f'{abs(100 * x):.0f} %'


def _rises(x: float, up: str = 'rises', down: str = 'falls') -> str:
    return up if x >= 0 else down


def _poly(c: Sequence[float] | None, x: float) -> float:
    return float(np.polynomial.polynomial.polyval(x, c)) if c else 0.0


def logged_unit_lines(paths: Sequence[str], result: DiagnosisResult) -> list[str]:
    """
    Return the report's key numbers in the units the recordings were imported in.

    Empty for recordings not imported (``friction_joint import``) or imported in SI.
    The first imported recording's units are used (a note says so when others differ).

    Parameters
    ----------
    paths : sequence of str
        The recordings.
    result : DiagnosisResult
        The diagnosis's result (its scales, adequacy and temperature range).

    """
    mappings = [m for m in map(import_mapping, paths) if m]
    if not mappings:
        return []
    units = ImportedUnits(mappings[0])
    scales, adequacy = result.data.scales, result.adequacy
    items = [('friction level', 'torque', scales.friction_level),
             ('held-out torque RMSE of the base model', 'torque', adequacy.base.rmse),
             ('held-out torque RMSE of the extended model', 'torque', adequacy.extended.rmse),
             ('sliding above', 'velocity', scales.v_stick),
             ('stroke', 'position', scales.stroke)]
    if result.data.has_temperature:
        items += [('temperature from', 'temperature', result.data.xi_range[0]),
                  ('temperature to', 'temperature', result.data.xi_range[1])]
    lines = [f'{label}: {quoted} ({value:.4g} {SI[quantity]})' for label, quantity, value in items
             if (quoted := units.quote(quantity, value)) is not None]
    if lines and any(ImportedUnits(m).units != units.units for m in mappings[1:]):
        lines.append(f'(the recordings were imported in different units; quoted in those of '
                     f'{paths[0]})')
    return lines


def data_ranges(diag: DiagnosisCore) -> DataRanges:
    """
    Return the data's ranges the findings speak of, from the sliding bins.

    ``temperature`` (min, max degC; None without a temperature signal), ``speed``
    (5..95 % of the sliding speeds, rad/s), ``load`` (5..95 % of abs(tau_ext), Nm),
    ``position`` (min, max rad), ``travel`` (accumulated travel, rad), ``level``
    (friction level, Nm) and ``inertia`` (the base's J).

    Parameters
    ----------
    diag : DiagnosisCore
        The diagnosis (its data, temperature range and base structure).

    Returns
    -------
    DataRanges

    """
    data, summary = diag.data, diag.result.data
    qd = np.abs(data.average(data.qd))
    q = data.average(data.q)
    tl = np.abs(data.average(data.tl))
    xi = summary.xi_range
    dq = np.abs(np.diff(np.asarray(data.qf, dtype=float)))
    travel = float(np.sum(dq[data.piece[1:] == data.piece[:-1]]))     # not across gaps
    return DataRanges(
        temperature=(xi[0], xi[1]) if summary.has_temperature else None,
        speed=(float(np.percentile(qd, 5)), float(np.percentile(qd, 95))),
        load=(float(np.percentile(tl, 5)), float(np.percentile(tl, 95))),
        position=(float(q.min()), float(q.max())),
        travel=travel, level=float(data.friction_level),
        inertia=float(getattr(diag.base, 'inertia', float('nan'))))


def _mid_t(rng: DataRanges) -> float:
    t = rng.temperature
    return 0.5 * (t[0] + t[1]) if t else 0.0


def _thermal(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    if not rng.temperature:
        return 'Thermal: friction changes with the housing temperature'
    lo, hi = rng.temperature
    parts, base_parts = [], []
    for key, name in (('fc', 'F_c'), ('fs', 'F_s'), ('fv', 'F_v')):
        c = fit.get(key)
        if not c or _poly(c, lo) <= 0:
            continue
        ch = (_poly(c, hi) - _poly(c, lo)) / _poly(c, lo)     # of the value at the lower end
        parts.append(f'{name} {_rises(ch)} about {_pct(ch)}')
        b = base.get(key) or []
        if len(b) > 1 and _poly(b, lo) > 0:
            bch = (_poly(b, hi) - _poly(b, lo)) / _poly(b, lo)
            base_parts.append(f'{name} {100 * bch:+.0f} %')
    what = ' and '.join(parts) if parts else 'friction changes'
    base_text = ('the base model has ' + ', '.join(base_parts) if base_parts
                 else 'the base model keeps them constant')
    ref = f'of the values at {lo:.0f} degC; ' if parts else ''
    return f'Thermal: {what} from {lo:.0f} to {hi:.0f} degC ({ref}{base_text})'


def _load(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    lo, hi = rng.load
    fc = _poly(fit.get('fc'), _mid_t(rng))
    terms = []
    for key, name in (('fc_load', 'F_c'), ('fv_load', 'F_v')):
        c = fit.get(key) or []
        if not c:
            continue
        d = sum(v * (hi ** (j + 1) - lo ** (j + 1)) for j, v in enumerate(c))
        ref = fc if key == 'fc_load' else _poly(fit.get('fv'), _mid_t(rng))
        rel = f' ({_pct(d / ref)} of {name})' if ref > 0 else ''
        unit = ' Nm' if key == 'fc_load' else ' Nm s/rad'
        terms.append(f'{name} {_rises(d)} by {abs(d):.3g}{unit}{rel}')
    what = ' and '.join(terms) if terms else 'friction changes'
    return (f'Load: {what} as the load torque goes from {lo:.3g} to {hi:.3g} Nm '
            f'(the base model ignores the load)')


def _ripple(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    r = fit.get('position_ripple') or {}
    amp = (r.get('amplitude') or [float('nan')])[0]
    cyc = r.get('cycles_per_rev', float('nan'))
    per = 2e3 * math.pi / cyc if cyc else float('nan')
    return (f'Position ripple: the torque varies by +-{amp:.3g} Nm ({_pct(amp / rng.level)} '
            f'of the friction level) periodically with position, {cyc:.4g} times per output '
            f'revolution (every {per:.3g} mrad), over positions {rng.position[0]:.2f} to '
            f'{rng.position[1]:.2f} rad')


def _viscous_torque(fit: Coefficients, v: float, dv: float, t: float) -> float:
    return _poly(fit.get('fv'), t) * float(abs(v) ** dv)


def _nonlinear_viscous(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    t = _mid_t(rng)
    dv = _poly(fit.get('delta_v') or [1.0], t)
    lo, hi = rng.speed
    a, b = _viscous_torque(fit, lo, dv, t), _viscous_torque(fit, hi, dv, t)
    way = 'less' if dv < 1 else 'more'
    return (f'Nonlinear viscous: the viscous torque grows as speed^{dv:.2f}, {way} than in '
            f'proportion to speed (the base model: speed^1): {a:.3g} Nm at {lo:.3g} rad/s, '
            f'{b:.3g} Nm at {hi:.3g} rad/s')


def _stribeck(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    t = _mid_t(rng)
    fs, fc = _poly(fit.get('fs'), t), _poly(fit.get('fc'), t)
    vs = _poly(fit.get('vs'), t) / fit.get('velocity_scale', 1.0)    # rad/s of the joint
    way = 'above' if fs >= fc else 'below'
    rel = f' ({_pct(fs / fc - 1)} {way} F_c = {fc:.3g} Nm)' if fc > 0 else ''
    moves = 'falls' if fs >= fc else 'rises'
    had = 'a different' if base.get('fs') else 'no such'
    return (f'Stribeck: the friction at breakaway F_s = {fs:.3g} Nm{rel} {moves} to the '
            f'Coulomb level within about {vs:.3g} rad/s of sliding speed (the base model has '
            f'{had} low-speed level; sliding speeds {rng.speed[0]:.3g} to '
            f'{rng.speed[1]:.3g} rad/s)')


def _presliding(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    p = fit.get('presliding') or {}
    k = p.get('stiffness', float('nan'))
    fc = _poly(fit.get('fc'), _mid_t(rng))
    length = 1e3 * fc / k if k and fc > 0 else float('nan')
    return (f'Pre-sliding: after a reversal the friction builds up over about {length:.3g} mrad '
            f'of travel ({p.get("model", "?")} model, stiffness {k:.4g} Nm/rad) instead of '
            'switching sign at once')


def _inertia(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    dj, j = fit.get('d_inertia', float('nan')), rng.inertia
    rel = f', {_pct(dj / j)} {"more" if dj >= 0 else "less"} than configured' if j > 0 else ''
    return (f'Inertia: the joint behaves as if its inertia were {j + dj:.4g} kg m^2 instead of '
            f'the configured {j:.4g} kg m^2{rel}')


def _asymmetry(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    off = fit.get('offset', float('nan'))
    way = 'positive' if off >= 0 else 'negative'
    return (f'Asymmetry: friction is about {2 * abs(off):.3g} Nm ({_pct(2 * off / rng.level)} '
            f'of the friction level) larger moving in the {way} direction than in the other '
            f'(a constant torque offset of {off:+.3g} Nm, which sliding alone cannot tell from '
            'a direction-dependent friction)')


def _drift(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    d = (fit.get('drift') or {}).get('fc_drift') or []
    # shifted Legendre P1(s) = 2 s - 1, P2(s) = 6 s^2 - 6 s + 1: start (s=0) to end (s=1)
    start = sum(c * (-1) ** (j + 1) for j, c in enumerate(d))
    change = sum(d) - start
    fc = _poly(fit.get('fc'), _mid_t(rng))
    rel = f' ({_pct(change / fc)} of F_c)' if fc > 0 else ''
    return (f'Drift: the Coulomb friction {_rises(change)} by {abs(change):.3g} Nm{rel} over '
            f'the {rng.travel:.3g} rad of accumulated travel, more than the temperature '
            'explains (run-in, wear or lubricant redistribution)')


def _gravity(fit: Coefficients, base: Coefficients, rng: DataRanges) -> str:
    g = fit.get('gravity') or {}
    lever = g.get('lever')
    pose = g.get('pose')
    if pose:
        lo, hi = rng.position
        c = pose['center']
        x = np.linspace(lo, hi, 41)
        tq = np.polynomial.polynomial.polyval(x - c, pose['coefficients'])
        return (f'Gravity (pose-dependent load): a direction-independent torque smooth in '
                f'position, {tq.min():.3g} to {tq.max():.3g} Nm over positions {lo:.2f} to '
                f'{hi:.2f} rad, is missing from the base model; over so short a stroke it is '
                'any pose-dependent load error (gravity, a payload, a cable, the gravity '
                'model), not necessarily the lever')
    if lever:
        mgl, mgl0 = lever.get('mgl', float('nan')), lever.get('mgl_base', float('nan'))
        rel = f' ({100 * (mgl / mgl0 - 1):+.0f} %)' if mgl0 else ''
        return (f'Gravity: the lever torque m g l is {mgl:.4g} Nm{rel} instead of {mgl0:.4g} Nm '
                f'in the base model, with its zero at {lever.get("angle_offset", 0.0):.3g} rad '
                f'instead of {lever.get("angle_offset_base", 0.0):.3g} rad')
    amp = math.hypot(g.get('sin', 0.0), g.get('cos', 0.0))
    return (f'Gravity: a torque of amplitude {amp:.3g} Nm varying as the sine of the angle '
            f'over positions {rng.position[0]:.2f} to {rng.position[1]:.2f} rad is '
            'missing from the base model')


#: effect -> sentence generator ``f(fit, base_fit, ranges)`` (the finding without its score)
SENTENCES: dict[str, Callable[[Coefficients, Coefficients, DataRanges], str]] = {
    'thermal': _thermal, 'load': _load, 'position_ripple': _ripple,
    'nonlinear_viscous': _nonlinear_viscous, 'stribeck': _stribeck, 'presliding': _presliding,
    'inertia': _inertia, 'asymmetry': _asymmetry, 'drift': _drift, 'gravity': _gravity,
}


def _round_rmse(result: DiagnosisResult, rnd: int) -> float:
    for r in result.rounds:
        if r.round == rnd:
            return r.model_torque_rmse
    return result.baseline.torque_rmse


def effect_finding(effect: str, result: DiagnosisResult, ranges: DataRanges) -> str:
    """
    Return the plain-language finding on one named effect (one sentence, physical units).

    Size, direction and range come from the fitted model with all named effects and the
    data's ``ranges`` (:func:`data_ranges`); the sentence ends with the RMS torque the
    effect explains held out against the model's error at the round it was added.

    Parameters
    ----------
    effect : str
        The named effect.
    result : DiagnosisResult
        The diagnosis's result (its fits, candidate verdicts and rounds).
    ranges : DataRanges
        The data's ranges.

    Returns
    -------
    str

    """
    fit = (result.diagnosed.fit if result.diagnosed and result.diagnosed.fit
           else result.extended_fit)
    gen = SENTENCES.get(effect)
    try:
        text = gen(fit, result.base_fit, ranges) if gen else None
    except (KeyError, IndexError, TypeError, ValueError, ZeroDivisionError):
        text = None
    if text is None:
        text = f'{effect.replace("_", " ").capitalize()}: missing from the base model'
    c = result.candidate(effect)
    explained = c.explained_torque if c else None
    if c and explained is not None:
        before = _round_rmse(result, 1 if c.round is None else c.round)
        text += (f'; explains {explained:.2g} Nm RMS of the {before:.2g} Nm of model error '
                 'held out')
    return text + '.'


def finding_lines(verdict: Verdict, result: DiagnosisResult,
                  ranges: DataRanges | None = None) -> list[str]:
    """
    Return the ``## Findings`` Markdown section, worded from the diagnosis's verdict.

    Parameters
    ----------
    verdict : Verdict
        The diagnosis's verdict (:func:`~friction_joint.diagnosis.criterion.verdict`).
    result : DiagnosisResult
        The diagnosis's result.
    ranges : DataRanges, optional
        The data's ranges (:func:`data_ranges`); needed when an effect is named.

    Returns
    -------
    list of str

    """
    lines = ['## Findings', '']
    fit = verdict.extended.text
    if verdict.named:
        assert ranges is not None, 'the data ranges are needed to word a named effect'
        lines += [f'* {effect_finding(eff, result, ranges)}' for eff in verdict.named]
        lines += ['', 'Held out: every number above comes from a model fitted without the '
                  'time block it is scored on, so it measures prediction, not curve fitting.',
                  '']
        if not verdict.explains:
            lines += [f'Even with {", ".join(verdict.named)} the model does not explain the '
                      f'measured friction torque ({fit}).  {verdict.structure}', '']
        return lines
    if not verdict.explains:
        text = (f'The base model does not explain the measured friction torque ({fit}), and no '
                'candidate effect is confirmed to improve it held out: what it misses lies '
                f'outside the candidates or beyond them.  {verdict.structure}')
    elif verdict.unconfirmed:
        text = ('No missing effect passes the criterion, but '
                f'{verdict.unconfirmed_text}: not consistent enough over the time blocks to '
                'name it; the recordings are too short or too uneven to confirm it.')
    else:
        text = ('No missing effect found: the base model explains the measured friction '
                f'torque ({fit}) as well as any ' + ('tested ' if verdict.untestable else '') +
                'candidate would, within the resolution of the recordings.')
    if verdict.unconfirmed and not verdict.explains:
        text += f'  Not named: {verdict.unconfirmed_text}, not consistent over the time blocks.'
    if verdict.untestable:
        text += (f'  Not tested: {", ".join(e for e, _ in verdict.untestable)} (these recordings '
                 'cannot tell them; see What to do next).')
    return lines + [text, '']


def next_step_lines(verdict: Verdict, result: DiagnosisResult, out_dir: str | None,
                    recordings: Sequence[str]) -> list[str]:
    """
    Return the ``## What to do next`` Markdown section, worded from the diagnosis's verdict.

    Parameters
    ----------
    verdict : Verdict
        The diagnosis's verdict (:func:`~friction_joint.diagnosis.criterion.verdict`).
    result : DiagnosisResult
        The diagnosis's result.
    out_dir : str or None
        The result directory, as given (None: ``DIR``).
    recordings : list of str
        The recordings, as given.

    Returns
    -------
    list of str

    """
    base_dir = os.path.normpath(out_dir) if out_dir else 'DIR'
    ext = base_dir + '/extended.yaml'
    recs = ' '.join(os.path.normpath(r) for r in recordings)
    lines = ['## What to do next', '']
    if verdict.named and verdict.written:
        lines += [f'* Use `{ext}` as the gear file: it is the base model with '
                  f'{", ".join(verdict.written)} added, fitted on these recordings, and '
                  'loads wherever a gear file does (`--model`, the gear file parameter of '
                  'the nodes).  Check it: diagnosing again with it should name nothing:',
                  '', f'        friction_joint diagnose {recs} --model {ext} --out '
                  f'{base_dir}_check', '']
        refusal = result.identify.reason if result.identify else None
        if refusal:             # identify would refuse these recordings: never suggest it
            lines += ['* To identify its coefficients with standard errors, record an '
                      'identification run first (constant-velocity plateaus in both directions '
                      'with the housing temperature, e.g. `friction_joint experiment '
                      'identification`) and identify on it with this file as the structure; '
                      f'these recordings cannot carry it: {refusal}', '']
        else:
            lines += ['* To identify its coefficients with standard errors and the pre-sliding '
                      'parameters on your own runs, use it as the structure:', '',
                      f'        friction_joint identify {recs} --model {ext} --out '
                      'identified.yaml', '']
    elif verdict.named:
        lines += ['* `extended.yaml` is the base model: the named effects cannot be written as '
                  'a gear file (see the notes below); keep the base model and the findings in '
                  'mind.', '']
    elif not verdict.explains:
        lines += ['* Do not rely on the base model as it is: its held-out error is comparable '
                  'to the friction level and no candidate effect is confirmed to reduce it.  '
                  f'{verdict.structure}  Check the recordings (sign and units of the torque, '
                  'the external torque) and the configuration of the base model, and look at the '
                  'residual scan below.', '']
    elif verdict.unconfirmed:
        u = verdict.unconfirmed.effect
        lines += [f'* Keep the base model for now; to confirm or rule out {u}, record more '
                  f'({RECORD_ADVICE.get(u, "longer runs")}) and diagnose again.', '']
    else:
        lines += ['* Keep the base model; nothing to change.', '']
    if verdict.named and not verdict.explains:
        lines += ['* Even the model with the named effects leaves a held-out error comparable '
                  f'to the friction level.  {verdict.structure}  Look there (the residual scan '
                  'below) before relying on it.', '']
    for eff in verdict.named:
        c = result.candidate(eff)
        if c and (c.representable is False or c.physical is False):
            lines += [f'* {eff}: not in `extended.yaml` ({c.reason or ""}).', '']
    if verdict.untestable:
        lines += ['* Effects these recordings cannot test, and what to record to test them:', '']
        for eff, why in verdict.untestable:
            advice = RECORD_ADVICE.get(eff, 'record data that covers the variable of this effect')
            if eff == 'gravity' and 'linear device' in why:
                advice = 'nothing to record: a linear device has no gravity torque'
            lines.append(f'  * {eff} ({why}): {advice}.')
        lines.append('')
    for pair in result.confounds:
        a, b = pair.effects
        if a not in verdict.named and b not in verdict.named:
            continue                # neither named: nothing in the findings to separate
        lines += [f'* {a} and {b} cannot be told apart in these recordings (they change '
                  f'together); to separate them: {pair.separate_by}.', '']
    return lines


def candidate_summary(result: DiagnosisResult) -> list[str]:
    """
    Return sentences for candidates whose first-round gain looks large but that were not named.

    A gain in round 1 is against the base model; after the named effects are in the
    model the same candidate is tested again and its entry in the table is from that
    last round.  These sentences say both numbers and why the candidate is not named.

    Parameters
    ----------
    result : DiagnosisResult
        The diagnosis's result (its rounds, candidates and criterion).

    Returns
    -------
    list of str

    """
    out: list[str] = []
    if not result.rounds:
        return out
    first = {c.effect: c for c in result.rounds[0].candidates}
    min_gain, alpha = result.criterion.min_gain, result.criterion.alpha
    named = result.named_causes
    for c in result.candidates:
        eff = c.effect
        f = first.get(eff)
        if eff in named or not f or _raw(f) < min_gain:
            continue
        why = _not_named_because(c, f, named, alpha)
        later = (f'; with {", ".join(named)} in the model it gains '
                 f'{100 * c.gain:.1f} % (round {"-" if c.round is None else c.round})'
                 if named and c.testable is not False else '')
        out.append(f'{eff} gained {100 * _raw(f):.1f} % against the base model (round 1) '
                   f'but is not named: ' + '; '.join(why) + later + '.')
    return out


def _raw(c: CandidateVerdict) -> float:
    return 0.0 if c.gain_raw is None else c.gain_raw


def _not_named_because(c: CandidateVerdict, f: CandidateVerdict, named: Sequence[str],
                       alpha: float) -> list[str]:
    """Return why ``c`` (first-round verdict ``f``) is not named, in words."""
    why = []
    p_holm = 1.0 if f.p_holm is None else f.p_holm
    if p_holm >= alpha:
        why.append(f'its improvement was not consistent over the time blocks (better in '
                   f'{_or_q(f.blocks_improved)} of {_or_q(f.blocks)}, p (Holm) '
                   f'{p_holm:.2g} >= {alpha:g})')
    conf = [e for e in f.confounds if e in named]
    if conf:
        why.append(f'it changes together with the named {", ".join(conf)} in this '
                   'recording, so it was showing that effect')
    if c.note and not conf:
        why.append(c.note)
    if f.significant and not conf:
        why.append('it was significant in round 1, but not once '
                   f'{", ".join(named)} was in the model')
    if not why:
        why.append('it was not significant')
    return why


def _or_q(n: int | None) -> str:
    return '?' if n is None else str(n)
