# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The greedy search of a diagnosis: the base fit, then rounds of candidate tests.

Each round tests every candidate against the current model
(:func:`~friction_joint.diagnosis.criterion.compare`, Holm over the round,
:func:`~friction_joint.diagnosis.criterion.relevant`), settles confounded and
preferred candidates, checks a short-stroke gravity against an offset and a
ripple across the travel, and adds the best; every verdict is a
:class:`~friction_joint.diagnosis.verdicts.CandidateVerdict`
(:func:`friction_joint.diagnosis.pipeline.diagnose` describes the method).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import dataclasses
import math
import os
import time
from typing import Any, TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from . import criterion as cr
from . import structures as dm
from .candidates import base_structure, extend
from .core import RoundFit
from .crossval import cross_validate_structures, fit_all
from .gravity import pose_beyond_offset
from .result import Timing
from .testability import inertia_noise_gain, inertia_noise_mse
from .verdicts import CandidateVerdict, Confound, Round

if TYPE_CHECKING:
    from .crossval import CVResult
    from .data import DiagnosisData
    from ..gear import GearParams

__all__ = ['ALPHA', 'MIN_GAIN', 'MIN_EXPLAINED', 'POSITION_BANDS', 'MAX_ROUNDS', 'Setup',
           'Search', 'fit_base', 'greedy_round']

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

Say = Callable[[str], None]
Array = npt.NDArray[np.float64]


def _nl_params(s: dm.CandidateStructure) -> list[str]:
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


def _g_nom(ctx: dm.Context, s: dm.CandidateStructure, beta: Array,
           names: Sequence[tuple[str, int]]) -> float:
    g = 0.0
    for (kind, i), b in zip(names, beta, strict=True):
        if kind == 'fc':
            g += b * float(np.mean(ctx.u ** i))
        elif kind == 'fc_load':
            g += b * float(np.mean(ctx.vl ** i))
    return float(max(g, 0.05 * ctx.data.friction_level))


def refine(s: dm.CandidateStructure, ctx: dm.Context, y: Array) -> tuple[Any, ...]:
    """Nonlinear parameters of ``s`` by grid on all data (one coordinate sweep)."""
    for p in _nl_params(s):
        s, beta, names, _ = fit_all(dm.grid_of(s, p, ctx), ctx, y)
    s, beta, names, pred = fit_all([s], ctx, y)
    return s, beta, names, pred


@dataclasses.dataclass
class Setup:
    """What the stages share: the inputs, the data, which candidates are testable, timing."""

    paths: Sequence[str | os.PathLike[str]]
    base: GearParams
    effects: Sequence[str]
    joint_name: str | None
    say: Say
    data: DiagnosisData
    ctx: dm.Context
    why: dict[str, str]
    testable: list[str]
    pose_note: str | None
    timing: Timing = Timing()
    #: mean squared torque (Nm^2) a refitted J removes from the encoder's quantisation alone
    inertia_noise: float = 0.0

    @property
    def y(self) -> Array:
        """Return the measured friction torque per bin."""
        return self.data.y

    def cv(self, s: dm.CandidateStructure, param: str | None = None, block: Any = None,
           k: int | None = None) -> CVResult:
        """Cross-validate ``s`` (over ``param``'s grid) on the time blocks, or ``block``."""
        return cross_validate_structures(
            dm.grid_of(s, param, self.ctx), self.ctx, self.y,
            self.data.block if block is None else block, k or self.data.n_blocks)


@dataclasses.dataclass
class Search:
    """The greedy search's state: the base, the current model, the named effects, the rounds."""

    base_struct: dm.CandidateStructure
    base_cv: CVResult
    cur: dm.CandidateStructure
    cur_cv: CVResult
    pairs: list[Confound]
    named: list[str] = dataclasses.field(default_factory=list)
    added: dict[str, CandidateVerdict] = dataclasses.field(default_factory=dict)
    rounds: list[Round] = dataclasses.field(default_factory=list)
    fits: list[RoundFit] = dataclasses.field(default_factory=list)
    last: dict[str, CandidateVerdict] = dataclasses.field(default_factory=dict)


