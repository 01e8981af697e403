# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Benchmark of the ROS 2 side: rates, latency, lockstep speed, recorder throughput.

    .venv/bin/python benchmarks/bench_nodes.py [--quick] [--load N]

1. realtime mode (joint_sim at 1 kHz + controller) for 60 s (10 s with
   --quick), recorded: achieved /joint_states rate, gaps, and the state ->
   command round-trip latency (the controller answers each state with a
   command carrying the state's stamp; latency = the recorder's receive time
   of the command - its receive time of that state; rate and gaps from
   receive times too, as the states' stamps may be simulated time); with
   ``--load N`` it runs again with N busy processes (one busy loop each)
   loading the machine;
2. lockstep mode (joint_sim + controller): simulated steps per wall second;
   then the full lockstep loop as ``bringup`` runs it (joint_sim + controller +
   estimator at 3 kHz with flow control on the estimator, recorded with
   ``record --use-sim-time``): steps/s, sim time / wall time (x real time),
   the recording's log-time span and /joint_states rate (sim time: 3000 Hz
   over the simulated seconds) and its completeness (every step on every
   loop topic); the wall time runs from the first step to the last;
3. recorder throughput: a publisher floods /joint_states for 5 s; the
   recorder's count written is compared with the count published;
4. replay timing: a 1 kHz recording (10 s, 3 s with --quick) is replayed at
   rate 1 into the recorder; each message's receive time against its log
   time / rate, as a lag behind the least delayed message (replay never
   publishes early, so that one is on time): p50/p99/max.  The tests
   only check that replay never publishes before a message's log time
   (test/ros/test_record_replay.py); how closely it keeps them is measured here.

