# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Running per-recording tasks on Dask distributed (the only module that imports Dask).

:func:`map_recordings` submits one task per recording: the task gets the
recording's *path* (and small arguments), never its data, so a worker reads
the recording itself and the client's memory does not grow with the fleet.
Results are handed to a callback as they complete
(``distributed.as_completed``).  The cluster is

* an embedded :class:`distributed.LocalCluster` by default: ``workers``
  worker processes (default the machine's cores), one thread each (the
  analysis is numpy-bound and holds the GIL in places), a memory limit per
  worker (:data:`MEMORY_LIMIT`, enforced by the worker's nanny: a worker
  above it is restarted and its task reported failed);
* or an existing cluster: ``scheduler='tcp://HOST:PORT'`` (started with
  ``dask scheduler`` and ``dask worker tcp://HOST:PORT``, docs/fleet.md); its
  workers need friction_joint installed and the recordings at the same paths.

The client (and an embedded cluster) is closed at the end, also on an error
or Ctrl-C (pending tasks are cancelled).  Dask is imported lazily, inside
:func:`map_recordings`.

The options are checked before use, each problem one
:class:`~friction_joint.exceptions.ArgumentError` line:
:func:`check_scheduler` takes ``tcp://HOST:PORT`` (or ``HOST:PORT``) only --
a host name, an IPv4 address or a bracketed IPv6 one, a port 1..65535, no
path --, :func:`check_workers` at most :data:`WORKERS_PER_CORE` embedded
workers per core.  Connecting to a scheduler is bounded by
:data:`CONNECT_TIMEOUT` whatever the other end does (answers garbage,
accepts and stays silent), and a scheduler without workers is waited for
:data:`WORKER_WAIT` s, then refused.

A stuck cluster (a worker stopped, hung or busy elsewhere) does not hang the run:
when no task has finished for the *stall guard* the tasks still pending are
reported failed (``stalled`` in the result counts them) and the run goes on.
The guard is :data:`STALL_TIMEOUT` s until the first task has finished (the
workers start, numba compiles); then it scales with the work: :data:`STALL_FACTOR`
x the median task time measured on the workers, at least :data:`STALL_MIN` s, or
the ``stall_timeout`` given.  The embedded cluster's worker processes end with
the command, even killed with SIGKILL (:func:`dask_setup`, a parent-death signal:
a worker that is stopped or hung would otherwise stay).
"""
from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import Executor
import contextlib
import ipaddress
import logging
import os
import re
import signal
import statistics
import sys
import threading
import time
from typing import Any
import uuid

from .._process import end_with_parent
from ..exceptions import ArgumentError

__all__ = ['MEMORY_LIMIT', 'CONNECT_TIMEOUT', 'CLOSE_TIMEOUT', 'STALL_TIMEOUT', 'STALL_FACTOR',
           'STALL_MIN', 'WORKER_WAIT', 'WORKERS_PER_CORE', 'map_recordings', 'default_workers',
           'local_cluster', 'check_scheduler', 'check_workers', 'stall_guard', 'dask_setup']

#: memory limit per worker of the embedded cluster
MEMORY_LIMIT = '2GiB'
#: seconds to wait for a scheduler given by address
CONNECT_TIMEOUT = 20
#: seconds to wait for the client and an embedded cluster to close
CLOSE_TIMEOUT = 30
#: seconds without any task finishing, before the first has finished, after which the tasks
#: still pending are reported failed and the run goes on (the workers' start-up and numba's
#: compilation; a stuck worker or scheduler must not hang the command)
STALL_TIMEOUT = 600
#: once tasks have finished: no task finishing for this many times the median task time is a
#: stall (a recording's task takes well under a second) ...
STALL_FACTOR = 20
#: ... and never less than this many seconds
STALL_MIN = 60
#: seconds to wait for a worker when the scheduler given by address has none
WORKER_WAIT = 30
#: most embedded worker processes per core (the analysis is CPU-bound: more only queue)
WORKERS_PER_CORE = 4

_HOST = re.compile(r'(?=.{1,253}\Z)[A-Za-z0-9](?:[A-Za-z0-9_-]{0,62})?'
                   r'(?:\.[A-Za-z0-9](?:[A-Za-z0-9_-]{0,62})?)*\.?', re.ASCII)


def default_workers() -> int:
    """Return the number of cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:                           # not on Linux
        return max(1, os.cpu_count() or 1)


def check_scheduler(address: str) -> str:
    """
    Check a Dask scheduler address; return it as ``tcp://HOST:PORT``.

    Parameters
    ----------
    address : str
        ``tcp://HOST:PORT`` or ``HOST:PORT``: a host name, an IPv4 address or a
        bracketed IPv6 address (``[::1]``), a port 1..65535.

    Returns
    -------
    str
        The address with its ``tcp://``.

    Raises
    ------
    ArgumentError
        Anything else (empty, no port, another protocol, a path, blanks), one line.

    """
    shown = repr(address) if not isinstance(address, str) or not address.isprintable() or \
        address != address.strip() or not address else address

    def bad(problem):
        return ArgumentError(f'--scheduler {shown}: {problem}; give tcp://HOST:PORT (e.g. '
                             'tcp://127.0.0.1:8786), or leave --scheduler out for an embedded '
                             'cluster')

    if not isinstance(address, str) or not address.strip():
        raise bad('empty')
    scheme, sep, rest = address.partition('://')
    if not sep:
        scheme, rest = 'tcp', address
    if scheme.lower() == 'tls':
        raise bad('TLS needs certificates, which the fleet command does not take')
    if scheme.lower() != 'tcp':
        raise bad(f'protocol {scheme!r} is not supported (only tcp)')
    m = re.fullmatch(r'(\[[^\]]*\]|[^:/\[\]]*):([0-9]+)', rest, re.ASCII)
    if m is None:
        raise bad('not HOST:PORT (a host, a colon, a port number; nothing after)')
    host, port = m.groups()
    if host.startswith('['):
        try:
            ipaddress.IPv6Address(host[1:-1])
        except ValueError:
            raise bad(f'{host} is not an IPv6 address') from None
    elif not _HOST.fullmatch(host):
        raise bad(f'{host!r} is not a host name or IPv4 address')
    if not 1 <= int(port) <= 65535:
        raise bad(f'port {port} is not in 1..65535')
    return f'tcp://{host}:{int(port)}'


def check_workers(workers: int) -> int:
    """
    Check the number of embedded workers: 1 .. :data:`WORKERS_PER_CORE` x the cores.

    Parameters
    ----------
    workers : int
        Worker processes asked for.

    Returns
    -------
    int
        ``workers``.

    Raises
    ------
    ArgumentError
        Not an integer, below 1 or beyond the machine, one line.

    """
    cores = default_workers()
    top = WORKERS_PER_CORE * cores
    if isinstance(workers, bool) or not isinstance(workers, int):
        raise ArgumentError(f'--workers must be a whole number, got {workers!r}')
    if workers < 1:
        raise ArgumentError(f'--workers must be >= 1, got {workers}')
    if workers > top:
        shown = str(workers) if workers < 10 ** 12 else f'{str(workers)[:6]}... ' \
            f'({len(str(workers))} digits)'
        raise ArgumentError(f'--workers {shown}: more than this machine can run ({cores} '
                            f'cores: at most {top}, {WORKERS_PER_CORE} per core)')
    return workers


def _client(address):
    """Connect to ``address`` within CONNECT_TIMEOUT, whatever the other end does."""
    from distributed import Client
    box = {}

    def connect():
        try:
            box['client'] = Client(address, timeout=CONNECT_TIMEOUT)
        except BaseException as exc:                # noqa: B902 - reported in the caller
            box['error'] = exc

    thread = threading.Thread(target=connect, name='friction_joint-connect', daemon=True)
    thread.start()
    thread.join(CONNECT_TIMEOUT + 5)
    if thread.is_alive():
        raise ArgumentError(f'cannot connect to the Dask scheduler {address}: no answer within '
                            f'{CONNECT_TIMEOUT} s (is it a Dask scheduler?)')
    if 'error' in box:
        exc = box['error']
        if isinstance(exc, KeyboardInterrupt):
            raise exc
        msg = ' '.join(str(exc).split())[:200] or type(exc).__name__
        what = '' if isinstance(exc, (OSError, TimeoutError)) else \
            f'not a Dask scheduler? {type(exc).__name__}: '
        raise ArgumentError(f'cannot connect to the Dask scheduler {address}: {what}{msg}')
    return box['client']


def _wait_for_workers(client, address):
    """Return the scheduler's worker count, waiting up to WORKER_WAIT s for the first."""
    n = len(client.scheduler_info().get('workers', {}))
    if n:
        return n
    try:
        client.wait_for_workers(1, timeout=WORKER_WAIT)
    except Exception:                               # noqa: B902 - a timeout, however spelt
        raise ArgumentError(f'the Dask scheduler {address} has no workers (waited '
                            f'{WORKER_WAIT} s); start some with "dask worker {address}"') \
            from None
    return len(client.scheduler_info().get('workers', {}))


def dask_setup(worker):
    """
    Preload of the embedded cluster's workers: each ends (SIGKILL) when the command does.

    Distributed ends a worker whose parent has gone, from a thread of the worker: a
    worker stopped (SIGSTOP) or hung outside Python runs none, and stayed behind a killed
    command.  The parent-death signal is the kernel's (Linux).
    """
    end_with_parent(signal.SIGKILL)


def stall_guard(durations, stall_timeout=None):
    """
    Return the seconds without a finished task that make the cluster stuck.

    Parameters
    ----------
    durations : sequence of float
        Seconds the finished tasks took on their workers (none yet: the start-up guard).
    stall_timeout : float, optional
        The guard once a task has finished (default: :data:`STALL_FACTOR` x the median
        of ``durations``, at least :data:`STALL_MIN`).

    Returns
    -------
    float
        :data:`STALL_TIMEOUT` (or ``stall_timeout`` if larger) until a task has finished.

    """
    if not durations:
        return float(max(STALL_TIMEOUT, stall_timeout or 0))
    if stall_timeout is not None:
        return float(stall_timeout)
    return float(max(STALL_MIN, STALL_FACTOR * statistics.median(durations)))


def _quiet_resource_tracker():
    """
    Start multiprocessing's resource tracker with its stderr on /dev/null.

    The embedded cluster's processes share it; when the command ends on Ctrl-C (at once,
    ``os._exit``), it wrote a ``leaked semaphore objects`` warning after the command's
    one line.  It has nothing else to say.
    """
    from multiprocessing import resource_tracker
    try:
        sys.stderr.flush()
        devnull, saved = os.open(os.devnull, os.O_WRONLY), os.dup(2)
    except (OSError, AttributeError, ValueError):    # no stderr to replace: start it as it is
        resource_tracker.ensure_running()
        return
    try:
        os.dup2(devnull, 2)
        resource_tracker.ensure_running()
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)


