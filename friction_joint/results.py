# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Results as files: experiment results, plain JSON and figures rendered in memory.

:class:`ExperimentResult` holds a run's numbers and figure closures;
:func:`result_files` turns it into ``[(file name, bytes), ...]`` for an
:class:`~friction_joint.output.OutputSet`.  matplotlib is imported only when a
figure is rendered.
"""
from __future__ import annotations

from collections.abc import Callable
import dataclasses
import io
import json
import math
from typing import Any, cast, TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ['json_clean', 'json_bytes', 'render_png', 'draw_figures', 'ExperimentResult',
           'result_files']


@dataclasses.dataclass
class ExperimentResult:
    """
    Numbers, signals and figures of one experiment run.

    Every experiment returns one: the test-bed experiments
    (:mod:`friction_joint.experiments`), the classic LuGre experiments
    (:mod:`friction_joint.experiments.classic`); the identification's report
    is written as one (:mod:`friction_joint.jobs.identify`).

    Attributes
    ----------
    name : str
        The experiment (e.g. ``chirp``, ``compensation``, ``presliding``,
        ``stick-slip``).
    summary : dict
        Plain numbers, as documented by the experiment function (written as JSON).
    series : dict
        The signals the figures are drawn from (numpy arrays), per experiment.
    truth_model : str
        Friction model of the simulated hardware (``lugre``, ``gms``; empty when
        not simulated on the test bed).
    figures : dict
        File name -> ``(draw(fig), (width, height))``: the figures drawn from
        the run, rendered by :func:`result_files` (or :func:`render_png`).

    """

    name: str
    summary: dict
    series: dict = dataclasses.field(default_factory=dict)
    truth_model: str = ''
    figures: dict[str, tuple[Callable[[Figure], None], tuple[float, float]]] = \
        dataclasses.field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """Return the summary as plain JSON types (what the run's JSON file holds)."""
        return cast('dict[str, Any]', json_clean(self.summary))

    def plot(self, fig: Figure, *, name: str | None = None) -> None:
        """
        Draw one figure of the run on the matplotlib Figure ``fig``.

        Parameters
        ----------
        fig : matplotlib.figure.Figure
            The (empty) figure to draw on.
        name : str, optional
            File name of the figure (a key of :attr:`figures`); default the first.

        """
        draw, _ = self.figures[name if name is not None else next(iter(self.figures))]
        draw(fig)


def json_clean(obj: object) -> object:
    """
    Return ``obj`` as plain JSON types; non-finite floats become null.

    Parameters
    ----------
    obj : object
        Dicts, lists, tuples, numpy arrays and scalars, nested.

    Returns
    -------
    object

    """
    if isinstance(obj, dict):
        return {str(k): json_clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [json_clean(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, (np.integer, np.bool_)):
        return obj.item()
    return obj


def json_bytes(obj: object) -> bytes:
    """
    Return ``obj`` as indented JSON (UTF-8 bytes).

    Parameters
    ----------
    obj : object
        What :func:`json_clean` takes.

    Returns
    -------
    bytes

    """
    return (json.dumps(json_clean(obj), indent=2, allow_nan=False) + '\n').encode('utf-8')


def render_png(draw: Callable[[Figure], None], size: tuple[float, float], *,
               dpi: float = 100, tight: bool = True) -> bytes:
    """
    Render ``draw(fig)`` on a new Agg figure of ``size`` inches.

    Parameters
    ----------
    draw : callable
        ``draw(fig)`` draws on a matplotlib figure.
    size : tuple of float
        ``(width, height)`` in inches.
    dpi : float
        Resolution.
    tight : bool
        Lay the figure out with ``tight_layout`` after drawing (False: the
        drawing lays itself out).

    Returns
    -------
    bytes
        The PNG file.

    """
    buf = io.BytesIO()
    _drawn(draw, size, tight).savefig(buf, format='png', dpi=dpi)
    return buf.getvalue()


def _drawn(draw, size, tight=True):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fig = Figure(figsize=size)
    FigureCanvasAgg(fig)
    draw(fig)
    if tight:
        fig.tight_layout()
    return fig


def draw_figures(figures: dict[str, tuple]) -> dict[str, Figure]:
    """
    Draw ``{name: (draw, size)}`` on new figures, as the report files are, without writing them.

    Each figure is a :class:`matplotlib.figure.Figure` of ``size`` inches on an
    Agg canvas (no pyplot, no window), drawn and laid out exactly as
    :func:`render_png` draws the report's PNG files.  A third element
    ``tight`` (default True) is :func:`render_png`'s option of that name.

    Parameters
    ----------
    figures : dict
        ``{name: (draw(fig), (width, height)[, tight])}``, e.g.
        :func:`~friction_joint.identification.report.identification_figures`.

    Returns
    -------
    dict of str to matplotlib.figure.Figure
        The drawn figures, by name.

    """
    return {name: _drawn(*spec) for name, spec in figures.items()}


def result_files(result: ExperimentResult, *,
                 json_name: str = 'summary.json') -> list[tuple[str, bytes]]:
    """
    Render the figures of ``result`` and its JSON summary: ``[(file name, bytes), ...]``.

    Parameters
    ----------
    result : ExperimentResult
        The run.
    json_name : str
        Name of the JSON file, which comes last.

    Returns
    -------
    list of tuple
        ``(name, PNG bytes)`` per figure, then ``(json_name, JSON bytes)``.

    """
    files = [(name, render_png(draw, size)) for name, (draw, size) in result.figures.items()]
    files.append((json_name, json_bytes(result.summary)))
    return files