Runs in its own ROS domain with localhost-only discovery; every process it
starts is stopped (SIGINT, then the process group is killed).
"""
import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
PY = sys.executable
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')


def env():
    e = dict(os.environ)
    e['ROS_DOMAIN_ID'] = str(150 + os.getpid() % 60)
    e['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    e.pop('ROS_LOCALHOST_ONLY', None)
    return e


def start(argv, e):
    return subprocess.Popen(argv, env=e, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True, start_new_session=True)


def stop(p, timeout=30):
    if p.poll() is None:
        try:
            os.killpg(p.pid, signal.SIGINT)
            p.wait(timeout)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            pass
    try:
        os.killpg(p.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    out = p.communicate(timeout=10)[0] if p.stdout else ''
    return out


def node(name, gear, **params):
    argv = [PY, '-m', f'friction_joint.ros.nodes.{name}', '--ros-args', '--params-file', gear]
    for k, v in params.items():
        argv += ['-p', f'{k}:={v}']
    return argv


def realtime(seconds, e, max_lead=None):
    """
    Sim + controller in real time, measured from a zero-loss recording.

    An in-process rclpy subscriber cannot keep up with 2 kHz of input (it
    takes one message per executor turn), so the recorder is the instrument:
    rate and gaps from its receive times of /joint_states, latency = its
    receive time of each /joint_command minus its receive time of the state the
    command answers (the state with the command's stamp).  Receive times, not
    stamps: the simulator may stamp its states with simulated time, regular
    however late it runs.
    """
    from friction_joint.bag import read_recording
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, 'rt')
        rec = start([PY, '-m', 'friction_joint', 'record', out, '--topics', '/joint_states',
                     '/joint_command', '/joint_temperature'], e)
        time.sleep(2.0)
        pacing = {} if max_lead is None else {'max_lead': max_lead}
        sim = start(node('joint_sim', TRUTH, mode='realtime', **pacing), e)
        ctrl = start(node('controller', MODEL, rate=1000.0, sync='false'), e)
        time.sleep(seconds + 5.0)
        stop(ctrl)
        stop(sim)
        stop(rec, timeout=60)
        r = read_recording(out)
    js, cmd = r.joint_states, r.joint_command
    t0 = js.t_recv[0] + 4.0                             # skip start-up
    sel = (js.t_recv >= t0) & (js.t_recv < t0 + seconds)
    tr = js.t_recv[sel]
    gaps = np.diff(tr) * 1e3
    csel = (cmd.t_recv >= t0) & (cmd.t_recv < t0 + seconds)
    i = np.clip(np.searchsorted(js.t, cmd.t[csel]), 0, len(js.t) - 1)
    same = np.abs(js.t[i] - cmd.t[csel]) < 1e-6         # the state each command answers
    lat = (cmd.t_recv[csel][same] - js.t_recv[i[same]]) * 1e3
    answered = np.isin(np.round(js.t[sel] * 1e6), np.round(cmd.t * 1e6))
    return {'answered': float(answered.mean()), 'q_max': float(np.max(np.abs(js.q[sel]))),
            'rate_hz': len(tr) / seconds, 'gap_p99_ms': float(np.percentile(gaps, 99)),
            'gap_max_ms': float(np.max(gaps)), 'latency_p50_ms': float(np.percentile(lat, 50)),
            'latency_p99_ms': float(np.percentile(lat, 99)), 'commands': int(csel.sum())}


def _lockstep_wall(sim, start_delay):
    """Return the wall seconds from the simulator's first step to its 'done' line, and t0."""
    t0 = None
    for line in sim.stdout:
        if t0 is None and 'subscriber(s) matched' in line:
            t0 = time.monotonic() + start_delay
        if 'done' in line:
            break
    return time.monotonic() - t0, t0


class CpuSampler(threading.Thread):
    """Sample the CPU seconds (user + system, all threads) of named processes until stopped."""

    def __init__(self, procs):
        super().__init__(daemon=True)
        self.procs = procs
        self.cpu = {}
        self.halt = threading.Event()

    def run(self):
        tick = os.sysconf('SC_CLK_TCK')
        while not self.halt.is_set():
            for name, p in self.procs.items():
                try:
                    with open(f'/proc/{p.pid}/stat') as fh:
                        f = fh.read().rsplit(')', 1)[1].split()
                    self.cpu[name] = (int(f[11]) + int(f[12])) / tick
                except (OSError, IndexError):
                    pass
            self.halt.wait(0.2)


def lockstep(sim_seconds, e):
    sim = start(node('joint_sim', TRUTH, mode='lockstep', duration=float(sim_seconds),
                     start_delay=0.5), e)
    ctrl = start(node('controller', MODEL, mode='lockstep'), e)
    try:
        wall, _ = _lockstep_wall(sim, 0.5)
        sim.wait(30)
    finally:
        stop(ctrl)
        stop(sim)
    steps = int(round(sim_seconds * 3000))
    return {'steps': steps, 'wall_s': wall, 'steps_per_s': steps / wall}


def lockstep_recorded(sim_seconds, e, composed=False):
    """
    Time the lockstep loop as ``bringup`` runs it, with a --use-sim-time recorder.

    Separate processes (sim, controller, estimator) or ``composed`` (one
    process).  Wall time from the first step to the last (``wall_s``) and to
    the simulator's exit, which waits until every subscriber (the recorder)
    has acknowledged every sample (``wall_acked_s``: the recording is
    complete); CPU seconds of each process per simulated second (start-up
    included, measured on a 1 s run and subtracted).
    """
    from friction_joint.bag import check_lockstep, read_recording
    from friction_joint.ros.bringup import composed_command, LOCKSTEP_WINDOW
    from rosbags.highlevel import AnyReader
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, 'ls')
        rec = start([PY, '-m', 'friction_joint', 'record', out, '--use-sim-time'], e)
        procs = {'record': rec}
        sim_params = {'mode': 'lockstep', 'duration': float(sim_seconds), 'start_delay': 2.0,
                      'wait_recorder': 'loop'}
        if composed:
            sim_params.update(wait_subscribers=1)
            sim = start(composed_command(MODEL, TRUTH, {
                'sim': sim_params, 'controller': {'mode': 'lockstep', 'friction_ff': 'lugre'},
                'estimator': {'mode': 'lockstep', 'friction': 'lugre'}}, d), e)
            procs['composed'] = sim
        else:
            procs['estimator'] = start(node('estimator', MODEL, friction='lugre',
                                            mode='lockstep'), e)
            procs['controller'] = start(node('controller', MODEL, friction_ff='lugre',
                                             mode='lockstep'), e)
            sim = start(node('joint_sim', TRUTH, wait_subscribers=3, follow='external_torque',
                             window=LOCKSTEP_WINDOW, **sim_params), e)
            procs['joint_sim'] = sim
        sampler = CpuSampler(procs)
        sampler.start()
        try:
            wall, t0 = _lockstep_wall(sim, 2.0)
            sim.wait(120)
            acked = time.monotonic() - t0
            sampler.halt.set()
            sampler.join()
            time.sleep(0.5)
        finally:
            for name, p in procs.items():
                if name != 'record':
                    stop(p)
            log = stop(rec, timeout=120)
        with AnyReader([__import__('pathlib').Path(out)]) as reader:
            js = [t for c, t, _ in reader.messages() if c.topic == '/joint_states']
        check = check_lockstep(read_recording(out))
    steps = int(round(sim_seconds * 3000))
    span = (js[-1] - js[0]) * 1e-9
    return {'steps': steps, 'wall_s': wall, 'wall_acked_s': acked, 'steps_per_s': steps / wall,
            'ratio': sim_seconds / wall, 'ratio_acked': sim_seconds / acked, 'bag_span_s': span,
            'bag_rate_hz': (len(js) - 1) / span if span > 0 else float('nan'),
            'recorded': len(js), 'log': log.strip().splitlines()[-1:],
            'check': check.describe(), 'cpu': sampler.cpu, 'complete': check.complete}


