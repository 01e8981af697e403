# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The verdicts of a diagnosis: per candidate, per round, the criterion and the adequacy.

Frozen dataclasses whose field names are their ``report.json`` keys: only their
``to_dict()`` writes the keys and only their ``from_dict()`` reads them
(:mod:`~friction_joint.diagnosis.result` puts them together).
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
import dataclasses
from typing import Any

__all__ = ['Json', 'emit_fields', 'known_fields', 'CandidateVerdict', 'Confound', 'Fit',
           'Adequacy', 'ModelScore', 'CriterionInfo', 'Round', 'ScanRow', 'IdentifyCheck',
           'DiagnosedModel', 'UNKNOWN_FIT']

#: a JSON object (``report.json`` or a part of it)
Json = dict[str, Any]

_NAN = float('nan')


def emit_fields(obj: object, order: Iterable[str]) -> Json:
    """Return ``obj``'s fields of ``order`` that are not None, in that order."""
    out: Json = {}
    for name in order:
        value = getattr(obj, name)
        if value is not None:
            out[name] = value
    return out


def known_fields(cls: type, d: Mapping[str, Any]) -> Json:
    """Return the items of ``d`` that are fields of the dataclass ``cls``."""
    names = {f.name for f in dataclasses.fields(cls)}
    return {k: v for k, v in d.items() if k in names}


#: key order of a tested candidate's entry (as the rounds build it)
_TESTED = ('effect', 'applicable', 'gain', 'gain_raw', 'p_value', 'explained_torque',
           'blocks_improved', 'blocks', 'heldout_torque_rmse', 'mean_log_mse_ratio',
           'median_log_mse_ratio', 'confounded_with', 'p_holm', 'significant', 'round',
           'gain_over_offset', 'position_bands_gain', 'note', 'testable', 'physical',
           'representable', 'reason', 'form', 'caveat')
#: ... of a candidate the current structure already holds
_NOT_APPLICABLE = ('effect', 'applicable', 'gain', 'significant', 'p_value', 'note', 'testable',
                   'physical', 'representable', 'reason', 'form', 'caveat')
#: ... of a candidate the recordings cannot test
_UNTESTABLE = ('effect', 'testable', 'reason', 'gain', 'significant', 'form', 'caveat')


@dataclasses.dataclass(frozen=True)
class CandidateVerdict:
    """
    One candidate effect's verdict in a round, or in the final candidate table.

    Attributes
    ----------
    effect : str
        The candidate.
    gain : float
        Held-out gain, clipped at 0 (``1 - RMSE_candidate / RMSE_current``).
    significant : bool
        Significant (final table: named).
    applicable, testable : bool or None
        False: the structure holds it already; the recordings cannot test it (None: not said).
    reason : str or None
        Why it is untestable, not physical or not representable.
    gain_raw, p_value, explained_torque, heldout_torque_rmse : float or None
        The paired test's numbers (:func:`~friction_joint.diagnosis.criterion.compare`).
    blocks_improved, blocks : int or None
        Blocks the candidate predicted better; blocks.
    mean_log_mse_ratio, median_log_mse_ratio : float or None
        Of the per-block statistic.
    confounded_with : dict or None
        ``{effect: {rank_correlation, separate_by}}`` of its confounded candidates.
    p_holm : float or None
        Holm-adjusted p-value.
    round : int or None
        The greedy round of the entry.
    gain_over_offset, position_bands_gain : float or None
        Gain of a short-stroke pose term over an offset; of a ripple across position bands.
    note : str or None
        Why a candidate is not significant or was preferred.
    physical, representable : bool or None
        A named effect fitted physically; writable to a gear file.
    form, caveat : str or None
        ``'pose'`` and its caveat for a gravity over a short stroke.

    """

    effect: str
    gain: float = 0.0
    significant: bool = False
    applicable: bool | None = None
    testable: bool | None = None
    reason: str | None = None
    gain_raw: float | None = None
    p_value: float | None = None
    explained_torque: float | None = None
    blocks_improved: int | None = None
    blocks: int | None = None
    heldout_torque_rmse: float | None = None
    mean_log_mse_ratio: float | None = None
    median_log_mse_ratio: float | None = None
    confounded_with: dict[str, dict[str, Any]] | None = None
    p_holm: float | None = None
    round: int | None = None    # noqa: A003 - the report.json key
    gain_over_offset: float | None = None
    position_bands_gain: float | None = None
    note: str | None = None
    physical: bool | None = None
    representable: bool | None = None
    form: str | None = None
    caveat: str | None = None

    @property
    def confounds(self) -> tuple[str, ...]:
        """Return the candidates it is confounded with in this recording."""
        return tuple(self.confounded_with or ())

    def to_dict(self) -> Json:
        """Return the entry (``report.json``; the keys in the order the diagnosis adds them)."""
        order = (_UNTESTABLE if self.testable is False else
                 _NOT_APPLICABLE if self.applicable is False else _TESTED)
        return emit_fields(self, order)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> CandidateVerdict:
        """Return the verdict of an entry (:meth:`to_dict`; missing keys: not said)."""
        return cls(**known_fields(cls, d))


