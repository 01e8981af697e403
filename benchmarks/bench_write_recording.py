#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Speed and peak memory of ``write_recording``: the streaming writer against the old path.

    .venv/bin/python benchmarks/bench_write_recording.py                 # both parts
    .venv/bin/python benchmarks/bench_write_recording.py --speed-rows 500000 --rows
    .venv/bin/python benchmarks/bench_write_recording.py --rows 1e6 5e6 2e7 --old-max-rows 5e6

The data: ``/joint_states`` (one joint) and ``/link_torque`` at 1 kHz, ``rows`` samples
each (two messages a row).  The old path is the writer as it was before streaming,
copied here: every topic encoded at once (``np.tile`` of a template), all receive stamps
concatenated and lexsorted, rosbags' ``Writer`` message by message, then
``seal_recording`` (re-read and re-written with the ``mcap`` library for zstd chunks
and CRCs).

1. Speed (``--speed-rows``, in this process, same data): messages/s of each path, the
   ratio, and whether both files are the same bytes.
2. Memory (``--rows``): each path writes in a child process (the only child at a time);
   the peak resident memory of the child (``VmHWM``: ``ru_maxrss`` would include this
   process's memory when it forked) and its part above the peak after building the
   input arrays (40 bytes a row) are printed.  The old path is run
   only up to ``--old-max-rows`` (it needs about 1.2 kB a row).
"""
import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

__all__ = ['make_topics', 'write_old', 'main']


def make_topics(rows):
    """Return ``/joint_states`` and ``/link_torque`` of ``rows`` samples at 1 kHz."""
    t = np.arange(rows) * 1e-3
    return {'/joint_states': {'t': t, 'q': np.sin(t), 'qd': np.cos(t), 'effort': 0.5 * t},
            '/link_torque': {'t': t, 'tau': -t}}


def _old_block(typestore, topic, spec, joint_name):
    """Encode one whole topic at once (the old writer's ``_topic_block``, two topics)."""
    from friction_joint.bag._cdr import WALKERS
    from friction_joint.bag.topics import CONTRACT_TYPES, NS

    T = typestore.types
    stamp = np.round(np.asarray(spec['t'], dtype=float) * NS).astype(np.int64)
    n = len(stamp)
    msgtype = CONTRACT_TYPES[topic]
    header = T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0),
                                      frame_id='')
    if topic == '/link_torque':
        torque = np.zeros((n, 3))
        torque[:, 2] = spec['tau']
        V = T['geometry_msgs/msg/Vector3']
        template = T[msgtype](header=header, wrench=T['geometry_msgs/msg/Wrench'](
            force=V(x=0.0, y=0.0, z=0.0), torque=V(x=0.0, y=0.0, z=0.0)))
        cols = {'force': np.zeros((n, 3)), 'torque': torque}
    else:
        template = T[msgtype](header=header, name=[joint_name], position=np.zeros(1),
                              velocity=np.zeros(1), effort=np.zeros(1))
        cols = {'position': spec['q'][:, None], 'velocity': spec['qd'][:, None],
                'effort': spec['effort'][:, None]}
    raw = typestore.serialize_cdr(template, msgtype)
    layout = WALKERS[msgtype](raw)
    block = np.tile(np.frombuffer(raw, dtype=np.uint8), (n, 1))
    block[:, 4:8] = (stamp // NS).astype('<i4').view(np.uint8).reshape(n, 4)
    block[:, 8:12] = (stamp % NS).astype('<u4').view(np.uint8).reshape(n, 4)
    for name, x in cols.items():
        off, count = layout.fields[name]
        block[:, off:off + 8 * count] = np.ascontiguousarray(x, dtype='<f8').view(
            np.uint8).reshape(n, 8 * count)
    return stamp, block, msgtype


def write_old(path, topics, joint_name='joint'):
    """Write a rosbag2 directory as the writer did before streaming (rosbags + seal)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    from friction_joint.bag import seal_recording

    typestore = get_typestore(Stores.ROS2_JAZZY)
    blocks = {t: _old_block(typestore, t, spec, joint_name) for t, spec in topics.items()}
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        conns, recvs, which, rows = [], [], [], []
        for i, (topic, (recv, block, msgtype)) in enumerate(blocks.items()):
            conns.append((writer.add_connection(topic, msgtype, typestore=typestore), block))
            recvs.append(recv)
            which.append(np.full(len(recv), i, dtype=np.int64))
            rows.append(np.arange(len(recv), dtype=np.int64))
        recvs, which, rows = (np.concatenate(x) for x in (recvs, which, rows))
        for j in np.lexsort((which, recvs)):
            conn, block = conns[which[j]]
            writer.write(conn, int(recvs[j]), block[rows[j]].tobytes())
    seal_recording(path)
    return path


def _write(kind, path, topics):
    if kind == 'old':
        return write_old(path, topics)
    from friction_joint.bag import write_recording
    return write_recording(path, topics)


def _hwm_kb():
    """
    Return this process's peak resident memory (KiB) since its exec (``VmHWM``).

    ``ru_maxrss`` of a child also counts the parent's resident memory when it forked.
    """
    with open('/proc/self/status') as fh:
        for line in fh:
            if line.startswith('VmHWM:'):
                return int(line.split()[1])
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def _child(kind, rows, path):
    """Build the arrays, write; print ``base_kb peak_kb seconds`` (the child's own)."""
    topics = make_topics(rows)
    base = _hwm_kb()
    t0 = time.perf_counter()
    _write(kind, path, topics)
    wall = time.perf_counter() - t0
    print(base, _hwm_kb(), f'{wall:.2f}')


def _speed(rows, tmp):
    from friction_joint.bag import write_recording

    topics = make_topics(rows)
    write_recording(os.path.join(tmp, 'warm'), make_topics(1000))      # imports, typestore
    write_old(os.path.join(tmp, 'warm_old'), make_topics(1000))
    res = {}
    for kind in ('new', 'old'):
        out = os.path.join(tmp, kind, 'rec')
        os.makedirs(os.path.dirname(out))
        t0 = time.perf_counter()
        _write(kind, out, topics)
        res[kind] = time.perf_counter() - t0
    same = all(open(os.path.join(tmp, k, 'rec', 'rec.mcap'), 'rb').read()
               == open(os.path.join(tmp, 'old', 'rec', 'rec.mcap'), 'rb').read()
               for k in ('new',))
    msgs = 2 * rows
    print(f'speed rows={rows} messages={msgs} new_s={res["new"]:.2f} old_s={res["old"]:.2f} '
          f'new_msg_per_s={msgs / res["new"]:.0f} old_msg_per_s={msgs / res["old"]:.0f} '
          f'ratio={res["old"] / res["new"]:.1f} same_bytes={same}')


def _memory(rows, kind, tmp):
    out = os.path.join(tmp, f'{kind}_{rows}')
    cmd = [sys.executable, os.path.abspath(__file__), '--child', kind, str(rows), out]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    shutil.rmtree(out, ignore_errors=True)
    if proc.returncode:
        print(f'memory rows={rows} path={kind} FAILED: {proc.stderr.strip()[-300:]}')
        return
    base, peak, wall = proc.stdout.split()
    base, peak = int(base) / 1024, int(peak) / 1024                 # KiB -> MiB
    print(f'memory rows={rows} messages={2 * rows} path={kind} write_s={wall} '
          f'peak_rss_mb={peak:.0f} above_inputs_mb={peak - base:.0f} '
          f'bytes_per_row_above_inputs={(peak - base) * 2**20 / rows:.0f}')


def main(argv=None):
    """Run the benchmark; print one line per measurement."""
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[1])
    ap.add_argument('--speed-rows', type=float, default=300_000)
    ap.add_argument('--rows', type=float, nargs='*', default=[1e6, 5e6, 2e7])
    ap.add_argument('--old-max-rows', type=float, default=5e6)
    ap.add_argument('--child', nargs=3, metavar=('PATH', 'ROWS', 'OUT'), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        _child(args.child[0], int(args.child[1]), args.child[2])
        return 0
    with tempfile.TemporaryDirectory(prefix='bench_write_') as tmp:
        if args.speed_rows:
            _speed(int(args.speed_rows), tmp)
        for rows in (int(r) for r in args.rows):
            _memory(rows, 'new', tmp)
            if rows <= args.old_max_rows:
                _memory(rows, 'old', tmp)
            else:
                print(f'memory rows={rows} path=old skipped (above --old-max-rows)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
