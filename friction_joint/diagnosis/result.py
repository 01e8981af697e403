# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
The typed result of a diagnosis; its ``report.json`` is built only by ``to_dict()``.

:class:`DiagnosisResult` holds what ``report.json`` holds, as frozen
dataclasses: a :class:`~.verdicts.CandidateVerdict` per candidate, the greedy
:class:`~.verdicts.Round` s, the :class:`~.verdicts.Fit` (adequacy) of the base
and the extended model (:mod:`~friction_joint.diagnosis.verdicts`), the
:class:`DataSummary` (recordings, scales, gaps), the :class:`Timing`.
Every class's field names are its JSON keys; only its ``to_dict()`` writes
them and only its ``from_dict()`` reads them (``report.json`` read back, e.g.
by tests).
:class:`~friction_joint.diagnosis.core.DiagnosisCore` adds the in-memory side
(the extended gear, the data, the cross-validations) for the figures and the
report.  Records another module owns (the fitted coefficients
of :func:`~friction_joint.diagnosis.structures.coefficients`, the residual
scan's rows, an import's current conversion) are carried as they came, the
fields the diagnosis reads typed beside them.
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
import dataclasses
from typing import Any

from .verdicts import (Adequacy, CandidateVerdict, Confound, CriterionInfo, DiagnosedModel,
                       emit_fields, IdentifyCheck, Json, known_fields, ModelScore, Round,
                       ScanRow, UNKNOWN_FIT)

__all__ = ['Scales', 'Gaps', 'CurrentSource', 'DataSummary', 'Timing', 'DataRanges',
           'DiagnosisResult']

_NAN = float('nan')


@dataclasses.dataclass(frozen=True)
class Scales:
    """
    The data's scales (:class:`~friction_joint.diagnosis.data.DiagnosisData`).

    Attributes
    ----------
    v_stick, resolution, friction_level, stroke : float
        Sliding threshold (rad/s), encoder resolution (rad), friction level (Nm), stroke (rad).
    velocity_noise, quantisation_noise, standstill_noise, standstill_fraction, cutoff : float
        The noise scales (None where the data have none).

    """

    v_stick: float = _NAN
    resolution: float | None = None
    friction_level: float = _NAN
    stroke: float = _NAN
    velocity_noise: float | None = None
    quantisation_noise: float | None = None
    standstill_noise: float | None = None
    standstill_fraction: float | None = None
    cutoff: float | None = None

    def to_dict(self) -> Json:
        """Return the scales (``report.json``, ``data.scales``)."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Scales:
        """Return the scales of :meth:`to_dict`."""
        return cls(**known_fields(cls, d))


@dataclasses.dataclass(frozen=True)
class Gaps:
    """
    The gaps of the stamps (:func:`friction_joint.bag.stamps.gap_summary`).

    Attributes
    ----------
    bridged, split : int
        Gaps bridged; gaps too long to bridge.
    longest_bridged_s, longest_bridged_samples : float
        The longest bridged gap, s and median sample times.
    bridge_limit_s : float or None
        The shortest bridging limit over the series.
    rule : str
        The rule in words.

    """

    bridged: int
    longest_bridged_s: float
    longest_bridged_samples: float
    split: int
    bridge_limit_s: float | None
    rule: str

    def to_dict(self) -> Json:
        """Return the gaps (``report.json``, ``data.gaps``)."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Gaps:
        """Return the gaps of :meth:`to_dict` (or of ``gap_summary``)."""
        return cls(**known_fields(cls, d))


@dataclasses.dataclass(frozen=True)
class CurrentSource:
    """
    How an import converted one recording's motor current to torque.

    Attributes
    ----------
    recording : str
        The recording.
    text : str
        The report line.
    record : dict
        The whole record (:func:`~friction_joint.bag.torque_from_current`, ``recording``
        first), as it goes into ``report.json``.

    """

    recording: str
    text: str
    record: Mapping[str, Any]

    def to_dict(self) -> Json:
        """Return the record (``report.json``, ``data.torque_from_current``)."""
        return dict(self.record)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> CurrentSource:
        """Return the source of a record."""
        return cls(str(d['recording']), str(d['text']), dict(d))


