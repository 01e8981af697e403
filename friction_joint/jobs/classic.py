# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ``classic`` command's work: run a classic LuGre experiment and write its two files.

:func:`run_classic` runs one of
:data:`friction_joint.experiments.classic.CLASSIC_EXPERIMENTS` and writes
``DIR/NAME.png`` (drawn by :func:`friction_joint.experiments.classic_report.draw_classic`)
and ``DIR/NAME.json``, together or not at all; :func:`write_experiment` writes
a result already computed (the demo's).  Both return a
:class:`~friction_joint.jobs.runs.ClassicRun`.
"""
from __future__ import annotations

import os

from .runs import ClassicRun
from ..experiments.classic import CLASSIC_EXPERIMENTS
from ..output import OutputSet
from ..results import ExperimentResult, json_bytes, render_png

__all__ = ['write_experiment', 'run_classic']


def _declare(outputs, name, out_dir):
    paths = tuple(os.path.join(os.fspath(out_dir), name + ext) for ext in ('.png', '.json'))
    for path in paths:
        outputs.add_file(path)
    outputs.check()
    return paths


def _write(outputs, result, paths):
    draw, size = result.figures[result.name + '.png']
    outputs.write_file(paths[0], render_png(draw, size, dpi=110))
    outputs.write_file(paths[1], json_bytes(result.to_dict()))
    return ClassicRun(result, tuple(outputs.publish()))


def write_experiment(result: ExperimentResult, out_dir: str | os.PathLike, *,
                     force: bool = False) -> ClassicRun:
    """
    Write ``out_dir/NAME.png`` and ``out_dir/NAME.json`` of ``result``, together or not at all.

    Both files are rendered in memory and staged next to their place first;
    only then are they renamed into place, so an error leaves no partial
    result.  NAME is ``result.name``.  ``out_dir`` is created if missing and
    may hold other files; an existing ``NAME.png`` or ``NAME.json`` is an
    error unless ``force``.

    Parameters
    ----------
    result : ExperimentResult
        The run of a classic experiment (its figure ``NAME.png``).
    out_dir : str or path-like
        Directory of the two files.
    force : bool
        Replace existing files of the same names.

    Returns
    -------
    ClassicRun
        ``result``, and the paths of the PNG and JSON files (``written``).

    """
    with OutputSet(force=force) as outputs:
        return _write(outputs, result, _declare(outputs, result.name, out_dir))


def run_classic(name: str, out_dir: str | os.PathLike, *,
                force: bool = False) -> ClassicRun:
    """
    Run classic experiment ``name`` and write its files (as :func:`write_experiment`).

    The outputs are checked before the experiment runs.

    Parameters
    ----------
    name : str
        One of :data:`~friction_joint.experiments.classic.CLASSIC_EXPERIMENTS`.
    out_dir : str or os.PathLike
        Directory of the two files.
    force : bool
        Replace existing files of the same names.

    Returns
    -------
    ClassicRun
        ``result``, and the paths of the PNG and JSON files (``written``).

    """
    with OutputSet(force=force) as outputs:
        paths = _declare(outputs, name, out_dir)
        return _write(outputs, CLASSIC_EXPERIMENTS[name](), paths)