def cpu_per_second(long, short, seconds):
    """CPU seconds per simulated second of each process, start-up (the short run) removed."""
    return {name: (long['cpu'].get(name, 0.0) - short['cpu'].get(name, 0.0)) / seconds
            for name in long['cpu']}


FLOOD = """
import sys, time, rclpy
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState
rclpy.init()
n = rclpy.create_node('flood')
pub = n.create_publisher(JointState, '/joint_states', QoSProfile(
    history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE))
t = time.monotonic() + 10
while pub.get_subscription_count() < 1 and time.monotonic() < t:
    rclpy.spin_once(n, timeout_sec=0.05)
time.sleep(1.0)
rate, secs = float(sys.argv[1]), float(sys.argv[2])
k = 0
t0 = time.monotonic()
while time.monotonic() - t0 < secs:
    m = JointState(); m.header.stamp.sec = k // 1000; m.header.stamp.nanosec = (k % 1000) * 1000000
    m.name = ['joint']; m.position = [k * 1e-3]; m.velocity = [0.0]; m.effort = [0.0]
    pub.publish(m); k += 1
    if rate > 0:
        while time.monotonic() - t0 < k / rate:
            pass
pub.wait_for_all_acked(rclpy.duration.Duration(seconds=5))
print('published', k, flush=True)
n.destroy_node(); rclpy.shutdown()
"""


def recorder(rate, seconds, e):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, 'bag')
        rec = start([PY, '-m', 'friction_joint', 'record', out, '--topics', '/joint_states'], e)
        time.sleep(2.0)
        t0 = time.monotonic()
        pub = subprocess.run([PY, '-c', FLOOD, str(rate), str(seconds)], env=e, text=True,
                             capture_output=True, timeout=120)
        wall = time.monotonic() - t0
        time.sleep(1.0)
        log = stop(rec, timeout=60)
        said = re.search(r'published (\d+)', pub.stdout)
        if said is None:                    # the publisher failed: say why, measure nothing
            raise RuntimeError(f'the flood publisher ended with {pub.returncode}: '
                               f'{pub.stderr.strip()[-500:]}')
        published = int(said.group(1))
        m = re.search(r'recorded \d+ messages \(/joint_states: (\d+)', log)
        written = int(m.group(1)) if m else -1
    return {'published': published, 'written': written, 'lost': published - written,
            'rate_msg_s': published / seconds, 'wall_s': wall}


