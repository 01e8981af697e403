# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The streaming recording writer (bag/writer.py, bag/mcap_stream.py).

Memory bounded by a block, whatever the length (the encoder and the MCAP stream never
see more than :data:`~friction_joint.bag.writer.WRITE_BLOCK` messages at a time), the same
messages in the same order as the writer before it (rosbags' Writer followed by
``seal_recording``: a digest computed with that code), and the same file, byte for
byte, as that path gives for the same messages.
"""
import hashlib
import os
from pathlib import Path
import subprocess

from friction_joint.bag import CONTRACT_TYPES, read_recording, seal_recording, write_recording
from friction_joint.bag.mcap_stream import McapStream
import friction_joint.bag.writer as writer
import numpy as np
import pytest
import sourcetree

MCAP_CLI = Path(sourcetree.MCAP_CLI)

#: digest of (topic, log time, publish time, data) of every message of _data() in file
#: order, as written by the writer before streaming (rosbags' Writer + seal_recording)
OLD_DIGEST = '0faeba2255891a521fc9da841c20a712728fa85479a3f72764b61f6a1c841413'


def _data():
    """Return topics with every writer feature: receive order unlike stamp order, ties..."""
    n = 3000
    t = np.arange(n) * 1e-3 + 5.0
    rng = np.random.default_rng(7)
    recv = t + rng.uniform(0, 3e-3, n)          # receive times out of order
    recv[10:20] = recv[10]                        # ties within a topic
    q = np.sin(t)
    q[5] = np.nan
    return {'/joint_states': {'t': t, 't_recv': recv, 'q': np.c_[q, -q],
                              'qd': np.c_[np.cos(t), t], 'effort': np.c_[t, t],
                              'name': ['a', 'bb'], 'frame_id': 'base'},
            '/link_torque': {'t': t, 'tau': -t},            # ties with /joint_states
            '/joint_temperature': {'t': t[::100], 'xi': 25 + t[::100], 'variance': 0.5},
            '/joint_command': {'t': t[::2], 'effort': t[::2], 'q_d': t[::2]},
            '/external_torque': {'t': np.zeros(0), 'effort': np.zeros(0)},
            '/clock': {'t': t[::10]}}


def _long(n):
    t = np.arange(n) * 1e-3
    return {'/joint_states': {'t': t, 'q': np.sin(t), 'qd': np.cos(t), 'effort': t},
            '/link_torque': {'t': t, 'tau': -t},
            '/joint_temperature': {'t': t[::3] + 5e-4, 'xi': 20 + t[::3]},
            '/clock': {'t': t[::7]}}


def _mcap(path):
    path = Path(path)
    return path if path.suffix == '.mcap' else next(path.glob('*.mcap'))


def _messages(path):
    from mcap.reader import make_reader

    with open(_mcap(path), 'rb') as fh:
        for _, channel, msg in make_reader(fh).iter_messages(log_time_order=False):
            yield channel.topic, msg.log_time, msg.publish_time, msg.data


def _digest(path):
    h = hashlib.sha256()
    for topic, log_time, publish_time, data in _messages(path):
        h.update(topic.encode())
        h.update(log_time.to_bytes(8, 'little'))
        h.update(publish_time.to_bytes(8, 'little'))
        h.update(len(data).to_bytes(4, 'little'))
        h.update(data)
    return h.hexdigest()


def _old_path(src, dst, topics, custom_data=None):
    """Write the messages of ``src`` as the writer did before: rosbags' Writer, then seal."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    typestore = get_typestore(Stores.ROS2_JAZZY)
    bagdir = Path(str(dst)[:-5] if str(dst).endswith('.mcap') else dst)
    with Writer(bagdir, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        for key, value in (custom_data or {}).items():
            w.set_custom_data(key, value)
        conns = {topic: w.add_connection(topic, CONTRACT_TYPES[topic], typestore=typestore)
                 for topic in topics}
        for topic, log_time, _, data in _messages(src):
            w.write(conns[topic], log_time, data)
    seal_recording(bagdir)
    return bagdir


@pytest.mark.parametrize('block', [writer.WRITE_BLOCK, 97])
def test_messages_and_order_are_those_of_the_old_writer(tmp_path, monkeypatch, block):
    monkeypatch.setattr(writer, 'WRITE_BLOCK', block)
    write_recording(tmp_path / 'rec', _data(), joint_name='j', custom_data={'k': 'v'})
    assert _digest(tmp_path / 'rec') == OLD_DIGEST


@pytest.mark.parametrize('name, topics, custom', [
    ('rec', _data, {'k': 'v', 'source': 'log.csv'}),
    ('rec.mcap', _data, None),
    ('long', lambda: _long(12_000), None),          # several chunks, several blocks
    ('empty', lambda: {'/joint_states': {'t': [], 'q': [], 'qd': [], 'effort': []}}, None),
    ('none', dict, None),
])
def test_the_file_is_byte_for_byte_what_rosbags_and_seal_recording_wrote(
        tmp_path, monkeypatch, name, topics, custom):
    monkeypatch.setattr(writer, 'WRITE_BLOCK', 5000)
    data = topics()
    (tmp_path / 'new').mkdir()
    (tmp_path / 'old').mkdir()
    new = write_recording(tmp_path / 'new' / name, data, joint_name='j', custom_data=custom)
    old = _old_path(new, tmp_path / 'old' / name, data, custom)
    assert _mcap(new).read_bytes() == next(old.glob('*.mcap')).read_bytes()
    if not name.endswith('.mcap'):
        assert (Path(new) / 'metadata.yaml').read_text() == (old / 'metadata.yaml').read_text()


def test_memory_is_a_block_whatever_the_length(tmp_path, monkeypatch):
    """The encoder and the MCAP stream get at most WRITE_BLOCK messages a call (its default)."""
    encoded, added = [], []
    encode, add = writer._encode, McapStream.add_messages

    def counting_encode(raw, layout, stamp, columns):
        encoded.append(len(stamp))
        return encode(raw, layout, stamp, columns)

    def counting_add(self, groups, which):
        added.append((len(which), sum(len(g[3]) for g in groups)))
        return add(self, groups, which)

    monkeypatch.setattr(writer, '_encode', counting_encode)
    monkeypatch.setattr(McapStream, 'add_messages', counting_add)
    n = 2 * writer.WRITE_BLOCK + 123
    write_recording(tmp_path / 'rec', _long(n))
    total = 2 * n + len(range(0, n, 3)) + len(range(0, n, 7))
    assert sum(encoded) == total and sum(a for a, _ in added) == total
    assert max(encoded) <= writer.WRITE_BLOCK
    assert all(a == b <= writer.WRITE_BLOCK for a, b in added)
    assert len(added) >= total // writer.WRITE_BLOCK
    rec = read_recording(tmp_path / 'rec')
    assert len(rec.joint_states) == n and len(rec.link_torque) == n


def test_large_messages_make_smaller_blocks(tmp_path, monkeypatch):
    """A block also stays within BLOCK_BYTES of message records (JointStates of many joints)."""
    monkeypatch.setattr(writer, 'BLOCK_BYTES', 1 << 20)
    added = []
    add = McapStream.add_messages

    def counting_add(self, groups, which):
        added.append(sum(g[3].nbytes for g in groups))
        return add(self, groups, which)

    monkeypatch.setattr(McapStream, 'add_messages', counting_add)
    n, k = 600, 1000
    t = np.arange(n) * 1e-3
    x = np.ones((n, k))
    write_recording(tmp_path / 'rec', {'/joint_states': {
        't': t, 'q': x, 'qd': x, 'effort': x, 'name': [f'j{i}' for i in range(k)]}})
    assert len(added) > 1 and max(added) <= 1 << 20


def test_a_failure_half_way_leaves_nothing(tmp_path, monkeypatch):
    calls = []
    add = McapStream.add_messages

    def failing_add(self, groups, which):
        calls.append(len(which))
        if len(calls) % 2 == 0:                   # the second block of each recording
            raise OSError('disk full')
        return add(self, groups, which)

    monkeypatch.setattr(McapStream, 'add_messages', failing_add)
    monkeypatch.setattr(writer, 'WRITE_BLOCK', 1000)
    with pytest.raises(OSError, match='disk full'):
        write_recording(tmp_path / 'rec', _long(3000))
    with pytest.raises(OSError, match='disk full'):
        write_recording(tmp_path / 'rec.mcap', _long(3000))
    assert os.listdir(tmp_path) == []


@pytest.mark.skipif(not MCAP_CLI.exists(), reason='mcap CLI not available')
def test_mcap_doctor_is_clean(tmp_path, monkeypatch):
    monkeypatch.setattr(writer, 'WRITE_BLOCK', 3000)
    path = write_recording(tmp_path / 'rec.mcap', _long(20_000))
    res = subprocess.run([str(MCAP_CLI), 'doctor', '--strict-message-order', path],
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0 and not res.stdout.strip(), res.stdout + res.stderr
    assert 'chunks' in subprocess.run([str(MCAP_CLI), 'info', path], capture_output=True,
                                      text=True, timeout=120).stdout
