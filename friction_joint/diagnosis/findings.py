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
Plain-language findings of a diagnosis: what is wrong, in physical units, and what to do next.

Every number is computed from the fitted model with all named effects
(``report['diagnosed']['fit']`` when it differs from ``extended.yaml``, else
``report['extended_fit']``), the base fit and the data's ranges (temperature,
sliding speed, load, position, accumulated travel); nothing is hard-coded for a
gear.  A change over a range is given against the value at the middle of the
range (as :mod:`friction_joint.experiments.hidden` sizes its effects).  One
sentence generator per effect kind (:data:`SENTENCES`), a generic
one for any other.  The text only words what the diagnosis computed: no number
of the diagnosis and no named effect is changed here.
"""
import math
import os

import numpy as np

__all__ = ['data_ranges', 'effect_finding', 'finding_lines', 'next_step_lines',
           'candidate_summary', 'RECORD_ADVICE', 'SENTENCES']

#: effect -> what to record so that an untestable candidate can be tested (plain words)
RECORD_ADVICE = {
    'thermal': 'record /joint_temperature while the housing temperature changes by several '
               'degC (runs at several temperatures, e.g. cold and warmed up)',
    'load': 'record runs under different loads (payload, lever angle) with the load measured '
            '(/link_torque from a load sensor, or a lever model in the gear file)',
    'position_ripple': 'move over a longer travel, several tooth periods, visiting all of '
                       'each period',
    'nonlinear_viscous': 'slide at speeds spanning at least a factor 5, slow ones included',
    'stribeck': 'slide at speeds spanning at least a factor 5, including very slow ones '
                'just above breakaway',
    'presliding': 'include velocity reversals (small back-and-forth motions)',
    'inertia': 'accelerate harder (faster changes of speed), or use a finer encoder',
    'asymmetry': 'move in both directions (at least 5 % of the time each way)',
    'drift': 'record longer runs (an accumulated travel of at least 5 strokes)',
    'gravity': 'travel over a larger angle (at least about 0.3 rad) on a rotary joint',
}


def _pct(x):
    return f'{abs(100 * x):.0f} %'


def _rises(x, up='rises', down='falls'):
    return up if x >= 0 else down


def _poly(c, x):
    return float(np.polynomial.polynomial.polyval(x, c)) if c else 0.0


def data_ranges(diag):
    """
    Return the data's ranges the findings speak of, from the sliding bins.

    ``temperature`` (min, max degC; None without a temperature signal), ``speed``
    (5..95 % of the sliding speeds, rad/s), ``load`` (5..95 % of abs(tau_ext), Nm),
    ``position`` (min, max rad), ``travel`` (accumulated travel, rad), ``level``
    (friction level, Nm) and ``inertia`` (the base's J).
    """
    data, rep = diag.data, diag.report
    qd = np.abs(data.average(data.qd))
    q = data.average(data.q)
    tl = np.abs(data.average(data.tl))
    xi = rep['data']['xi_range']
    dq = np.abs(np.diff(np.asarray(data.qf, dtype=float)))
    travel = float(np.sum(dq[data.piece[1:] == data.piece[:-1]]))     # not across gaps
    return {'temperature': tuple(xi) if rep['data'].get('has_temperature', True) else None,
            'speed': (float(np.percentile(qd, 5)), float(np.percentile(qd, 95))),
            'load': (float(np.percentile(tl, 5)), float(np.percentile(tl, 95))),
            'position': (float(q.min()), float(q.max())),
            'travel': travel, 'level': float(data.friction_level),
            'inertia': float(getattr(diag.base, 'inertia', float('nan')))}


def _mid_t(rng):
    t = rng['temperature']
    return 0.5 * (t[0] + t[1]) if t else 0.0


def _thermal(fit, base, rng):
    if not rng['temperature']:
        return 'Thermal: friction changes with the housing temperature'
    lo, hi = rng['temperature']
    parts, base_parts = [], []
    for key, name in (('fc', 'F_c'), ('fs', 'F_s'), ('fv', 'F_v')):
        c = fit.get(key)
        if not c or _poly(c, 0.5 * (lo + hi)) <= 0:
            continue
        ch = (_poly(c, hi) - _poly(c, lo)) / _poly(c, 0.5 * (lo + hi))   # of the mid value
        parts.append(f'{name} {_rises(ch)} about {_pct(ch)}')
        b = base.get(key) or []
        if len(b) > 1 and _poly(b, 0.5 * (lo + hi)) > 0:
            bch = (_poly(b, hi) - _poly(b, lo)) / _poly(b, 0.5 * (lo + hi))
            base_parts.append(f'{name} {100 * bch:+.0f} %')
    what = ' and '.join(parts) if parts else 'friction changes'
    base_text = ('the base model has ' + ', '.join(base_parts) if base_parts
                 else 'the base model keeps them constant')
    return f'Thermal: {what} from {lo:.0f} to {hi:.0f} degC ({base_text})'


def _load(fit, base, rng):
    lo, hi = rng['load']
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


def _ripple(fit, base, rng):
    r = fit.get('position_ripple') or {}
    amp = (r.get('amplitude') or [float('nan')])[0]
    cyc = r.get('cycles_per_rev', float('nan'))
    per = 2e3 * math.pi / cyc if cyc else float('nan')
    return (f'Position ripple: the torque varies by +-{amp:.3g} Nm ({_pct(amp / rng["level"])} '
            f'of the friction level) periodically with position, {cyc:.4g} times per output '
            f'revolution (every {per:.3g} mrad), over positions {rng["position"][0]:.2f} to '
            f'{rng["position"][1]:.2f} rad')


def _viscous_torque(fit, v, dv, t):
    return _poly(fit.get('fv'), t) * abs(v) ** dv


def _nonlinear_viscous(fit, base, rng):
    t = _mid_t(rng)
    dv = _poly(fit.get('delta_v') or [1.0], t)
    lo, hi = rng['speed']
    a, b = _viscous_torque(fit, lo, dv, t), _viscous_torque(fit, hi, dv, t)
    way = 'less' if dv < 1 else 'more'
    return (f'Nonlinear viscous: the viscous torque grows as speed^{dv:.2f}, {way} than in '
            f'proportion to speed (the base model: speed^1): {a:.3g} Nm at {lo:.3g} rad/s, '
            f'{b:.3g} Nm at {hi:.3g} rad/s')


def _stribeck(fit, base, rng):
    t = _mid_t(rng)
    fs, fc = _poly(fit.get('fs'), t), _poly(fit.get('fc'), t)
    vs = _poly(fit.get('vs'), t)
    way = 'above' if fs >= fc else 'below'
    rel = f' ({_pct(fs / fc - 1)} {way} F_c = {fc:.3g} Nm)' if fc > 0 else ''
    moves = 'falls' if fs >= fc else 'rises'
    had = 'a different' if base.get('fs') else 'no such'
    return (f'Stribeck: the friction at breakaway F_s = {fs:.3g} Nm{rel} {moves} to the '
            f'Coulomb level within about {vs:.3g} rad/s of sliding speed (the base model has '
            f'{had} low-speed level; sliding speeds {rng["speed"][0]:.3g} to '
            f'{rng["speed"][1]:.3g} rad/s)')


def _presliding(fit, base, rng):
    p = fit.get('presliding') or {}
    k = p.get('stiffness', float('nan'))
    fc = _poly(fit.get('fc'), _mid_t(rng))
    length = 1e3 * fc / k if k and fc > 0 else float('nan')
    return (f'Pre-sliding: after a reversal the friction builds up over about {length:.3g} mrad '
            f'of travel ({p.get("model", "?")} model, stiffness {k:.4g} Nm/rad) instead of '
            'switching sign at once')


def _inertia(fit, base, rng):
    dj, j = fit.get('d_inertia', float('nan')), rng['inertia']
    rel = f', {_pct(dj / j)} {"more" if dj >= 0 else "less"} than configured' if j > 0 else ''
    return (f'Inertia: the joint behaves as if its inertia were {j + dj:.4g} kg m^2 instead of '
            f'the configured {j:.4g} kg m^2{rel}')


def _asymmetry(fit, base, rng):
    off = fit.get('offset', float('nan'))
    way = 'positive' if off >= 0 else 'negative'
    return (f'Asymmetry: friction is about {2 * abs(off):.3g} Nm ({_pct(2 * off / rng["level"])} '
            f'of the friction level) larger moving in the {way} direction than in the other '
            f'(a constant torque offset of {off:+.3g} Nm, which sliding alone cannot tell from '
            'a direction-dependent friction)')


def _drift(fit, base, rng):
    d = (fit.get('drift') or {}).get('fc_drift') or []
    # shifted Legendre P1(s) = 2 s - 1, P2(s) = 6 s^2 - 6 s + 1: start (s=0) to end (s=1)
    start = sum(c * (-1) ** (j + 1) for j, c in enumerate(d))
    change = sum(d) - start
    fc = _poly(fit.get('fc'), _mid_t(rng))
    rel = f' ({_pct(change / fc)} of F_c)' if fc > 0 else ''
    return (f'Drift: the Coulomb friction {_rises(change)} by {abs(change):.3g} Nm{rel} over '
            f'the {rng["travel"]:.3g} rad of accumulated travel, more than the temperature '
            'explains (run-in, wear or lubricant redistribution)')


def _gravity(fit, base, rng):
    g = fit.get('gravity') or {}
    lever = g.get('lever')
    if lever:
        mgl, mgl0 = lever.get('mgl', float('nan')), lever.get('mgl_base', float('nan'))
        rel = f' ({100 * (mgl / mgl0 - 1):+.0f} %)' if mgl0 else ''
        return (f'Gravity: the lever torque m g l is {mgl:.4g} Nm{rel} instead of {mgl0:.4g} Nm '
                f'in the base model, with its zero at {lever.get("angle_offset", 0.0):.3g} rad '
                f'instead of {lever.get("angle_offset_base", 0.0):.3g} rad')
    amp = math.hypot(g.get('sin', 0.0), g.get('cos', 0.0))
    return (f'Gravity: a torque of amplitude {amp:.3g} Nm varying as the sine of the angle '
            f'over positions {rng["position"][0]:.2f} to {rng["position"][1]:.2f} rad is '
            'missing from the base model')


#: effect -> sentence generator ``f(fit, base_fit, ranges)`` (the finding without its score)
SENTENCES = {
    'thermal': _thermal, 'load': _load, 'position_ripple': _ripple,
    'nonlinear_viscous': _nonlinear_viscous, 'stribeck': _stribeck, 'presliding': _presliding,
    'inertia': _inertia, 'asymmetry': _asymmetry, 'drift': _drift, 'gravity': _gravity,
}


def _entry(rep, effect):
    return next((c for c in rep['candidates'] if c['effect'] == effect), {})


def _round_rmse(rep, rnd):
    for r in rep.get('rounds', []):
        if r['round'] == rnd:
            return r['model_torque_rmse']
    return rep['baseline']['torque_rmse']


def effect_finding(effect, rep, ranges):
    """
    Return the plain-language finding on one named effect (one sentence, physical units).

    Size, direction and range come from the fitted model with all named effects and the
    data's ``ranges`` (:func:`data_ranges`); the sentence ends with the RMS torque the
    effect explains held out against the model's error at the round it was added.
    """
    fit = (rep.get('diagnosed') or {}).get('fit') or rep['extended_fit']
    gen = SENTENCES.get(effect)
    try:
        text = gen(fit, rep['base_fit'], ranges) if gen else None
    except (KeyError, IndexError, TypeError, ValueError, ZeroDivisionError):
        text = None
    if text is None:
        text = f'{effect.replace("_", " ").capitalize()}: missing from the base model'
    c = _entry(rep, effect)
    explained = c.get('explained_torque')
    if explained is not None:
        before = _round_rmse(rep, c.get('round', 1))
        text += (f'; explains {explained:.2g} Nm RMS of the {before:.2g} Nm of model error '
                 'held out')
    return text + '.'


def finding_lines(diag):
    """Return the ``## Findings`` Markdown section: one sentence per named effect."""
    rep = diag.report
    named = rep['named_causes']
    lines = ['## Findings', '']
    if not named:
        return lines + ['No missing effect found: the base model explains the measured friction '
                        'torque as well as any candidate would, within the resolution of '
                        'the recordings.', '']
    ranges = data_ranges(diag)
    for eff in named:
        lines.append(f'* {effect_finding(eff, rep, ranges)}')
    return lines + ['', 'Held out: every number above comes from a model fitted without the '
                    'time block it is scored on, so it measures prediction, not curve fitting.',
                    '']


def next_step_lines(rep, out_dir, recordings):
    """Return the ``## What to do next`` Markdown section."""
    base_dir = os.path.normpath(out_dir) if out_dir else 'DIR'
    ext = base_dir + '/extended.yaml'
    recs = ' '.join(os.path.normpath(r) for r in recordings)
    lines = ['## What to do next', '']
    if rep['named_causes'] and rep.get('extended_effects'):
        lines += [f'* Use `{ext}` as the gear file: it is the base model with '
                  f'{", ".join(rep["extended_effects"])} added, fitted on these recordings, and '
                  'loads wherever a gear file does (`--model`, the gear file parameter of '
                  'the nodes).  Check it: diagnosing again with it should name nothing:',
                  '', f'        friction_joint diagnose {recs} --model {ext} --out '
                  f'{base_dir}_check', '',
                  '* To identify its coefficients with standard errors and the pre-sliding '
                  'parameters on your own runs, use it as the structure:', '',
                  f'        friction_joint identify {recs} --model {ext} --out identified.yaml',
                  '']
    elif rep['named_causes']:
        lines += ['* `extended.yaml` is the base model: the named effects cannot be written as '
                  'a gear file (see the notes below); keep the base model and the findings in '
                  'mind.', '']
    else:
        lines += ['* Keep the base model; nothing to change.', '']
    for eff in rep['named_causes']:
        c = _entry(rep, eff)
        if c.get('representable') is False or c.get('physical') is False:
            lines += [f'* {eff}: not in `extended.yaml` ({c.get("reason", "")}).', '']
    untestable = rep.get('untestable') or {}
    if untestable:
        lines += ['* Effects these recordings cannot test, and what to record to test them:', '']
        for eff, why in untestable.items():
            advice = RECORD_ADVICE.get(eff, 'record data that covers the variable of this effect')
            if eff == 'gravity' and 'linear device' in why:
                advice = 'nothing to record: a linear device has no gravity torque'
            lines.append(f'  * {eff} ({why}): {advice}.')
        lines.append('')
    for pair in rep.get('confounds', []):
        a, b = pair['effects']
        if a not in rep['named_causes'] and b not in rep['named_causes']:
            continue                # neither named: nothing in the findings to separate
        lines += [f'* {a} and {b} cannot be told apart in these recordings (they change '
                  f'together); to separate them: {pair["separate_by"]}.', '']
    return lines


def candidate_summary(rep):
    """
    Return sentences for candidates whose first-round gain looks large but that were not named.

    A gain in round 1 is against the base model; after the named effects are in the
    model the same candidate is tested again and its entry in the table is from that
    last round.  These sentences say both numbers and why the candidate is not named.
    """
    out = []
    rounds = rep.get('rounds') or []
    if not rounds:
        return out
    first = {c['effect']: c for c in rounds[0]['candidates']}
    min_gain, alpha = rep['criterion']['min_gain'], rep['criterion']['alpha']
    for c in rep['candidates']:
        eff = c['effect']
        f = first.get(eff)
        if eff in rep['named_causes'] or not f or f.get('gain_raw', 0.0) < min_gain:
            continue
        why = []
        if f.get('p_holm', 1.0) >= alpha:
            why.append(f'its improvement was not consistent over the time blocks (better in '
                       f'{f.get("blocks_improved", "?")} of {f.get("blocks", "?")}, p (Holm) '
                       f'{f.get("p_holm", 1.0):.2g} >= {alpha:g})')
        conf = [e for e in f.get('confounded_with', {}) if e in rep['named_causes']]
        if conf:
            why.append(f'it changes together with the named {", ".join(conf)} in this '
                       'recording, so it was showing that effect')
        if c.get('note') and not conf:
            why.append(c['note'])
        if not why:
            why.append('it was not significant')
        later = (f'; with {", ".join(rep["named_causes"])} in the model it gains '
                 f'{100 * c.get("gain", 0.0):.1f} % (round {c.get("round", "-")})'
                 if rep['named_causes'] and c.get('testable', True) else '')
        out.append(f'{eff} gained {100 * f["gain_raw"]:.1f} % against the base model (round 1) '
                   f'but is not named: ' + '; '.join(why) + later + '.')
    return out
