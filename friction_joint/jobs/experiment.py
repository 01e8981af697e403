# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The ``experiment`` command's work: load the gear files, run an experiment, write its results.

:func:`run_experiment` looks the experiment up in
:data:`friction_joint.experiments.runner.EXPERIMENTS`, runs it on the
simulated test bed and writes one output: the directory with its figures
(drawn by :mod:`friction_joint.experiments.plots`) and ``summary.json``, or
the recording of the identification excitation.
"""
from __future__ import annotations

from collections.abc import Callable
import inspect
import os
import threading
import time
from typing import Any

from .runs import ExperimentRun
from ..bag import write_recording
from ..control.gains import gain_design, GainDesign
from ..exceptions import ExperimentError, FrictionJointError
from ..experiments._common import check_scale
from ..experiments.runner import check_gains, CLOSED_LOOP, EXPERIMENTS
from ..gear import load_gear
from ..output import OutputSet
from ..results import result_files

__all__ = ['run_experiment', 'QUIET_FOR']

#: s an experiment that reports nothing itself runs before the job says that it runs
QUIET_FOR = 5.0


def run_experiment(name: str, model_path: str | os.PathLike | None,
                   truth_path: str | os.PathLike, out_dir: str | os.PathLike, *,
                   duration_scale: float = 1.0, progress: Callable[[str], None] | None = None,
                   force: bool = False,
                   gains: str | GainDesign | None = None) -> ExperimentRun:
    """
    Load the gear files, run experiment ``name`` and write its results.

    ``model_path`` may be None for experiments that do not use a model
    (``identification``).  Experiments with ``output == 'recording'`` write a
    rosbag2 recording at ``out_dir`` (a directory, or a file if the name ends in
    ``.mcap``); the others write the directory ``out_dir`` with their figures and
    ``summary.json``.  Either is one output: an existing one (not an empty
    directory) is an error unless ``force``, which replaces it as a whole; one
    that is, contains or lies in ``model_path`` or ``truth_path`` always.
    ``gains`` (a :class:`~friction_joint.control.gains.GainDesign` or its
    text, e.g. ``paper``, ``J=0.05``, ``kp=40,kd=1``) is the controller's gain
    design of the closed-loop experiments (:data:`CLOSED_LOOP`); default
    their ``paper`` preset.  It is an error for the others.  ``progress(message)``
    reports steps of the experiments that take it (``identification`` per
    block, ``compensation`` per warm-up and temperature).

    Parameters
    ----------
    name : str
        An experiment of :data:`~friction_joint.experiments.runner.EXPERIMENTS`.
    model_path : str or os.PathLike or None
        The model gear file (None for ``identification``).
    truth_path : str or os.PathLike
        The simulated hardware's gear file.
    out_dir : str or os.PathLike
        The output (a directory, or the recording).
    duration_scale : float
        Multiplies every run's duration.
    progress : callable, optional
        Called with a message per step of the experiments that report steps.
    force : bool
        Replace an existing output as a whole.
    gains : str or GainDesign, optional
        The controller's gain design of the closed-loop experiments.

    Returns
    -------
    ExperimentRun
        The summary, the run (None for a recording) and the paths written
        (figures, then ``summary.json``; or the recording).

    """
    if name not in EXPERIMENTS:
        raise ExperimentError(f'unknown experiment {name!r}; choose from {", ".join(EXPERIMENTS)}')
    exp = EXPERIMENTS[name]
    scale = check_scale(duration_scale)
    options: dict[str, Any] = {}
    if gains is not None:
        if name not in CLOSED_LOOP:
            raise ExperimentError(f'experiment {name} has no controller: --gains applies to '
                                  f'{" and ".join(CLOSED_LOOP)} only')
        try:
            options['gains'] = gain_design(gains)
        except FrictionJointError as exc:
            raise ExperimentError(str(exc)) from None
    if exp.needs_model and model_path is None:
        raise ExperimentError(f'experiment {name} needs --model (the identified model gear file)')
    out_dir = os.fspath(out_dir)
    inputs = [('--model', model_path), ('--truth', truth_path)]
    with OutputSet(force=force, inputs=inputs, error=ExperimentError) as outputs:
        if exp.output == 'recording' and out_dir.endswith('.mcap'):
            outputs.add_file(out_dir)
        else:
            outputs.add_directory(out_dir)
        outputs.check()
        model = load_gear(model_path) if model_path is not None else None
        truth = load_gear(truth_path)
        if 'gains' in options:
            check_gains(options['gains'], model, truth)
        start = time.perf_counter()
        if exp.output == 'recording':
            topics, summary = exp.func(model, truth, scale, progress=progress)
            try:
                write_recording(outputs.staging_path(out_dir), topics,
                                joint_name=truth.joint_name)
            except OSError as exc:          # a full disk, a read-only target found late
                raise ExperimentError(f'cannot write {out_dir}: '
                                      f'{exc.strerror or exc}') from None
            written = outputs.publish()
            summary['wall_time_s'] = time.perf_counter() - start
            if progress is not None:
                progress(f'{len(summary.get("plateaus", []))} plateaus planned, '
                         f'{summary.get("duration_s", 0.0):.1f} s simulated in '
                         f'{summary["wall_time_s"]:.1f} s')
            return ExperimentRun(name, summary, written)
        said, timers = [], []
        if progress is not None and 'progress' in inspect.signature(exp.func).parameters:
            options['progress'] = progress
        elif progress is not None:          # the experiment says nothing itself: a run that
            def running():                  # lasts says that it runs (a refusal stays alone)
                said.append(True)
                progress(f'{name}: still simulating on the test bed after {QUIET_FOR:g} s '
                         f'(duration scale {scale:g}) ...')
            timers.append(threading.Timer(QUIET_FOR, running))
            timers[0].daemon = True
            timers[0].start()
        try:
            result = exp.func(model, truth, scale, **options)
        finally:
            for timer in timers:
                timer.cancel()
        result.summary['model_file'] = (os.path.abspath(model_path) if model_path is not None
                                        else None)      # every 'results' experiment has one
        result.summary['truth_file'] = os.path.abspath(truth_path)
        result.summary['wall_time_s'] = time.perf_counter() - start
        if said and progress is not None:
            progress(f'{name}: simulated in {result.summary["wall_time_s"]:.1f} s; '
                     'drawing the figures')
        outputs.write_directory(out_dir, result_files(result))
        return ExperimentRun(name, result.summary, outputs.publish(), result)