def replay_timing(seconds, e, rate=1.0):
    """Replay a 1 kHz recording at ``rate`` into the recorder; receive times against log times."""
    from friction_joint.bag import read_recording, write_recording
    with tempfile.TemporaryDirectory() as d:
        src, out = os.path.join(d, 'src'), os.path.join(d, 'rx')
        n = int(round(seconds * 1000))
        t = 100.0 + np.arange(n) * 1e-3
        write_recording(src, {'/joint_states': {'t': t, 'q': np.arange(n) * 1e-3,
                                                'qd': np.ones(n), 'effort': np.zeros(n)}})
        rec = start([PY, '-m', 'friction_joint', 'record', out, '--topics', '/joint_states'], e)
        rep = subprocess.run([PY, '-m', 'friction_joint', 'replay', src, '--rate', str(rate),
                              '--no-clock', '--wait', '60', '--topics', '/joint_states'], env=e,
                             text=True, capture_output=True, timeout=seconds / rate + 180)
        log = stop(rec, timeout=60)
        if rep.returncode != 0 or not os.path.isdir(out):
            raise RuntimeError(f'replay timing run failed:\n{rep.stdout}{rep.stderr}{log}')
        js = read_recording(out).joint_states
    lag = ((js.t_recv - js.t_recv[0]) - (js.t - js.t[0]) / rate) * 1e3
    lag -= np.min(lag)                      # behind the least delayed message
    took = re.search(r'replay took ([0-9.]+) s', rep.stdout + rep.stderr)
    return {'messages': len(js.t), 'sent': n, 'span_s': (t[-1] - t[0]) / rate,
            'took_s': float(took.group(1)) if took else float('nan'),
            'lag_p50_ms': float(np.percentile(lag, 50)),
            'lag_p99_ms': float(np.percentile(lag, 99)), 'lag_max_ms': float(np.max(lag))}


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument('--quick', action='store_true', help='10 s instead of 60 s of real time')
    ap.add_argument('--load', type=int, default=0, metavar='N',
                    help='repeat the realtime run with N busy processes loading the machine')
    a = ap.parse_args()
    e = env()
    os.environ.update({k: e[k] for k in ('ROS_DOMAIN_ID', 'ROS_AUTOMATIC_DISCOVERY_RANGE')})
    secs = 10.0 if a.quick else 60.0
    rt = realtime(secs, e)
    print(f'realtime {secs:g} s: /joint_states {rt["rate_hz"]:.1f} Hz (target 1000 +- 1 %), '
          f'gap p99 {rt["gap_p99_ms"]:.2f} ms, max {rt["gap_max_ms"]:.2f} ms; '
          f'state->command latency p50 {rt["latency_p50_ms"]:.3f} ms, '
          f'p99 {rt["latency_p99_ms"]:.3f} ms',
          flush=True)
    print(f'  states answered by a command {100 * rt["answered"]:.1f} %, lever max |q| '
          f'{rt["q_max"]:.3f} rad (reference amplitude 0.4)', flush=True)
    loaded = None
    if a.load > 0:
        busy = [subprocess.Popen([PY, '-c', 'while True: pass']) for _ in range(a.load)]
        try:
            # pacing off (hardware's behaviour, the simulator before pacing), then the default
            unpaced = realtime(secs, e, max_lead=0.0)
            loaded = realtime(secs, e)
        finally:
            for p in busy:
                p.kill()
                p.wait()
        for what, res in (('pacing off', unpaced), ('pacing on (default)', loaded)):
            print(f'realtime {secs:g} s with {a.load} busy processes, {what}: /joint_states '
                  f'{res["rate_hz"]:.1f} Hz, gap p99 {res["gap_p99_ms"]:.2f} ms, max '
                  f'{res["gap_max_ms"]:.2f} ms; latency p50 {res["latency_p50_ms"]:.3f} ms; '
                  f'answered {100 * res["answered"]:.1f} %, lever max |q| {res["q_max"]:.3f} rad',
                  flush=True)
    ls = lockstep(1.0 if a.quick else 3.0, e)
    print(f'lockstep: {ls["steps"]} steps in {ls["wall_s"]:.2f} s = '
          f'{ls["steps_per_s"]:.0f} steps/s ({ls["steps_per_s"] / 3000:.3f} x real time)',
          flush=True)
    sim_s = 3.0 if a.quick else 10.0
    runs = {}
    for composed in (False, True):
        name = 'composed' if composed else '3 processes'
        lr = lockstep_recorded(sim_s, e, composed)
        short = lockstep_recorded(1.0, e, composed)
        cpu = cpu_per_second(lr, short, sim_s - 1.0)
        runs[name] = lr
        print(f'lockstep {name} + recorder (--use-sim-time), {sim_s:g} s: last step after '
              f'{lr["wall_s"]:.2f} s ({lr["ratio"]:.3f} x real time), every sample '
              f'acknowledged after {lr["wall_acked_s"]:.2f} s ({lr["ratio_acked"]:.3f} x real '
              f'time); bag spans {lr["bag_span_s"]:.3f} s of log time, /joint_states '
              f'{lr["recorded"]} msgs at {lr["bag_rate_hz"]:.0f} Hz', flush=True)
        print('  CPU s per simulated s: ' + ', '.join(f'{k} {v:.2f}' for k, v in cpu.items())
              + f' (sum {sum(cpu.values()):.2f} on {os.cpu_count()} cores)', flush=True)
        print(f'  recording: {lr["check"]}', flush=True)
    lr, lc = runs['3 processes'], runs['composed']
    r3 = recorder(3000.0, 5.0, e)
    rf = recorder(0.0, 5.0, e)
    for name, r in (('3 kHz', r3), ('flood', rf)):
        print(f'recorder {name}: published {r["published"]}, written {r["written"]}, '
              f'lost {r["lost"]} ({r["rate_msg_s"]:.0f} msg/s)', flush=True)
    rp = replay_timing(3.0 if a.quick else 10.0, e)
    print(f'replay {rp["span_s"]:.3f} s of log time at rate 1: {rp["messages"]} of '
          f'{rp["sent"]} messages recorded, replay took {rp["took_s"]:.3f} s; receive time '
          f'behind log time p50 {rp["lag_p50_ms"]:.3f} ms, p99 {rp["lag_p99_ms"]:.3f} ms, '
          f'max {rp["lag_max_ms"]:.3f} ms', flush=True)
    print(f'rate_hz={rt["rate_hz"]:.1f} '
          + (f'rate_loaded_hz={loaded["rate_hz"]:.1f} ' if loaded else '')
          + f'latency_p50_ms={rt["latency_p50_ms"]:.3f} '
          f'latency_p99_ms={rt["latency_p99_ms"]:.3f} '
          f'lockstep_steps_per_s={ls["steps_per_s"]:.0f} '
          f'lockstep_recorded_steps_per_s={lr["steps_per_s"]:.0f} '
          f'lockstep_recorded_x_realtime={lr["ratio_acked"]:.3f} '
          f'lockstep_composed_recorded_x_realtime={lc["ratio_acked"]:.3f} '
          f'recorder_lost={r3["lost"] + rf["lost"]} recorder_flood_msg_s={rf["rate_msg_s"]:.0f} '
          f'replay_lag_p99_ms={rp["lag_p99_ms"]:.3f}')


if __name__ == '__main__':
    main()
