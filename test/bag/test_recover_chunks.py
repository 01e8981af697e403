# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``recover`` on hostile chunks: garbage where zstd or lz4 data should be, decompression bombs.

The files are built by hand, record by record (MCAP: magic, header, schema,
channel, chunks, data end, footer), so each chunk is exactly what the test
says.  A garbage chunk gave a ``ZstdError`` traceback; a zstd chunk declaring
1 KiB that inflates to gigabytes was decompressed whole (3.4 GB, then
``MemoryError``).  Now an unreadable chunk is named in one warning and skipped,
the others recovered; decompression stops one byte past the declared size.
"""
import os
import struct
import subprocess
import sys
import tracemalloc
import warnings
import zlib

from friction_joint.bag import read_recording
from friction_joint.bag.recover import recover_recording
from friction_joint.exceptions import RecordingError
import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
JS = 'sensor_msgs/msg/JointState'
MAGIC = b'\x89MCAP0\r\n'


def _zstd():
    try:
        from compression import zstd
    except ImportError:
        zstd = pytest.importorskip('backports.zstd')
    return zstd


def _record(op, body):
    return struct.pack('<BQ', op, len(body)) + body


def _str(text):
    data = text.encode()
    return struct.pack('<I', len(data)) + data


def _messages(first, n):
    """Return ``n`` JointState message records (position = index / 1000), from ``first``."""
    from rosbags.typesys import Stores, get_typestore
    ts = get_typestore(Stores.ROS2_JAZZY)
    T = ts.types
    out = b''
    for i in range(first, first + n):
        stamp = T['builtin_interfaces/msg/Time'](sec=100 + i // 1000, nanosec=i % 1000 * 10**6)
        msg = T[JS](header=T['std_msgs/msg/Header'](stamp=stamp, frame_id=''), name=['joint'],
                    position=np.array([i * 1e-3]), velocity=np.array([1.0]),
                    effort=np.array([0.5]))
        data = bytes(ts.serialize_cdr(msg, JS))
        t = 100 * 10**9 + i * 10**6
        out += _record(0x05, struct.pack('<HIQQ', 1, i, t, t) + data)
    return out


def _chunk(records, compression='', data=None, size=None, crc=None):
    """Return a chunk record of ``records``; ``data``, ``size``, ``crc`` override the stored."""
    if data is None:
        if compression == 'zstd':
            data = _zstd().compress(records)
        elif compression == 'lz4':
            data = pytest.importorskip('lz4.frame').compress(records)
        else:
            data = records
    size = len(records) if size is None else size
    crc = zlib.crc32(records) if crc is None else crc
    return _record(0x06, struct.pack('<QQQI', 0, 0, size, crc) + _str(compression)
                   + struct.pack('<Q', len(data)) + data)


def _mcap(path, chunks, complete=True):
    """Write an MCAP file: header, JointState schema and channel 1, ``chunks``, end."""
    from rosbags.typesys import Stores, get_typestore
    msgdef, _ = get_typestore(Stores.ROS2_JAZZY).generate_msgdef(JS, ros_version=2)
    data = (MAGIC + _record(0x01, _str('ros2') + _str('test'))
            + _record(0x03, struct.pack('<H', 1) + _str(JS) + _str('ros2msg')
                      + struct.pack('<I', len(msgdef)) + msgdef.encode())
            + _record(0x04, struct.pack('<HH', 1, 1) + _str('/joint_states') + _str('cdr')
                      + struct.pack('<I', 0)))
    data += b''.join(chunks)
    if complete:
        data += _record(0x0F, struct.pack('<I', 0)) + _record(0x02, bytes(20)) + MAGIC
    path.write_bytes(data)
    return path


def _zstd_bomb(size):
    """Return a zstd frame of ``size`` zero bytes in RLE blocks (4 bytes per 128 KiB)."""
    block = 1 << 17
    out = bytearray(b'\x28\xb5\x2f\xfd' + b'\x00' + b'\x38')  # no content size, 128 KiB window
    left = size
    while left:
        n = min(block, left)
        left -= n
        out += ((n << 3) | (1 << 1) | (left == 0)).to_bytes(3, 'little') + b'\x00'
    return bytes(out)


def _positions(out):
    return np.round(read_recording(out).joint_states.q * 1000).astype(int).tolist()


@pytest.mark.parametrize('compression', ['zstd', 'lz4'])
def test_garbage_chunk_is_skipped_the_rest_recovered(tmp_path, compression):
    """Garbage where the chunk's compressed data should be: that chunk lost, one warning."""
    garbage = bytes(range(256)) * 4
    src = _mcap(tmp_path / 'in.mcap', [
        _chunk(_messages(0, 100), compression),
        _chunk(_messages(100, 100), compression, data=garbage),
        _chunk(_messages(200, 100), compression)])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        res = recover_recording(src, tmp_path / 'out')
    assert res.counts == {'/joint_states': 200}
    assert _positions(tmp_path / 'out') == list(range(100)) + list(range(200, 300))
    assert len(res.unreadable) == 1 and f'not {compression} data' in res.unreadable[0]
    texts = [str(w.message) for w in caught]
    assert len(texts) == 1 and '1 chunk unreadable' in texts[0] and 'in.mcap' in texts[0], texts
    assert '\n' not in texts[0]


