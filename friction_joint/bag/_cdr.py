# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
CDR byte layouts of the contract messages, decoded as numpy columns.

The messages of one topic nearly always share one byte layout (same frame
id, joint names and array lengths), so each layout is parsed once
(:data:`WALKERS`) and all messages sharing it are decoded as columns of one
numpy array.
"""
import struct

import numpy as np

from .topics import NS
from ..exceptions import RecordingError

__all__ = ['MessageLayout', 'Cdr', 'WALKERS', 'f64_columns', 'stamps_ns', 'layout_groups',
           'walk_joint_state', 'MAX_LAYOUTS', 'DECODE_BLOCK']

#: beyond this many layouts per block, decode message by message
MAX_LAYOUTS = 64
#: messages decoded per numpy block (bounds memory)
DECODE_BLOCK = 200_000


class MessageLayout:
    """
    Byte layout of one serialized message: where the stamp and float64 data lie.

    ``fields`` maps a field name to ``(offset, count)`` of a float64 run; ``mask`` is True
    on every byte that is *not* data (encapsulation, string and sequence lengths, names),
    which identical-layout messages share.  The frame id's characters (``frame``:
    ``(start, stop)``) are not compared either: messages whose frame ids differ but have
    one length share a layout (a frame id per message must not make one group each).
    """

    __slots__ = ('size', 'fields', 'names', 'mask')

    def __init__(self, size, fields_, names=(), frame=None):
        self.size = size
        self.fields = fields_
        self.names = tuple(names)
        mask = np.ones(size, dtype=bool)
        mask[4:12] = False                        # stamp sec, nanosec
        if frame is not None:
            mask[frame[0]:frame[1]] = False       # frame id characters
        for off, count in fields_.values():
            mask[off:off + 8 * count] = False
        self.mask = mask

    def key(self):
        """Return what decoding depends on: size, names and field offsets."""
        return self.size, self.names, tuple(sorted(self.fields.items()))


class Cdr:
    """A cursor over one little-endian CDR message (alignment relative to byte 4)."""

    _U32 = struct.Struct('<I')

    def __init__(self, raw):
        self.raw = raw
        if len(raw) < 12:
            raise ValueError(f'{len(raw)} bytes is too short')
        if raw[0:2] != b'\x00\x01':
            raise ValueError(f'unsupported CDR encapsulation {bytes(raw[0:2]).hex()} '
                             '(only little-endian CDR)')
        self.o = 4

    def align(self, n):
        rel = self.o - 4
        self.o = 4 + ((rel + n - 1) & ~(n - 1))

    def u32(self):
        self.align(4)
        if self.o + 4 > len(self.raw):
            raise ValueError('message ends inside a length field')
        v = self._U32.unpack_from(self.raw, self.o)[0]
        self.o += 4
        return v

    def string(self):
        n = self.u32()
        if n == 0 or self.o + n > len(self.raw):
            raise ValueError('bad string length')
        s = bytes(self.raw[self.o:self.o + n - 1]).decode('utf-8', 'replace')
        self.o += n
        return s

    def f64(self, count):
        """Skip ``count`` aligned float64 values; return their offset."""
        if count:
            self.align(8)
        off = self.o
        self.o += 8 * count
        if self.o > len(self.raw):
            raise ValueError('message ends inside float64 data')
        return off

    def header(self):
        """Skip the header; return the byte range of the frame id's characters."""
        self.o = 12                                # stamp at 4..12
        self.string()                              # frame_id
        return 16, self.o - 1

    def done(self):
        if len(self.raw) - self.o >= 8 or self.o > len(self.raw):
            raise ValueError(f'{len(self.raw) - self.o} unexpected trailing bytes')


def walk_joint_state(raw):
    c = Cdr(raw)
    frame = c.header()
    names = [c.string() for _ in range(c.u32())]
    flds = {}
    for name in ('position', 'velocity', 'effort'):
        n = c.u32()
        flds[name] = (c.f64(n), n)
    c.done()
    return MessageLayout(len(raw), flds, names, frame)


def walk_temperature(raw):
    c = Cdr(raw)
    frame = c.header()
    flds = {'temperature': (c.f64(1), 1), 'variance': (c.f64(1), 1)}
    c.done()
    return MessageLayout(len(raw), flds, (), frame)