def fit_base(setup: Setup) -> Search:
    """Fit the base structure, cross-validate it, and rule out a J the noise alone would gain."""
    t0 = time.perf_counter()
    data, ctx = setup.data, setup.ctx
    cur, beta, names, _ = refine(base_structure(setup.base), ctx, setup.y)
    ctx.g_nom = _g_nom(ctx, cur, beta, names)
    base_cv = setup.cv(cur)
    if 'inertia' in setup.testable:
        setup.inertia_noise = inertia_noise_mse(data)
        spurious = inertia_noise_gain(data, base_cv.rmse ** 2, setup.inertia_noise)
        if spurious >= 0.5 * MIN_GAIN:
            setup.why['inertia'] = (f'the encoder quantisation alone would let a refitted J gain '
                                    f'{100 * spurious:.1f} % held out (errors in the acceleration '
                                    f'regressor): a finer encoder or a lower noise is needed')
            setup.testable.remove('inertia')
    setup.timing = dataclasses.replace(setup.timing, base_fit_s=time.perf_counter() - t0)
    setup.say(f'base: held-out torque RMSE {base_cv.rmse:.4f} Nm '
              f'({setup.timing.base_fit_s:.2f} s)')
    pairs = [Confound.from_dict(p) for p in
             cr.confounds(cr.effect_variables(data, ctx.travel), setup.testable)]
    return Search(cur, base_cv, cur, base_cv, pairs)


def greedy_round(rnd: int, setup: Setup, search: Search) -> bool:
    """Run greedy round ``rnd``: test the candidates, add the best; return whether one was."""
    table, cvs = _test_candidates(rnd, setup, search)
    tested = [e for e in table if table[e].applicable]
    best = _settle(table, [e for e in tested if table[e].significant], search.pairs)
    search.rounds.append(Round(rnd, search.cur_cv.rmse, tuple(table.values())))
    search.fits.append(RoundFit(rnd, search.cur_cv, cvs, search.cur))
    against = ('the base model' if not search.named else
               'the model with ' + ', '.join(search.named))
    setup.say(f'round {rnd} (held-out gain against {against}; * significant): ' + ', '.join(
        f'{e} {100 * (table[e].gain_raw or 0.0):+.1f} %{"*" if table[e].significant else ""} '
        f'(p_holm {_or(table[e].p_holm, 1):.2g})' for e in tested))
    search.last = table
    if best is None:
        return False
    search.named.append(best)
    search.added[best] = table[best]
    extended = extend(search.cur, best)
    assert extended is not None
    search.cur = refine(extended[0], setup.ctx, setup.y)[0]
    search.cur_cv = setup.cv(search.cur)
    setup.say(f'  added {best}: held-out torque RMSE {search.cur_cv.rmse:.4f} Nm')
    return True


def _or(x: float | None, default: float) -> float:
    return default if x is None else x


def _test_candidates(rnd: int, setup: Setup, search: Search
                     ) -> tuple[dict[str, CandidateVerdict], dict[str, CVResult]]:
    """Return every candidate's verdict in round ``rnd`` (Holm, relevance, confounds)."""
    table: dict[str, CandidateVerdict] = {}
    cvs: dict[str, CVResult] = {}
    level = setup.data.friction_level
    floor = (MIN_EXPLAINED * level) ** 2     # errors below 1 % of the friction level: a tie
    for eff in setup.testable:
        if eff in search.named:
            continue
        ext = extend(search.cur, eff)
        if ext is None:
            table[eff] = CandidateVerdict(eff, applicable=False, gain=0.0, significant=False,
                                          p_value=1.0, note='already in the model structure')
            continue
        cvs[eff] = setup.cv(*ext)
        table[eff] = _confound_entry(
            CandidateVerdict(eff, applicable=True,
                             **cr.compare(search.cur_cv, cvs[eff], floor)),
            search.pairs)
    tested = [e for e in table if table[e].applicable]
    adj = [float(p) for p in cr.holm([_or(table[e].p_value, 1.0) for e in tested])]
    for e, pa in zip(tested, adj, strict=True):
        v = table[e]
        gain, explained = _or(v.gain_raw, 0.0), _or(v.explained_torque, 0.0)
        if e == 'inertia' and setup.inertia_noise > 0:
            v, gain, explained = _inertia_beyond_noise(v, search.cur_cv.rmse,
                                                       setup.inertia_noise, level)
        table[e] = dataclasses.replace(v, p_holm=pa, round=rnd, significant=bool(
            pa < ALPHA and cr.relevant(gain, explained, level, MIN_GAIN, MIN_EXPLAINED)))
    for e in tested:            # one variable with a named effect: not told apart from it
        other = [n for n in search.named if n in table[e].confounds]
        if table[e].significant and other:
            table[e] = dataclasses.replace(
                table[e], significant=False,
                note=f'confounded with the named {other[0]} in this recording: not told apart '
                     'from it')
    gravity = table.get('gravity')
    if setup.ctx.pose is not None and gravity is not None and gravity.significant:
        entry = gravity.to_dict()
        pose_beyond_offset(entry, cvs.get('asymmetry'), cvs['gravity'], level, alpha=ALPHA,
                           min_gain=MIN_GAIN, min_explained=MIN_EXPLAINED)
        table['gravity'] = CandidateVerdict.from_dict(entry)
    ripple = table.get('position_ripple')
    if ripple is not None and ripple.significant:
        table['position_ripple'] = _ripple_across_travel(ripple, search.cur, setup)
    return table, cvs