@pytest.mark.parametrize('compression', ['zstd', 'lz4'])
def test_a_bomb_is_never_inflated_past_its_declared_size(tmp_path, compression):
    """A chunk declaring 1 KiB that inflates to 256 MiB: skipped, memory stays small."""
    big = 256 << 20
    if compression == 'zstd':
        bomb = _zstd_bomb(big)
    else:
        bomb = pytest.importorskip('lz4.frame').compress(bytes(big))
    src = _mcap(tmp_path / 'in.mcap', [
        _chunk(_messages(0, 50), compression),
        _chunk(b'', compression, data=bomb, size=1024, crc=0),
        _chunk(_messages(50, 50), compression)])
    del bomb
    tracemalloc.start()
    try:
        with warnings.catch_warnings(record=True):
            warnings.simplefilter('always')
            res = recover_recording(src, tmp_path / 'out')
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 32 << 20, f'{peak >> 20} MiB'
    assert res.counts == {'/joint_states': 100}
    assert len(res.unreadable) == 1 and 'inflate beyond the 1024 bytes' in res.unreadable[0]


def test_a_declared_size_beyond_the_budget_is_refused_unread(tmp_path):
    """A chunk declaring 2^62 bytes is not decompressed at all."""
    src = _mcap(tmp_path / 'in.mcap', [
        _chunk(_messages(0, 10), 'zstd', size=1 << 62, crc=0),
        _chunk(_messages(10, 10), 'zstd')])
    with pytest.warns(RuntimeWarning, match='memory budget'):
        res = recover_recording(src, tmp_path / 'out')
    assert _positions(tmp_path / 'out') == list(range(10, 20))
    assert res.counts == {'/joint_states': 10}


def test_a_chunk_failing_its_crc_is_skipped_not_the_end(tmp_path):
    """A chunk with a wrong CRC stopped the reading; the chunks after it are fine."""
    src = _mcap(tmp_path / 'in.mcap', [
        _chunk(_messages(0, 10), 'zstd', crc=12345),
        _chunk(_messages(10, 10), 'lz4'),
        _chunk(_messages(20, 10))], complete=False)
    with pytest.warns(RuntimeWarning, match='fails its checksum'):
        res = recover_recording(src, tmp_path / 'out')
    assert _positions(tmp_path / 'out') == list(range(10, 30))
    assert not res.complete


def test_nothing_readable_is_one_line_exit_2(tmp_path):
    """Every chunk garbage: one line naming the file and why, exit 2, nothing written."""
    src = _mcap(tmp_path / 'in.mcap', [
        _chunk(_messages(0, 10), 'zstd', data=b'\x00' * 64),
        _chunk(_messages(10, 10), 'lz4', data=b'\xff' * 64)])
    with pytest.raises(RecordingError, match='2 chunks unreadable') as err:
        recover_recording(src, tmp_path / 'out')
    assert '\n' not in str(err.value)
    proc = subprocess.run([sys.executable, '-m', 'friction_joint', 'recover', str(src),
                           str(tmp_path / 'out')], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ, PYTHONPATH=ROOT))
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1, proc.stderr
    assert 'in.mcap' in lines[0] and 'nothing to recover' in lines[0], lines[0]
    assert sorted(os.listdir(tmp_path)) == ['in.mcap']


def test_cli_warns_in_one_line_and_recovers(tmp_path):
    """The command line: exit 0, one warning line on stderr, the counts on stdout."""
    src = _mcap(tmp_path / 'in.mcap', [
        _chunk(_messages(0, 10), 'zstd'),
        _chunk(_messages(10, 10), 'zstd', data=os.urandom(300))])
    proc = subprocess.run([sys.executable, '-m', 'friction_joint', 'recover', str(src),
                           str(tmp_path / 'out')], capture_output=True, text=True,
                          timeout=300, env=dict(os.environ, PYTHONPATH=ROOT))
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 0, proc.stderr
    assert len(lines) == 1 and lines[0].startswith('friction_joint recover: warning: '), lines
    assert 'recovered 10 messages' in proc.stdout and 'nothing was lost' not in proc.stdout
