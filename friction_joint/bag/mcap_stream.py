# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
An MCAP writer that takes messages in numpy blocks, in one pass.

:class:`McapStream` writes what ``mcap.writer.Writer`` (``compression=ZSTD``,
``enable_crcs=True``, ``enable_data_crcs=True``, default chunk size and indexes)
writes for the same calls, byte for byte: the header, schemas and channels
(also at the start of the first chunk), messages in zstd-compressed chunks with
their CRCs and message indexes, metadata records, the data-section CRC and the
summary (schemas, channels, statistics, chunk, attachment and metadata indexes,
summary offsets, summary CRC).  The records other than messages are written by
the ``mcap`` library's record classes; the message records of a block are built
with numpy (the library's writer costs a few microseconds per message in
Python), so its memory is that of the block and of one chunk, whatever the
length of the file.
"""
import struct
import zlib

import numpy as np

__all__ = ['McapStream', 'CHUNK_SIZE', 'MESSAGE_HEADER']

#: a chunk is closed after the message that takes it past this many bytes (mcap's default)
CHUNK_SIZE = 1024 * 1024
#: bytes of a message record before its data: opcode, length, channel, sequence, 2 times
MESSAGE_HEADER = 31

_MAGIC = b'\x89MCAP0\r\n'
_OP_MESSAGE, _OP_MESSAGE_INDEX = 0x05, 0x07


class _Chunk:
    """The chunk being filled: record bytes and, per message, channel, log time, offset."""

    def __init__(self, prefix=b''):
        self.parts = [prefix] if prefix else []
        self.count = len(prefix)
        self.channels, self.times, self.offsets = [], [], []
        self.messages = 0

    def add(self, data, channels, times, starts):
        self.channels.append(channels)
        self.times.append(times)
        self.offsets.append(starts + self.count)
        self.parts.append(data)
        self.count += len(data)
        self.messages += len(channels)


class McapStream:
    """
    Write one MCAP file to a binary stream, messages given in blocks.

    Parameters
    ----------
    stream : file object
        Opened for binary writing (positioned at 0; ``tell`` is used for offsets).
    chunk_size : int
        A chunk is closed after the message that takes its uncompressed size past
        this (as ``mcap.writer.Writer``).

    Notes
    -----
    Calls: :meth:`start`, :meth:`register_schema` / :meth:`register_channel`, then
    :meth:`add_messages` any number of times, :meth:`add_metadata`, :meth:`finish`.
    Metadata records are written after the last chunk (the chunk in progress is
    closed first).

    """

    def __init__(self, stream, chunk_size=CHUNK_SIZE):
        """Hold the stream; nothing is written before :meth:`start`."""
        from mcap.data_stream import RecordBuilder
        from mcap.records import Statistics

        self._stream = stream
        self._chunk_size = int(chunk_size)
        self._builder = RecordBuilder()
        self._prefix = RecordBuilder()              # schemas and channels of the first chunk
        self._chunk = None
        self._crc = 0
        self._schemas, self._channels = {}, {}
        self._chunk_indexes, self._metadata_indexes = [], []
        self._stats = Statistics(attachment_count=0, channel_count=0, channel_message_counts={},
                                 chunk_count=0, message_count=0, metadata_count=0,
                                 message_start_time=0, message_end_time=0, schema_count=0)

    def _flush(self):
        data = self._builder.end()
        self._crc = zlib.crc32(data, self._crc)
        self._stream.write(data)

    def start(self, profile, library):
        """Write the magic and the header record."""
        from mcap.records import Header

        self._stream.write(_MAGIC)
        self._crc = zlib.crc32(_MAGIC)
        Header(profile, library).write(self._builder)
        self._flush()

    def register_schema(self, name, encoding, data):
        """Add a schema; return its id (1, 2, ...)."""
        from mcap.records import Schema

        sid = len(self._schemas) + 1
        schema = Schema(id=sid, data=data, encoding=encoding, name=name)
        self._schemas[sid] = schema
        self._stats.schema_count += 1
        schema.write(self._prefix)
        return sid

    def register_channel(self, topic, message_encoding, schema_id, metadata):
        """Add a channel; return its id (1, 2, ...)."""
        from mcap.records import Channel

        cid = len(self._channels) + 1
        channel = Channel(id=cid, topic=topic, message_encoding=message_encoding,
                          schema_id=schema_id, metadata=dict(metadata))
        self._channels[cid] = channel
        self._stats.channel_count += 1
        channel.write(self._prefix)
        return cid

    def add_messages(self, groups, which):
        """
        Append a block of messages.

        Parameters
        ----------
        groups : list of tuple
            ``(channel_id, log_time, publish_time, data)`` per group: ``m`` log and
            publish times (ns) and an ``(m, size)`` uint8 array of message data (one size
            per group).
        which : numpy.ndarray
            The group of each message of the block in file order; a group's messages
            come in their own order.

        """
        which = np.asarray(which, dtype=np.intp)
        n = len(which)
        if n == 0:
            return
        widths = np.array([MESSAGE_HEADER + g[3].shape[1] for g in groups], dtype=np.int64)
        width = int(widths.max())
        rows = np.empty((n, width), dtype=np.uint8)
        channels = np.empty(n, dtype=np.int64)
        times = np.empty(n, dtype=np.uint64)
        for k, (cid, log_time, publish_time, data) in enumerate(groups):
            sel = which == k
            m, w = len(data), int(widths[k])
            rec = np.empty((m, w), dtype=np.uint8)
            rec[:, :15] = np.frombuffer(struct.pack('<BQHI', _OP_MESSAGE, w - 9, cid, 0),
                                        dtype=np.uint8)
            stamps = np.empty((m, 2), dtype='<u8')
            stamps[:, 0] = log_time
            stamps[:, 1] = publish_time
            rec[:, 15:MESSAGE_HEADER] = stamps.view(np.uint8)
            rec[:, MESSAGE_HEADER:] = data
            rows[sel, :w] = rec
            channels[sel] = cid
            times[sel] = log_time
        sizes = widths[which]
        if len(groups) == 1 or np.all(widths == width):
            buf = rows.reshape(-1)
        else:
            buf = rows[(np.arange(width) < widths[:, None])[which]]
        del rows
        ends = np.cumsum(sizes)
        self._count_messages(channels, times)
        pos, at = 0, 0
        while pos < n:
            if self._chunk is None:
                self._chunk = _Chunk(self._prefix.end())      # empty after the first chunk
            limit = self._chunk_size - self._chunk.count + at
            last = max(int(np.searchsorted(ends, limit, side='right')), pos)
            stop = min(last + 1, n)
            self._chunk.add(buf[at:ends[stop - 1]].tobytes(), channels[pos:stop], times[pos:stop],
                            ends[pos:stop] - sizes[pos:stop] - at)
            if last < n:
                self._close_chunk()
            pos, at = stop, int(ends[stop - 1])

    def _count_messages(self, channels, times):
        st = self._stats
        lo, hi = int(times.min()), int(times.max())
        st.message_start_time = lo if st.message_count == 0 else min(lo, st.message_start_time)
        st.message_end_time = max(hi, st.message_end_time)
        st.message_count += len(channels)
        ids, first, counts = np.unique(channels, return_index=True, return_counts=True)
        for j in np.argsort(first, kind='stable'):
            cid = int(ids[j])
            st.channel_message_counts[cid] = st.channel_message_counts.get(cid, 0) + int(counts[j])

    def _close_chunk(self):
        from mcap.records import Chunk, ChunkIndex
        import zstandard

        chunk, self._chunk = self._chunk, None
        if chunk is None or chunk.messages == 0:
            return
        self._stats.chunk_count += 1
        data = b''.join(chunk.parts)
        chunk.parts = None
        channels = np.concatenate(chunk.channels)
        times = np.concatenate(chunk.times)
        offsets = np.concatenate(chunk.offsets)
        compressed = zstandard.compress(data)
        record = Chunk(compression='zstd', data=compressed,
                       message_start_time=int(times.min()), message_end_time=int(times.max()),
                       uncompressed_crc=zlib.crc32(data), uncompressed_size=len(data))
        self._flush()
        start = self._stream.tell()
        record.write(self._builder)
        length = self._builder.count
        self._flush()
        index_start = self._stream.tell()
        ids, first = np.unique(channels, return_index=True)
        parts, index_offsets, at = [], {}, index_start
        for cid in ids[np.argsort(first, kind='stable')].tolist():
            sel = channels == cid
            entries = np.empty((int(sel.sum()), 2), dtype='<u8')
            entries[:, 0] = times[sel]
            entries[:, 1] = offsets[sel]
            body = entries.tobytes()
            part = struct.pack('<BQHI', _OP_MESSAGE_INDEX, 6 + len(body), cid, len(body)) + body
            index_offsets[cid] = at
            at += len(part)
            parts.append(part)
        index = b''.join(parts)
        self._crc = zlib.crc32(index, self._crc)
        self._stream.write(index)
        self._chunk_indexes.append(ChunkIndex(
            message_start_time=record.message_start_time,
            message_end_time=record.message_end_time, chunk_start_offset=start,
            chunk_length=length, message_index_offsets=index_offsets,
            message_index_length=len(index), compression='zstd',
            compressed_size=len(compressed), uncompressed_size=len(data)))

    def add_metadata(self, name, data):
        """Write a metadata record (after closing the chunk in progress)."""
        from mcap.records import Metadata, MetadataIndex

        self._close_chunk()
        self._flush()
        offset = self._stream.tell()
        self._stats.metadata_count += 1
        Metadata(name=name, metadata=dict(data)).write(self._builder)
        self._metadata_indexes.append(MetadataIndex(offset=offset, length=self._builder.count,
                                                    name=name))
        self._flush()

    def finish(self):
        """Close the last chunk; write the data end, the summary, the footer and the magic."""
        from mcap.data_stream import RecordBuilder
        from mcap.opcode import Opcode
        from mcap.records import DataEnd, Footer, SummaryOffset

        self._close_chunk()
        DataEnd(self._crc).write(self._builder)
        self._flush()
        summary_start = self._stream.tell()
        summary = RecordBuilder()
        offsets = []
        groups = ((Opcode.SCHEMA, self._schemas.values()),
                  (Opcode.CHANNEL, self._channels.values()),
                  (Opcode.STATISTICS, [self._stats]),
                  (Opcode.CHUNK_INDEX, self._chunk_indexes),
                  (Opcode.ATTACHMENT_INDEX, []),
                  (Opcode.METADATA_INDEX, self._metadata_indexes))
        for opcode, records in groups:
            group_start = summary.count
            for rec in records:
                rec.write(summary)
            offsets.append(SummaryOffset(group_opcode=opcode,
                                         group_start=summary_start + group_start,
                                         group_length=summary.count - group_start))
        offset_start = summary_start + summary.count
        for rec in offsets:
            rec.write(summary)
        data = summary.end()
        crc = zlib.crc32(struct.pack('<BQQQ', Opcode.FOOTER, 20, summary_start, offset_start),
                         zlib.crc32(data))
        self._stream.write(data)
        Footer(summary_start=summary_start, summary_offset_start=offset_start,
               summary_crc=crc).write(self._builder)
        self._flush()
        self._stream.write(_MAGIC)