def _connect(scheduler, workers, memory_limit):
    from distributed import Client, LocalCluster
    if scheduler is not None:
        address = check_scheduler(scheduler)
        return _client(address), None
    n = check_workers(int(workers or default_workers()))
    _quiet_resource_tracker()
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                           memory_limit=memory_limit, silence_logs=logging.CRITICAL,
                           dashboard_address=':0',    # its HTTP endpoint on a free port
                           preload=[__name__])        # dask_setup: end with the command
    try:
        return Client(cluster), cluster
    except BaseException:
        cluster.close(timeout=CLOSE_TIMEOUT)
        raise


@contextlib.contextmanager
def local_cluster(*, workers: int | None = None, memory_limit: str | int = MEMORY_LIMIT,
                  ) -> Iterator[tuple[str, Executor]]:
    """
    Start an embedded LocalCluster for several runs (benchmarks, tests).

    Parameters
    ----------
    workers : int, optional
        Worker processes (default the cores).
    memory_limit : str or int
        Per worker.

    Yields
    ------
    address : str
        The scheduler's address, for ``scheduler=`` of :func:`map_recordings` and
        :func:`~friction_joint.jobs.fleet.run_fleet`.
    executor : concurrent.futures.Executor
        Runs functions on the cluster's workers (e.g. ``executor=`` of
        :func:`~friction_joint.jobs.fleet_simulation.run_fleet_simulation`).

    """
    client, cluster = _connect(None, workers, memory_limit)
    try:
        yield cluster.scheduler_address, client.get_executor()
    finally:
        client.close(timeout=CLOSE_TIMEOUT)
        _close_cluster(cluster)


