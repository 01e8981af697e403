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
The ``classic`` command's work: run a classic LuGre experiment and write its two files.

:func:`run_classic` runs one of
:data:`friction_joint.experiments.classic.CLASSIC_EXPERIMENTS` and writes
``DIR/NAME.png`` (drawn by :func:`friction_joint.experiments.classic_report.draw_classic`)
and ``DIR/NAME.json``, together or not at all; :func:`write_experiment` writes
a result already computed (the demo's).
"""
from __future__ import annotations

import os

from ..experiments.classic import CLASSIC_EXPERIMENTS, ClassicResult
from ..experiments.classic_report import draw_classic
from ..output import OutputSet
from ..results import json_bytes, render_png

__all__ = ['write_experiment', 'run_classic']


def _declare(outputs, name, out_dir):
    paths = tuple(os.path.join(os.fspath(out_dir), name + ext) for ext in ('.png', '.json'))
    for path in paths:
        outputs.add_file(path)
    outputs.check()
    return paths


def _write(outputs, result, paths):
    size = (10, 5) if result.name != 'stick-slip' else (9, 6.5)
    png = render_png(lambda fig: draw_classic(fig, result), size, dpi=110)
    outputs.write_file(paths[0], png)
    outputs.write_file(paths[1], json_bytes(result.to_dict()))
    return tuple(outputs.publish())


def write_experiment(result: ClassicResult, out_dir: str | os.PathLike, *,
                     force: bool = False) -> tuple[str, ...]:
    """
    Write ``out_dir/NAME.png`` and ``out_dir/NAME.json`` of ``result``, together or not at all.

    Both files are rendered in memory and staged next to their place first;
    only then are they renamed into place, so an error leaves no partial
    result.  NAME is ``result.name``.  ``out_dir`` is created if missing and
    may hold other files; an existing ``NAME.png`` or ``NAME.json`` is an
    error unless ``force``.

    Parameters
    ----------
    result : ClassicResult
        The run of a classic experiment.
    out_dir : str or path-like
        Directory of the two files.
    force : bool
        Replace existing files of the same names.

    Returns
    -------
    tuple of str
        Paths of the PNG and JSON files.

    """
    with OutputSet(force=force) as outputs:
        return _write(outputs, result, _declare(outputs, result.name, out_dir))


def run_classic(name: str, out_dir: str | os.PathLike, *,
                force: bool = False) -> tuple[str, ...]:
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
    tuple of str
        Paths of the PNG and JSON files.

    """
    with OutputSet(force=force) as outputs:
        paths = _declare(outputs, name, out_dir)
        return _write(outputs, CLASSIC_EXPERIMENTS[name](), paths)
