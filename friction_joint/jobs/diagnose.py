# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ``diagnose`` command's work: load, compute, write (docs/interfaces.md, ``diagnose`` outputs).

:func:`run_diagnose` reads the base gear file, runs
:func:`friction_joint.diagnosis.diagnose` on the recordings, renders the
figures and the report (:mod:`friction_joint.diagnosis.report`) and writes
the result directory as one output set (:class:`~friction_joint.output.OutputSet`):
``report.json``, ``extended.yaml``, ``report.md``, ``report.html`` and the
figures.  The diagnosis subpackage computes and draws; only this layer reads
and writes files.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
import os
import time
from typing import Any, TYPE_CHECKING

import yaml

from ..bag import recording_custom_data, torque_from_current
from ..diagnosis import diagnose, Diagnosis, EFFECTS
from ..diagnosis.findings import candidate_summary, logged_unit_lines
from ..diagnosis.report import figures, markdown
from ..diagnosis.result import CurrentSource
from ..gear import gear_from_dict, load_gear
from ..output import OutputSet, recording_inputs
from ..report_html import markdown_to_html
from ..results import json_bytes

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['DiagnoseRun', 'run_diagnose', 'current_sources']


def current_sources(paths: Sequence[str | os.PathLike[str]]) -> list[dict[str, Any]]:
    """
    Return, per recording whose torque an import converted from a motor current, how.

    Parameters
    ----------
    paths : sequence of str or os.PathLike
        Recordings (their ``metadata.yaml`` custom data is read).

    Returns
    -------
    list of dict
        ``recording`` (the path) and the fields of
        :func:`~friction_joint.bag.torque_from_current` (``text``: the report line).

    """
    out = []
    for path in (os.fspath(p) for p in paths):
        src = torque_from_current(recording_custom_data(path))
        if src is not None:
            out.append({'recording': path, **src})
    return out


def _gear_yaml(gear: GearParams, header: str) -> str:
    text = yaml.safe_dump(gear.to_dict(), sort_keys=False, default_flow_style=None)
    doc = yaml.safe_load(text)                    # must load like a gear file does
    gear_from_dict(doc['/**']['ros__parameters'], source='extended.yaml')
    return ''.join(f'# {ln}\n' for ln in header.splitlines()) + text


def _html(md: str, figs: Sequence[tuple[str, bytes]]) -> str:
    """Return ``report.md`` as one self-contained HTML page, the figures embedded (only they)."""
    return str(markdown_to_html(md, images=dict(figs), title='friction_joint diagnose report'))


@dataclass(frozen=True)
class DiagnoseRun:
    """
    What a ``diagnose`` run computed and wrote.

    Attributes
    ----------
    diagnosis : Diagnosis
        The result (its ``to_dict()`` is the content of ``report.json``).
    written : list of str
        The paths written, as given (``report.json`` last).

    """

    diagnosis: Diagnosis
    written: list[str]

    @property
    def named_causes(self) -> list[str]:
        """Return the missing effects named, in the order they were added."""
        return list(self.diagnosis.named_causes)


def run_diagnose(paths: Sequence[str | os.PathLike[str]], model_path: str | os.PathLike[str],
                 out: str | os.PathLike[str], *, effects: Sequence[str] = EFFECTS,
                 joint_name: str | None = None, progress: Callable[[str], None] | None = None,
                 force: bool = False, velocity_from_position: bool = False) -> DiagnoseRun:
    """
    Diagnose and write the result directory ``out`` as a whole.

    ``out`` is checked before the work: an existing non-empty ``out`` is an error
    unless ``force`` (then it is replaced as a whole, no file of an earlier run
    remains), an ``out`` that is, contains or lies in an input always.  Everything
    is computed and rendered first, then ``out`` is built next to its place and
    renamed into it (:class:`~friction_joint.output.OutputSet`).

    Parameters
    ----------
    paths : sequence of str or os.PathLike
        Recordings.
    model_path : str or os.PathLike
        The base gear file.
    out : str or os.PathLike
        The result directory.
    effects, joint_name, progress
        As for :func:`~friction_joint.diagnosis.diagnose`.
    force : bool
        Replace an existing ``out``.
    velocity_from_position : bool
        Use the position's centred difference as the recorded velocity (recorded in
        ``report.json``, ``data.velocity_from_position``).

    Returns
    -------
    DiagnoseRun
        The diagnosis and the paths written.

    """
    start = time.perf_counter()
    inputs = [('--model', model_path)] + recording_inputs(paths)
    with OutputSet(force=force, inputs=inputs) as outputs:
        outputs.add_directory(out)
        outputs.check()
        return _diagnose_into(outputs, paths, model_path, out, start,
                              effects=effects, joint_name=joint_name, progress=progress,
                              velocity_from_position=velocity_from_position)


def _diagnose_into(outputs: OutputSet, paths: Sequence[str | os.PathLike[str]],
                   model_path: str | os.PathLike[str], out: str | os.PathLike[str],
                   start: float, *, effects: Sequence[str], joint_name: str | None,
                   progress: Callable[[str], None] | None,
                   velocity_from_position: bool) -> DiagnoseRun:
    base = load_gear(model_path)
    currents = current_sources(paths)
    diag = diagnose(paths, base, effects=effects, joint_name=joint_name, progress=progress,
                    velocity_from_position=velocity_from_position)
    logged = logged_unit_lines([os.fspath(p) for p in paths], diag.result)
    data = replace(diag.result.data, in_logged_units=tuple(logged),
                   torque_from_current=tuple(CurrentSource.from_dict(c) for c in currents))
    diag = replace(diag, result=replace(diag.result, data=data))
    if progress and logged:
        progress('in the units the recordings were imported in: ' + '; '.join(logged))
    gaps = data.gaps
    if progress and gaps is not None and (gaps.bridged or gaps.split):
        progress(f'gaps in the stamps: {gaps.bridged} bridged (longest '
                 f'{1e3 * gaps.longest_bridged_s:.1f} ms), {gaps.split} split')
    t0 = time.perf_counter()
    figs = figures(diag)
    report_s = time.perf_counter() - t0
    result = diag.result
    header = (f'Extended by "friction_joint diagnose" from {os.path.abspath(model_path)}\n'
              f'named causes: {", ".join(result.named_causes) or "none"}\n'
              f'held-out torque RMSE {result.baseline.torque_rmse:.4f} -> '
              f'{result.extended.torque_rmse:.4f} Nm\n'
              'recordings: ' + ', '.join(os.path.abspath(p) for p in paths))
    gear_text = _gear_yaml(diag.gear, header)
    result = replace(result, model_file=os.path.abspath(model_path),
                     extended_file=os.path.abspath(os.path.join(out, 'extended.yaml')),
                     timing=replace(result.timing, report_s=report_s,
                                    total_s=time.perf_counter() - start))
    diag = replace(diag, result=result)
    md = markdown(diag, [n for n, _ in figs], model_path, out_dir=os.path.normpath(out))
    targets = figs + [('report.md', md.encode('utf-8')),
                      ('report.html', _html(md, figs).encode('utf-8')),
                      ('extended.yaml', gear_text.encode('utf-8')),
                      ('report.json', json_bytes(diag.to_dict()))]
    outputs.write_directory(out, targets)
    paths_written = outputs.publish()
    if progress:
        for text in candidate_summary(result):
            progress('not named: ' + text)
        progress('timing: ' + ', '.join(f'{k} {v:.2f} s' for k, v in result.timing.stages()))
    return DiagnoseRun(diagnosis=diag, written=paths_written)
