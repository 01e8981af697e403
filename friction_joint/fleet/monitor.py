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
The result of one fleet monitoring run (:func:`friction_joint.jobs.fleet.run_fleet`).

:class:`FleetRun` holds the assessment and what the run wrote; its
:meth:`~FleetRun.plot` draws the report's per-joint trend plots in memory
(:mod:`~friction_joint.fleet.plots`).  Reading the manifest and the cache,
the Dask tasks and writing DIR are the job's
(:mod:`friction_joint.jobs.fleet`).
"""
from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

from .assess import FleetAssessment
from .plots import trend_figures
from ..results import draw_figures

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ['FleetRun']


@dataclasses.dataclass
class FleetRun:
    """
    What :func:`~friction_joint.jobs.fleet.run_fleet` did.

    Attributes
    ----------
    assessment : FleetAssessment
    written : list of str
        The files written.
    computed, cached : int
        Recordings analysed by tasks in this run, and taken from the cache.
    workers : int
    timings : dict

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
        return draw_figures(trend_figures(self.assessment))
