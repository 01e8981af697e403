# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint bringup``: start simulator, controller, estimator and recorder as processes.

    friction_joint bringup --model config/csd25.yaml --truth config/csd25_truth.yaml \
        --duration 10 --record bags/run1

There is no ``ros2 launch`` on a pip-installed ROS 2, so this is the launch
file: each node is its own process (``python -m friction_joint.ros.nodes.<node>``
with ``--ros-args --params-file``), the simulator on the truth gear, the
controller and estimator on the model gear.  In ``lockstep`` mode (default)
the simulator ends itself after ``--duration`` simulated seconds; in
``realtime`` mode the command waits that long.  The simulator starts last and
waits for its subscribers to match before its first state.

In lockstep the run is lossless by construction: the simulator advances on
the controller's command (the controller is in the loop) and waits whenever
the estimator's ``external_torque`` echo lags more than ``window`` steps
(``follow:=external_torque``, see :mod:`~friction_joint.ros.nodes.joint_sim`);
publishers keep every sample until the recorder has acknowledged it.  The
recorder logs at ``/clock`` time (``--use-sim-time``), so the recording spans
the simulated time and replays in it.  Controller and estimator stamp their
answers with the stamp of the state they answer and need no clock; they are
not put on ``use_sim_time`` (it would cost each of them one executor turn per
step for ``/clock``), which they honour when it is set.  Then the other processes are
stopped with SIGINT (the recorder last, after the others have flushed), so
the recording is finalised with nothing lost, and the bag path is printed.

SIGTERM and SIGHUP stop the nodes the same way (the recording is finalised),
then bringup ends as Ctrl-C does, with 128 + the signal's number (143, 129).
Killed outright (SIGKILL: no handler of its runs), bringup takes its nodes with
it: each was started with a parent-death signal (``prctl(PR_SET_PDEATHSIG)``,
:data:`PARENT_DEATH_SIGNAL`), which stops it as ``kill PID`` does, so the nodes
end and the recorder finalises the recording it has (what arrived until then).
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
import os
import signal
import subprocess
import sys
import tempfile
import time
from typing import Any

from .nodes.ranges import DURATION_BOUNDS
from .qos import dds_environ
from .._process import parent_death_preexec
from ..exceptions import ArgumentError, NodeError, OutputError
from ..gear import load_gear
from ..gear.files import format_ros_params, read_ros_params_file

__all__ = ['bringup', 'run_summary', 'SUMMARY_STARTS', 'PROGRESS_EVERY', 'NodeProcess',
           'LOCKSTEP_WINDOW', 'composed_command', 'PARENT_DEATH_SIGNAL']

#: steps the estimator may lag behind the lockstep simulator (0.1 s at 3 kHz; its
#: input queue holds 1000 states and 1000 temperatures)
LOCKSTEP_WINDOW = 300


#: the signal a child gets when bringup ends without stopping it (killed with SIGKILL): the
#: nodes stop and the recorder seals its recording on it as on ``kill PID``
PARENT_DEATH_SIGNAL = signal.SIGTERM


class NodeProcess:
    """
    A child process in its own process group, stopped with SIGINT then SIGKILL.

    It gets :data:`PARENT_DEATH_SIGNAL` when this process ends (even by SIGKILL), so no child
    outlives it.
    """

    def __init__(self, name: str, argv: Sequence[str], env: Mapping[str, str] | None = None,
                 log_dir: str | None = None) -> None:
        self.name = name
        self.log = (open(os.path.join(log_dir, f'{name}.log'), 'w') if log_dir
                    else subprocess.DEVNULL)
        self.proc = subprocess.Popen(argv, env=env, stdout=self.log, stderr=subprocess.STDOUT,
                                     start_new_session=True,
                                     preexec_fn=parent_death_preexec(PARENT_DEATH_SIGNAL))

    def alive(self) -> bool:
        return self.proc.poll() is None

    def stop(self, timeout: float = 45.0) -> int | None:
        """SIGINT, wait, then kill the process group; returns the exit status."""
        if self.alive():
            try:
                os.killpg(self.proc.pid, signal.SIGINT)
            except ProcessLookupError:
                pass
            try:
                self.proc.wait(timeout)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        if not isinstance(self.log, int):          # not subprocess.DEVNULL
            self.log.close()
        return self.proc.returncode


