# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Recordings cut short: the reader's error, ``friction_joint recover``, staging directories."""
import errno
import importlib.util
import json
import os
from pathlib import Path
import shutil
import subprocess

from friction_joint.bag import read_recording
from friction_joint.bag.recover import recover_recording
from friction_joint.bag.staging import (flush_chunks, killed_recordings, MARKER,
                                        RecorderStaging, recovery_command)
from friction_joint.cli import main
from friction_joint.exceptions import RecordingError
import numpy as np
import pytest
import sourcetree

MCAP_CLI = Path(sourcetree.MCAP_CLI)
CONFIG = Path(__file__).resolve().parents[2] / 'config'
TOPICS = [('/joint_states', 'sensor_msgs/msg/JointState'),
          ('/joint_temperature', 'sensor_msgs/msg/Temperature')]


def _doctor(mcap):
    if not MCAP_CLI.exists():
        pytest.skip('no mcap CLI')
    res = subprocess.run([str(MCAP_CLI), 'doctor', '--strict-message-order', str(mcap)],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr


def _killed(tmp_path, n_flushed, n_after, out_name='rec', every=500, tag='rec-abcd1234'):
    """
    Make a recorder's staging directory as SIGKILL leaves it: ``n_flushed`` messages flushed.

    Written as ``record`` writes (rosbags writer, :func:`flush_chunks` every ``every``
    messages), then the file copied while the writer is still open (``n_after`` more
    messages only in memory).  Returns (staging directory, OUT).
    """
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types
    out = tmp_path / out_name
    staging = tmp_path / f'.{out_name}.{tag}.tmp'
    staging.mkdir()
    marker = RecorderStaging(staging, out, TOPICS)
    never = {'sec': 9223372036, 'nsec': 854775807}
    marker.update({'/joint_states': [
        {'history': 'keep_all', 'depth': 0, 'reliability': 'reliable',
         'durability': 'volatile', 'deadline': never, 'lifespan': never,
         'liveliness': 'automatic', 'liveliness_lease_duration': never,
         'avoid_ros_namespace_conventions': False}, {'history': 'broken'}]})
    w = Writer(tmp_path / 'live', version=9, storage_plugin=StoragePlugin.MCAP)
    w.open()
    js = w.add_connection('/joint_states', TOPICS[0][1], typestore=ts)
    w.add_connection('/joint_temperature', TOPICS[1][1], typestore=ts)
    for i in range(n_flushed + n_after):
        stamp = T['builtin_interfaces/msg/Time'](sec=100 + i // 1000, nanosec=i % 1000 * 10**6)
        msg = T['sensor_msgs/msg/JointState'](
            header=T['std_msgs/msg/Header'](stamp=stamp, frame_id=''), name=['joint'],
            position=np.array([i * 1e-3]), velocity=np.array([1.0]), effort=np.array([0.5]))
        w.write(js, 100 * 10**9 + i * 10**6, ts.serialize_cdr(msg, TOPICS[0][1]))
        if (i + 1) % every == 0 and i < n_flushed:
            flush_chunks(w)
    (staging / out_name).mkdir()
    shutil.copy(tmp_path / 'live' / 'live.mcap', staging / out_name / f'{out_name}.mcap')
    w.close()
    shutil.rmtree(tmp_path / 'live')
    marker.close()                                  # the recorder is gone
    return staging, out


def test_killed_recording_is_recovered(tmp_path, capsys):
    staging, out = _killed(tmp_path, 3000, 400)
    partial = staging / 'rec' / 'rec.mcap'
    assert killed_recordings(out) == [(str(staging), 'killed')]
    assert recovery_command(staging) == f'friction_joint recover {os.path.relpath(staging)} ' \
                                        f'{os.path.relpath(out)}'

    # the readers name the file and the recovery command, in one line
    for path in (partial, staging / 'rec', staging):
        with pytest.raises(RecordingError) as err:
            read_recording(path)
        text = str(err.value)
        assert 'friction_joint recover' in text and '\n' not in text, text
        assert 'File end magic' not in text
    with pytest.raises(RecordingError, match='truncated or corrupt recording: .*without the '
                       'MCAP footer'):
        read_recording(partial)

    assert main(['recover', str(staging), str(out)]) == 0
    printed = capsys.readouterr().out
    assert 'recovered 3000 messages (/joint_states: 3000, /joint_temperature: 0)' in printed
    assert not staging.exists()                    # recovered: the staging directory is gone
    rec = read_recording(out)
    np.testing.assert_allclose(rec.joint_states.q, np.arange(3000) * 1e-3)
    assert rec.temperature is None
    assert sorted(os.listdir(out)) == ['metadata.yaml', 'rec.mcap']
    _doctor(out / 'rec.mcap')
    meta = (out / 'metadata.yaml').read_text()
    assert 'friction_joint.recovered' in meta and 'keep_all' in meta   # QoS from the marker
    assert killed_recordings(out) == []


def test_a_chunk_cut_in_the_middle_keeps_its_complete_messages(tmp_path):
    staging, _ = _killed(tmp_path, 2000, 0, every=2000)
    partial = staging / 'rec' / 'rec.mcap'
    data = partial.read_bytes()
    cut = tmp_path / 'cut.mcap'
    cut.write_bytes(data[:len(data) * 3 // 4])          # in the one uncompressed chunk
    res = recover_recording(cut, tmp_path / 'rec.mcap')
    assert not res.complete and 'chunk' in res.reason
    n = res.counts['/joint_states']
    assert 1000 < n < 2000, n
    rec = read_recording(tmp_path / 'rec.mcap')
    np.testing.assert_allclose(rec.joint_states.q, np.arange(n) * 1e-3)
    _doctor(tmp_path / 'rec.mcap')


def test_a_complete_file_is_recovered_whole(tmp_path):
    from friction_joint.bag import write_recording
    t = np.arange(500) * 1e-3
    write_recording(tmp_path / 'a.mcap', {'/joint_states': {'t': t, 'q': t, 'qd': t * 0 + 1,
                                                            'effort': t * 0}})
    res = recover_recording(tmp_path / 'a.mcap', tmp_path / 'b')
    assert res.complete and res.counts == {'/joint_states': 500} and res.lost_bytes > 0
    assert len(read_recording(tmp_path / 'b').joint_states.t) == 500


def test_recover_refuses_bad_input_with_one_line(tmp_path, capsys):
    staging, out = _killed(tmp_path, 1000, 0)
    out.mkdir()
    (out / 'x').write_text('old')
    empty = tmp_path / 'empty.mcap'
    empty.write_bytes(b'')
    text = tmp_path / 'text.mcap'
    text.write_text('not mcap at all')
    for args, words in ((['recover', str(staging), str(out)], ('exists already', '--force')),
                        (['recover', str(empty), str(tmp_path / 'o1')], ('empty', 'nothing')),
                        (['recover', str(text), str(tmp_path / 'o2')], ('not an MCAP',)),
                        (['recover', str(tmp_path / 'nope'), str(tmp_path / 'o3')],
                         ('does not exist',)),
                        (['recover', str(staging), str(staging / 'inside')], ('input',))):
        assert main(args) == 2, args
        err = capsys.readouterr().err.strip()
        assert err.count('\n') == 0 and err.startswith('friction_joint recover: error:'), err
        assert all(w in err for w in words), err
    assert (out / 'x').read_text() == 'old'
    assert not any(p.name.startswith('.o') for p in tmp_path.iterdir())
    assert staging.exists()
    assert main(['recover', str(staging), str(out), '--force', '--keep']) == 0
    assert f'kept the staging directory {staging}' in capsys.readouterr().out
    assert staging.exists() and not (out / 'x').exists()
    assert len(read_recording(out).joint_states.t) == 1000


def test_an_older_recorders_directory_survives_the_output_clean_up(tmp_path, capsys):
    # named as OutputSet's staging directories, no owner record, older than an hour: the
    # output rules' clean-up of killed runs' staging directories must leave it alone
    staging, out = _killed(tmp_path, 1000, 0, tag='abcd1234')
    os.remove(staging / MARKER)
    old = os.stat(staging).st_mtime - 7200
    os.utime(staging, (old, old))
    assert killed_recordings(out) == [(str(staging), 'unknown')]
    assert main(['recover', str(staging), str(out), '--keep']) == 0
    printed = capsys.readouterr().out
    assert 'recovered 1000 messages' in printed
    assert f'kept the staging directory {staging}' in printed and staging.exists()
    assert len(read_recording(out).joint_states.t) == 1000


def test_a_running_recorder_is_not_taken_for_a_killed_one(tmp_path):
    out = tmp_path / 'rec'
    staging = tmp_path / '.rec.zz99yy88.tmp'
    staging.mkdir()
    marker = RecorderStaging(staging, out, TOPICS)
    try:
        info = json.loads((staging / MARKER).read_text())
        assert info['pid'] == os.getpid() and info['out'] == str(out)
        assert killed_recordings(out) == []
        with pytest.raises(RecordingError, match='still'):
            read_recording(staging)
        with pytest.raises(RecordingError, match='still running'):
            recover_recording(staging, tmp_path / 'x')
    finally:
        marker.close()
    assert killed_recordings(out) == [(str(staging), 'killed')]
    # an older recorder's directory (no marker) is named too
    old = tmp_path / '.rec.old12345.tmp'
    (old / 'rec').mkdir(parents=True)
    (old / 'rec' / 'rec.mcap').write_bytes(b'')
    assert (str(old), 'unknown') in killed_recordings(out)
    with pytest.raises(RecordingError, match='is empty.*nothing to recover'):
        read_recording(old / 'rec' / 'rec.mcap')


# --------------------------------------- a missing OUT whose recorder was killed ---

def _fleet_reason(tmp_path, rec, capsys):
    """Run ``fleet`` on a manifest of one row, ``rec``; return that row's reason."""
    import csv
    manifest = tmp_path / 'manifest.csv'
    manifest.write_text(f'recording,joint,time,travel\n{rec},j01,2026-03-02T18:46:42+00:00,'
                        '1.0\n')
    assert main(['fleet', '--manifest', str(manifest), '--model', str(CONFIG / 'csd25.yaml'),
                 '--out', str(tmp_path / 'fleet'), '--workers', '1', '--quiet']) == 0
    capsys.readouterr()
    with open(tmp_path / 'fleet' / 'recordings.csv', encoding='utf-8') as fh:
        row, = csv.DictReader(fh)
    assert row['status'] == 'failed'
    return row['reason']


@pytest.mark.parametrize('given', ['rec', 'rec/rec.mcap'])
def test_every_reader_names_the_killed_recorders_staging_and_the_command(
        tmp_path, capsys, monkeypatch, given):
    """``identify rec`` said only 'recording rec does not exist' beside .rec.rec-*.tmp."""
    staging, out = _killed(tmp_path, 1000, 0)
    monkeypatch.chdir(tmp_path)
    command = f'friction_joint recover {staging.name} rec'
    assert recovery_command(staging) == command
    base = str(CONFIG / 'csd25_base.yaml')
    commands = [['identify', given, '--model', base, '--out', 'g.yaml'],
                ['diagnose', given, '--model', base, '--out', 'd'], ['recover', given, 'out']]
    if importlib.util.find_spec('rclpy') is not None:        # replay imports rclpy first
        commands.append(['replay', given])
    for argv in commands:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err.strip()
        assert '\n' not in err and err.startswith(f'friction_joint {argv[0]}: error: '), err
        assert f'recording {given} does not exist' in err and 'was killed' in err, err
        assert err.endswith(f'recover it with: {command}'), err
    with pytest.raises(RecordingError, match=f'recover it with: {command}$'):
        read_recording(given)
    assert f'recover it with: {command}' in _fleet_reason(tmp_path, given, capsys)
    # the command named works
    assert main(command.split()[1:]) == 0
    assert len(read_recording(out).joint_states.t) == 1000 and not staging.exists()


def test_missing_recording_while_its_recorder_runs_and_with_several_killed(
        tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    first, _ = _killed(tmp_path, 500, 0, tag='rec-aaaa1111')
    second, _ = _killed(tmp_path, 500, 0, tag='rec-bbbb2222')
    os.utime(first, (1e9, 1e9))                    # the older one
    with pytest.raises(RecordingError) as err:
        read_recording('rec')
    assert f'in {second.name} (1 older staging directory of it beside)' in str(err.value)
    assert str(err.value).endswith(f'friction_joint recover {second.name} rec')
    running = tmp_path / '.rec.rec-cccc3333.tmp'
    running.mkdir()
    marker = RecorderStaging(running, tmp_path / 'rec', TOPICS)
    try:
        with pytest.raises(RecordingError, match=f'does not exist yet: a recorder \\(pid '
                           f'{os.getpid()}\\) is still writing it in {running.name}; stop it'):
            read_recording('rec')
    finally:
        marker.close()
    with pytest.raises(RecordingError, match='^recording other does not exist$'):
        read_recording('other')


# ------------------------------------------- a recorder stopped by a write error ---

@pytest.mark.parametrize('code, room', [(errno.ENOSPC, True), (errno.ENOSPC, False),
                                        (errno.EROFS, False)])
def test_salvage_seals_when_there_is_room_else_names_the_command(tmp_path, monkeypatch, code,
                                                                 room):
    """The recorder's one line after a failed write: sealed into OUT, or how to recover."""
    from friction_joint.bag import recover
    staging, out = _killed(tmp_path, 1000, 0)
    if not room:
        monkeypatch.setattr(recover.os, 'statvfs', lambda path: os.statvfs_result(
            (4096, 4096, 100, 0, 0, 100, 0, 0, 0, 255)))
    line = recover.salvage_recording(staging, out, OSError(code, os.strerror(code)))
    assert '\n' not in line and line.startswith(f'cannot write {out}: {os.strerror(code)}; '
                                                'stopped; '), line
    if room:
        assert f'the 1000 messages written before it are in {out} (sealed' in line, line
        assert len(read_recording(out).joint_states.t) == 1000 and not staging.exists()
    else:
        then = 'make room, then ' if code == errno.ENOSPC else ''
        assert line.endswith(f'kept in {staging}: {then}recover it with: '
                             f'{recovery_command(staging)}'), line
        assert staging.exists() and not out.exists()