@dataclasses.dataclass(frozen=True)
class DataSummary:
    """
    What the diagnosis read (``report.json``, ``data``).

    Attributes
    ----------
    recordings : tuple of str
        As given.
    bins, velocity_windows : int
        Sliding bins; open-loop velocity windows.
    bin_s, sliding_s, window_s : float
        Bin length, sliding time, window length (s).
    xi_range : tuple of float
        Housing temperature range (degC).
    torque_source : str
        ``'link_torque'``, ``'lever model'`` or ``'none'``.
    has_temperature : bool
        A temperature signal was logged.
    scales : Scales
        The data's scales.
    velocity_from_position : bool or None
        The velocity was the position's centred difference (None: not said).
    torque_from_current : tuple of CurrentSource or None
        Recordings whose torque an import converted from a current.
    in_logged_units : tuple of str or None
        Key numbers in the units of the import.
    gaps : Gaps or None
        The gaps of the stamps.

    """

    recordings: tuple[str, ...] = ()
    bins: int = 0
    bin_s: float = _NAN
    sliding_s: float = _NAN
    xi_range: tuple[float, float] = (_NAN, _NAN)
    torque_source: str = 'none'
    velocity_windows: int = 0
    window_s: float = _NAN
    has_temperature: bool = True
    scales: Scales = Scales()
    velocity_from_position: bool | None = None
    torque_from_current: tuple[CurrentSource, ...] | None = None
    in_logged_units: tuple[str, ...] | None = None
    gaps: Gaps | None = None

    def to_dict(self) -> Json:
        """Return the summary (``report.json``, ``data``)."""
        out = emit_fields(self, [f.name for f in dataclasses.fields(self)])
        out.update(recordings=list(self.recordings), xi_range=list(self.xi_range),
                   scales=self.scales.to_dict())
        if self.torque_from_current is not None:
            out.update(torque_from_current=[c.to_dict() for c in self.torque_from_current])
        if self.in_logged_units is not None:
            out.update(in_logged_units=list(self.in_logged_units))
        if self.gaps is not None:
            out.update(gaps=self.gaps.to_dict())
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> DataSummary:
        """Return the summary of :meth:`to_dict` (missing keys: their defaults)."""
        known = known_fields(cls, d)
        for key, conv in (('recordings', tuple), ('in_logged_units', tuple),
                          ('xi_range', tuple), ('scales', Scales.from_dict),
                          ('gaps', Gaps.from_dict)):
            if known.get(key) is not None:
                known[key] = conv(known[key])
        if known.get('torque_from_current') is not None:
            known['torque_from_current'] = tuple(
                CurrentSource.from_dict(c) for c in known['torque_from_current'])
        return cls(**known)


@dataclasses.dataclass(frozen=True)
class Timing:
    """
    Seconds per stage (``report.json``, ``timing``).

    Attributes
    ----------
    read_s, base_fit_s, candidates_s, extended_fit_s, velocity_sim_s, residual_scan_s : float
        The stages of :func:`~friction_joint.diagnosis.pipeline.diagnose`.
    report_s, total_s : float or None
        Rendering the report and the whole run (``diagnose`` command; None: not run).

    """

    read_s: float = 0.0
    base_fit_s: float = 0.0
    candidates_s: float = 0.0
    extended_fit_s: float = 0.0
    velocity_sim_s: float = 0.0
    residual_scan_s: float = 0.0
    report_s: float | None = None
    total_s: float | None = None

    def stages(self) -> list[tuple[str, float]]:
        """Return ``[(stage, seconds), ...]`` of the stages timed, in order."""
        return list(self.to_dict().items())

    def to_dict(self) -> Json:
        """Return the timing (``report.json``)."""
        return emit_fields(self, [f.name for f in dataclasses.fields(self)])

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Timing:
        """Return the timing of :meth:`to_dict`."""
        return cls(**known_fields(cls, d))


@dataclasses.dataclass(frozen=True)
class DataRanges:
    """
    The data's ranges the findings speak of (from the sliding bins).

    Attributes
    ----------
    temperature : tuple of float or None
        Min, max housing temperature (degC; None without a temperature signal).
    speed, load : tuple of float
        5..95 % of the sliding speeds (rad/s) and of abs(tau_ext) (Nm).
    position : tuple of float
        Min, max position (rad).
    travel, level, inertia : float
        Accumulated travel (rad), friction level (Nm), the base's J (kg m^2).

    """

    temperature: tuple[float, float] | None
    speed: tuple[float, float]
    load: tuple[float, float]
    position: tuple[float, float]
    travel: float
    level: float
    inertia: float


def _scan_table(rows: Iterable[Mapping[str, Any]]) -> tuple[ScanRow, ...]:
    return tuple(ScanRow.from_dict(r) for r in rows)


