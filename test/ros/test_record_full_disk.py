# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``record`` on a disk that fills up: it stops at the first failed write, says so in one line.

Before, the error came as two lines (the staging directory kept, then ``[Errno 28]``),
and a disk that filled while the recording was being finished lost it all (the
staging directory was removed).  Now: one line, exit 2, and what was written is
either sealed into OUT at once (when the file system has room for it) or left
in the staging directory that the line names with the ``recover`` command.
"""
import errno
import json
import os
from pathlib import Path
import shutil
import subprocess
import textwrap
import threading
import time

import numpy as np
import pytest
from roshelpers import PYTHON, reliable_qos
import sourcetree

pytestmark = pytest.mark.ros

pytest.importorskip('rclpy')


def _joint_state(i, width=1):
    from sensor_msgs.msg import JointState
    m = JointState()
    m.header.stamp.sec, m.header.stamp.nanosec = 100 + i // 1000, (i % 1000) * 1_000_000
    m.name = ['joint'] * width
    m.position, m.velocity, m.effort = [float(i)] * width, [1000.0] * width, [0.5] * width
    return m


def _record(ros_node, out, seconds=None):
    """
    Record ``/joint_states`` into ``out`` (in a thread) while publishing at about 1 kHz.

    Stops after ``seconds`` (or when the recorder ends by itself); returns the log lines
    and ``{'counts': ...}`` or ``{'error': one line, 't': when it came}``.
    """
    from friction_joint.exceptions import RecordingError
    from friction_joint.ros.record import record
    from sensor_msgs.msg import JointState
    lines, result, stop = [], {}, threading.Event()

    def run():
        try:
            result['counts'] = record(out, topics=['/joint_states'], log=lines.append,
                                      stop=stop)
        except RecordingError as exc:
            result['error'], result['t'] = str(exc), time.monotonic()
    thread = threading.Thread(target=run)
    thread.start()
    try:
        assert ros_node.spin_until(lambda: any('recording' in x for x in lines), 60), lines
        pub = ros_node.node.create_publisher(JointState, '/joint_states', reliable_qos(None))
        assert ros_node.spin_until(lambda: any('matched' in x for x in lines), 15), lines
        i, t_end = 0, time.monotonic() + (seconds or 20)
        while thread.is_alive() and time.monotonic() < t_end:
            pub.publish(_joint_state(i))
            i += 1
            ros_node.spin_for(0.001)
    finally:
        stop.set()
        thread.join(30)
    return lines, result


def _failing(monkeypatch, method, after):
    """Make the recorder's MCAP writer fail with ENOSPC in ``method`` after ``after`` calls."""
    from friction_joint.bag.staging import STAGING_TAG
    from rosbags.rosbag2 import storage_mcap
    real = getattr(storage_mcap.McapWriter, method)
    calls, failed = [0], []

    def fail(self, *args, **kwargs):                 # the recorder's file only
        ours = STAGING_TAG in str(self.path)
        calls[0] += ours
        if calls[0] <= after or not ours:
            return real(self, *args, **kwargs)
        self.bio.write(b'\x06' + bytes(64))          # part of the record reached the disk
        self.bio.flush()
        failed.append(time.monotonic())
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(storage_mcap.McapWriter, method, fail)
    return failed


def _sealed_from_the_start(out):
    from friction_joint.bag import read_recording
    q = read_recording(out).joint_states.q
    assert len(q) > 0 and np.array_equal(q, np.arange(len(q))), 'the first messages, all'
    return len(q)


def test_full_disk_stops_at_once_and_seals_what_was_written(ros_node, tmp_path, monkeypatch):
    """ENOSPC at the third chunk: one line at once, the first chunks sealed into OUT."""
    failed = _failing(monkeypatch, 'close_chunk', 2)
    out = tmp_path / 'rec'
    lines, result = _record(ros_node, out)
    assert failed and 'error' in result, (lines, result)
    assert result['t'] - failed[0] < 5.0, 'not at once'
    error = result['error']
    assert '\n' not in error and 'No space left on device' in error, error
    assert f'are in {out} (sealed' in error, error
    assert not any('kept in' in x for x in lines), lines
    _sealed_from_the_start(out)
    assert sorted(os.listdir(tmp_path)) == ['rec']        # no staging directory left