def walk_wrench(raw):
    c = Cdr(raw)
    frame = c.header()
    flds = {'force': (c.f64(3), 3), 'torque': (c.f64(3), 3)}
    c.done()
    return MessageLayout(len(raw), flds, (), frame)


def walk_clock(raw):
    c = Cdr(raw)
    c.o = 12
    c.done()
    return MessageLayout(len(raw), {})


WALKERS = {
    'sensor_msgs/msg/JointState': walk_joint_state,
    'sensor_msgs/msg/Temperature': walk_temperature,
    'geometry_msgs/msg/WrenchStamped': walk_wrench,
    'rosgraph_msgs/msg/Clock': walk_clock,
}


def f64_columns(block, off, count):
    return np.ascontiguousarray(block[:, off:off + 8 * count]).view('<f8')


def stamps_ns(block, label=None, index=None):
    """
    Return the header stamps (ns) of a block of messages.

    With ``label`` (the recording and topic), a nanosecond field of 1e9 or more (a
    malformed stamp: it would be read as a later second) is an error naming message
    ``index[k]``.
    """
    sec = np.ascontiguousarray(block[:, 4:8]).view('<i4')[:, 0].astype(np.int64)
    nsec = np.ascontiguousarray(block[:, 8:12]).view('<u4')[:, 0].astype(np.int64)
    if label is not None:
        bad = np.flatnonzero(nsec >= NS)
        if len(bad):
            k = int(bad[0])
            where = int(index[k]) if index is not None else k
            raise RecordingError(
                f'{label}: message {where}: header stamp nanosec {int(nsec[k])} is not below '
                f'1e9 (sec {int(sec[k])}; {len(bad)} such messages): a malformed stamp')
    return sec * NS + nsec


def _walk(walk, raw, msgtype, topic, index):
    try:
        return walk(raw)
    except (ValueError, struct.error) as exc:
        raise RecordingError(f'{topic}: message {index} is not a valid {msgtype}: {exc}'
                             ) from None


def _block(part, cand, size):
    data = np.frombuffer(b''.join([part[i] for i in cand]), dtype=np.uint8)
    return data.reshape(len(cand), size)


def _by_key(part, pending, walk, msgtype, topic, start):
    """Group the ``pending`` messages by walking each once (layouts that vary: linear)."""
    groups = {}
    for i in pending.tolist():
        layout = _walk(walk, part[i], msgtype, topic, start + i)
        groups.setdefault(layout.key(), (layout, []))[1].append(i)
    for layout, members in groups.values():
        cand = np.asarray(members, dtype=np.int64)
        yield start + cand, layout, _block(part, cand, layout.size)


def layout_groups(raws, msgtype, topic):
    """
    Yield ``(indices, layout, block)`` covering every message of ``raws`` once.

    ``block`` is a ``(len(indices), layout.size)`` uint8 array of the messages that share
    ``layout``.  The first :data:`MAX_LAYOUTS` layouts of a block are found by comparing
    every message's non-data bytes with one message of the layout (numpy, fast for the
    usual one or few layouts); beyond that each remaining message is walked once and
    grouped by what decoding depends on (:meth:`MessageLayout.key`), so the time stays
    linear in the number of messages however many layouts there are.
    """
    walk = WALKERS[msgtype]
    for start in range(0, len(raws), DECODE_BLOCK):
        part = raws[start:start + DECODE_BLOCK]
        lengths = np.fromiter(map(len, part), dtype=np.int64, count=len(part))
        pending = np.arange(len(part))
        groups = 0
        while pending.size:
            if groups >= MAX_LAYOUTS:             # layouts vary: walk each message once
                yield from _by_key(part, pending, walk, msgtype, topic, start)
                break
            i0 = int(pending[0])
            layout = _walk(walk, part[i0], msgtype, topic, start + i0)
            groups += 1
            cand = pending[lengths[pending] == layout.size]
            block = _block(part, cand, layout.size)
            ref = np.frombuffer(part[i0], dtype=np.uint8)
            same = (block[:, layout.mask] == ref[layout.mask]).all(axis=1)
            yield start + cand[same], layout, block[same]
            taken = np.zeros(len(part), dtype=bool)
            taken[cand[same]] = True
            pending = pending[~taken[pending]]
