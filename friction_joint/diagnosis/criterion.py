# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

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
(:func:`holm`).  A floor is added to both MSEs of a block (the greedy search
passes the square of :data:`~friction_joint.diagnosis.greedy.MIN_EXPLAINED` of
the friction level): in a block that both models predict to within a sliver of
the friction level (steady one-way motion, where a pre-sliding model has nothing
to add) the ratio of two tiny errors is not a large loss, and a candidate that
removes most of the error where the model fails (the velocity reversals) is not
ranked down by it.

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

Verdict
-------
:func:`verdict` builds the one :class:`Verdict` of a diagnosis from its report
(named effects, the base and extended :class:`Fit`, the largest unexplained
structure of the residual scan, an unconfirmed large gain, the untestable
candidates); the headline (:attr:`Verdict.headline`), the adequacy table
(:meth:`Verdict.adequacy_lines`), the findings and the next steps
(:mod:`~friction_joint.diagnosis.findings`) are all worded from it, so they
cannot disagree.
"""
from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
import dataclasses
from typing import Any, TYPE_CHECKING, TypeAlias

import numpy as np
import numpy.typing as npt
from scipy import stats

from .verdicts import CandidateVerdict, Confound, Fit, ScanRow

if TYPE_CHECKING:
    from .result import DiagnosisResult

#: a :class:`~friction_joint.diagnosis.data.DiagnosisData`, a
#: :class:`~friction_joint.diagnosis.crossval.CVResult`: both modules import this one (through
#: ``reblock``), so naming their classes here would close an import cycle
_Data: TypeAlias = Any
_CV: TypeAlias = Any

__all__ = ['MIN_BLOCKS', 'MAX_BLOCKS', 'BLOCK_BINS', 'CONFOUND_RHO', 'PREFERENCE', 'INADEQUATE',
           'LARGE_GAIN', 'n_blocks', 'reblock', 'holm', 'compare', 'explained_torque', 'relevant',
           'effect_variables', 'confounds', 'prefer', 'adequacy', 'headline', 'Fit', 'Unconfirmed',
           'Verdict', 'verdict']

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


def n_blocks(n_bins: int) -> int:
    """Return the number of cross-validation blocks for ``n_bins`` sliding bins."""
    return int(np.clip(n_bins // BLOCK_BINS, MIN_BLOCKS, MAX_BLOCKS))


def reblock(data: _Data, k: int) -> _Data:
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


def holm(p: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Return the Holm-Bonferroni adjusted p-values of ``p``."""
    p = np.asarray(p, float)
    m = len(p)
    adj = np.empty(m)
    run = 0.0
    for rank, i in enumerate(np.argsort(p)):
        run = max(run, min(1.0, (m - rank) * p[i]))
        adj[i] = run
    return adj


def compare(cur: _CV, cand: _CV, floor: float = 0.0) -> dict[str, Any]:
    """
    Return the paired one-sided test of a candidate's per-block held-out MSE (a dict).

    ``cur`` and ``cand`` are :class:`~friction_joint.diagnosis.crossval.CVResult`
    of the current model and the candidate on the same blocks.  ``floor`` (Nm^2) is
    added to both MSEs of a block: a block that both models predict to within its
    square root is nearly a tie, whatever the ratio of their tiny errors.
    """
    d = np.log((cur.mse + floor) / np.maximum(cand.mse + floor, 1e-300))
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


def explained_torque(rmse_m: float, rmse_c: float) -> float:
    """Return the RMS torque (Nm) a candidate explains: sqrt(MSE_m - MSE_c), 0 if none."""
    return float(np.sqrt(max(rmse_m ** 2 - rmse_c ** 2, 0.0)))


def relevant(gain: float, explained: float, level: float, min_gain: float,
             min_explained: float) -> bool:
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


def effect_variables(data: _Data,
                     travel: npt.NDArray[np.float64]) -> dict[str, npt.NDArray[np.float64]]:
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


def confounds(variables: Mapping[str, npt.NDArray[np.float64]],
              effects: Iterable[str]) -> list[dict[str, Any]]:
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


def prefer(significant: Sequence[str], table: Mapping[str, CandidateVerdict],
           pairs: Sequence[Confound]) -> str:
    """
    Return the effect to add among ``significant`` (a round's significant candidates).

    The one with the largest gain, unless it is confounded (``pairs``, from
    :func:`confounds`) with another significant candidate that measures a
    physical cause first in :data:`PREFERENCE`: then that one.
    """
    best = max(significant, key=lambda e: _gain(table[e]))
    group = {best}
    for pair in pairs:
        if best in pair.effects:
            group.update(e for e in pair.effects if e in significant)
    return min(group, key=PREFERENCE.index)


def _gain(v: CandidateVerdict) -> float:
    return 0.0 if v.gain_raw is None else v.gain_raw


def adequacy(y: npt.ArrayLike, pred: npt.ArrayLike, level: float) -> dict[str, Any]:
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


def _largest_structure(scan: Sequence[ScanRow]) -> str | None:
    """Return the residual scan's largest finding as text, or None."""
    rows = [(r, r.explained) for r in scan if r.explained is not None]
    if not rows:
        return None
    flagged = [(r, x) for r, x in rows if r.flagged]
    top, explained = max(flagged or rows, key=lambda rx: rx[1])
    where = f' (period {top.period:.4g} rad)' if top.period else ''
    return (f'{top.variable}{where}, {100 * explained:.0f} % of the residual variance '
            'held out' + ('' if top.flagged else ', not significant'))