class _Stalled(Exception):
    """No task finished for the stall guard's seconds (``args[0]``)."""


class _StalledFuture:
    """A pending future given up on: its ``result()`` raises :class:`_Stalled`."""

    def __init__(self, fut, guard):
        self.key = fut.key
        self._fut = fut
        self.guard = guard

    def result(self, timeout=None):
        raise _Stalled(self.guard)

    def release(self):
        self._fut.release()


def _timed(func, *args, **kwargs):
    """Run a task on its worker; return (seconds it took, its result)."""
    t0 = time.perf_counter()
    result = func(*args, **kwargs)
    return time.perf_counter() - t0, result


def _fetch(fut, guard):
    """
    Return a finished task's result, fetched from the worker that holds it.

    A task done is not yet a result here: its data stays on its worker, and a worker
    stopped (SIGSTOP) or hung after finishing never sends it.  Past ``guard`` s the
    fetch counts as stalled (:class:`_Stalled`) like a task that never finished.
    """
    try:
        return fut.result(timeout=guard)
    except TimeoutError:
        if not fut.done() or fut.status != 'finished':
            raise
        raise _Stalled(guard) from None


def _completed(futures, guard):
    """Yield the futures as they finish; after ``guard()`` s with none, the rest as stalled."""
    from distributed import wait
    pending = list(futures)
    while pending:
        timeout = guard()
        try:
            done, rest = wait(pending, timeout=timeout, return_when='FIRST_COMPLETED')
        except TimeoutError:
            yield from (_StalledFuture(fut, timeout) for fut in pending)
            return
        pending = list(rest)
        yield from done


