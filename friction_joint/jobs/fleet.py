# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
The ``fleet`` command's work: manifest -> per-recording tasks on Dask -> verdict -> files.

:func:`run_fleet` reads and checks the manifest and the model gear file,
checks the output directory (one output set,
:class:`~friction_joint.output.OutputSet`: an existing DIR is refused unless
``force``; a DIR that is, contains or lies inside the manifest, the model or
any recording it lists -- :func:`~friction_joint.output.recording_inputs` --
always), then

1. hashes every recording (:func:`content_hash`: SHA-256 over its bytes; a
   rosbag2 directory: over its files' names and bytes) and looks the result up
   in the **cache**: ``DIR/cache.json`` of the previous run into the same DIR
   (read before the directory is replaced), keyed by the recording's hash, the
   model gear file's hash and the analysis version.  A day's new logs cost only
   their own work; a changed recording or model is recomputed.  The cache is
   data, not trust: an unreadable ``cache.json`` (a special file, larger than
   :data:`CACHE_LIMIT`, not JSON) and every entry that fails
   :func:`~friction_joint.fleet.recording.result_problem` (schema, types,
   finite numbers in bounds, the model's terms, shapes) are recomputed, with
   one :class:`~friction_joint.exceptions.CacheWarning` line naming the rows;
2. runs one task per remaining recording on Dask
   (:func:`~friction_joint.fleet.cluster.map_recordings`,
   :func:`~friction_joint.fleet.recording.recording_task`: plain data back, a
   :class:`~friction_joint.fleet.recording.RecordingResult` here), reporting a
   line per finished recording through ``progress``;
3. assesses the fleet (:func:`~friction_joint.fleet.assess.assess_fleet`) and
   writes ``fleet.json``, ``recordings.csv``, ``report.html``
   (:func:`~friction_joint.fleet.report.fleet_files`) and ``cache.json`` into
   DIR, all or nothing.

It returns a :class:`~friction_joint.jobs.runs.FleetRun` (the assessment,
what was written, :meth:`~friction_joint.jobs.runs.FleetRun.plot`).
"""
from __future__ import annotations

from collections.abc import Callable
import hashlib
import json
import os
import time
from typing import cast
import warnings

from .runs import FleetRun
from ..bag import missing_recording_error
from ..exceptions import (ArgumentError, CacheWarning, FrictionJointError, GearConfigError,
                          InputFileError, RecordingError, StallWarning)
from ..fleet.assess import assess_fleet
from ..fleet.cluster import check_scheduler, check_workers, map_recordings
from ..fleet.manifest import read_manifest
from ..fleet.recording import FIT_VERSION, recording_task, RecordingResult, result_problem
from ..fleet.report import fleet_files
from ..gear import parse_gear
from ..inputs import check_input_dir, open_input, read_input
from ..output import json_bytes, OutputSet, recording_inputs

__all__ = ['run_fleet', 'content_hash', 'CACHE_NAME', 'CACHE_LIMIT']

#: the per-recording cache inside DIR
CACHE_NAME = 'cache.json'
_CHUNK = 1 << 20


def _hash_file(h, path):
    with open_input(path, kind='recording', what='a recording') as fh:
        while True:
            block = fh.read(_CHUNK)
            if not block:
                break
            h.update(block)


def content_hash(path: str | os.PathLike) -> str:
    """
    Return the SHA-256 (hex) of a recording's content.

    A file: its bytes.  A directory (rosbag2): every file below it, in sorted
    order of their relative paths, each as its path and its bytes.

    Parameters
    ----------
    path : str or os.PathLike
        The recording (a file or a rosbag2 directory).

    Returns
    -------
    str
        The hex digest.

    """
    path = os.fspath(path)
    h = hashlib.sha256()
    if os.path.isdir(path):
        check_input_dir(path)
        names = []
        for root, dirs, files in os.walk(path):
            dirs.sort()
            names += [os.path.relpath(os.path.join(root, f), path) for f in files]
        for rel in sorted(names):
            h.update(rel.encode('utf-8') + b'\0')
            _hash_file(h, os.path.join(path, rel))
    else:
        _hash_file(h, path)
    return h.hexdigest()


#: largest cache file read (bytes); a larger one is not read, its results recomputed
CACHE_LIMIT = 256 << 20


def _read_cache(out):
    """
    Return the old DIR's cache (key -> entry) and a problem with it (None when sound).

    No cache is an empty one; an unreadable one (a special file, too large, not
    UTF-8 JSON, nested too deeply, not ``{"entries": {...}}``) is an empty one
    and its problem.  The entries themselves are checked when used.
    """
    path = os.path.join(os.fspath(out), CACHE_NAME)
    if not os.path.lexists(path):
        return {}, None
    try:
        raw = read_input(path, kind='table', what='a fleet cache', limit=CACHE_LIMIT)
        doc = json.loads(raw.decode('utf-8'))
    except FrictionJointError as exc:
        return {}, str(exc)
    except (ValueError, RecursionError) as exc:
        return {}, f'{path}: not a fleet cache (not JSON: {type(exc).__name__})'
    entries = doc.get('entries') if isinstance(doc, dict) else None
    if not isinstance(entries, dict):
        return {}, f'{path}: not a fleet cache (no "entries" object)'
    return entries, None


def _cache_warning(path, refused):
    """Warn once about refused cache entries: ``refused`` is ``[(entry, problem)]``."""
    shown = '; '.join(f'row {e.row} ({e.recording}): {why}' for e, why in refused[:3])
    more = f'; and {len(refused) - 3} more' if len(refused) > 3 else ''
    warnings.warn(f'{path}: {len(refused)} cached result{"s" if len(refused) > 1 else ""} '
                  f'refused, recomputed: {" ".join(shown.split())}{more}', CacheWarning,
                  stacklevel=3)


def _say(progress, msg):
    if progress:
        progress(msg)


def run_fleet(manifest: str | os.PathLike, model: str | os.PathLike, out: str | os.PathLike, *,
              scheduler: str | None = None, workers: int | None = None, force: bool = False,
              progress: Callable[[str], None] | None = None, seed: int = 0,
              stall_timeout: float | None = None) -> FleetRun:
    """
    Monitor a fleet: analyse its recordings and write DIR (module docstring).

    Parameters
    ----------
    manifest : str or os.PathLike
        The fleet manifest (:mod:`~friction_joint.fleet.manifest`).
    model : str or os.PathLike
        The model gear file (structure and temperature/load dependence).
    out : str or os.PathLike
        Output directory DIR.
    scheduler : str, optional
        Dask scheduler address; default an embedded LocalCluster.
    workers : int, optional
        Workers of the embedded cluster (default the cores).
    force : bool
        Replace an existing DIR (its cache is reused).
    progress : callable, optional
        Called with one line per finished recording and per stage.
    seed : int
        Of the wear test's bootstrap.
    stall_timeout : float, optional
        Seconds without a finished task (once one has finished) after which the pending
        recordings are reported failed, with one :class:`StallWarning` line (default:
        scaled with the task times, :func:`~friction_joint.fleet.cluster.stall_guard`).

    Returns
    -------
    FleetRun

    """
    t_start = time.perf_counter()
    if scheduler is not None:                    # the options first: refusals cost nothing
        scheduler = check_scheduler(scheduler)
        if workers is not None:
            raise ArgumentError('--workers is for the embedded cluster: not with --scheduler')
    if workers is not None:
        check_workers(workers)
    entries = read_manifest(manifest)
    raw = read_input(model, kind='gear', what='a gear file', error=GearConfigError)
    try:
        gear_text = raw.decode('utf-8')
    except UnicodeDecodeError:
        raise GearConfigError(f'{model}: not UTF-8 text') from None
    gear = parse_gear(gear_text, os.fspath(model))
    model_hash = hashlib.sha256(raw).hexdigest()
    inputs = [('--manifest', manifest), ('--model', model)]
    for e in entries:                   # never written over, into or above: even with force
        inputs += recording_inputs([e.path], label=f'recording of {manifest} row {e.row}')
    with OutputSet(force=force, inputs=inputs) as outputs:
        outputs.add_directory(out, label='--out')
        outputs.check()
        cache, problem = _read_cache(out) if force else ({}, None)
        if problem:
            warnings.warn(f'{" ".join(problem.split())}; every recording is recomputed',
                          CacheWarning, stacklevel=2)
        refused = []
        t0 = time.perf_counter()
        keys: list[str | None] = []
        results: list[RecordingResult | None] = [None] * len(entries)
        todo: list[int] = []
        for i, e in enumerate(entries):
            try:
                if not os.path.lexists(e.path):     # a killed recorder's: how to recover
                    raise missing_recording_error(e.path)
                h = content_hash(e.path)
            except (InputFileError, RecordingError) as exc:
                results[i] = RecordingResult(e.path, 'failed', str(exc))
                keys.append(None)
                continue
            key = hashlib.sha256(f'{h}:{model_hash}:{FIT_VERSION}'.encode()).hexdigest()
            keys.append(key)
            old = cache.get(key)
            # the key holds FIT_VERSION: an entry under it of another version, or null, is
            # as poisoned as any other bad entry
            why = None if key not in cache else result_problem(old, gear)
            if key not in cache:
                todo.append(i)                  # not cached
            elif why:
                refused.append((e, why))
                todo.append(i)
            else:
                results[i] = RecordingResult.from_dict(old, path=e.path, cached=True)
        if refused:
            _cache_warning(os.path.join(os.fspath(out), CACHE_NAME), refused)
        t_hash = time.perf_counter() - t0
        n_cached = sum(1 for r in results if r and r.cached)
        _say(progress, f'{len(entries)} recordings: {n_cached} from the cache, {len(todo)} to '
                       'analyse')
        done = [0]

        def on_result(k, res):
            done[0] += 1
            e = entries[todo[k]]
            res = RecordingResult.from_dict(res)
            what = f'{res.plateaus} plateaus' if res.ok else f'failed: {res.reason}'
            _say(progress, f'[{done[0]}/{len(todo)}] {e.joint} {e.time.isoformat()} '
                           f'{e.recording}: {what}')

        t0 = time.perf_counter()
        nworkers = 0
        if todo:
            run = map_recordings(recording_task, [entries[i].path for i in todo],
                                 args=(gear_text,), kwargs={'gear_name': os.fspath(model)},
                                 scheduler=scheduler, workers=workers, on_result=on_result,
                                 stall_timeout=stall_timeout)
            nworkers = run['workers']
            if run['stalled']:
                warnings.warn(f'no task of the cluster finished for {run["stall_guard"]:g} s '
                              f'(a worker stopped or hung?): {run["stalled"]} recording(s) '
                              'reported failed', StallWarning, stacklevel=2)
            for i, res in zip(todo, run['results'], strict=True):
                results[i] = RecordingResult.from_dict(res)
            where = run['scheduler']
        else:
            where = 'none needed'
        t_tasks = time.perf_counter() - t0
        t0 = time.perf_counter()
        filled = cast('list[RecordingResult]', results)      # every entry has its result now
        assessment = assess_fleet(entries, filled, gear, seed=seed)
        new_cache = {}
        for cache_key, res in zip(keys, results, strict=True):
            if cache_key and res is not None and res.version == FIT_VERSION:   # not a dead
                new_cache[cache_key] = res.to_dict()                          # worker's
        info = {'manifest': os.fspath(manifest), 'model': os.fspath(model),
                'computed': len(todo), 'cached': n_cached, 'workers': nworkers,
                'scheduler': where}
        files = fleet_files(assessment, info)
        files.append((CACHE_NAME, json_bytes({'version': FIT_VERSION, 'entries': new_cache})))
        t_assess = time.perf_counter() - t0
        outputs.write_directory(out, files)
        written = outputs.publish()
    timings = {'hash_s': t_hash, 'tasks_s': t_tasks, 'assess_and_report_s': t_assess,
               'total_s': time.perf_counter() - t_start}
    _say(progress, f'done in {timings["total_s"]:.1f} s ({t_tasks:.1f} s analysing the '
                   f'recordings, {t_assess:.1f} s assessing the joints and writing)')
    return FleetRun(assessment, written, len(todo), n_cached, nworkers, timings)
