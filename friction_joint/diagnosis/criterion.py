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
The criterion of the diagnosis: blocks, a robust paired test, confounds, model adequacy.

Blocks
------
The sliding bins are cut into K contiguous time blocks, K from the data
(:func:`n_blocks`): one block per :data:`BLOCK_BINS` bins, at least
:data:`MIN_BLOCKS` and at most :data:`MAX_BLOCKS`.  More blocks give the paired
test more power and make one bad block (a disturbance, a stretch the model
does not cover) matter less.

Paired test
-----------
For a candidate c against the current model m the per-block statistic is
``d_k = log(MSE_m,k / MSE_c,k)`` of the held-out torque errors; H0 "the
candidate does not predict held-out blocks better" is tested with the
one-sided **Wilcoxon signed-rank test** of the d_k (exact for small K): it
uses the signs and the ranks of the block improvements, so one block with a
large loss costs one rank, where it would dominate the mean and variance of
a t-test.  The p-values of a round are Holm-Bonferroni adjusted
(:func:`holm`).

Confounds
---------
Some candidates are told apart by different variables (``thermal``: the
temperature; ``drift``: the accumulated travel; ``gravity`` and
``position_ripple``: the position; ``load``: |tau_ext|); when two of those
variables are one in a recording (|Spearman rank correlation| >=
:data:`CONFOUND_RHO` over the bins: a temperature that only rises during a
run, a one-way sweep whose position grows with the travel), the recording
cannot tell the candidates apart.  :func:`confounds` reports every such pair
with its rank correlation and the recording that would separate them; when
confounded candidates are both significant the measured physical cause is
preferred (:data:`PREFERENCE`: ``drift``, a cause without a measured
variable, comes last) and the confound is stated.