def map_recordings(func: Callable[..., Any], paths: Sequence[str], *, args: Sequence[Any] = (),
                   kwargs: Mapping[str, Any] | None = None, scheduler: str | None = None,
                   workers: int | None = None, memory_limit: str | int = MEMORY_LIMIT,
                   on_result: Callable[[int, Any], None] | None = None,
                   stall_timeout: float | None = None) -> dict[str, Any]:
    """
    Run ``func(path, *args, **kwargs)`` for every path on a Dask cluster.

    Parameters
    ----------
    func : callable
        Module-level function (workers import it by name); returns plain data.
    paths : sequence of str
        The recordings, one task each.
    args, kwargs
        Further arguments of every task (small: they are sent with each task).
    scheduler : str, optional
        Address of an existing scheduler; default an embedded LocalCluster.
    workers : int, optional
        Worker processes of the embedded cluster (default the cores).
    memory_limit : str or int
        Per worker of the embedded cluster.
    on_result : callable, optional
        ``on_result(index, result)`` as each task completes (in completion order).
    stall_timeout : float, optional
        Seconds without a finished task, once one has finished, that make the cluster
        stuck (default: scaled with the task times, :func:`stall_guard`).

    Returns
    -------
    dict
        ``results`` (list in ``paths`` order), ``workers`` (how many the cluster had),
        ``scheduler`` (its address), ``tasks`` (submitted), ``stalled`` (how many were
        given up on) and ``stall_guard`` (the guard that fired, or None).  A task that
        raised, or whose worker died, gives ``{'status': 'failed', 'reason': ...}``; so
        do the tasks still pending when no task has finished for the stall guard.

    """
    import distributed

    results = [None] * len(paths)
    durations: list[float] = []
    stalled: list[str] = []
    client, cluster = _connect(scheduler, workers, memory_limit)
    futures = []
    try:
        nworkers = (len(client.scheduler_info().get('workers', {})) if cluster is not None
                    else _wait_for_workers(client, check_scheduler(str(scheduler))))
        tag = uuid.uuid4().hex[:8]
        index = {}
        for i, path in enumerate(paths):
            fut = client.submit(_timed, func, path, *args, key=f'fleet-{tag}-{i}',
                                pure=False, retries=0, **(kwargs or {}))
            index[fut.key] = i
            futures.append(fut)
        for fut in _completed(futures, lambda: stall_guard(durations, stall_timeout)):
            i = index[fut.key]
            try:
                seconds, res = _fetch(fut, stall_guard(durations, stall_timeout))
                durations.append(seconds)
            except _Stalled as exc:
                stalled.append(exc.args[0])
                res = {'path': paths[i], 'status': 'failed',
                       'reason': f'no task of the run finished for {exc.args[0]:g} s: the '
                                 'cluster is stuck (a worker stopped, hung or busy elsewhere)'}
            except distributed.KilledWorker:
                res = {'path': paths[i], 'status': 'failed',
                       'reason': 'its worker died (over the memory limit, or killed)'}
            except Exception as exc:                 # noqa: B902 - one recording, not the run
                res = {'path': paths[i], 'status': 'failed',
                       'reason': ' '.join(f'{type(exc).__name__}: {exc}'.split())}
            results[i] = res
            if on_result:
                on_result(i, res)
            fut.release()
        return {'results': results, 'workers': nworkers, 'tasks': len(paths),
                'stalled': len(stalled), 'stall_guard': stalled[0] if stalled else None,
                'scheduler': ('embedded LocalCluster' if cluster is not None
                              else check_scheduler(str(scheduler)))}
    finally:
        try:
            if futures:
                client.cancel([f for f in futures if not f.done()])
        finally:
            if stalled and cluster is not None:
                _kill_workers(cluster)
            client.close(timeout=CLOSE_TIMEOUT)
            if cluster is not None:
                _close_cluster(cluster)


def _kill_workers(cluster):
    """
    End the embedded cluster's worker processes at once (SIGKILL), not to be restarted.

    After a stall one of them may be stopped (SIGSTOP) or hung: asked to close, it never
    answers, and closing the cluster waited on it for longer than the stall guard.
    """
    for nanny in list(getattr(cluster, 'workers', {}).values()):
        with contextlib.suppress(AttributeError):
            nanny.close_gracefully(reason='stalled')       # not restarted once killed
        pid = getattr(nanny, 'pid', None)
        if pid:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)


def _close_cluster(cluster):
    """Close the embedded cluster within :data:`CLOSE_TIMEOUT`; past it, kill its workers."""
    try:
        cluster.close(timeout=CLOSE_TIMEOUT)
    except TimeoutError:
        _kill_workers(cluster)
