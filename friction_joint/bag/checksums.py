# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Checksummed MCAP files: sealing what rosbags wrote, verifying on read.

rosbags' MCAP writer stores every CRC as 0, so a flipped bit in a recording
goes unnoticed.  :func:`seal_recording` rewrites the ``.mcap`` file(s) of a
recording with the ``mcap`` library: the header profile, schemas, channels
(with their metadata), every message, the metadata records (rosbags'
``rosbag2`` record) and attachments are copied (channel and metadata entries
can be replaced on the way, see :func:`seal_recording`), messages in log-time order
across topics, into compressed chunks with chunk CRCs, a data-section CRC and
a summary CRC.  ``metadata.yaml`` needs no change: the file keeps its name,
and rosbags' reader takes chunk compression from the chunks themselves.

:func:`verify_checksums` checks the data-section and summary CRCs of a file
(one pass of ``zlib.crc32`` over the file); chunk CRCs are checked by rosbags
as it decompresses each chunk.  A CRC of 0 means "not recorded" (files of
other tools) and is skipped.
"""
from __future__ import annotations

import os
from pathlib import Path
import struct
import zlib

from ..exceptions import RecordingError

__all__ = ['seal_recording', 'seal_rosbag2', 'verify_checksums', 'mcap_files', 'COMPRESSIONS']

#: chunk compression names -> mcap.writer.CompressionType member names
COMPRESSIONS = {'zstd': 'ZSTD', 'lz4': 'LZ4', 'none': 'NONE'}

_MAGIC = b'\x89MCAP0\r\n'
_FOOTER = struct.Struct('<BQQQI')          # opcode, length, summary start, offsets start, crc
_DATA_END = struct.Struct('<BQI')          # opcode, length, data section crc
_OP_FOOTER, _OP_DATA_END = 0x02, 0x0F
_BLOCK = 1 << 24


def mcap_files(path):
    """Return the ``.mcap`` files of a recording (the file itself, or those in the directory)."""
    p = Path(path)
    if p.is_dir():
        return sorted(x for x in p.iterdir() if x.suffix == '.mcap' and x.is_file())
    return [p] if p.suffix == '.mcap' and p.is_file() else []


def _crc_of(fh, start, stop):
    crc = 0
    fh.seek(start)
    left = stop - start
    while left > 0:
        block = fh.read(min(_BLOCK, left))
        if not block:
            return None                           # shorter than its own footer says
        crc = zlib.crc32(block, crc)
        left -= len(block)
    return crc


def verify_checksums(path: str | os.PathLike, *, label: str | None = None) -> None:
    """
    Check the data-section and summary CRCs of one MCAP file.

    Parameters
    ----------
    path : str or os.PathLike
        An ``.mcap`` file.
    label : str, optional
        How to name the recording in the error (default ``path``).

    Raises
    ------
    RecordingError
        A recorded CRC does not match the bytes: the file changed after it was written.
        Files whose footer cannot be found are left to the reader (truncated files).

    """
    path = os.fspath(path)
    label = path if label is None else label
    size = os.path.getsize(path)
    tail = _FOOTER.size + len(_MAGIC)
    if size < len(_MAGIC) + _DATA_END.size + tail:
        return
    with open(path, 'rb') as fh:
        if fh.read(len(_MAGIC)) != _MAGIC:
            return
        fh.seek(size - tail)
        raw = fh.read(tail)
        if raw[_FOOTER.size:] != _MAGIC:
            return
        op, length, summary_start, offsets_start, summary_crc = _FOOTER.unpack(raw[:_FOOTER.size])
        footer_at = size - tail
        if op != _OP_FOOTER or length != 20 or summary_start > footer_at:
            return
        data_end_at = (summary_start or footer_at) - _DATA_END.size
        if data_end_at < len(_MAGIC):
            return
        fh.seek(data_end_at)
        op, length, data_crc = _DATA_END.unpack(fh.read(_DATA_END.size))
        if op != _OP_DATA_END or length != 4:
            return
        name = os.path.basename(path)
        if summary_crc and summary_start:
            got = _crc_of(fh, summary_start, footer_at + _FOOTER.size - 4)
            if got != summary_crc:
                raise RecordingError(
                    f'{label}: truncated or corrupt recording: the summary section of {name} '
                    f'fails its checksum (CRC {summary_crc:08x}, computed {got or 0:08x}); '
                    'the file changed after it was written (a flipped bit, a partial copy)')
        if data_crc:
            got = _crc_of(fh, 0, data_end_at)
            if got != data_crc:
                raise RecordingError(
                    f'{label}: truncated or corrupt recording: the data of {name} fails its '
                    f'checksum (CRC {data_crc:08x}, computed {got or 0:08x}); the file '
                    'changed after it was written (a flipped bit, a partial copy)')


def _copy(reader, writer, channels, log_time_order):
    """Copy every message; return False (and stop) on the first one out of log-time order."""
    last = None
    for _, channel, message in reader.iter_messages(log_time_order=log_time_order):
        if not log_time_order and last is not None and message.log_time < last:
            return False
        last = message.log_time
        writer.add_message(channels[channel.id], message.log_time, message.data,
                           message.publish_time, message.sequence)
    return True


def _seal_file(src, compression, data_crc, overrides=(None, None)):
    from mcap.reader import make_reader
    from mcap.writer import CompressionType, Writer

    kind = getattr(CompressionType, COMPRESSIONS[compression])
    metadata, channel_metadata = (x or {} for x in overrides)
    tmp = src.with_name(f'.{src.name}.seal.tmp')
    try:
        with open(src, 'rb') as fin:
            reader = make_reader(fin)
            header, summary = reader.get_header(), reader.get_summary()
            if summary is None:
                raise RecordingError(f'{src}: MCAP file without a summary section, cannot '
                                     'seal it')
            for log_time_order in (False, True):   # file order if that is log-time order
                with open(tmp, 'wb') as fout:
                    writer = Writer(fout, compression=kind, enable_crcs=True,
                                    enable_data_crcs=data_crc)
                    writer.start(profile=header.profile, library=header.library)
                    schemas = {sid: writer.register_schema(s.name, s.encoding, s.data)
                               for sid, s in sorted(summary.schemas.items())}
                    channels = {cid: writer.register_channel(c.topic, c.message_encoding,
                                                             schemas.get(c.schema_id, 0),
                                                             {**c.metadata, **channel_metadata.get(
                                                                 c.topic, {})})
                                for cid, c in sorted(summary.channels.items())}
                    if not _copy(reader, writer, channels, log_time_order):
                        continue
                    writer.flush()
                    for att in reader.iter_attachments():
                        writer.add_attachment(att.create_time, att.log_time, att.name,
                                              att.media_type, att.data)
                    seen = set()
                    for meta in reader.iter_metadata():
                        seen.add(meta.name)
                        writer.add_metadata(meta.name, {**meta.metadata,
                                                        **metadata.get(meta.name, {})})
                    for name in sorted(set(metadata) - seen):
                        writer.add_metadata(name, dict(metadata[name]))
                    writer.finish()
                    break
        os.replace(tmp, src)
    finally:
        if os.path.lexists(tmp):
            os.remove(tmp)


def seal_recording(path: str | os.PathLike, *, compression: str = 'zstd', data_crc: bool = True,
                   metadata: dict[str, dict[str, str]] | None = None,
                   channel_metadata: dict[str, dict[str, str]] | None = None) -> list[str]:
    """
    Rewrite a recording's MCAP file(s) with CRCs, compressed chunks and messages in time order.

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 directory or a single ``.mcap`` file, as rosbags wrote it.
    compression : {'zstd', 'lz4', 'none'}
        Chunk compression.
    data_crc : bool
        Also record the data-section CRC (chunk and summary CRCs are always recorded).
    metadata : dict, optional
        Metadata record name -> ``{key: value}`` entries to set in that record (added
        if the file has no record of that name), e.g. ``{'rosbag2': {'ROS_DISTRO':
        'jazzy', 'serialized_metadata': ...}}``.
    channel_metadata : dict, optional
        Topic -> ``{key: value}`` entries to set in the metadata of that topic's
        channel(s), e.g. ``{'/joint_states': {'offered_qos_profiles': ...}}``.

    Returns
    -------
    list of str
        The files rewritten.

    Raises
    ------
    RecordingError
        Unknown compression or a file without an MCAP summary section.
    OSError
        Writing failed; the original file is then unchanged.

    Notes
    -----
    Each file is rewritten into a temporary file beside it and renamed over it, so a
    failure leaves the original.  Messages already in log-time order are copied in one
    pass; otherwise a second pass copies them in log-time order (a heap over the chunks,
    so memory stays at a few chunks).

    """
    if compression not in COMPRESSIONS:
        raise RecordingError(f'unknown chunk compression {compression!r} '
                             f'(one of {", ".join(COMPRESSIONS)})')
    files = mcap_files(path)
    for f in files:
        _seal_file(f, compression, data_crc, (metadata, channel_metadata))
    return [os.fspath(f) for f in files]


def _dump_yaml(data):
    from io import StringIO

    from ruamel.yaml import YAML
    yaml = YAML(typ='safe')
    yaml.default_flow_style = False
    stream = StringIO()
    yaml.dump(data, stream)
    return stream.getvalue()


def seal_rosbag2(bagdir, *, ros_distro=None, offered_qos=None, compression='zstd'):
    """
    Set ``ros_distro`` and offered QoS profiles in a rosbag2 directory, then seal it.

    Parameters
    ----------
    bagdir : str or os.PathLike
        A rosbag2 directory (``metadata.yaml`` and uncompressed ``.mcap`` file(s)) as
        rosbags wrote it: rosbags writes ``ros_distro: rosbags``.
    ros_distro : str, optional
        Distribution to write (default: the environment's ``ROS_DISTRO``, else
        ``'jazzy'``).
    offered_qos : dict, optional
        Topic -> list of QoS profiles in rosbag2's version 9 form (dicts with
        ``history``, ``depth``, ``reliability``, ``durability``, ``deadline``,
        ``lifespan``, ``liveliness``, ``liveliness_lease_duration``,
        ``avoid_ros_namespace_conventions``); topics not named keep theirs.
    compression : {'zstd', 'lz4', 'none'}
        Chunk compression of :func:`seal_recording`.

    Returns
    -------
    list of str
        The ``.mcap`` files rewritten.

    Notes
    -----
    ``metadata.yaml`` is replaced atomically first; the ``.mcap`` file(s) then get
    the same metadata in their ``rosbag2`` record (``serialized_metadata`` and
    ``ROS_DISTRO``, as rosbag2 writes them) and the profiles in each channel's
    ``offered_qos_profiles``, while :func:`seal_recording` rewrites them.

    """
    from ruamel.yaml import YAML

    distro = ros_distro or os.environ.get('ROS_DISTRO') or 'jazzy'
    offered_qos = offered_qos or {}
    meta_path = Path(bagdir) / 'metadata.yaml'
    meta = YAML(typ='safe').load(meta_path.read_text('utf8'))
    info = meta['rosbag2_bagfile_information']
    info['ros_distro'] = distro
    for entry in info.get('topics_with_message_count') or []:
        topic = entry['topic_metadata']
        if topic['name'] in offered_qos:
            topic['offered_qos_profiles'] = list(offered_qos[topic['name']])
    tmp = meta_path.with_name('.metadata.yaml.tmp')
    tmp.write_text(_dump_yaml(meta), 'utf8')
    os.replace(tmp, meta_path)
    channels = {t: {'offered_qos_profiles': _dump_yaml(list(p)).strip()}
                for t, p in offered_qos.items()}
    record = {'serialized_metadata': _dump_yaml(info).strip(), 'ROS_DISTRO': distro}
    return seal_recording(bagdir, compression=compression, metadata={'rosbag2': record},
                          channel_metadata=channels)
