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
from dataclasses import dataclass
import os
import time

import yaml

from ..diagnosis import diagnose, Diagnosis, EFFECTS
from ..diagnosis.findings import candidate_summary
from ..diagnosis.report import figures, markdown
from ..gear import gear_from_dict, load_gear
from ..output import OutputSet, recording_inputs
from ..report_html import markdown_to_html
from ..results import json_bytes

__all__ = ['DiagnoseRun', 'run_diagnose']


def _gear_yaml(gear, header):
    text = yaml.safe_dump(gear.to_dict(), sort_keys=False, default_flow_style=None)
    doc = yaml.safe_load(text)                    # must load like a gear file does
    gear_from_dict(doc['/**']['ros__parameters'], source='extended.yaml')
    return ''.join(f'# {ln}\n' for ln in header.splitlines()) + text


def _html(md, figs):
    """Return ``report.md`` as one self-contained HTML page, the figures embedded (only they)."""
    return markdown_to_html(md, images=dict(figs), title='friction_joint diagnose report')


@dataclass(frozen=True)
class DiagnoseRun:
    """
    What a ``diagnose`` run computed and wrote.

    Attributes
    ----------
    diagnosis : Diagnosis
        The result (its ``report`` is the content of ``report.json``).
    written : list of str
        The paths written, as given (``report.json`` last).

    """

    diagnosis: Diagnosis
    written: list[str]

    @property
    def named_causes(self) -> list[str]:
        """Return the missing effects named, in the order they were added."""
        return list(self.diagnosis.report['named_causes'])


def run_diagnose(paths: Sequence[str | os.PathLike], model_path: str | os.PathLike,
                 out: str | os.PathLike, *, effects: Sequence[str] = EFFECTS,
                 joint_name: str | None = None, progress: Callable[[str], None] | None = None,
                 force: bool = False) -> DiagnoseRun:
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
                              effects=effects, joint_name=joint_name, progress=progress)


def _diagnose_into(outputs, paths, model_path, out, start, *, effects, joint_name, progress):
    base = load_gear(model_path)
    diag = diagnose(paths, base, effects=effects, joint_name=joint_name, progress=progress)
    gaps = getattr(diag.data, 'gaps', None)
    if gaps is not None:
        diag.report['data']['gaps'] = gaps
        if progress and (gaps['bridged'] or gaps['split']):
            progress(f'gaps in the stamps: {gaps["bridged"]} bridged (longest '
                     f'{1e3 * gaps["longest_bridged_s"]:.1f} ms), {gaps["split"]} split')
    t0 = time.perf_counter()
    figs = figures(diag)
    diag.report['timing']['report_s'] = time.perf_counter() - t0
    rep = diag.report
    header = (f'Extended by "friction_joint diagnose" from {os.path.abspath(model_path)}\n'
              f'named causes: {", ".join(rep["named_causes"]) or "none"}\n'
              f'held-out torque RMSE {rep["baseline"]["torque_rmse"]:.4f} -> '
              f'{rep["extended"]["torque_rmse"]:.4f} Nm\n'
              'recordings: ' + ', '.join(os.path.abspath(p) for p in paths))
    gear_text = _gear_yaml(diag.gear, header)
    rep['model_file'] = os.path.abspath(model_path)
    rep['extended_file'] = os.path.abspath(os.path.join(out, 'extended.yaml'))
    rep['timing']['total_s'] = time.perf_counter() - start
    md = markdown(diag, [n for n, _ in figs], model_path, out_dir=os.path.normpath(out))
    targets = figs + [('report.md', md.encode('utf-8')),
                      ('report.html', _html(md, figs).encode('utf-8')),
                      ('extended.yaml', gear_text.encode('utf-8')),
                      ('report.json', json_bytes(rep))]
    outputs.write_directory(out, targets)
    paths_written = outputs.publish()
    if progress:
        for text in candidate_summary(rep):
            progress('not named: ' + text)
        progress('timing: ' + ', '.join(f'{k} {v:.2f} s' for k, v in rep['timing'].items()))
    return DiagnoseRun(diagnosis=diag, written=paths_written)
