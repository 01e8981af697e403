# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``fleet`` with a stuck or killed process: bounded, one line, no orphaned worker.

* a worker of the embedded LocalCluster stopped (SIGSTOP) mid-run: the stall
  guard (here ``--stall-timeout 5``) reports its recordings failed with one
  warning line and the run ends, writing its outputs;
* the command killed (SIGKILL) while a worker is stopped: no worker outlives it
  (distributed ends a worker whose parent has gone from a thread of the worker,
  which a stopped worker never runs; the parent-death signal is the kernel's);
* Ctrl-C mid-run: one line after the progress, exit 130, nothing written.

Processes are found and ended by PID; waits are for conditions.
"""
import contextlib
import csv
import os
import signal
import subprocess
import sys
import threading
import time

from friction_joint.cli import main
from friction_joint.fleet.cluster import map_recordings, stall_guard, STALL_MIN, STALL_TIMEOUT
from procs import alive, descendants
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
DEADLINE = 300.0


@pytest.fixture(scope='module')
def fleet(tmp_path_factory):
    """Return the manifest of a simulated fleet of 12 recordings."""
    out = tmp_path_factory.mktemp('fleet') / 'fleet'
    assert main(['experiment', 'fleet', '--out', str(out), '--joints', '3', '--days', '4',
                 '--seed', '1', '--quiet']) == 0
    return out / 'manifest.csv'


def workers(pid):
    """Return the pids of the Dask worker processes below ``pid``."""
    found = []
    for k in descendants(pid):
        with contextlib.suppress(OSError):
            with open(f'/proc/{k}/cmdline', 'rb') as fh:
                if b'spawn_main' in fh.read():
                    found.append(k)
    return found


def default_sigint():
    """Give the child Python's default SIGINT (a suite run in the background ignores it)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def start_fleet(manifest, out, *extra):
    """Start ``friction_joint fleet`` on two workers; return it once a recording is done."""
    proc = subprocess.Popen([sys.executable, '-m', 'friction_joint', 'fleet', '--manifest',
                             str(manifest), '--model', MODEL, '--out', str(out), '--workers',
                             '2', *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, preexec_fn=default_sigint,
                            env={**os.environ, 'PYTHONFAULTHANDLER': '1'})
    seen = ''
    while '[1/' not in seen:
        line = proc.stderr.readline()
        assert line, f'fleet ended before a recording was done: {seen}'
        seen += line
    return proc, seen


def finish(proc, seen):
    """
    Return the command's (stdout, stderr) once it ends; past the deadline, where it hung.

    The command runs with Python's fault handler: SIGABRT makes it print every thread's
    stack, which the failure shows (a hang on a loaded machine is otherwise a bare
    timeout).
    """
    try:
        return proc.communicate(timeout=DEADLINE)
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGABRT)
        _, stderr = proc.communicate(timeout=60)
        raise AssertionError(f'fleet did not end within {DEADLINE:g} s; its threads:\n'
                             f'{seen}{stderr[-20000:]}') from None


def test_a_stopped_worker_fires_the_stall_guard_with_one_line(fleet, tmp_path):
    """SIGSTOP of a worker mid-run: its recordings failed after the guard, one warning."""
    out = tmp_path / 'out'
    proc, seen = start_fleet(fleet, out, '--stall-timeout', '5')
    pids = []
    try:
        pids = workers(proc.pid)
        assert len(pids) == 2, pids
        os.kill(pids[0], signal.SIGSTOP)
        stdout, stderr = finish(proc, seen)
    finally:
        proc.kill()
        proc.wait()
        for pid in pids:
            if alive(pid):
                os.kill(pid, signal.SIGKILL)
    assert proc.returncode == 0, seen + stderr
    warning = [line for line in (seen + stderr).splitlines() if 'warning' in line]
    assert len(warning) == 1 and warning[0].startswith(
        'friction_joint fleet: warning: no task of the cluster finished for 5 s'), warning
    with open(out / 'recordings.csv', encoding='utf-8') as fh:
        rows = list(csv.DictReader(fh))
    failed = [r for r in rows if r['status'] != 'ok']
    assert len(rows) == 12 and failed, rows
    assert all('the cluster is stuck' in r['reason'] for r in failed), failed
    assert f'{len(failed)} recording(s) reported failed' in warning[0]


def test_killed_fleet_takes_its_workers_with_it(fleet, tmp_path):
    """SIGKILL of the command while one of its workers is stopped: no worker stays."""
    proc, _ = start_fleet(fleet, tmp_path / 'out')
    pids = []
    try:
        pids = workers(proc.pid)
        assert len(pids) == 2, pids
        os.kill(pids[0], signal.SIGSTOP)
        proc.kill()
        proc.wait()
        t_end = time.monotonic() + 60
        while [p for p in pids if alive(p)] and time.monotonic() < t_end:
            time.sleep(0.1)
        assert not [p for p in pids if alive(p)], 'orphaned workers'
    finally:
        proc.kill()
        proc.wait()
        for pid in pids:
            if alive(pid):
                os.kill(pid, signal.SIGKILL)


@pytest.mark.parametrize('moment', ['mid-run', 'cluster-closed'])
def test_ctrl_c_is_one_line(fleet, tmp_path, moment):
    """
    SIGINT once a recording is done, or once the cluster has closed: one line, exit 130.

    Nothing is written.  After the cluster had closed (the verdict and report being
    made), the resource tracker of its processes wrote a ``leaked semaphore`` warning
    after the line (the command ends at once on Ctrl-C).
    """
    out = tmp_path / 'out'
    proc, seen = start_fleet(fleet, out)
    pids = []
    try:
        pids = workers(proc.pid)
        assert len(pids) == 2, pids
        t_end = time.monotonic() + DEADLINE
        while (moment == 'cluster-closed' and [p for p in pids if alive(p)]
               and proc.poll() is None and time.monotonic() < t_end):
            time.sleep(0.01)
        proc.send_signal(signal.SIGINT)
        stdout, stderr = finish(proc, seen)
    finally:
        proc.kill()
        proc.wait()
    if proc.returncode == 0:                 # a fast machine had finished: nothing to check
        return
    assert proc.returncode == 130, seen + stderr
    lines = [line for line in stderr.splitlines() if not line.startswith('[')]
    assert lines == ['friction_joint fleet: interrupted'], seen + stderr
    assert stdout == '' and not out.exists()
    t_end = time.monotonic() + 60
    while [p for p in pids if alive(p)] and time.monotonic() < t_end:
        time.sleep(0.1)
    assert not [p for p in pids if alive(p)], 'workers left running'


def test_stall_guard_scales_with_the_task_times():
    """The start-up guard, then 20 x the median task time, at least STALL_MIN; or the option."""
    assert stall_guard([]) == STALL_TIMEOUT == 600
    assert stall_guard([], stall_timeout=5) == STALL_TIMEOUT       # start-up: never shorter
    assert stall_guard([0.1, 0.2, 9.0]) == STALL_MIN == 60         # median 0.2 s: the floor
    assert stall_guard([10.0, 12.0, 11.0]) == 220.0                # 20 x the median
    assert stall_guard([10.0], stall_timeout=5) == 5.0


def test_a_worker_stopped_holding_a_finished_result_is_a_stall_not_a_hang():
    """
    A worker stopped after its task finished, before the result was fetched: a stall.

    The data of a finished task stays on its worker; fetching it from a stopped worker
    waited for ever (the command hung past the stall guard).  One worker runs a short
    task, then a 1 s one; on the first result the worker is stopped once the second
    has had time to finish (or not: either way it is a stall).
    """
    stopped = []

    def stop_worker(index, result):
        if not stopped:
            time.sleep(2.0)
            stopped.extend(workers(os.getpid()))
            for pid in stopped:
                os.kill(pid, signal.SIGSTOP)

    box = {}
    run = threading.Thread(target=lambda: box.update(out=map_recordings(
        time.sleep, [0.0, 1.0], workers=1, stall_timeout=3, on_result=stop_worker)),
        daemon=True)
    run.start()
    try:
        run.join(DEADLINE)
        assert not run.is_alive(), 'map_recordings did not end past its stall guard'
    finally:
        for pid in stopped:
            if alive(pid):
                os.kill(pid, signal.SIGKILL)
    out = box['out']
    assert len(stopped) == 1 and out['stalled'] == 1 and out['stall_guard'] == 3.0, out
    assert out['results'][0] is None and out['results'][1]['status'] == 'failed', out
    assert 'the cluster is stuck' in out['results'][1]['reason']