@dataclasses.dataclass(frozen=True)
class Confound:
    """
    Two candidates whose variables are one in the recordings.

    Attributes
    ----------
    effects : tuple of str
        The pair (the measured cause first).
    rank_correlation : float
        Spearman rank correlation of their variables over the bins.
    separate_by : str
        The recording that would tell them apart.

    """

    effects: tuple[str, ...]
    rank_correlation: float
    separate_by: str

    def other(self, effect: str) -> str | None:
        """
        Return the other effect of the pair (None: ``effect`` is not in it).

        Parameters
        ----------
        effect : str
            One effect.

        """
        if effect not in self.effects:
            return None
        return next(e for e in self.effects if e != effect)

    def to_dict(self) -> Json:
        """Return the pair (``report.json``, ``confounds``)."""
        return {'effects': list(self.effects), 'rank_correlation': self.rank_correlation,
                'separate_by': self.separate_by}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Confound:
        """Return the pair of :meth:`to_dict` (or :func:`~.criterion.confounds`)."""
        return cls(tuple(d['effects']), float(d['rank_correlation']), str(d['separate_by']))


@dataclasses.dataclass(frozen=True)
class Fit:
    """
    How much of the measured friction torque one model explains held out.

    Attributes
    ----------
    r2, rmse, friction_level, rmse_over_level : float
        Held-out R^2, RMSE (Nm), friction level (Nm), RMSE / friction level.
    explains : bool
        The RMSE is below :data:`~friction_joint.diagnosis.criterion.INADEQUATE` of the
        friction level.

    """

    r2: float
    rmse: float
    friction_level: float
    rmse_over_level: float
    explains: bool

    @property
    def text(self) -> str:
        """Return the fit in words: held-out R^2 and RMSE against the friction level."""
        return (f'held-out R^2 {self.r2:.2f}, RMSE {self.rmse:.3g} Nm against a friction level '
                f'of {self.friction_level:.3g} Nm')

    def to_dict(self) -> Json:
        """Return the fit (``report.json``, ``adequacy.base`` and ``adequacy.extended``)."""
        return emit_fields(self, ('r2', 'rmse', 'friction_level', 'rmse_over_level', 'explains'))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Fit:
        """Return the fit of :meth:`to_dict` (or :func:`~.criterion.adequacy`)."""
        return cls(float(d['r2']), float(d['rmse']), float(d['friction_level']),
                   float(d['rmse_over_level']), bool(d['explains']))

    @classmethod
    def of(cls, ad: Mapping[str, Any]) -> Fit:
        """
        Return the Fit of an :func:`~.criterion.adequacy` dict (as :meth:`from_dict`).

        Parameters
        ----------
        ad : dict
            ``r2``, ``rmse``, ``friction_level``, ``rmse_over_level``, ``explains``.

        """
        return cls.from_dict(ad)


@dataclasses.dataclass(frozen=True)
class Adequacy:
    """
    The :class:`Fit` of the base and of the extended model.

    Attributes
    ----------
    base, extended : Fit
        Held out.

    """

    base: Fit
    extended: Fit

    def to_dict(self) -> Json:
        """Return both fits (``report.json``, ``adequacy``)."""
        return {'base': self.base.to_dict(), 'extended': self.extended.to_dict()}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Adequacy:
        """Return the adequacy of :meth:`to_dict`."""
        return cls(Fit.from_dict(d['base']), Fit.from_dict(d['extended']))


#: the fit of a report that does not say
UNKNOWN_FIT = Fit(_NAN, _NAN, _NAN, _NAN, False)


@dataclasses.dataclass(frozen=True)
class ModelScore:
    """
    Held-out torque and open-loop velocity RMSE of one model.

    Attributes
    ----------
    torque_rmse : float
        Nm.
    velocity_rmse : float or None
        rad/s (None: no velocity window).

    """

    torque_rmse: float
    velocity_rmse: float | None = None

    def to_dict(self) -> Json:
        """Return the scores (``report.json``, ``baseline`` and ``extended``)."""
        return {'torque_rmse': self.torque_rmse, 'velocity_rmse': self.velocity_rmse}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> ModelScore:
        """Return the scores of :meth:`to_dict`."""
        return cls(d['torque_rmse'], d.get('velocity_rmse'))