def _settle(table: dict[str, CandidateVerdict], sig: list[str],
            pairs: Sequence[Confound]) -> str | None:
    """
    Return the effect a round adds (None: none), its significant candidates settled.

    Of the significant candidates ``sig`` the one :func:`~.criterion.prefer`
    chooses is added; one confounded with it (``pairs``) is not told apart from it
    in this recording and is not significant in this round either (note says why),
    so the console, the round tables, ``gains.png`` and the text agree.
    """
    if not sig:
        return None
    best = cr.prefer(sig, table, pairs)
    peers = [e for e in sig if e != best and e in table[best].confounds]
    if best != max(sig, key=lambda e: _or(table[e].gain_raw, 0.0)):
        table[best] = dataclasses.replace(
            table[best], note='preferred to the confounded ' + ', '.join(peers) +
            ': the measured cause first')
    for e in peers:
        table[e] = dataclasses.replace(
            table[e], significant=False,
            note=f'confounded with {best} in this recording: not told apart from it '
                 f'({best} is added)')
    return best


def _inertia_beyond_noise(entry: CandidateVerdict, rmse: float, noise: float,
                          level: float) -> tuple[CandidateVerdict, float, float]:
    """
    Return the inertia entry, its held-out gain and explained torque beyond the noise's.

    A refitted J removes ``noise`` (Nm^2, :func:`~.testability.inertia_noise_mse`)
    of the mean squared error from the encoder's quantisation alone, whatever the
    true J; against a current model whose held-out RMSE is ``rmse`` the candidate
    is judged on what it removes beyond that.  The entry gets a note when its gain
    would matter but what it removes beyond the noise does not.
    """
    cand = _or(entry.heldout_torque_rmse, rmse)
    if rmse <= 0:
        return entry, 0.0, 0.0
    gain = 1.0 - math.sqrt(cand ** 2 + noise) / rmse
    explained = math.sqrt(max(rmse ** 2 - cand ** 2 - noise, 0.0))
    relevant = cr.relevant(gain, explained, level, MIN_GAIN, MIN_EXPLAINED)
    if not relevant and cr.relevant(_or(entry.gain_raw, 0.0), _or(entry.explained_torque, 0.0),
                                    level, MIN_GAIN, MIN_EXPLAINED):
        alone = 1.0 - math.sqrt(max(1.0 - noise / rmse ** 2, 0.0))
        entry = dataclasses.replace(
            entry, note=f'the encoder quantisation alone lets a refitted J gain '
                        f'{100 * alone:.1f} % against this model (errors in the acceleration '
                        f'regressor); beyond it the gain is {100 * max(gain, 0.0):.1f} %')
    return entry, gain, explained


def _ripple_across_travel(entry: CandidateVerdict, cur: dm.CandidateStructure,
                          setup: Setup) -> CandidateVerdict:
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
    data = setup.data
    q = data.average(data.q)
    edges = np.quantile(q, np.linspace(0.0, 1.0, POSITION_BANDS + 1)[1:-1])
    band = np.searchsorted(edges, q)
    ext = extend(cur, 'position_ripple')
    assert ext is not None
    base = setup.cv(cur, None, band, POSITION_BANDS)
    cand = setup.cv(*ext, band, POSITION_BANDS)
    gain = 1.0 - cand.rmse / base.rmse
    entry = dataclasses.replace(entry, position_bands_gain=float(gain))
    if cr.relevant(gain, cr.explained_torque(base.rmse, cand.rmse), data.friction_level,
                   MIN_GAIN, MIN_EXPLAINED):
        return entry
    return dataclasses.replace(
        entry, significant=False,
        note=f'not periodic across the travel: fitted on {POSITION_BANDS - 1} of '
             f'{POSITION_BANDS} position bands it gains {100 * gain:.1f} % on the '
             'held-out band (a slow position dependence, see the residual scan)')


def _confound_entry(entry: CandidateVerdict, pairs: Sequence[Confound]) -> CandidateVerdict:
    """Return the entry with the candidates it is confounded with in this recording."""
    found = {}
    for pair in pairs:
        other = pair.other(entry.effect)
        if other is not None:
            found[other] = {'rank_correlation': pair.rank_correlation,
                            'separate_by': pair.separate_by}
    return dataclasses.replace(entry, confounded_with=found) if found else entry