def _structure(scan: Sequence[ScanRow]) -> str:
    """Return the sentence that points at the largest unexplained structure of the residual."""
    top = _largest_structure(scan)
    if top:
        return f'Largest unexplained structure: {top}.'
    if any(r.explained is not None for r in scan):
        return 'The residual scan finds no structure in time, position or velocity.'
    why = '; '.join(f'{r.variable}: {r.untestable or r.note or "untestable"}'
                    for r in scan[:3])
    return f'The residual scan cannot test the variables of this recording ({why}).'


@dataclasses.dataclass(frozen=True)
class Unconfirmed:
    """
    A tested candidate not named whose held-out gain is large (:data:`LARGE_GAIN`).

    Attributes
    ----------
    effect : str
        The candidate.
    gain : float
        Its held-out gain.
    improved, blocks : int or str
        Blocks it predicted better, of all (``'?'``: not said).
    p_holm : float
        Its Holm-adjusted p-value.

    """

    effect: str
    gain: float
    improved: int | str
    blocks: int | str
    p_holm: float


@dataclasses.dataclass(frozen=True)
class Verdict:
    """
    The one story of a diagnosis, built once from its report (:func:`verdict`).

    The headline, the findings, the next steps and the adequacy table are all
    worded from it, so they cannot disagree.

    Attributes
    ----------
    named : tuple of str
        The named effects, in the order they were added.
    written : tuple of str
        The named effects ``extended.yaml`` holds.
    base, extended : Fit
        How much the base and the extended model explain held out.
    structure : str
        The sentence that points at the largest unexplained structure (residual scan).
    unconfirmed : Unconfirmed or None
        A tested candidate not named whose held-out gain is at least
        :data:`LARGE_GAIN`; None when there is none or an effect is named.
    untestable : tuple of (str, str)
        The candidates the recordings cannot test, with their reasons.

    """

    named: tuple[str, ...]
    written: tuple[str, ...]
    base: Fit
    extended: Fit
    structure: str
    unconfirmed: Unconfirmed | None
    untestable: tuple[tuple[str, str], ...]

    @property
    def explains(self) -> bool:
        """Return whether the final model explains the data (:func:`adequacy`)."""
        return self.extended.explains

    @property
    def nothing_missing(self) -> bool:
        """Return whether the base model stands: it explains the data, nothing is missing."""
        return not self.named and self.explains and self.unconfirmed is None

    @property
    def unconfirmed_text(self) -> str:
        """Return the unconfirmed candidate's gain in words ('' without one)."""
        u = self.unconfirmed
        if not u:
            return ''
        return (f'{u.effect} gains {100 * u.gain:.0f} % held out ({u.improved}/'
                f'{u.blocks} blocks, Holm p {u.p_holm:.2g})')

    @property
    def headline(self) -> str:
        """
        Return the report's first sentence: adequacy first, then what is missing.

        A model whose held-out RMSE stays comparable to the friction level does not
        explain the data, named causes or not; a candidate with a large held-out
        gain (:data:`LARGE_GAIN`) is never summed up as "nothing missing".
        """
        fit = self.extended.text
        if not self.explains:
            return ('The model does not explain the data' +
                    (f' even with {", ".join(self.named)}' if self.named else '') +
                    f': {fit}. ' + self.structure)
        if self.named:
            return f'Missing effects: {", ".join(self.named)} ({fit}).'
        if self.unconfirmed:
            return (f'No effect passes the criterion, but {self.unconfirmed_text}: the '
                    f'recordings are too short or too uneven to confirm it ({fit}).')
        return f'Nothing significant is missing from the base model ({fit}).'

    def adequacy_lines(self) -> list[str]:
        """Return the Markdown table of how much of the friction torque each model explains."""
        def row(label: str, get: Callable[[Fit], object], spec: str) -> str:
            return f'| {label} | {format(get(self.base), spec)} | ' \
                   f'{format(get(self.extended), spec)} |'

        def yes(f: Fit) -> str:
            return 'yes' if f.explains else '**no**'
        return ['| model adequacy | base | extended |', '|---|---|---|',
                row('held-out R^2 of the friction torque', lambda f: f.r2, '.3f'),
                row('held-out RMSE / friction level', lambda f: f.rmse_over_level, '.3f'),
                row(f'explains the data (RMSE / friction level below {INADEQUATE:g})', yes, ''),
                '', f'Friction level (the median of abs(measured friction torque)): '
                f'{self.base.friction_level:.4g} Nm.', '']


def verdict(result: DiagnosisResult) -> Verdict:
    """
    Return the :class:`Verdict` of a diagnosis result.

    Parameters
    ----------
    result : DiagnosisResult
        The diagnosis's result (the ``report.json`` content, typed; read back with
        :meth:`~friction_joint.diagnosis.result.DiagnosisResult.from_dict`).

    Returns
    -------
    Verdict

    """
    named = tuple(result.named_causes)
    unconfirmed = None
    if not named:
        tested = [c for c in result.candidates if c.testable and c.gain_raw is not None]
        large = [c for c in tested if _gain(c) >= LARGE_GAIN]
        if large:
            c = max(large, key=_gain)
            p = c.p_holm if c.p_holm is not None else c.p_value
            unconfirmed = Unconfirmed(
                c.effect, _gain(c), '?' if c.blocks_improved is None else c.blocks_improved,
                '?' if c.blocks is None else c.blocks, float(1.0 if p is None else p))
    return Verdict(named=named, written=tuple(result.extended_effects),
                   base=result.adequacy.base, extended=result.adequacy.extended,
                   structure=_structure(result.residual_scan), unconfirmed=unconfirmed,
                   untestable=tuple(result.untestable.items()))


def headline(result: DiagnosisResult) -> str:
    """
    Return the report's first sentence (:attr:`Verdict.headline` of the result).

    Parameters
    ----------
    result : DiagnosisResult
        The diagnosis's result.

    Returns
    -------
    str

    """
    return verdict(result).headline
