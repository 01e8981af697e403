# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Recovering a recording cut short (a recorder killed with SIGKILL, a full disk).

:func:`recover_recording` (``friction_joint recover PATH OUT``) reads a
truncated MCAP file (no summary, no footer; see
:mod:`~friction_joint.bag.staging` for where a killed recorder leaves it)
record by record up to where it ends, also into a chunk cut in the middle if it
is uncompressed, and writes the messages into a new, sealed recording
(``metadata.yaml`` + ``.mcap``).  A chunk that cannot be read is skipped
with a warning (its messages lost, the rest kept), and none is ever
decompressed into more than the size it declares.
"""
from __future__ import annotations

import dataclasses
import errno
import glob
import json
import mmap
import os
import shutil
import struct
import warnings
import zlib

from .checksums import seal_rosbag2
from .staging import (missing_recording_error, read_marker, recovery_command, staging_directory,
                      staging_state)
from ..exceptions import RecordingError
from ..inputs import check_input, MEMORY_BUDGET

__all__ = ['recover_recording', 'RecoveredRecording', 'salvage_recording']

_MAGIC = b'\x89MCAP0\r\n'
_OP_FOOTER, _OP_SCHEMA, _OP_CHANNEL, _OP_MESSAGE, _OP_CHUNK = 2, 3, 4, 5, 6
_OP_DATA_END, _OP_LAST = 0x0F, 0x10
_U16, _U32, _U64, _REC = (struct.Struct(f) for f in ('<H', '<I', '<Q', '<BQ'))
_MESSAGE_HEAD = struct.Struct('<HIQQ')
_CHUNK_HEAD = struct.Struct('<QQQI')


# ------------------------------------------------------------------ scanning ---

@dataclasses.dataclass
class _Scan:
    """What a pass over a (possibly truncated) MCAP file found."""

    size: int
    schemas: dict = dataclasses.field(default_factory=dict)
    channels: dict = dataclasses.field(default_factory=dict)
    end: int = 0                 # bytes up to the end of the last record read whole
    complete: bool = False       # reached the data end / footer
    reason: str = ''
    orphans: int = 0             # messages on channels never defined
    bad: list = dataclasses.field(default_factory=list)     # chunks skipped, and why


def _string(buf, pos):
    n, = _U32.unpack_from(buf, pos)
    return bytes(buf[pos + 4:pos + 4 + n]).decode('utf8'), pos + 4 + n


def _inner(buf, pos, end, scan, emit, top):
    """
    Handle the records in ``buf[pos:end]``; return where reading stopped and why ('' = end).

    ``top``: the file's data section (else a chunk's records).
    """
    while pos < end:
        if pos + _REC.size > end:
            return pos, 'cut in a record header'
        op, length = _REC.unpack_from(buf, pos)
        body, nxt = pos + _REC.size, pos + _REC.size + length
        if not 0 < op <= _OP_LAST:
            return pos, f'no MCAP record at byte {pos} (opcode {op:#x})'
        if nxt > end:
            if top and op == _OP_CHUNK:
                _partial_chunk(buf, body, end, scan, emit)
            return pos, f'cut in a {"chunk" if op == _OP_CHUNK else "record"}'
        try:
            if op == _OP_SCHEMA:
                sid, = _U16.unpack_from(buf, body)
                name, p = _string(buf, body + 2)
                encoding, p = _string(buf, p)
                n, = _U32.unpack_from(buf, p)
                scan.schemas[sid] = (name, encoding, bytes(buf[p + 4:p + 4 + n]))
            elif op == _OP_CHANNEL:
                cid, sid = struct.unpack_from('<HH', buf, body)
                topic, p = _string(buf, body + 4)
                encoding, p = _string(buf, p)
                scan.channels.setdefault(cid, (topic, sid, encoding))
            elif op == _OP_MESSAGE:
                cid, _, log_time, _ = _MESSAGE_HEAD.unpack_from(buf, body)
                if cid in scan.channels:
                    emit(cid, log_time, bytes(buf[body + _MESSAGE_HEAD.size:nxt]))
                else:
                    scan.orphans += 1
            elif op == _OP_CHUNK and top:
                data = _chunk(buf, body, nxt, scan)
                if data is not None:
                    _, why = _inner(memoryview(data), 0, len(data), scan, emit, False)
                    if why:                  # its messages before the break are kept
                        scan.bad.append(f'the chunk at byte {pos}: {why}')
            elif op in (_OP_DATA_END, _OP_FOOTER) and top:
                scan.complete = True
                return nxt, ''
        except (struct.error, UnicodeDecodeError, ValueError) as exc:
            return pos, f'malformed record at byte {pos} ({exc})'
        pos = nxt
        if top:
            scan.end = pos
    return pos, ''


def _codec(compression):
    """Return ``(make a streaming decompressor, its errors)`` of an MCAP chunk compression."""
    if compression == 'zstd':
        try:
            from compression import zstd
        except ImportError:
            from backports import zstd
        return zstd.ZstdDecompressor, (zstd.ZstdError, EOFError, ValueError)
    if compression == 'lz4':
        import lz4.frame
        return lz4.frame.LZ4FrameDecompressor, (RuntimeError, EOFError, ValueError)
    raise _BadChunk(f'unknown compression {compression!r}')


class _BadChunk(Exception):
    """A chunk that cannot be read (its reason); the records after it still can."""


def _decompress(compression, data, size):
    """
    Return the records of a chunk: ``data`` decompressed, never more than ``size`` + 1 bytes.

    Frames are decompressed one after the other with streaming decompressors asked for
    at most one byte more than the chunk declares, so a chunk declaring 1 KiB that
    inflates to gigabytes costs 1 KiB; a declared size beyond the memory budget is
    refused before decompressing.  Raises :class:`_BadChunk` naming the reason.
    """
    if compression == '':
        return bytes(data)
    make, errors = _codec(compression)
    if size > MEMORY_BUDGET:
        raise _BadChunk(f'declares {size} bytes uncompressed, beyond the memory budget '
                        f'({MEMORY_BUDGET >> 20} MiB)')
    parts, n, rest = [], 0, data
    try:
        while True:
            d = make()
            parts.append(d.decompress(rest, max_length=size - n + 1))
            n += len(parts[-1])
            if n > size:
                raise _BadChunk(f'its {compression} data inflate beyond the {size} bytes it '
                                'declares')
            if not d.eof:
                raise _BadChunk(f'its {compression} data end early')
            rest = d.unused_data
            if not rest:
                return b''.join(parts)
    except errors as exc:
        raise _BadChunk(f'not {compression} data ({exc})') from None


def _chunk(buf, body, end, scan):
    """
    Return the records of one whole chunk, or None if it is unreadable (noted in ``scan``).

    An unreadable chunk (not decompressible, inflating beyond its declared size, failing
    its CRC) loses its own messages only: its record's length says where the next begins.
    """
    where = f'the chunk at byte {body - _REC.size}'
    _, _, size, crc = _CHUNK_HEAD.unpack_from(buf, body)
    compression, p = _string(buf, body + _CHUNK_HEAD.size)
    n, = _U64.unpack_from(buf, p)
    try:
        data = _decompress(compression, buf[p + 8:min(p + 8 + n, end)], size)
    except _BadChunk as exc:
        scan.bad.append(f'{where}: {exc}')
        return None
    if len(data) != size or (crc and zlib.crc32(data) != crc):
        scan.bad.append(f'{where} fails its checksum')
        return None
    return data


def _partial_chunk(buf, body, end, scan, emit):
    """Take the complete messages of an uncompressed chunk cut short."""
    try:
        compression, p = _string(buf, body + _CHUNK_HEAD.size)
    except (struct.error, UnicodeDecodeError):
        return
    if compression == '' and p + 8 <= end:
        _inner(buf, p + 8, end, scan, emit, False)


def _scan(path, scan, emit):
    """Read ``path`` into ``scan`` up to where it ends or breaks; ``emit(channel, time, data)``."""
    if scan.size < len(_MAGIC):
        scan.reason = 'empty' if scan.size == 0 else 'shorter than the MCAP magic'
        return scan
    with open(path, 'rb') as fh, mmap.mmap(fh.fileno(), 0, access=mmap.ACCESS_READ) as m:
        if m[:len(_MAGIC)] != _MAGIC:
            raise RecordingError(f'{path} is not an MCAP file (no MCAP magic)')
        buf = memoryview(m)
        try:
            scan.end = len(_MAGIC)
            _, scan.reason = _inner(buf, len(_MAGIC), scan.size, scan, emit, True)
        finally:
            buf.release()
    if not scan.complete and not scan.reason:
        scan.reason = f'ends after byte {scan.end}, between two records'
    return scan


# ---------------------------------------------------------------- recovering ---

@dataclasses.dataclass
class RecoveredRecording:
    """
    What :func:`recover_recording` wrote.

    Attributes
    ----------
    out : str
        The recording written.
    source : str
        The MCAP file read.
    counts : dict
        Topic -> messages recovered.
    span : tuple of float
        First and last log time (s) recovered.
    complete : bool
        The source was not cut short (it had its data end).
    reason : str
        Where and why reading stopped ('' when complete).
    lost_bytes : int
        Bytes after the last record read whole.
    removed : str or None
        The staging directory removed after recovering it.
    staging : str or None
        The staging directory read and kept (``keep``; perhaps renamed).
    unreadable : list of str
        The chunks skipped (where, and why: not decompressible, inflating beyond
        their declared size, failing their CRC); their messages are lost.

    """

    out: str
    source: str
    counts: dict[str, int]
    span: tuple[float, float]
    complete: bool
    reason: str
    lost_bytes: int
    removed: str | None = None
    staging: str | None = None
    unreadable: list[str] = dataclasses.field(default_factory=list)


def _source_file(path):
    """Return the one ``.mcap`` file of ``path`` (file, bag or staging directory)."""
    if not os.path.lexists(path):
        raise RecordingError(f'{path} does not exist')
    if not os.path.isdir(path):                   # a FIFO or device: refused, never opened
        check_input(path, kind='recording', what='a recording', error=RecordingError)
        return path
    files = []
    for pattern in ('*.mcap', os.path.join('*', '*.mcap')):
        files = [f for f in sorted(glob.glob(os.path.join(glob.escape(path), pattern)))
                 if not os.path.basename(f).startswith('.')]
        if files:
            break
    if not files:
        raise RecordingError(f'{path}: no .mcap file to recover (the recorder was killed before '
                             'it opened one)')
    if len(files) > 1:
        raise RecordingError(f'{path}: several .mcap files ({", ".join(files)}); recover '
                             'them one by one')
    check_input(files[0], kind='recording', what='a recording', error=RecordingError)
    return files[0]


class _Sink:
    """Writes scanned messages into a rosbags writer."""

    def __init__(self, writer, scan, label):
        from rosbags.typesys import Stores, get_typestore
        self.writer, self.scan, self.label = writer, scan, label
        self.typestore = get_typestore(Stores.ROS2_JAZZY)
        self.conns, self.by_topic = {}, {}
        self.counts = {}
        self.first, self.last = None, None

    def connection(self, cid):
        conn = self.conns.get(cid)
        if conn is None:
            topic, sid, encoding = self.scan.channels[cid]
            msgtype, _, msgdef = self.scan.schemas.get(sid, ('', '', b''))
            conn = self.by_topic.get((topic, msgtype))
            if conn is None:
                conn = self._add(topic, msgtype, msgdef.decode('utf8', 'replace'), encoding)
                self.by_topic[(topic, msgtype)] = conn
                self.counts.setdefault(topic, 0)
            self.conns[cid] = conn
        return conn

    def _add(self, topic, msgtype, msgdef, encoding):
        ts = self.typestore
        if msgtype not in ts.types:
            try:
                from rosbags.typesys import get_types_from_msg
                ts.register(get_types_from_msg(msgdef, msgtype))
            except Exception as exc:           # rosbags raises various types
                raise RecordingError(f'{self.label}: {topic}: cannot use message type '
                                     f'{msgtype!r} from the file ({exc})') from None
        return self.writer.add_connection(topic, msgtype, typestore=ts,
                                          serialization_format=encoding or 'cdr')

    def __call__(self, cid, log_time, data):
        conn = self.connection(cid)
        self.writer.write(conn, log_time, data)
        self.counts[conn.topic] += 1
        self.first = log_time if self.first is None else min(self.first, log_time)
        self.last = log_time if self.last is None else max(self.last, log_time)


def _unreadable(bad):
    """Return one line about the chunks skipped: how many, the first (and where)."""
    more = f' and {len(bad) - 1} more' if len(bad) > 1 else ''
    several = len(bad) > 1
    return (f'{len(bad)} chunk{"s" if several else ""} unreadable, '
            f'{"their" if several else "its"} messages lost ({bad[0]}{more})')


def _write_bag(src, bagdir, label, qos):
    """Scan ``src`` into a new rosbag2 directory ``bagdir``; return (scan, sink)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    writer = Writer(bagdir, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    try:
        scan = _Scan(os.path.getsize(src))
        sink = _Sink(writer, scan, label)
        _scan(src, scan, sink)
        for cid in sorted(scan.channels):           # topics without a message too
            sink.connection(cid)
        if not any(sink.counts.values()):
            why = '; '.join(([_unreadable(scan.bad)] if scan.bad else []) +
                            ([scan.reason] if scan.reason else [])) or 'no messages'
            raise RecordingError(f'{label}: no complete message in {src} ({why}); nothing '
                                 'to recover')
        writer.set_custom_data('friction_joint.recovered', json.dumps(
            {'source': os.path.abspath(src), 'source_bytes': scan.size,
             'bytes_read': scan.end, 'complete': scan.complete, 'stopped': scan.reason,
             'unreadable_chunks': scan.bad, 'messages': sink.counts}, sort_keys=True))
    except BaseException:
        writer.abort()
        raise
    writer.close()
    seal_rosbag2(bagdir, offered_qos={t: q for t, q in qos.items() if t in sink.counts})
    return scan, sink


_QOS_KEYS = {'history', 'depth', 'reliability', 'durability', 'deadline', 'lifespan',
             'liveliness', 'liveliness_lease_duration', 'avoid_ros_namespace_conventions'}


def _marker_qos(staging):
    """Offered QoS profiles kept in a staging marker (complete rosbag2 v9 entries only)."""
    qos = (read_marker(staging) or {}).get('offered_qos') if staging else None
    if not isinstance(qos, dict):
        return {}
    return {t: [q for q in p if isinstance(q, dict) and set(q) == _QOS_KEYS]
            for t, p in qos.items() if isinstance(p, list)}


def recover_recording(path: str | os.PathLike, out: str | os.PathLike, *, force: bool = False,
                      keep: bool = False) -> RecoveredRecording:
    """
    Turn a truncated MCAP file (or a killed recorder's staging directory) into a recording.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.mcap`` file, a rosbag2 directory whose ``.mcap`` is cut short, or a
        recorder's staging directory (``.OUT.rec-XXXXXXXX.tmp``, or an older
        recorder's ``.OUT.XXXXXXXX.tmp``).
    out : str or os.PathLike
        The recording to write: a rosbag2 directory, or a bare ``.mcap`` file if the
        name ends in ``.mcap``.  Never overwritten without ``force``.
    force : bool
        Replace an existing ``out``.
    keep : bool
        Keep a recovered staging directory (by default it is removed once ``out``
        is complete: its messages are all in ``out``).

    Returns
    -------
    RecoveredRecording

    Raises
    ------
    RecordingError
        ``path`` is missing, not MCAP, holds no complete message, its recorder is still
        running, or ``out`` exists (without ``force``) or cannot be written; nothing
        is left at ``out`` then.

    Notes
    -----
    Every record is read in file order until the file ends or a record is broken;
    the messages of complete chunks (with CRC, checked), and the complete messages
    of an uncompressed chunk cut short, are kept.  A whole chunk that cannot be
    read (garbage where zstd or lz4 data should be, data inflating beyond the
    size the chunk declares, a failed CRC) is skipped with a warning naming it:
    only its messages are lost.  A chunk is never decompressed into more than
    the size it declares (streaming decompression with a bound; a declared size
    beyond :data:`~friction_joint.inputs.MEMORY_BUDGET` is refused).  The result is sealed as
    :func:`~friction_joint.bag.checksums.seal_rosbag2` seals a recording (log-time
    order, zstd chunks with CRCs), with the offered QoS from the staging marker
    when there is one, and ``custom_data`` ``friction_joint.recovered`` (source,
    bytes read, counts, unreadable chunks).

    """
    from ..output import OutputSet, recording_inputs

    path, out = os.fspath(path), os.fspath(out)
    if not os.path.lexists(path):
        raise missing_recording_error(path)      # OUT of a killed recorder: its staging dir
    staging = staging_directory(path)
    if staging and staging_state(staging) == 'running':
        raise RecordingError(f'{path}: its recorder is still running (pid '
                             f'{(read_marker(staging) or {}).get("pid", "?")}); stop it first')
    src = _source_file(path)
    qos = _marker_qos(staging)
    inputs = recording_inputs([path], label='PATH') + [('its staging directory', staging)]
    with OutputSet(force=force, inputs=inputs, error=RecordingError) as outputs:
        if out.endswith('.mcap'):
            outputs.add_file(out, label='OUT')
        else:
            outputs.add_directory(out, label='OUT')
        outputs.check()
        target = outputs.staging_path(out)
        bagdir = target[:-5] if target.endswith('.mcap') else target
        try:
            found, sink = _write_bag(src, bagdir, path, qos)
            if target.endswith('.mcap'):
                made = [f for f in os.listdir(bagdir) if f.endswith('.mcap')]
                os.rename(os.path.join(bagdir, made[0]), target)
        except OSError as exc:
            raise RecordingError(f'cannot write {out}: {exc.strerror or exc}') from None
        outputs.publish()
    removed = None
    if staging and os.path.abspath(path) == staging and not keep:
        shutil.rmtree(staging, ignore_errors=True)
        removed = staging
    if found.bad:
        warnings.warn(f'{path}: {_unreadable(found.bad)}', RuntimeWarning, stacklevel=2)
    ns = 1e-9
    return RecoveredRecording(out=out, source=src, counts=dict(sink.counts),
                              span=(sink.first * ns, sink.last * ns), complete=found.complete,
                              reason=found.reason, lost_bytes=found.size - found.end,
                              removed=removed, staging=None if removed else staging,
                              unreadable=list(found.bad))


#: free space needed to seal a stopped recording where it is: the copy and its sealed rewrite
_SALVAGE_ROOM = 2.5


def salvage_recording(staging: str | os.PathLike, out: str | os.PathLike,
                      exc: OSError) -> str:
    """
    Seal what a recorder stopped by a write error wrote, if it fits; return the message.

    The recorder stops at the first failed write (a full disk, a quota, a read-only
    remount).  Its staging directory then holds an MCAP file cut short: everything up
    to the last flush, and whatever of the chunk being written reached the disk.  If
    the file system has room for the recording twice over, it is recovered into
    ``out`` at once (:func:`recover_recording`, sealed) and the staging directory
    removed; otherwise (or if that fails) it is left for ``friction_joint recover``.

    Parameters
    ----------
    staging : str or os.PathLike
        The recorder's staging directory.
    out : str or os.PathLike
        Where the recording was to go.
    exc : OSError
        The write error that stopped the recorder.

    Returns
    -------
    str
        One line: the error, and where the messages are (``out``, or the staging
        directory with the command that recovers it).

    """
    staging, out = os.fspath(staging), os.fspath(out)
    what = exc.strerror or str(exc)
    if exc.filename:
        what += f' ({os.fsdecode(exc.filename)})'
    text = f'cannot write {out}: {what}; stopped'
    try:
        size = sum(os.path.getsize(f) for f in glob.glob(os.path.join(
            glob.escape(staging), '*', '*.mcap')))
        vfs = os.statvfs(staging)
        room = vfs.f_bavail * vfs.f_frsize > _SALVAGE_ROOM * size + (1 << 20)
    except OSError:
        room = False
    if room:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter('ignore')
                res = recover_recording(staging, out)
            n = sum(res.counts.values())
            return (f'{text}; the {n} messages written before it are in {out} (sealed; '
                    'what arrived after the last flush did not fit)')
        except (OSError, RecordingError):
            pass
    then = 'make room, then ' if exc.errno in (errno.ENOSPC, errno.EDQUOT) else ''
    return (f'{text}; what was recorded is kept in {staging}: {then}recover it with: '
            f'{recovery_command(staging)}')
