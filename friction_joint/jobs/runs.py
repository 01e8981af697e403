# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
What each job computed and wrote: one ``...Run`` per ``run_*`` job (``written``: the paths).

Every ``run_*`` of :mod:`friction_joint.jobs` returns one of these (and
``run_diagnose`` its :class:`~friction_joint.jobs.diagnose.DiagnoseRun`): the
computed result beside ``written``, the paths the job wrote, as given.
"""
from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

from ..results import ExperimentResult

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..fleet.assess import FleetAssessment
    from ..identification.pipeline import IdentificationRun

__all__ = ['ClassicRun', 'ExperimentRun', 'IdentifyRun', 'DemoRun', 'FleetRun',
           'FleetSimulationRun']


@dataclasses.dataclass(frozen=True)
class ClassicRun:
    """
    What a ``classic`` run computed and wrote.

    Attributes
    ----------
    result : ExperimentResult
        The classic experiment's run (its ``name`` is the experiment's).
    written : tuple of str
        The paths written: ``NAME.png``, then ``NAME.json``.

    """

    result: ExperimentResult
    written: tuple[str, ...]


@dataclasses.dataclass(frozen=True)
class ExperimentRun:
    """
    What an ``experiment`` run computed and wrote.

    Attributes
    ----------
    name : str
        The experiment.
    summary : dict
        Its numbers (``summary.json``; for ``identification``, the plan of the
        recording written).
    written : list of str
        The paths written (figures, then ``summary.json``; or the recording).
    result : ExperimentResult or None
        The run with its figures (None for an experiment that writes a recording).

    """

    name: str
    summary: dict
    written: list[str]
    result: ExperimentResult | None = None


@dataclasses.dataclass(frozen=True)
class IdentifyRun:
    """
    What an ``identify`` run computed and wrote.

    Attributes
    ----------
    identification : IdentificationRun
        The identification (steps 1-3, the identified gear).
    report : dict
        The content of ``identification.json``.
    written : list of str
        The paths written (report files, then the gear file).

    """

    identification: IdentificationRun
    report: dict
    written: list[str]


@dataclasses.dataclass(frozen=True)
class DemoRun:
    """
    What a ``demo`` run wrote.

    Attributes
    ----------
    report : str
        The path of ``report.md`` (``report.html`` beside it).
    written : list of str
        The paths written (the result directory).

    """

    report: str
    written: list[str]


@dataclasses.dataclass(frozen=True)
class FleetSimulationRun:
    """
    What an ``experiment fleet`` run (a simulated fleet) computed and wrote.

    Attributes
    ----------
    truth : dict
        The truth, as written to ``truth.json`` (``joints``, ``recordings``, ...).
    manifest : str
        The path of ``manifest.csv``.
    written : list of str
        The paths written (the fleet's directory).

    """

    truth: dict
    manifest: str
    written: list[str]


@dataclasses.dataclass
class FleetRun:
    """
    What a ``fleet`` run computed and wrote.

    Attributes
    ----------
    assessment : FleetAssessment
        The joints' verdicts and the recordings' rows.
    written : list of str
        The files written.
    computed, cached : int
        Recordings analysed by tasks in this run, and taken from the cache.
    workers : int
        Workers of the cluster (0 when no task ran).
    timings : dict
        Seconds per stage.

    """

    assessment: FleetAssessment
    written: list
    computed: int
    cached: int
    workers: int
    timings: dict

    def to_dict(self) -> dict:
        """Return plain JSON types."""
        return {'fleet': self.assessment.to_dict(), 'written': list(self.written),
                'computed': self.computed, 'cached': self.cached, 'workers': self.workers,
                'timings': dict(self.timings)}

    def plot(self) -> dict[str, Figure]:
        """
        Draw the report's trend plot of every joint in memory (no file written).

        Returns
        -------
        dict of str to matplotlib.figure.Figure
            By joint id, as embedded in ``report.html``.

        """
        from ..fleet.plots import trend_figures
        from ..results import draw_figures
        return draw_figures(trend_figures(self.assessment))