def _node(module, gear_file, params):
    """Return the argv of node ``module``; a parameter is passed only when it has a value."""
    argv = [sys.executable, '-m', f'friction_joint.ros.nodes.{module}', '--ros-args',
            '--params-file', gear_file]
    return argv + _overrides(params)


def _overrides(params, node=''):
    """Return ``-p [node:]key:=value`` for each parameter that has a value."""
    argv = []
    for key, value in params.items():
        if value is None or value == '':
            continue                          # rcl cannot parse an empty override (key:=)
        argv += ['-p', f'{node}{key}:={value}']
    return argv


def _gear_parameters(path):
    """Return the ``ros__parameters`` of a gear file (its node sections merged)."""
    found = {}

    def walk(tree):
        for key, value in tree.items():
            if key == 'ros__parameters':
                found.update(value)
            elif isinstance(value, dict):
                walk(value)
    walk(read_ros_params_file(path))
    return found


def composed_command(model: str, truth: str, params: Mapping[str, Mapping[str, Any]],
                     directory: str) -> list[str]:
    """
    Return the composed process's argv: a params file with the gear of each node.

    The nodes' own parameters go on the command line as node-specific
    overrides (``-p estimator:friction:=lugre``): a node's own ``friction``
    (a model name) cannot sit beside the gear's ``friction`` section in one file.
    """
    gears = {'joint_sim': truth, 'controller': model, 'estimator': model}
    tree = {node: {'ros__parameters': _gear_parameters(path)} for node, path in gears.items()}
    path = os.path.join(directory, 'composed.yaml')
    with open(path, 'w', encoding='utf-8') as fh:
        fh.write(format_ros_params(tree))
    argv = [sys.executable, '-m', 'friction_joint.ros.nodes.composed', '--ros-args',
            '--params-file', path]
    for node, own in (('joint_sim', params['sim']), ('controller', params['controller']),
                      ('estimator', params['estimator'])):
        argv += _overrides(own, f'{node}:')
    return argv


def _last_line(path):
    try:
        with open(path, encoding='utf-8', errors='replace') as fh:
            lines = [line.strip() for line in fh if line.strip()]
    except OSError:
        return ''
    return lines[-1] if lines else ''


#: what a node's closing log lines begin with (their summary of the run)
SUMMARY_STARTS = ('realtime run:', 'lockstep run:', 'answered ', 'rejected ')
#: s between the progress lines of a running bring-up
PROGRESS_EVERY = 10.0


def run_summary(log_dir: str, record: str | None = None) -> list[str]:
    """
    Return the closing lines of a bring-up: each node's own summary, its warnings, the recording.

    Parameters
    ----------
    log_dir : str
        Where the processes' logs are (``NAME.log``; a composed process logs every node).
    record : str, optional
        The recording, whose topics and message counts are listed.

    """
    lines: list[str] = []
    warned: dict[str, int] = {}
    for name in sorted(os.listdir(log_dir)) if os.path.isdir(log_dir) else ():
        if not name.endswith('.log'):
            continue
        try:
            with open(os.path.join(log_dir, name), encoding='utf-8', errors='replace') as fh:
                text = fh.read().splitlines()
        except OSError:
            continue
        for line in text:
            head, sep, message = line.partition(']: ')
            node = head.rsplit('[', 1)[-1] if sep else name[:-4]
            if '[WARN]' in head or '[ERROR]' in head:
                warned[node] = warned.get(node, 0) + 1
            if sep and message.startswith(SUMMARY_STARTS):
                lines.append(f'{node}: {message.strip()}')
    lines += [f'{node}: {n} warning(s) in its log' for node, n in sorted(warned.items())]
    if record and os.path.exists(record):
        from ..bag import recording_topics
        try:
            topics = recording_topics(record)
        except Exception as exc:                # noqa: BLE001 - the summary never fails
            lines.append(f'recording {record}: not readable ({exc})')
        else:
            lines.append(f'recording {record}: ' + ', '.join(
                f'{topic} {count}' for topic, (_, count) in sorted(topics.items())))
    return lines


