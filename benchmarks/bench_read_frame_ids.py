#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Reading a recording whose every message has its own ``frame_id`` (issue 23).

    .venv/bin/python benchmarks/bench_read_frame_ids.py 100000 200000

Writes (not timed) a recording of N ``/joint_states`` messages at 1 kHz, each with
the frame id ``frame_<index>``, into a temporary directory, and times
``read_recording`` on it.  The time should grow linearly with N.
"""
import argparse
import struct
import sys
import tempfile
import time

import numpy as np

__all__ = ['main']


def _write(path, n):
    from friction_joint.bag._cdr import walk_joint_state
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types
    msg = T['sensor_msgs/msg/JointState'](
        header=T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](
            sec=0, nanosec=0), frame_id='frame_000000'),
        name=['joint'], position=np.array([0.0]), velocity=np.array([0.0]),
        effort=np.array([0.0]))
    raw = bytes(ts.serialize_cdr(msg, 'sensor_msgs/msg/JointState'))
    fields = walk_joint_state(raw).fields
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        c = w.add_connection('/joint_states', 'sensor_msgs/msg/JointState', typestore=ts)
        for i in range(n):
            b = bytearray(raw)
            t = i * 1_000_000
            b[4:12] = struct.pack('<iI', t // 10**9, t % 10**9)
            b[16:28] = f'frame_{i:06d}'.encode()
            for name, x in (('position', 0.5 * np.sin(i * 1e-3)),
                            ('velocity', 0.5 * np.cos(i * 1e-3))):
                off = fields[name][0]
                b[off:off + 8] = struct.pack('<d', x)
            w.write(c, t + 1, bytes(b))


def main(argv=None):
    """Time reading recordings of the given sizes; print one line per size."""
    from friction_joint.bag import read_recording
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument('sizes', nargs='*', type=int, default=[100_000, 200_000])
    args = ap.parse_args(argv)
    for n in args.sizes:
        with tempfile.TemporaryDirectory() as tmp:
            path = f'{tmp}/rec'
            _write(path, n)
            t0 = time.perf_counter()
            rec = read_recording(path)
            dt = time.perf_counter() - t0
            print(f'messages={n} read_s={dt:.2f} us_per_message={1e6 * dt / n:.1f} '
                  f'read={len(rec.joint_states)}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
