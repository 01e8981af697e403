# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
The in-memory side of a diagnosis: the result with what it was computed from.

:class:`DiagnosisCore` holds the typed result
(:class:`~friction_joint.diagnosis.result.DiagnosisResult`, the ``report.json``
content) beside the extended gear, the data, the cross-validations per round
(:class:`RoundFit`) and the open-loop velocities (:class:`VelocitySim`) the
figures are drawn from; :class:`ExtendedModel` is the gear file's model.
"""
from __future__ import annotations

from collections.abc import Mapping
import dataclasses
from typing import Any, TYPE_CHECKING

from .result import DiagnosisResult, Timing
from .verdicts import Adequacy, Json, Round
from ..results import json_clean

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from .crossval import CVResult
    from .data import DiagnosisData
    from .structures import CandidateStructure, Context
    from ..gear import GearParams

__all__ = ['ExtendedModel', 'VelocitySim', 'RoundFit', 'DiagnosisCore']


@dataclasses.dataclass(frozen=True)
class ExtendedModel:
    """
    The gear file's model: the greedy sequence walked back to what fits physically.

    Attributes
    ----------
    gear : GearParams
        The extended gear (the base when nothing is kept).
    structure : CandidateStructure
        Its structure.
    fit : dict
        Its coefficients (``report.json``, ``extended_fit``).
    kept : int
        Named effects kept (-1: the base file as given).
    reason : str or None
        Why the others are left out (None if none is).

    """

    gear: GearParams
    structure: CandidateStructure
    fit: dict[str, Any]
    kept: int
    reason: str | None

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> ExtendedModel:
        """Return the model of :func:`~friction_joint.diagnosis.fitted_gear.extended_model`."""
        return cls(d['gear'], d['structure'], d['coef'], int(d['kept']), d['reason'])


@dataclasses.dataclass(frozen=True)
class VelocitySim:
    """
    Open-loop velocities of held-out windows (one row per window, rad/s).

    Attributes
    ----------
    base, extended, measured : numpy.ndarray
        Simulated with the base and the extended model; measured.
    folds : numpy.ndarray
        The held-out block of each window.

    """

    base: npt.NDArray[np.float64]
    extended: npt.NDArray[np.float64]
    measured: npt.NDArray[np.float64]
    folds: npt.NDArray[Any]


@dataclasses.dataclass(frozen=True)
class RoundFit:
    """
    The models of one greedy round (in memory: what its figures are drawn from).

    Attributes
    ----------
    round : int
        1, 2, ...
    cur_cv : CVResult
        Cross-validation of the round's current model.
    cv : dict of str to CVResult
        Of each tested candidate.
    structure : CandidateStructure
        The round's current structure.

    """

    round: int                  # noqa: A003 - the report.json key
    cur_cv: CVResult
    cv: Mapping[str, CVResult]
    structure: CandidateStructure


@dataclasses.dataclass(frozen=True)
class DiagnosisCore:
    """
    Everything a diagnosis found: the result and what it was computed from.

    Attributes
    ----------
    result : DiagnosisResult
        The ``report.json`` content, typed.
    gear : GearParams
        The extended gear (the base when nothing was added).
    data : DiagnosisData
        The data.
    base : GearParams
        The base gear (as given).
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

    """

    result: DiagnosisResult
    gear: GearParams
    data: DiagnosisData
    base: GearParams
    ctx: Context
    base_cv: CVResult
    final_cv: CVResult
    velocity: VelocitySim
    fits: tuple[RoundFit, ...] = ()
    scan: dict[str, Any] | None = None

    @property
    def named_causes(self) -> tuple[str, ...]:
        """Return the named effects, in the order they were added."""
        return self.result.named_causes

    @property
    def rounds(self) -> tuple[Round, ...]:
        """Return the greedy rounds."""
        return self.result.rounds

    @property
    def adequacy(self) -> Adequacy:
        """Return how much of the friction torque the base and the extended model explain."""
        return self.result.adequacy

    @property
    def timing(self) -> Timing:
        """Return the seconds per stage."""
        return self.result.timing

    @property
    def report(self) -> Json:
        """Return the ``report.json`` content (:meth:`to_dict`)."""
        return self.to_dict()

    def to_dict(self) -> Json:
        """Return the ``report.json`` content (plain JSON types)."""
        clean = json_clean(self.result.to_dict())
        assert isinstance(clean, dict)
        return clean