@dataclasses.dataclass(frozen=True)
class DiagnosisResult:
    """
    What ``report.json`` holds, typed (its keys are the field names).

    Attributes
    ----------
    named_causes : tuple of str
        The named effects, in the order they were added.
    candidates : tuple of CandidateVerdict
        One per candidate effect, testable or not.
    baseline, extended : ModelScore
        Held-out scores of the base and the extended model.
    criterion : CriterionInfo
        The criterion.
    adequacy : Adequacy
        How much of the friction torque each explains.
    confounds : tuple of Confound
        The confounded candidate pairs.
    rounds : tuple of Round
        The greedy rounds.
    data : DataSummary
        What was read.
    base_fit, extended_fit : dict
        Coefficients of the base and the extended fit.
    extended_effects : tuple of str
        The named effects ``extended.yaml`` holds.
    residual_scan : tuple of ScanRow
        The residual scan's table.
    untestable : dict of str to str
        Untestable candidates and why.
    notes : tuple of str
        Notes of the report.
    timing : Timing
        Seconds per stage.
    identify : IdentifyCheck or None
        Whether ``identify`` can run next (None: nothing to identify).
    diagnosed : DiagnosedModel or None
        The model with every named effect when ``extended.yaml`` differs from it.
    headline : str
        The report's first sentence.
    model_file, extended_file : str or None
        The base and the extended gear file (absolute; None: not written).

    """

    named_causes: tuple[str, ...] = ()
    candidates: tuple[CandidateVerdict, ...] = ()
    baseline: ModelScore = ModelScore(_NAN)
    extended: ModelScore = ModelScore(_NAN)
    criterion: CriterionInfo = CriterionInfo()
    adequacy: Adequacy = Adequacy(UNKNOWN_FIT, UNKNOWN_FIT)
    confounds: tuple[Confound, ...] = ()
    rounds: tuple[Round, ...] = ()
    data: DataSummary = DataSummary()
    base_fit: dict[str, Any] = dataclasses.field(default_factory=dict)
    extended_fit: dict[str, Any] = dataclasses.field(default_factory=dict)
    extended_effects: tuple[str, ...] = ()
    residual_scan: tuple[ScanRow, ...] = ()
    untestable: dict[str, str] = dataclasses.field(default_factory=dict)
    notes: tuple[str, ...] = ()
    timing: Timing = Timing()
    identify: IdentifyCheck | None = None
    diagnosed: DiagnosedModel | None = None
    headline: str = ''
    model_file: str | None = None
    extended_file: str | None = None

    def candidate(self, effect: str) -> CandidateVerdict | None:
        """
        Return the final table's verdict on ``effect`` (None: not a candidate).

        Parameters
        ----------
        effect : str
            The candidate.

        """
        return next((c for c in self.candidates if c.effect == effect), None)

    def to_dict(self) -> Json:
        """Return the ``report.json`` content (keys in their order; plain containers)."""
        out: Json = {
            'named_causes': list(self.named_causes),
            'candidates': [c.to_dict() for c in self.candidates],
            'baseline': self.baseline.to_dict(), 'extended': self.extended.to_dict(),
            'criterion': self.criterion.to_dict(),
            'adequacy': self.adequacy.to_dict(),
            'confounds': [c.to_dict() for c in self.confounds],
            'rounds': [r.to_dict() for r in self.rounds],
            'data': self.data.to_dict(), 'base_fit': self.base_fit,
            'extended_fit': self.extended_fit, 'extended_effects': list(self.extended_effects),
            'residual_scan': [r.to_dict() for r in self.residual_scan],
            'untestable': dict(self.untestable), 'notes': list(self.notes),
            'timing': self.timing.to_dict()}
        if self.identify is not None:
            out['identify'] = self.identify.to_dict()
        if self.diagnosed is not None:
            out['diagnosed'] = self.diagnosed.to_dict()
        out['headline'] = self.headline
        for key in ('model_file', 'extended_file'):
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> DiagnosisResult:
        """
        Return the result of a ``report.json`` content (missing keys: their defaults).

        Parameters
        ----------
        d : dict
            The ``report.json`` content, or a part of it.

        """
        parts: dict[str, Any] = {
            'candidates': tuple(CandidateVerdict.from_dict(c) for c in d.get('candidates', ())),
            'confounds': tuple(Confound.from_dict(c) for c in d.get('confounds', ())),
            'rounds': tuple(Round.from_dict(r) for r in d.get('rounds', ())),
            'residual_scan': _scan_table(d.get('residual_scan') or ())}
        for key in ('named_causes', 'extended_effects', 'notes'):
            parts[key] = tuple(d.get(key) or ())
        typed: dict[str, Any] = {
            'baseline': ModelScore.from_dict, 'extended': ModelScore.from_dict,
            'criterion': CriterionInfo.from_dict, 'adequacy': Adequacy.from_dict,
            'data': DataSummary.from_dict, 'timing': Timing.from_dict,
            'identify': IdentifyCheck.from_dict, 'diagnosed': DiagnosedModel.from_dict}
        for key, conv in typed.items():
            if d.get(key) is not None:
                parts[key] = conv(d[key])
        for key in ('base_fit', 'extended_fit', 'untestable', 'headline', 'model_file',
                    'extended_file'):
            if d.get(key) is not None:
                parts[key] = d[key]
        return cls(**parts)
