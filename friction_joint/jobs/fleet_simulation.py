# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``experiment fleet``'s work: simulate a fleet (:mod:`~friction_joint.experiments.fleet`), write it.

:func:`run_fleet_simulation` draws the fleet's plan, simulates every
joint-day's recording (here, in worker processes or on an executor: each
task simulates and writes its recording) and writes ``DIR/manifest.csv``,
``DIR/recordings/`` and ``DIR/truth.json`` as one output
(:class:`~friction_joint.output.OutputSet`: built beside DIR and renamed into
place; an existing DIR is an error unless ``force``).
"""
from __future__ import annotations

from collections.abc import Callable
import concurrent.futures
import csv
import io
import json
import os

from .runs import FleetSimulationRun
from ..bag import write_recording
from ..exceptions import ExperimentError
from ..experiments.fleet import (check_fleet_size, default_gear, draw_fleet, fleet_recording,
                                 fleet_truth, MANIFEST_COLUMNS, manifest_rows)
from ..gear import load_gear
from ..output import OutputSet

__all__ = ['run_fleet_simulation']


def _write_one(gear, joint, rec, path, cfg):
    """Simulate one joint-day and write its recording to ``path``."""
    write_recording(path, fleet_recording(gear, joint, rec, cfg), joint_name=gear.joint_name)


def _one(args):
    """Do :func:`_write_one` in a worker: the gear file's path is shipped, not the gear."""
    gear_path, joint, rec, path, cfg = args
    _write_one(load_gear(gear_path), joint, rec, path, cfg)
    return path


def run_fleet_simulation(out: str | os.PathLike, *, joints: int, days: int, seed: int = 0,
                         gear: str | os.PathLike | None = None, cfg: dict | None = None,
                         jobs: int = 1,
                         executor: concurrent.futures.Executor | None = None,
                         force: bool = False,
                         progress: Callable[[str], None] | None = None) -> FleetSimulationRun:
    """
    Simulate a fleet and write ``out/manifest.csv``, the recordings and ``out/truth.json``.

    Parameters
    ----------
    out : str or os.PathLike
        Directory to write, one output (:class:`~friction_joint.output.OutputSet`: built
        beside it and renamed into place; an existing one is an error unless ``force``).
    joints : int
        Number of joints.
    days : int
        Number of days: one recording per joint and day
        (:func:`~friction_joint.experiments.fleet.check_fleet_size`: at most
        :data:`~friction_joint.experiments.fleet.MAX_RECORDINGS`, refused before any
        work with an estimate).
    seed : int
        Draws everything (conditions, wear, noise); >= 0.
    gear : str or os.PathLike, optional
        The joints' nominal gear file (default
        :func:`~friction_joint.experiments.fleet.default_gear`).
    cfg : dict, optional
        Overrides of :data:`~friction_joint.experiments.fleet.FLEET`.
    jobs : int
        Processes simulating recordings in parallel.
    executor : concurrent.futures.Executor, optional
        Runs the recordings' simulations instead (e.g. on a Dask cluster); ``jobs`` is
        then not used.
    force : bool
        Replace an existing ``out`` as a whole.
    progress : callable, optional
        Called with a message per joint.

    Returns
    -------
    FleetSimulationRun
        The truth (as written to ``truth.json``), the manifest's final path and the
        paths written.

    """
    out = os.fspath(out)
    check_fleet_size(joints, days, seed)          # before anything: a refusal costs nothing
    gear = os.fspath(gear) if gear is not None else default_gear()
    with OutputSet(force=force, inputs=[('--truth', gear)], error=ExperimentError) as outputs:
        outputs.add_directory(out)
        outputs.check()
        base = load_gear(gear)
        plan = draw_fleet(base, joints, days, seed=seed, cfg=cfg)
        stage = outputs.staging_path(out)
        rows = manifest_rows(plan)
        _write_recordings(stage, gear, base, plan, (jobs, executor), progress)
        buf = io.StringIO()
        writer = csv.DictWriter(buf, list(MANIFEST_COLUMNS), lineterminator='\n')
        writer.writeheader()
        writer.writerows(rows)
        with open(os.path.join(stage, 'manifest.csv'), 'w', encoding='utf-8') as fh:
            fh.write(buf.getvalue())
        truth = fleet_truth(plan, gear, seed)
        with open(os.path.join(stage, 'truth.json'), 'w', encoding='utf-8') as fh:
            json.dump(truth, fh, indent=2)
        written = outputs.publish()
    return FleetSimulationRun(truth, os.path.join(out, 'manifest.csv'), written)


def _write_recordings(stage, gear, base, plan, jobs, progress):
    os.makedirs(os.path.join(stage, 'recordings'))
    work = [(gear, plan['joints'][rec['joint']], rec, os.path.join(stage, rec['recording']),
             plan['cfg']) for rec in plan['recordings']]
    days = len(plan['recordings']) // max(len(plan['joints']), 1)

    def say(done):
        for k, _ in enumerate(done):
            if progress and (k + 1) % days == 0:
                progress(f'{k + 1}/{len(work)} recordings')

    jobs, executor = jobs
    if executor is not None:
        say(executor.map(_one, work))
    elif jobs > 1:
        with concurrent.futures.ProcessPoolExecutor(int(jobs)) as pool:
            say(pool.map(_one, work, chunksize=4))
    else:
        say(_write_one(base, *item[1:]) for item in work)