def test_full_disk_while_finishing_loses_nothing_written(ros_node, tmp_path, monkeypatch):
    """ENOSPC in the final close (after Ctrl-C) removed the staging directory: all lost."""
    failed = _failing(monkeypatch, 'close', 0)
    out = tmp_path / 'rec'
    lines, result = _record(ros_node, out, seconds=2.5)
    assert failed and 'No space left on device' in result.get('error', ''), (lines, result)
    assert '\n' not in result['error'] and f'are in {out} (sealed' in result['error']
    assert _sealed_from_the_start(out) > 500                # two flushes at 1 kHz at least
    assert sorted(os.listdir(tmp_path)) == ['rec']


_SCRIPT = textwrap.dedent("""
    import json, os, subprocess, sys, time
    sys.path.insert(0, {ros_tests!r})
    import roshelpers
    from roshelpers import reliable_qos
    from sensor_msgs.msg import JointState
    mnt, env = {mnt!r}, dict(os.environ)

    def _joint_state(i, width):
        m = JointState()
        m.header.stamp.sec, m.header.stamp.nanosec = 100 + i // 1000, (i % 1000) * 1_000_000
        m.name = ['joint'] * width
        m.position, m.velocity, m.effort = [float(i)] * width, [1000.0] * width, [0.5] * width
        return m

    rec = roshelpers.Proc([sys.executable, '-m', 'friction_joint', 'record', mnt + '/rec',
                           '--topics', '/joint_states'], env)
    assert rec.wait_for('recording /joint_states', 60), rec.describe()
    with roshelpers.ros_node('pub', env['ROS_DOMAIN_ID']) as node:
        pub = node.node.create_publisher(JointState, '/joint_states', reliable_qos(None))
        assert rec.wait_for('/joint_states: 1 publisher matched', 30), rec.describe()
        i, t_end = 0, time.monotonic() + 60
        while rec.popen.poll() is None and time.monotonic() < t_end:
            pub.publish(_joint_state(i, 50))
            i += 1
            node.spin_for(0.0005)
        stopped = rec.popen.poll() is not None
    status = rec.wait(30)
    cmd = rec.stderr.strip().rsplit('recover it with: ', 1)[-1].split()
    rc = subprocess.run([sys.executable, '-m'] + cmd[:3] + [{outside!r}],
                        capture_output=True).returncode
    print(json.dumps({{'published': i, 'stopped': stopped, 'status': status,
                      'stderr': rec.stderr, 'recover': rc}}))
""")


@pytest.mark.skipif(shutil.which('unshare') is None, reason='needs unshare')
def test_real_full_tmpfs_one_line_staging_kept_and_recoverable(ros_env, tmp_path):
    """A real 2 MiB tmpfs: the recorder stops, one line names the staging and the command."""
    from friction_joint.bag import read_recording
    mnt, outside = tmp_path / 'mnt', tmp_path / 'recovered'
    mnt.mkdir()
    script = tmp_path / 'run.py'
    script.write_text(_SCRIPT.format(ros_tests=str(Path(__file__).parent), mnt=str(mnt),
                                     outside=str(outside)))
    env = dict(ros_env, PYTHONPATH=os.pathsep.join([sourcetree.ROOT,
                                                   ros_env.get('PYTHONPATH', '')]))
    proc = subprocess.run(['unshare', '-rm', 'sh', '-c', f'mount -t tmpfs -o size=2m none {mnt} '
                           f'&& {PYTHON} {script}'], capture_output=True, text=True,
                          timeout=300, env=env, cwd=str(tmp_path))
    if '"published"' not in proc.stdout:
        pytest.skip(f'cannot run a recorder on a tmpfs here: {proc.stderr.strip()[-300:]}')
    got = json.loads(proc.stdout.strip().splitlines()[-1])
    assert got['stopped'] and got['status'] == 2, got
    errors = [x for x in got['stderr'].splitlines()
              if not x.startswith(('recording /joint_states to ', '/joint_states: 1 publisher'))]
    assert len(errors) == 1, got['stderr']
    line = errors[0]
    assert line.startswith('friction_joint record: error: cannot write ') and \
        'No space left on device; stopped; what was recorded is kept in ' in line, line
    assert 'recover it with: friction_joint recover ' in line and '[Errno' not in line, line
    assert got['recover'] == 0, got
    assert len(read_recording(outside).joint_states.t) > 0