def _check_alive(procs, sim, log_dir, kept, record=None):
    """Raise a one-line error naming the first process (but the simulator) that has ended."""
    for p in procs:
        if p is not sim and not p.alive():
            log = os.path.join(log_dir, p.name + '.log')
            last = _last_line(log)
            where = f'; see {log}' if kept else ''
            hint = _recover_hint(record) if p.name == 'record' and record else ''
            raise NodeError(f'{p.name} ended early (exit {p.proc.returncode})'
                            + (f': {last}' if last else '') + where + hint)


def _recover_hint(record):
    """Return how to recover what a recorder that ended early staged beside ``record``."""
    from ..bag.staging import killed_recordings, recovery_command
    killed = killed_recordings(record)
    if not killed:
        return ''
    staging = killed[-1][0]
    return (f'; what it recorded is kept in {os.path.relpath(staging)}: '
            f'{recovery_command(staging)} makes it a recording')


class _Stop(KeyboardInterrupt):
    """
    SIGTERM / SIGHUP reached bringup: stop the children, then end like Ctrl-C.

    ``signum`` tells the command line the signal: its exit status is 128 + it (143, 129).
    """

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _on_signal(signum, frame):
    raise _Stop(signum)


def bringup(model: str, truth: str, duration: float, *, record: str | None = None,
            mode: str = 'lockstep', friction: str = 'lugre', amplitude: float = 0.4,
            omega: float = 1.5, xi0: float | None = None, log_dir: str | None = None,
            env: Mapping[str, str] | None = None, quiet: bool = False,
            composed: bool = False) -> str | None:
    """
    Run the closed loop as separate processes; returns the bag path (or None).

    Parameters
    ----------
    model, truth : str
        Gear files of the controller/estimator and of the simulator.
    duration : float
        Seconds of simulated (lockstep) or wall (realtime) time.
    record : str, optional
        Bag directory to record the contract topics into (must not exist).
    mode : {'lockstep', 'realtime'}
        Simulator mode: lockstep (simulated time, nothing lost) or real time.
    friction : str
        Friction model of controller feed-forward and estimator.
    amplitude, omega : float
        Reference q_d = amplitude sin(omega t) of the controller (rad, rad/s).
    xi0 : float, optional
        Initial gear temperature of the simulator (degC; default: the truth gear's).
    log_dir : str, optional
        Directory for one log file per process (default: logs discarded).
    env : dict, optional
        Environment of the processes (default: this process's).
    quiet : bool
        Print no progress lines.
    composed : bool
        Lockstep only: run simulator, controller and estimator in one process
        (:mod:`~friction_joint.ros.nodes.composed`), the loop wired by calls;
        the recorder stays a process of its own.

    """
    for path in (model, truth):
        load_gear(path)                       # fail early, with the file's own error
    env = dds_environ(env)
    if mode not in ('lockstep', 'realtime'):
        raise ArgumentError(f"mode must be 'lockstep' or 'realtime', got {mode!r}")
    if composed and mode != 'lockstep':
        raise ArgumentError('the composed loop runs in lockstep only')
    if not 0 < duration <= DURATION_BOUNDS[1]:
        raise ArgumentError(f'duration must be in (0, {DURATION_BOUNDS[1]:g}] s '
                            f'({DURATION_BOUNDS[2]}), got {duration}')
    if record and os.path.exists(record):
        raise OutputError(f'{record} exists already; choose a new recording path')
    if log_dir:
        os.makedirs(log_dir, exist_ok=True)
    say = (lambda *a: None) if quiet else (lambda *a: print(*a, flush=True))
    # controller + estimator (+ recorder) must be matched before the loop starts
    lockstep = mode == 'lockstep'
    sim_params = {'mode': mode, 'duration': float(duration),
                  'wait_subscribers': 2 + (1 if record else 0), 'start_delay': 2.0}
    sim_params.update(follow='external_torque' if lockstep else '', window=LOCKSTEP_WINDOW)
    if composed:                        # the followers are in the process: only a recorder
        sim_params.update(wait_subscribers=1 if record else 0, follow='', start_delay=0.5)
    if xi0 is not None:
        sim_params['xi0'] = float(xi0)
    if record:
        # the first state waits until the recorder has matched every loop topic's publisher
        sim_params['wait_recorder'] = 'loop'
    rate = {} if mode == 'lockstep' else {'rate': 1000.0}
    procs = []
    scratch = tempfile.TemporaryDirectory(prefix='friction_joint_bringup_')
    old = {s: signal.signal(s, _on_signal) for s in (signal.SIGTERM, signal.SIGHUP)}
    kept = bool(log_dir)
    log_dir = log_dir or scratch.name
    try:
        if record:
            procs.append(NodeProcess('record', [sys.executable, '-m', 'friction_joint', 'record',
                                                record] + (['--use-sim-time'] if lockstep else []),
                                     env, log_dir))
        params = {'estimator': dict(friction=friction, mode=mode, **rate),
                  'controller': dict(friction_ff=friction, amplitude=float(amplitude),
                                     omega=float(omega), mode=mode, **rate),
                  'sim': sim_params}
        if composed:
            sim = NodeProcess('joint_sim', composed_command(model, truth, params, scratch.name),
                              env, log_dir)
        else:
            for name in ('estimator', 'controller'):
                procs.append(NodeProcess(name, _node(name, model, params[name]), env, log_dir))
            sim = NodeProcess('joint_sim', _node('joint_sim', truth, sim_params), env, log_dir)
        procs.append(sim)
        say(f'bringup: {len(procs)} processes up ({mode}{", composed" if composed else ""}, '
            f'{duration:g} s)')
        t0 = time.monotonic()
        limit = duration + 30.0 if mode == 'realtime' else max(60.0, 40.0 * duration)
        next_say = t0 + PROGRESS_EVERY
        while sim.alive() and time.monotonic() - t0 < limit:
            _check_alive(procs, sim, log_dir, kept, record)
            time.sleep(0.1)
            if time.monotonic() >= next_say:
                next_say += PROGRESS_EVERY
                say(f'bringup: running for {time.monotonic() - t0:.0f} s ({duration:g} s of '
                    f'{"simulated" if lockstep else "wall"} time to run)')
        if sim.alive():
            raise NodeError(f'the simulator did not finish within {limit:.0f} s')
        if sim.proc.returncode != 0:
            last = _last_line(os.path.join(log_dir, 'joint_sim.log'))
            raise NodeError(f'the simulator failed (exit {sim.proc.returncode})'
                            + (f': {last}' if last else '')
                            + (f'; see {log_dir}' if kept else ''))
        time.sleep(0.5)                       # let the last messages arrive
    except _Stop as stop:
        say(f'bringup: {signal.Signals(stop.signum).name}: stopping the nodes')
        raise
    finally:
        # a second SIGTERM while the children stop must not orphan them
        for sig in old:
            signal.signal(sig, signal.SIG_IGN)
        # stop in reverse order: simulator, controller, estimator, recorder last
        for p in reversed(procs):
            code = p.stop()
            if code not in (0, -signal.SIGINT, 130, None):
                say(f'bringup: {p.name} exited with {code}')
        for sig, handler in old.items():
            signal.signal(sig, handler)
        for line in run_summary(log_dir, record):
            say(f'bringup: {line}')
        scratch.cleanup()
    if record:
        say(f'bringup: recording in {record}')
    return record