Adequacy
--------
:func:`adequacy` states how much of the measured friction torque a model
explains: the held-out R^2 and the held-out RMSE against the friction level
(the median |measured friction torque|).  A model whose held-out RMSE is
:data:`INADEQUATE` (half) of the friction level or more does not explain the
data, whatever the candidates say.
"""
import numpy as np
from scipy import stats

__all__ = ['MIN_BLOCKS', 'MAX_BLOCKS', 'BLOCK_BINS', 'CONFOUND_RHO', 'PREFERENCE', 'INADEQUATE',
           'LARGE_GAIN', 'n_blocks', 'reblock', 'holm', 'compare', 'explained_torque', 'relevant',
           'effect_variables', 'confounds', 'prefer', 'adequacy', 'headline']

#: fewest cross-validation blocks
MIN_BLOCKS = 10
#: most cross-validation blocks
MAX_BLOCKS = 20
#: sliding bins per block when the data allow more than :data:`MIN_BLOCKS`
BLOCK_BINS = 100
#: |rank correlation| of two candidates' variables from which they are confounded
CONFOUND_RHO = 0.9
#: order of preference among confounded significant candidates (measured causes first)
PREFERENCE = ('thermal', 'load', 'gravity', 'position_ripple', 'inertia', 'presliding',
              'stribeck', 'nonlinear_viscous', 'asymmetry', 'drift')
#: held-out RMSE / friction level from which a model does not explain the data
INADEQUATE = 0.5
#: held-out gain that is never reported as "nothing missing", significant or not
LARGE_GAIN = 0.10

#: what separates two confounded candidates: a recording that ...
_SEPARATE = {
    frozenset(('thermal', 'drift')): 'changes the temperature independently of the run time '
                                     'and travel (runs at several temperatures in varying '
                                     'order, or a cool-down run after the warm-up)',
    frozenset(('load', 'drift')): 'varies the load independently of the run time',
    frozenset(('thermal', 'load')): 'varies the load at constant temperature',
}
_POSITION = 'travels the same positions repeatedly in both directions (so that position and ' \
            'accumulated travel part)'


def n_blocks(n_bins):
    """Return the number of cross-validation blocks for ``n_bins`` sliding bins."""
    return int(np.clip(n_bins // BLOCK_BINS, MIN_BLOCKS, MAX_BLOCKS))


def reblock(data, k):
    """
    Cut ``data``'s bins into ``k`` contiguous blocks (in place): ``block``, ``block_of``.

    The blocks are of equal size in bins, in recording order; every sample
    belongs to the block of the next bin at or after it.
    """
    nb = data.n_bins
    block = (np.arange(nb) * k) // nb
    sel = data.bin_of >= 0
    first = np.zeros(nb, dtype=np.int64)
    first[data.bin_of[sel][::-1]] = np.flatnonzero(sel)[::-1]
    edges = [first[np.argmax(block == j)] for j in range(1, k)]
    data.block = block
    data.block_of = np.searchsorted(np.asarray(edges), np.arange(len(data.t)), side='right')
    data.n_blocks = k
    return data


def holm(p):
    """Return the Holm-Bonferroni adjusted p-values of ``p``."""
    p = np.asarray(p, float)
    m = len(p)
    adj = np.empty(m)
    run = 0.0
    for rank, i in enumerate(np.argsort(p)):
        run = max(run, min(1.0, (m - rank) * p[i]))
        adj[i] = run
    return adj


def compare(cur, cand):
    """
    Return the paired one-sided test of a candidate's per-block held-out MSE (a dict).

    ``cur`` and ``cand`` are :class:`~friction_joint.diagnosis.crossval.CVResult`
    of the current model and the candidate on the same blocks.
    """
    d = np.log(cur.mse / np.maximum(cand.mse, 1e-300))
    if np.all(d == d[0]):
        p = 0.0 if d[0] > 0 else 1.0
    else:
        p = float(stats.wilcoxon(d, alternative='greater', zero_method='zsplit').pvalue)
    gain = 1.0 - cand.rmse / cur.rmse
    return {'gain': float(max(gain, 0.0)), 'gain_raw': float(gain), 'p_value': p,
            'explained_torque': explained_torque(cur.rmse, cand.rmse),
            'blocks_improved': int(np.count_nonzero(d > 0)), 'blocks': int(len(d)),
            'heldout_torque_rmse': cand.rmse, 'mean_log_mse_ratio': float(np.mean(d)),
            'median_log_mse_ratio': float(np.median(d))}


def explained_torque(rmse_m, rmse_c):
    """Return the RMS torque (Nm) a candidate explains: sqrt(MSE_m - MSE_c), 0 if none."""
    return float(np.sqrt(max(rmse_m ** 2 - rmse_c ** 2, 0.0)))


def relevant(gain, explained, level, min_gain, min_explained):
    """
    Return whether a held-out improvement matters in practice.

    It removes at least ``min_gain`` of the current model's held-out RMSE, or it
    explains an RMS torque of at least ``min_explained`` of the friction level
    ``level`` while removing at least a quarter of ``min_gain``: an effect of a
    physically relevant size is not dismissed because other errors (sensor
    noise, a lagging temperature sensor) inflate the current model's RMSE, and a
    sliver of a large error (a refitted J taking a share of a drive's torque lag)
    is not named for the size of that error.
    """
    return bool(gain >= min_gain or (gain >= 0.25 * min_gain
                                     and explained >= min_explained * level))


def effect_variables(data, travel):
    """
    Return ``{effect: bin-averaged variable}`` of the candidates told apart by one variable.

    ``travel`` is the accumulated travel at full rate
    (:func:`~friction_joint.diagnosis.structures.accumulated_travel`).
    """
    out = {'drift': data.average(travel), 'gravity': data.average(data.q),
           'position_ripple': data.average(data.q), 'load': data.average(data.tl)}
    if getattr(data, 'has_temperature', True):
        out['thermal'] = data.average(data.xi)
    return out


def confounds(variables, effects):
    """
    Return the confounded pairs among ``effects`` (list of dicts).

    Each: ``effects`` (the pair), ``rank_correlation`` (Spearman over the bins),
    ``separate_by`` (the recording that would tell them apart).  ``gravity`` and
    ``position_ripple`` share the position and are not a confound of each other
    (their shapes differ: one cycle per turn against a repeating period).
    """
    names = [e for e in effects if e in variables]
    out = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if {a, b} == {'gravity', 'position_ripple'}:
                continue
            va, vb = variables[a], variables[b]
            if np.ptp(va) <= 0 or np.ptp(vb) <= 0:
                continue
            rho = float(stats.spearmanr(va, vb)[0])
            if abs(rho) >= CONFOUND_RHO:
                pair = frozenset((a, b))
                sep = _SEPARATE.get(pair, _POSITION if pair & {'gravity', 'position_ripple'}
                                    else 'moves the two variables independently')
                out.append({'effects': sorted(pair, key=PREFERENCE.index),
                            'rank_correlation': rho, 'separate_by': 'a recording that ' + sep})
    return out


def prefer(significant, table, pairs):
    """
    Return the effect to add among ``significant`` (a round's significant candidates).

    The one with the largest gain, unless it is confounded (``pairs``, from
    :func:`confounds`) with another significant candidate that measures a
    physical cause first in :data:`PREFERENCE`: then that one.
    """
    best = max(significant, key=lambda e: table[e]['gain_raw'])
    group = {best}
    for pair in pairs:
        if best in pair['effects']:
            group.update(e for e in pair['effects'] if e in significant)
    return min(group, key=PREFERENCE.index)


def adequacy(y, pred, level):
    """
    Return how much of the measured friction torque ``y`` a held-out prediction explains.

    ``r2`` (1 - SSE / SST about the mean of y), ``rmse`` (Nm), ``rmse_over_level``
    (held-out RMSE / friction level) and ``explains`` (RMSE below
    :data:`INADEQUATE` of the friction level).
    """
    y = np.asarray(y, float)
    r = y - np.asarray(pred, float)
    sst = float(np.sum((y - y.mean()) ** 2))
    rmse = float(np.sqrt(np.mean(r ** 2)))
    ratio = rmse / level if level > 0 else float('inf')
    return {'r2': 1.0 - float(r @ r) / sst if sst > 0 else 0.0, 'rmse': rmse,
            'friction_level': float(level), 'rmse_over_level': ratio,
            'explains': bool(ratio < INADEQUATE)}


def _largest_structure(scan):
    """Return the residual scan's largest finding as text, or None."""
    rows = [r for r in scan or () if r.get('explained') is not None]
    if not rows:
        return None
    flagged = [r for r in rows if r.get('flagged')]
    top = max(flagged or rows, key=lambda r: r['explained'])
    where = f' (period {top["period"]:.4g} rad)' if top.get('period') else ''
    return (f'{top["variable"]}{where}, {100 * top["explained"]:.0f} % of the residual variance '
            'held out' + ('' if top.get('flagged') else ', not significant'))


def headline(report):
    """
    Return the report's first sentence: adequacy first, then what is missing.

    A model whose held-out RMSE stays comparable to the friction level does not
    explain the data, named causes or not; a candidate with a large held-out
    gain (:data:`LARGE_GAIN`) is never summed up as "nothing missing".
    """
    named = report['named_causes']
    ext = report['adequacy']['extended']
    fit = (f'held-out R^2 {ext["r2"]:.2f}, RMSE {ext["rmse"]:.3g} Nm against a friction level '
           f'of {ext["friction_level"]:.3g} Nm')
    if not ext['explains']:
        top = _largest_structure(report.get('residual_scan'))
        scan = report.get('residual_scan') or []
        why = '; '.join(f'{r["variable"]}: {r.get("untestable") or r.get("note") or "untestable"}'
                        for r in scan[:3])
        if top:
            where = f'Largest unexplained structure: {top}.'
        elif any(r.get('explained') is not None for r in scan):
            where = 'The residual scan finds no structure in time, position or velocity.'
        else:
            where = f'The residual scan cannot test the variables of this recording ({why}).'
        return ('The model does not explain the data' +
                (f' even with {", ".join(named)}' if named else '') + f': {fit}. ' + where)
    if named:
        return f'Missing effects: {", ".join(named)} ({fit}).'
    tested = [c for c in report['candidates'] if c.get('testable') and 'gain_raw' in c]
    large = [c for c in tested if c['gain_raw'] >= LARGE_GAIN]
    if large:
        c = max(large, key=lambda c: c['gain_raw'])
        return (f'No effect passes the criterion, but {c["effect"]} gains '
                f'{100 * c["gain_raw"]:.0f} % held out ({c["blocks_improved"]}/{c["blocks"]} '
                f'blocks, Holm p {c.get("p_holm", c["p_value"]):.2g}): the recordings are too '
                f'short or too uneven to confirm it ({fit}).')
    return f'Nothing significant is missing from the base model ({fit}).'
