# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ``identify`` command's work: load, compute, write (the paper's identification, Section V-A).

:func:`run_identify` runs :func:`friction_joint.identification.identify_recordings`
on the recordings in the structure of a gear file, draws the report figures
(:mod:`friction_joint.identification.report`) and writes GEAR.yaml (a gear
file whose header says what was fitted, with standard errors) together with
its report directory, as one output set (:class:`~friction_joint.output.OutputSet`);
it returns an :class:`~friction_joint.jobs.runs.IdentifyRun`.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import dataclasses
import datetime
import os
import time

import numpy as np

from .diagnose import current_sources
from .runs import IdentifyRun
from ..gear import format_gear, parse_gear
from ..identification import identify_recordings
from ..identification.report import identification_figures
from ..identification.stick_slip import stick_slip_summary
from ..output import OutputSet, recording_inputs
from ..results import ExperimentResult, result_files

__all__ = ['run_identify']


def _fmt_list(vals, ses):
    return '[' + ', '.join(f'{v:.6g} +- {e:.2g}' for v, e in zip(vals, ses, strict=True)) + ']'


def _header(run, paths, structure_path, currents=()):
    ident = run.identifier
    p = run.plateaus
    lines = [
        f'Identified by "friction_joint identify" (seed paper Section V-A) on '
        f'{datetime.date.today().isoformat()}',
        'from: ' + ', '.join(paths) + f' (joint {run.gear.joint_name!r})',
        f'  {len(p)} constant-velocity plateaus, |qd| {np.abs(p.qd).min():.3g}..'
        f'{np.abs(p.qd).max():.3g} rad/s, xi {p.xi.min():.2f}..{p.xi.max():.2f} degC, '
        f'tau_L {p.load.min():.2f}..{p.load.max():.2f} Nm',
        f'structure: {os.path.abspath(structure_path)} ({ident.structure.describe()}); '
        'other sections kept from it',
        f'steps 1-2 (static curve, eq. 6-7, least squares eq. 16): RMS residual '
        f'{ident.rms:.4f} Nm',
        'friction.temperature_range = the recorded temperature range (polynomials are not '
        'extrapolated)',
        'coefficients +- standard error (powers of xi; load: powers 1.. of tau_L):',
    ]
    gaps = run.gaps
    if gaps and (gaps['bridged'] or gaps['split']):
        lines.insert(3, f'  gaps in the joint-state stamps: {gaps["bridged"]} bridged (longest '
                        f'{1e3 * gaps["longest_bridged_s"]:.1f} ms, interpolated and left out '
                        f'of the fits), {gaps["split"]} split the recordings')
    lines[2:2] = [f'  {c["recording"]}: {c["text"]}' for c in currents]
    for name, vals in ident.coefficients.items():
        lines.append(f'  {name}: {_fmt_list(vals, ident.standard_errors[name])}')
    for name, vals in ident.structure.fixed.items():
        lines.append(f'  {name}: {[float(f"{v:.6g}") for v in vals]} (kept, not fitted)')
    lines.append(f'  delta_s: {ident.structure.delta_s:.4g}'
                 + (' (kept, not fitted)' if 'delta_s' not in ident.coefficients else ''))
    lines.append('what the data pin (standard errors: '
                 f'{ident.info["covariance_method"]["method"]}):')
    lines += [f'  {line}' for line in ident.identifiability['lines']]
    val = ident.validation
    if val.get('blocks'):
        lines.append(f'held-out check ({val["blocks"]} blocks of plateaus, each predicted by a '
                     f'fit without it): RMS {val["rms"]:.4f} Nm (in-sample '
                     f'{val["rms_in_sample"]:.4f})')
        lines += [f'  |qd| {b["v_low"]:.3g}..{b["v_high"]:.3g} rad/s: RMS {b["rms"]:.4f} Nm '
                  f'({100 * b["rel_rms"]:.2g} %), worst {b["worst"]:.4f} Nm '
                  f'({100 * b["worst_rel"]:.2g} %), {b["plateaus"]} plateaus'
                  for b in val['bands']]
    slip = stick_slip_summary(p)
    if slip:
        lines.append(f'stick-slip: {slip}')
    s3 = run.presliding
    if s3.status == 'done' and s3.models is not None:
        for model, r in s3.models.items():
            if r.get('status') == 'rejected':
                lines.append(f'step 3 ({model}) rejected: {r["reason"]}')
                continue
            kept = r.get('kept_values', {})
            lines.append(f'step 3 ({model}, pattern search): ' + ', '.join(
                (f'{k} = {kept[k]:.6g} written, kept from the structure: undetermined by the '
                 f'data (fit {v:.3g} +- {r["stderr"][k]:.2g})' if k in kept else
                 f'{k} = {v:.6g} +- {r["stderr"][k]:.2g}'
                 + (' (undetermined by the data: structure value kept)'
                    if k in r['kept_from_structure'] else ''))
                for k, v in r['params'].items() if k in r['stderr'])
                + f'; RMS {r["report"]["objective_final"]:.4f} Nm')
    else:
        lines.append(f'step 3 (pre-sliding) {s3.status}: {s3.reason}; pre-sliding '
                     'parameters kept from the structure')
    if s3.why:
        lines += [f'step 3: why: {s3.why}', f'step 3: to fit it, {s3.advice}']
    return '\n'.join(lines)