@dataclasses.dataclass(frozen=True)
class CriterionInfo:
    """
    The criterion a diagnosis applied, in words and numbers (``report.json``, ``criterion``).

    Attributes
    ----------
    statistic, test, multiplicity, gain, selection : str
        In words.
    alpha, min_gain, min_explained, confound_rank_correlation : float
        Significance level, least gain, least explained torque / friction level, the
        rank correlation from which two candidates are confounded.
    blocks : int
        Cross-validation blocks.

    """

    statistic: str = ''
    test: str = ''
    multiplicity: str = ''
    alpha: float = 0.05
    min_gain: float = 0.03
    min_explained: float = 0.0
    blocks: int = 0
    gain: str = ''
    selection: str = ''
    confound_rank_correlation: float = _NAN

    def to_dict(self) -> Json:
        """Return the criterion (``report.json``)."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> CriterionInfo:
        """Return the criterion of :meth:`to_dict` (missing keys: their defaults)."""
        return cls(**known_fields(cls, d))


@dataclasses.dataclass(frozen=True)
class Round:
    """
    One greedy round: the model it starts from and every candidate's verdict.

    Attributes
    ----------
    round : int
        1, 2, ...
    model_torque_rmse : float
        Held-out torque RMSE of the round's current model (Nm).
    candidates : tuple of CandidateVerdict
        The candidates tested (or already in the structure).

    """

    round: int                  # noqa: A003 - the report.json key
    model_torque_rmse: float
    candidates: tuple[CandidateVerdict, ...]

    def to_dict(self) -> Json:
        """Return the round (``report.json``, ``rounds``)."""
        return {'round': self.round, 'model_torque_rmse': self.model_torque_rmse,
                'candidates': [c.to_dict() for c in self.candidates]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Round:
        """Return the round of :meth:`to_dict`."""
        return cls(int(d['round']), d.get('model_torque_rmse', _NAN),
                   tuple(CandidateVerdict.from_dict(c) for c in d.get('candidates', ())))


@dataclasses.dataclass(frozen=True)
class ScanRow:
    """
    One variable's row of the residual scan (:func:`~friction_joint.diagnosis.scan.residual_scan`).

    Attributes
    ----------
    variable : str
        The variable (or group of collinear variables).
    explained : float or None
        Held-out explained variance of the residual (None: untested).
    flagged : bool
        Significant.
    period : float or None
        The position period of the test (rad).
    note, untestable : str
        Its note; why it is untestable ('' if it is testable).
    record : dict
        The row as the scan made it (into ``report.json`` as it is).

    """

    variable: str
    explained: float | None
    flagged: bool
    period: float | None
    note: str
    untestable: str
    record: Mapping[str, Any]

    def to_dict(self) -> Json:
        """Return the row (``report.json``, ``residual_scan``)."""
        return dict(self.record)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> ScanRow:
        """Return the row of a scan's table."""
        return cls(str(d['variable']), d.get('explained'), bool(d.get('flagged')),
                   d.get('period'), str(d.get('note') or ''), str(d.get('untestable') or ''),
                   dict(d))


@dataclasses.dataclass(frozen=True)
class IdentifyCheck:
    """
    Whether ``identify`` can run on the recordings with ``extended.yaml``.

    Attributes
    ----------
    ready : bool
        It can.
    reason : str or None
        Why it would refuse.

    """

    ready: bool
    reason: str | None

    def to_dict(self) -> Json:
        """Return the check (``report.json``, ``identify``)."""
        return {'ready': self.ready, 'reason': self.reason}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> IdentifyCheck:
        """Return the check of :meth:`to_dict`."""
        return cls(bool(d.get('ready')), d.get('reason'))


@dataclasses.dataclass(frozen=True)
class DiagnosedModel:
    """
    The model with every named effect, when ``extended.yaml`` cannot hold them all.

    Attributes
    ----------
    effects : tuple of str
        The named effects.
    torque_rmse : float
        Its held-out torque RMSE (Nm).
    fit : dict
        Its coefficients (:func:`~friction_joint.diagnosis.structures.coefficients`).

    """

    effects: tuple[str, ...]
    torque_rmse: float
    fit: Mapping[str, Any]

    def to_dict(self) -> Json:
        """Return the model (``report.json``, ``diagnosed``)."""
        return {'effects': list(self.effects), 'torque_rmse': self.torque_rmse,
                'fit': self.fit}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> DiagnosedModel:
        """Return the model of :meth:`to_dict`."""
        return cls(tuple(d.get('effects', ())), d.get('torque_rmse', _NAN), d['fit'])
