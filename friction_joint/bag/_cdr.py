# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

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
           'walk_joint_state', 'MAX_LAYOUTS', 'BLOCK']

#: beyond this many layouts per block, decode message by message
MAX_LAYOUTS = 64
#: messages decoded per numpy block (bounds memory)
BLOCK = 200_000


class MessageLayout:
    """
    Byte layout of one serialized message: where the stamp and float64 data lie.

    ``fields`` maps a field name to ``(offset, count)`` of a float64 run; ``mask`` is True
    on every byte that is *not* data (encapsulation, string and sequence lengths, names),
    which identical-layout messages share.
    """

    __slots__ = ('size', 'fields', 'names', 'mask')

    def __init__(self, size, fields_, names=()):
        self.size = size
        self.fields = fields_
        self.names = tuple(names)
        mask = np.ones(size, dtype=bool)
        mask[4:12] = False                        # stamp sec, nanosec
        for off, count in fields_.values():
            mask[off:off + 8 * count] = False
        self.mask = mask


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
        self.o = 12                                # stamp at 4..12
        self.string()                              # frame_id

    def done(self):
        if len(self.raw) - self.o >= 8 or self.o > len(self.raw):
            raise ValueError(f'{len(self.raw) - self.o} unexpected trailing bytes')


def walk_joint_state(raw):
    c = Cdr(raw)
    c.header()
    names = [c.string() for _ in range(c.u32())]
    flds = {}
    for name in ('position', 'velocity', 'effort'):
        n = c.u32()
        flds[name] = (c.f64(n), n)
    c.done()
    return MessageLayout(len(raw), flds, names)


def walk_temperature(raw):
    c = Cdr(raw)
    c.header()
    flds = {'temperature': (c.f64(1), 1), 'variance': (c.f64(1), 1)}
    c.done()
    return MessageLayout(len(raw), flds)


def walk_wrench(raw):
    c = Cdr(raw)
    c.header()
    flds = {'force': (c.f64(3), 3), 'torque': (c.f64(3), 3)}
    c.done()
    return MessageLayout(len(raw), flds)


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


def stamps_ns(block):
    sec = np.ascontiguousarray(block[:, 4:8]).view('<i4')[:, 0].astype(np.int64)
    nsec = np.ascontiguousarray(block[:, 8:12]).view('<u4')[:, 0].astype(np.int64)
    return sec * NS + nsec


def layout_groups(raws, msgtype, topic):
    """
    Yield ``(indices, layout, block)`` covering every message of ``raws`` once.

    ``block`` is a ``(len(indices), layout.size)`` uint8 array of the messages that share
    ``layout``.
    """
    walk = WALKERS[msgtype]
    for start in range(0, len(raws), BLOCK):
        part = raws[start:start + BLOCK]
        lengths = np.fromiter(map(len, part), dtype=np.int64, count=len(part))
        pending = np.arange(len(part))
        groups = 0
        while pending.size:
            i0 = int(pending[0])
            try:
                layout = walk(part[i0])
            except (ValueError, struct.error) as exc:
                raise RecordingError(f'{topic}: message {start + i0} is not a valid '
                                     f'{msgtype}: {exc}') from None
            groups += 1
            if groups > MAX_LAYOUTS:              # layouts vary: one message at a time
                cand = pending[:1]
            else:
                cand = pending[lengths[pending] == layout.size]
            block = np.frombuffer(b''.join([part[i] for i in cand]),
                                  dtype=np.uint8).reshape(len(cand), layout.size)
            ref = np.frombuffer(part[i0], dtype=np.uint8)
            same = (block[:, layout.mask] == ref[layout.mask]).all(axis=1)
            yield start + cand[same], layout, block[same]
            taken = np.zeros(len(part), dtype=bool)
            taken[cand[same]] = True
            pending = pending[~taken[pending]]