def _relocated(obj, relocate):
    """Return ``obj`` (plain JSON types) with every string passed through ``relocate``."""
    if isinstance(obj, dict):
        return {k: _relocated(v, relocate) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_relocated(v, relocate) for v in obj]
    return relocate(obj) if isinstance(obj, str) else obj


def _gear_bytes(gear, header):
    """Return the gear file's text (UTF-8), checked to load as every node loads it."""
    text = format_gear(gear, header=header)          # in memory: no temporary file to fill a disk
    parse_gear(text, 'the identified gear file')
    return text.encode('utf-8')


def run_identify(paths: Sequence[str | os.PathLike], model_path: str | os.PathLike,
                 out: str | os.PathLike, *, orders: str | dict[str, int] | None = None,
                 presliding: str = 'auto', joint_name: str | None = None,
                 progress: Callable[[str], None] | None = None,
                 report_dir: str | os.PathLike | None = None, force: bool = False,
                 relocate: Callable[[str], str] | None = None,
                 velocity_from_position: bool = False) -> IdentifyRun:
    """
    Run the identification and write GEAR.yaml and its report directory, one set of outputs.

    Parameters
    ----------
    paths : sequence of str
        Recordings.
    model_path : str
        The structure gear file.
    out : str
        GEAR.yaml to write.
    orders, presliding, joint_name, progress
        As for :func:`identify_recordings`.
    report_dir : str, optional
        Report directory (default ``GEAR_report`` next to GEAR.yaml).
    force : bool
        Replace an existing GEAR.yaml and report directory (as a whole); without it
        either existing is an error, checked before the work.
    relocate : callable, optional
        Maps the absolute paths named in the header and report to the paths they will
        have (for a caller that builds everything in a staging directory, ``demo``).
    velocity_from_position : bool
        As for :func:`identify_recordings` (recorded in ``identification.json``).

    Returns
    -------
    IdentifyRun
        The identification, the report (``identification.json``) and the paths
        written (report files, then the gear file).

    """
    start = time.perf_counter()
    out = os.fspath(out)
    where = relocate or (lambda path: path)
    if report_dir is None:
        stem = os.path.splitext(os.path.basename(out))[0]
        report_dir = os.path.join(os.path.dirname(os.path.abspath(out)), f'{stem}_report')
    inputs = [('--model', model_path)] + recording_inputs(paths)
    with OutputSet(force=force, inputs=inputs) as outputs:
        outputs.add_directory(report_dir, label='--report')
        outputs.add_file(out, label='--out')
        outputs.check()
        currents = current_sources(paths)
        run = identify_recordings(paths, os.fspath(model_path), orders=orders,
                                  joint_name=joint_name,
                                  presliding=presliding, progress=progress,
                                  velocity_from_position=velocity_from_position)
        if relocate is not None:
            run.recordings = [dataclasses.replace(r, path=relocate(os.path.abspath(r.path)))
                              for r in run.recordings]
        t0 = time.perf_counter()
        rep = run.report()
        rep['structure_file'] = os.path.abspath(model_path)
        rep['gear_file'] = where(os.path.abspath(out))
        rep['joint_name'] = run.gear.joint_name
        rep['velocity_from_position'] = bool(velocity_from_position)
        rep['torque_from_current'] = currents
        figures = identification_figures(run.identifier, run.recordings, run.presliding)
        rep['timings']['time_total_s'] = time.perf_counter() - start
        if relocate is not None:
            rep = _relocated(rep, relocate)
        report = ExperimentResult('identification', rep, figures=figures)
        outputs.write_directory(report_dir,
                                result_files(report, json_name='identification.json'))
        header = _header(run, [where(os.path.abspath(x)) for x in paths], model_path,
                         currents)
        outputs.write_file(out, _gear_bytes(run.gear, header))
        written = outputs.publish()
    if progress:
        progress(f'report: {report_dir} ({time.perf_counter() - t0:.1f} s)')
    return IdentifyRun(run, rep, written)
