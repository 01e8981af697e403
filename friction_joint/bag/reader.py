"""Recordings (rosbag2 / MCAP) as numpy arrays: reading and writing, without ROS.

A recording is a rosbag2 directory (``metadata.yaml`` + ``.mcap``, CDR, ROS 2
Jazzy message definitions) or a single ``.mcap`` file, with the topics of the
contract (``CONTRACT.md`` sections 2 and 3).  :func:`read_recording` turns one
into a :class:`Recording` of per-topic arrays; :func:`write_recording` writes
one from arrays (tests, offline simulator runs, identification experiments).

Topic fields (the same names on reading and writing; times in seconds)

================== ========================= ===================================
topic              class                     fields
================== ========================= ===================================
/joint_states      :class:`JointStates`      ``t, q, qd, effort``
/joint_temperature :class:`Temperature`      ``t, xi, variance``
/link_torque       :class:`LinkTorque`       ``t, tau`` (``wrench.torque.z``)
/joint_command     :class:`JointCommand`     ``t, effort, q_d, qd_d``
/external_torque   :class:`ExternalTorque`   ``t, effort``
/clock             (not read)                ``t`` (writing only)
================== ========================= ===================================

``t`` is the header stamp, ``t_recv`` the bag (receive) time of each message.
Messages are returned sorted by header stamp.  ``q_d``/``qd_d`` are NaN where
a command message carries no reference; everything else must be finite.

Decoding does not go through a generic deserializer: the messages of one
topic nearly always share one byte layout (same frame id, joint names and
array lengths), so each layout is parsed once and all messages sharing it are
decoded as columns of one numpy array (about 3 µs per message in total,
dominated by reading the file).
"""
import os
import shutil
import struct
import tempfile
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ..exceptions import RecordingError

__all__ = ['CONTRACT_TYPES', 'REQUIRED_TOPICS', 'JointStates', 'Temperature', 'LinkTorque',
           'JointCommand', 'ExternalTorque', 'Recording', 'read_recording', 'write_recording',
           'zero_order_hold', 'recording_topics', 'iter_messages']

#: topic -> message type of the contract (section 2)
CONTRACT_TYPES = {
    '/joint_states': 'sensor_msgs/msg/JointState',
    '/joint_temperature': 'sensor_msgs/msg/Temperature',
    '/link_torque': 'geometry_msgs/msg/WrenchStamped',
    '/joint_command': 'sensor_msgs/msg/JointState',
    '/external_torque': 'sensor_msgs/msg/JointState',
    '/clock': 'rosgraph_msgs/msg/Clock',
}

#: topics every recording has (section 3)
REQUIRED_TOPICS = ('/joint_states', '/joint_temperature')

_NS = 1_000_000_000
_BLOCK = 200_000          # messages decoded per numpy block (bounds memory)
_MAX_LAYOUTS = 64         # beyond this many layouts per block, decode message by message


# --------------------------------------------------------------------------- data classes

@dataclass(frozen=True)
class JointStates:
    """``/joint_states`` of one joint: stamps ``t``, ``t_recv`` (s), ``q`` (rad), ``qd`` (rad/s),
    ``effort`` τ (N m); ``skipped`` messages did not name the joint."""

    t: np.ndarray
    t_recv: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    effort: np.ndarray
    skipped: int = 0

    def __len__(self):
        return len(self.t)


@dataclass(frozen=True)
class Temperature:
    """``/joint_temperature``: stamps ``t``, ``t_recv`` (s), housing temperature ``xi`` (°C),
    sensor ``variance``."""

    t: np.ndarray
    t_recv: np.ndarray
    xi: np.ndarray
    variance: np.ndarray

    def __len__(self):
        return len(self.t)


@dataclass(frozen=True)
class LinkTorque:
    """``/link_torque``: stamps ``t``, ``t_recv`` (s), measured τ_ext ``tau`` (N m)."""

    t: np.ndarray
    t_recv: np.ndarray
    tau: np.ndarray

    def __len__(self):
        return len(self.t)


@dataclass(frozen=True)
class JointCommand:
    """``/joint_command``: commanded ``effort`` (N m), desired ``q_d``, ``qd_d`` (NaN where the
    message has no reference); ``skipped`` messages did not name the joint."""

    t: np.ndarray
    t_recv: np.ndarray
    effort: np.ndarray
    q_d: np.ndarray
    qd_d: np.ndarray
    skipped: int = 0

    def __len__(self):
        return len(self.t)


@dataclass(frozen=True)
class ExternalTorque:
    """``/external_torque``: estimated τ̂_ext ``effort`` (N m); ``skipped`` messages did not
    name the joint."""

    t: np.ndarray
    t_recv: np.ndarray
    effort: np.ndarray
    skipped: int = 0

    def __len__(self):
        return len(self.t)


def zero_order_hold(t_src, x_src, t):
    """Sample ``x_src(t_src)`` at ``t`` holding the last value (zero-order hold).

    Parameters
    ----------
    t_src, x_src : array_like
        Sample times (sorted ascending) and values.
    t : array_like
        Query times.

    Returns
    -------
    numpy.ndarray
        ``x_src[k]`` of the last ``t_src[k] <= t``; query times before the first sample
        get the first value.
    """
    t_src = np.asarray(t_src, dtype=float)
    x_src = np.asarray(x_src)
    if t_src.size == 0:
        raise RecordingError('zero_order_hold: no samples to hold')
    idx = np.searchsorted(t_src, np.asarray(t, dtype=float), side='right') - 1
    return x_src[np.clip(idx, 0, len(t_src) - 1)]


def _span_stats(t):
    n = len(t)
    if n < 2:
        return {'count': n, 'rate': None, 'max_gap': None}
    span = float(t[-1] - t[0])
    return {'count': n, 'rate': (n - 1) / span if span > 0 else None,
            'max_gap': float(np.max(np.diff(t)))}


@dataclass(frozen=True)
class Recording:
    """A recording of one joint as numpy arrays (see the module docstring for the fields).

    Attributes
    ----------
    path : str
        Where it was read from.
    joint_name : str
        The joint picked from the JointState topics.
    joint_states, temperature : JointStates, Temperature
        Always present.
    link_torque, joint_command, external_torque : LinkTorque, JointCommand, ExternalTorque or None
        Present if the recording has the topic.
    topics : dict
        Every topic of the bag -> ``(message type, message count)``, including ones not read.
    unordered : dict
        Topic -> number of messages whose header stamp went backwards in bag order
        (they are returned sorted by stamp).
    """

    path: str
    joint_name: str
    joint_states: JointStates
    temperature: Temperature
    link_torque: LinkTorque = None
    joint_command: JointCommand = None
    external_torque: ExternalTorque = None
    topics: dict = field(default_factory=dict)
    unordered: dict = field(default_factory=dict)

    @property
    def t0(self):
        """First joint-state stamp (s)."""
        return float(self.joint_states.t[0])

    @property
    def duration(self):
        """Joint-state time span (s)."""
        return float(self.joint_states.t[-1] - self.joint_states.t[0])

    def temperature_at(self, t=None):
        """Housing temperature ξ at ``t`` (default: the joint-state stamps), zero-order hold."""
        t = self.joint_states.t if t is None else t
        return zero_order_hold(self.temperature.t, self.temperature.xi, t)

    def series(self):
        """Topic -> data class of every topic present (the input :func:`write_recording` takes)."""
        pairs = (('/joint_states', self.joint_states), ('/joint_temperature', self.temperature),
                 ('/link_torque', self.link_torque), ('/joint_command', self.joint_command),
                 ('/external_torque', self.external_torque))
        return {k: v for k, v in pairs if v is not None}

    def summary(self):
        """Duration, counts, mean rates and largest gaps per topic, as a JSON-able dict."""
        topics = {}
        for topic, data in self.series().items():
            entry = _span_stats(data.t)
            if getattr(data, 'skipped', 0):
                entry['skipped'] = int(data.skipped)
            if self.unordered.get(topic):
                entry['unordered'] = int(self.unordered[topic])
            topics[topic] = entry
        return {'path': self.path, 'joint_name': self.joint_name, 'start': self.t0,
                'duration': self.duration, 'topics': topics,
                'other_topics': {k: {'type': v[0], 'count': v[1]} for k, v in self.topics.items()
                                 if k not in topics}}

    def __str__(self):
        s = self.summary()
        lines = [f'{s["path"]}: joint {s["joint_name"]!r}, {s["duration"]:.3f} s '
                 f'from t = {s["start"]:.3f} s']
        for topic, e in s['topics'].items():
            rate = f'{e["rate"]:.1f} Hz' if e['rate'] else '-'
            gap = f', max gap {e["max_gap"] * 1e3:.1f} ms' if e['max_gap'] is not None else ''
            extra = ''.join(f', {k} {e[k]}' for k in ('skipped', 'unordered') if k in e)
            lines.append(f'  {topic}: {e["count"]} messages, {rate}{gap}{extra}')
        for topic, e in s['other_topics'].items():
            lines.append(f'  {topic}: {e["count"]} messages ({e["type"]}, not read)')
        return '\n'.join(lines)


# --------------------------------------------------------------------------- CDR layouts

class _Layout:
    """Byte layout of one serialized message: where the stamp and float64 data lie.

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


class _Cdr:
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


def _walk_joint_state(raw):
    c = _Cdr(raw)
    c.header()
    names = [c.string() for _ in range(c.u32())]
    flds = {}
    for name in ('position', 'velocity', 'effort'):
        n = c.u32()
        flds[name] = (c.f64(n), n)
    c.done()
    return _Layout(len(raw), flds, names)


def _walk_temperature(raw):
    c = _Cdr(raw)
    c.header()
    flds = {'temperature': (c.f64(1), 1), 'variance': (c.f64(1), 1)}
    c.done()
    return _Layout(len(raw), flds)


def _walk_wrench(raw):
    c = _Cdr(raw)
    c.header()
    flds = {'force': (c.f64(3), 3), 'torque': (c.f64(3), 3)}
    c.done()
    return _Layout(len(raw), flds)


def _walk_clock(raw):
    c = _Cdr(raw)
    c.o = 12
    c.done()
    return _Layout(len(raw), {})


_WALKERS = {
    'sensor_msgs/msg/JointState': _walk_joint_state,
    'sensor_msgs/msg/Temperature': _walk_temperature,
    'geometry_msgs/msg/WrenchStamped': _walk_wrench,
    'rosgraph_msgs/msg/Clock': _walk_clock,
}


def _f64_columns(block, off, count):
    return np.ascontiguousarray(block[:, off:off + 8 * count]).view('<f8')


def _stamps(block):
    sec = np.ascontiguousarray(block[:, 4:8]).view('<i4')[:, 0].astype(np.int64)
    nsec = np.ascontiguousarray(block[:, 8:12]).view('<u4')[:, 0].astype(np.int64)
    return sec * _NS + nsec


def _layout_groups(raws, msgtype, topic):
    """Yield ``(indices, layout, block)`` covering every message of ``raws`` once.

    ``block`` is a ``(len(indices), layout.size)`` uint8 array of the messages that share
    ``layout``.
    """
    walk = _WALKERS[msgtype]
    for start in range(0, len(raws), _BLOCK):
        part = raws[start:start + _BLOCK]
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
            if groups > _MAX_LAYOUTS:              # layouts vary: one message at a time
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


# --------------------------------------------------------------------------- decoding

def _decode_joint_state(raws, topic, joint, required):
    """Stamps (ns), column dict and skipped count of ``joint`` in JointState messages.

    ``required`` names the fields that must be present; others are NaN where absent.
    """
    n = len(raws)
    stamp = np.zeros(n, dtype=np.int64)
    keep = np.zeros(n, dtype=bool)
    cols = {k: np.full(n, np.nan) for k in ('position', 'velocity', 'effort')}
    missing = {k: 0 for k in required}
    for idx, layout, block in _layout_groups(raws, 'sensor_msgs/msg/JointState', topic):
        names = layout.names
        if joint in names:
            j = names.index(joint)
        elif not names and all(c <= 1 for _, c in layout.fields.values()):
            j = 0                                  # anonymous single-joint message
        else:
            continue
        stamp[idx] = _stamps(block)
        keep[idx] = True
        for name, (off, count) in layout.fields.items():
            if count == 0:
                if name in missing:
                    missing[name] += len(idx)
                continue
            if count != max(len(names), 1):
                raise RecordingError(f'{topic}: malformed JointState: {count} {name} values '
                                     f'for {len(names)} names')
            cols[name][idx] = _f64_columns(block, off + 8 * j, 1)[:, 0]
    for name, k in missing.items():
        if k:
            raise RecordingError(f'{topic}: {k} messages have no {name} for joint {joint!r}')
    return stamp, cols, keep


def _decode_fixed(raws, topic, msgtype, picks):
    """Stamps and ``picks`` (out name -> (field, index)) of fixed-layout messages."""
    n = len(raws)
    stamp = np.zeros(n, dtype=np.int64)
    cols = {k: np.full(n, np.nan) for k in picks}
    for idx, layout, block in _layout_groups(raws, msgtype, topic):
        stamp[idx] = _stamps(block)
        for out, (name, i) in picks.items():
            off, _ = layout.fields[name]
            cols[out][idx] = _f64_columns(block, off + 8 * i, 1)[:, 0]
    return stamp, cols


def _check_finite(topic, cols):
    bad = {k: int(np.count_nonzero(~np.isfinite(v))) for k, v in cols.items()}
    bad = {k: v for k, v in bad.items() if v}
    if bad:
        total = sum(bad.values())
        detail = ', '.join(f'{k} {v}' for k, v in bad.items())
        raise RecordingError(f'{topic}: {total} NaN/inf values ({detail})')


def _sorted(stamp, recv, cols):
    """Sort by stamp; returns t, t_recv, columns and the number of backward steps."""
    back = int(np.count_nonzero(np.diff(stamp) < 0))
    order = np.argsort(stamp, kind='stable')
    return (stamp[order] / _NS, recv[order] / _NS, {k: v[order] for k, v in cols.items()}, back)


def _open_reader(path):
    try:
        from rosbags.rosbag2 import Reader
    except ImportError as exc:                    # pragma: no cover - packaging problem
        raise RecordingError(f'reading recordings needs the rosbags package ({exc})') from None
    p = Path(path)
    if not p.exists():
        raise RecordingError(f'recording {path} does not exist')
    if p.is_dir():
        if not (p / 'metadata.yaml').exists():
            raise RecordingError(f'{path} is not a rosbag2 recording: no metadata.yaml '
                                 '(pass the .mcap file itself to read a bare MCAP file)')
    elif p.suffix not in ('.mcap', '.db3'):
        raise RecordingError(f'{path} is not a recording: expected a rosbag2 directory or '
                             'a .mcap file')
    try:
        reader = Reader(p)
        reader.open()
    except Exception as exc:                       # rosbags raises various types
        raise RecordingError(f'{path}: cannot open recording, truncated or corrupt '
                             f'({type(exc).__name__}: {exc})') from None
    return reader


def _topic_table(reader, path):
    """``{topic: (msgtype, count)}`` of an open reader (counts from the bag's index)."""
    topics = {}
    for con in reader.connections:
        msgtype, count = topics.get(con.topic, (con.msgtype, 0))
        if msgtype != con.msgtype:
            raise RecordingError(f'{path}: topic {con.topic} has two message types, '
                                 f'{msgtype} and {con.msgtype}')
        topics[con.topic] = (msgtype, count + (con.msgcount or 0))
    return topics


def _close(reader):
    try:
        reader.close()
    except Exception:                              # pragma: no cover - closing a broken file
        pass


def _read_raw(path, wanted):
    """Open ``path``; return ``{topic: (type, count)}`` and ``{topic: (raws, recv_ns)}``."""
    reader = _open_reader(path)
    try:
        topics = _topic_table(reader, path)
        for topic, (msgtype, _) in topics.items():
            expected = CONTRACT_TYPES.get(topic)
            if expected and msgtype != expected:
                raise RecordingError(f'{path}: {topic} has message type {msgtype}, '
                                     f'expected {expected}')
        for topic in REQUIRED_TOPICS:
            if topic not in topics:
                raise RecordingError(f'{path}: no {topic} topic (topics: '
                                     f'{", ".join(sorted(topics)) or "none"})')
        conns = [c for c in reader.connections if c.topic in wanted]
        data = {t: ([], []) for t in wanted if t in topics}
        try:
            for con, stamp, raw in reader.messages(connections=conns):
                raws, recv = data[con.topic]
                raws.append(raw)
                recv.append(stamp)
        except RecordingError:
            raise
        except Exception as exc:
            raise RecordingError(f'{path}: truncated or corrupt recording '
                                 f'({type(exc).__name__}: {exc})') from None
        for topic, (raws, recv) in data.items():
            topics[topic] = (topics[topic][0], len(raws))
        return topics, {k: (v[0], np.asarray(v[1], dtype=np.int64)) for k, v in data.items()}
    finally:
        _close(reader)


def recording_topics(path):
    """``{topic: (message type, count)}`` of a recording, reading no messages.

    Raises
    ------
    RecordingError
        ``path`` is missing or not a readable recording.
    """
    path = os.fspath(path)
    reader = _open_reader(path)
    try:
        return _topic_table(reader, path)
    finally:
        _close(reader)


def iter_messages(path, topics=None):
    """Yield the serialized messages of a recording in bag-time order.

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 directory or a single ``.mcap`` file.
    topics : iterable of str, optional
        Only these topics (default: all); a topic the recording lacks is an error.

    Yields
    ------
    tuple
        ``(topic, msgtype, bag_time_ns, raw)`` with ``raw`` the CDR bytes.

    Raises
    ------
    RecordingError
        The path is missing, not a recording, truncated or corrupt, or lacks a topic.
    """
    path = os.fspath(path)
    reader = _open_reader(path)
    try:
        conns = reader.connections
        if topics is not None:
            topics = list(topics)
            have = {c.topic for c in conns}
            missing = [t for t in topics if t not in have]
            if missing:
                raise RecordingError(f'{path}: no {", ".join(missing)} topic (topics: '
                                     f'{", ".join(sorted(have)) or "none"})')
            conns = [c for c in conns if c.topic in topics]
        it = reader.messages(connections=conns)
        while True:
            try:
                con, stamp, raw = next(it)
            except StopIteration:
                return
            except Exception as exc:
                raise RecordingError(f'{path}: truncated or corrupt recording '
                                     f'({type(exc).__name__}: {exc})') from None
            yield con.topic, con.msgtype, stamp, bytes(raw)
    finally:
        _close(reader)


def read_recording(path, joint_name=None):
    """Read a recording into arrays.

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 directory (``metadata.yaml`` + ``.mcap``) or a single ``.mcap`` file.
    joint_name : str, optional
        Joint to pick from the JointState topics; default: the first name of the first
        ``/joint_states`` message.  Messages that do not name the joint are skipped and
        counted (``skipped``).

    Returns
    -------
    Recording

    Raises
    ------
    RecordingError
        The path is missing or not a recording, the file is truncated or corrupt, a
        required topic (``/joint_states``, ``/joint_temperature``) is missing or empty, a
        contract topic has the wrong message type, no message names the joint, or data
        are NaN/inf.  The message names the topic and the problem.
    """
    path = os.fspath(path)
    wanted = [t for t in CONTRACT_TYPES if t != '/clock']
    topics, data = _read_raw(path, wanted)
    for topic in REQUIRED_TOPICS:
        if not data[topic][0]:
            raise RecordingError(f'{path}: {topic} has no messages')

    js_raws, js_recv = data['/joint_states']
    if joint_name is None:
        try:
            names = _walk_joint_state(js_raws[0]).names
        except (ValueError, struct.error) as exc:
            raise RecordingError(f'/joint_states: message 0 is not a valid '
                                 f'sensor_msgs/msg/JointState: {exc}') from None
        joint_name = names[0] if names else ''

    unordered = {}

    def joint_topic(topic, required, rename):
        raws, recv = data[topic]
        stamp, cols, keep = _decode_joint_state(raws, topic, joint_name, required)
        skipped = int(len(raws) - np.count_nonzero(keep))
        cols = {rename[k]: v[keep] for k, v in cols.items() if k in rename}
        _check_finite(topic, {k: v for k, v in cols.items()
                              if k in {rename[r] for r in required}})
        t, t_recv, cols, back = _sorted(stamp[keep], recv[keep], cols)
        if back:
            unordered[topic] = back
        return t, t_recv, cols, skipped

    t, t_recv, c, skipped = joint_topic('/joint_states', ('position', 'velocity', 'effort'),
                                        {'position': 'q', 'velocity': 'qd', 'effort': 'effort'})
    if len(t) == 0:
        seen = sorted({n for n in _walk_joint_state(js_raws[0]).names})
        raise RecordingError(f'{path}: no /joint_states message names joint {joint_name!r} '
                             f'(first message names: {", ".join(seen) or "none"})')
    joint_states = JointStates(t, t_recv, c['q'], c['qd'], c['effort'], skipped)

    def fixed_topic(topic, picks):
        raws, recv = data[topic]
        stamp, cols = _decode_fixed(raws, topic, CONTRACT_TYPES[topic], picks)
        _check_finite(topic, cols)
        t, t_recv, cols, back = _sorted(stamp, recv, cols)
        if back:
            unordered[topic] = back
        return t, t_recv, cols

    t, t_recv, c = fixed_topic('/joint_temperature', {'xi': ('temperature', 0),
                                                      'variance': ('variance', 0)})
    temperature = Temperature(t, t_recv, c['xi'], c['variance'])

    link_torque = joint_command = external_torque = None
    if data.get('/link_torque', ((),))[0]:
        t, t_recv, c = fixed_topic('/link_torque', {'tau': ('torque', 2)})
        link_torque = LinkTorque(t, t_recv, c['tau'])
    if data.get('/joint_command', ((),))[0]:
        t, t_recv, c, skipped = joint_topic(
            '/joint_command', ('effort',),
            {'position': 'q_d', 'velocity': 'qd_d', 'effort': 'effort'})
        joint_command = JointCommand(t, t_recv, c['effort'], c['q_d'], c['qd_d'], skipped)
    if data.get('/external_torque', ((),))[0]:
        t, t_recv, c, skipped = joint_topic('/external_torque', ('effort',),
                                            {'effort': 'effort'})
        external_torque = ExternalTorque(t, t_recv, c['effort'], skipped)

    return Recording(path=path, joint_name=joint_name, joint_states=joint_states,
                     temperature=temperature, link_torque=link_torque,
                     joint_command=joint_command, external_torque=external_torque,
                     topics=topics, unordered=unordered)


# --------------------------------------------------------------------------- writing

# topic -> (required fields, optional fields); 't_recv' and 'frame_id' are optional everywhere
_WRITE_FIELDS = {
    '/joint_states': (('t', 'q', 'qd', 'effort'), ('name',)),
    '/joint_temperature': (('t', 'xi'), ('variance',)),
    '/link_torque': (('t', 'tau'), ()),
    '/joint_command': (('t', 'effort'), ('q_d', 'qd_d', 'name')),
    '/external_torque': (('t', 'effort'), ('name',)),
    '/clock': (('t',), ()),
}


def _as_fields(topic, spec):
    """A mapping of arrays from a dict or one of the data classes."""
    if hasattr(spec, '__dataclass_fields__'):
        spec = {f.name: getattr(spec, f.name) for f in fields(spec) if f.name != 'skipped'}
    if not hasattr(spec, 'keys'):
        raise RecordingError(f'{topic}: expected a dict of arrays, got {type(spec).__name__}')
    required, optional = _WRITE_FIELDS[topic]
    unknown = set(spec) - set(required) - set(optional) - {'t_recv', 'frame_id'}
    if unknown:
        raise RecordingError(f'{topic}: unknown field(s) {", ".join(sorted(unknown))} '
                             f'(fields: {", ".join(required + optional)}, t_recv, frame_id)')
    missing = [k for k in required if k not in spec]
    if missing:
        raise RecordingError(f'{topic}: missing field(s) {", ".join(missing)}')
    return dict(spec)


def _stamp_ns(topic, name, t, n=None):
    t = np.asarray(t, dtype=float).reshape(-1)
    if n is not None and len(t) != n:
        raise RecordingError(f'{topic}: {name} has {len(t)} values for {n} messages')
    if not np.all(np.isfinite(t)) or np.any(t < 0) or np.any(t >= 2**31):
        raise RecordingError(f'{topic}: {name} must be finite times in [0, 2^31) s')
    return np.round(t * _NS).astype(np.int64)


def _column(topic, name, x, n, k):
    x = np.asarray(x, dtype=float)
    if x.ndim == 1 and k == 1:
        x = x[:, None]
    if x.shape != (n, k):
        raise RecordingError(f'{topic}: {name} has shape {x.shape}, expected ({n},)'
                             + (f' or ({n}, {k})' if k > 1 else ''))
    return x


def _encode(typestore, msgtype, template, n, stamp, columns):
    """Serialize ``n`` messages: ``template`` with stamps and float64 ``columns`` replaced.

    ``columns`` maps a layout field to an ``(n, count)`` array.
    """
    raw = typestore.serialize_cdr(template, msgtype)
    layout = _WALKERS[msgtype](raw)
    block = np.tile(np.frombuffer(raw, dtype=np.uint8), (n, 1))
    block[:, 4:8] = (stamp // _NS).astype('<i4').view(np.uint8).reshape(n, 4)
    block[:, 8:12] = (stamp % _NS).astype('<u4').view(np.uint8).reshape(n, 4)
    for name, x in columns.items():
        off, count = layout.fields[name]
        block[:, off:off + 8 * count] = np.ascontiguousarray(x, dtype='<f8').view(
            np.uint8).reshape(n, 8 * count)
    return block


def _topic_block(typestore, topic, spec, joint_name):
    """(stamp ns, receive ns, uint8 block of serialized messages) of one topic."""
    T = typestore.types
    spec = _as_fields(topic, spec)
    stamp = _stamp_ns(topic, 't', spec['t'])
    n = len(stamp)
    recv = stamp if spec.get('t_recv') is None else _stamp_ns(topic, 't_recv', spec['t_recv'], n)
    msgtype = CONTRACT_TYPES[topic]
    header = T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0),
                                      frame_id=str(spec.get('frame_id') or ''))
    if n == 0:
        return stamp, recv, None, msgtype
    if topic == '/clock':
        template = T[msgtype](clock=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0))
        return stamp, recv, _encode(typestore, msgtype, template, n, stamp, {}), msgtype
    if topic == '/joint_temperature':
        var = spec.get('variance')
        cols = {'temperature': _column(topic, 'xi', spec['xi'], n, 1),
                'variance': _column(topic, 'variance', np.broadcast_to(
                    np.asarray(0.0 if var is None else var, dtype=float), (n,)), n, 1)}
        template = T[msgtype](header=header, temperature=0.0, variance=0.0)
        return stamp, recv, _encode(typestore, msgtype, template, n, stamp, cols), msgtype
    if topic == '/link_torque':
        tau = _column(topic, 'tau', spec['tau'], n, 1)
        torque = np.zeros((n, 3))
        torque[:, 2] = tau[:, 0]
        V = T['geometry_msgs/msg/Vector3']
        template = T[msgtype](header=header, wrench=T['geometry_msgs/msg/Wrench'](
            force=V(x=0.0, y=0.0, z=0.0), torque=V(x=0.0, y=0.0, z=0.0)))
        cols = {'force': np.zeros((n, 3)), 'torque': torque}
        return stamp, recv, _encode(typestore, msgtype, template, n, stamp, cols), msgtype
    # JointState topics
    names = spec.get('name', joint_name)
    names = [names] if isinstance(names, str) else [str(x) for x in names]
    k = len(names)
    src = {'/joint_states': {'position': 'q', 'velocity': 'qd', 'effort': 'effort'},
           '/joint_command': {'position': 'q_d', 'velocity': 'qd_d', 'effort': 'effort'},
           '/external_torque': {'effort': 'effort'}}[topic]
    cols = {f: _column(topic, key, spec[key], n, k) for f, key in src.items()
            if spec.get(key) is not None}
    template = T[msgtype](header=header, name=names,
                          **{f: np.zeros(k if f in cols else 0)
                             for f in ('position', 'velocity', 'effort')})
    return stamp, recv, _encode(typestore, msgtype, template, n, stamp, cols), msgtype


def write_recording(path, topics, joint_name=None):
    """Write a recording (rosbag2 directory, or a single ``.mcap`` file) from arrays.

    Parameters
    ----------
    path : str or os.PathLike
        Target; must not exist.  A name ending in ``.mcap`` gives a bare MCAP file,
        anything else a rosbag2 directory (version 9, MCAP storage, CDR, Jazzy types).
    topics : Recording or dict
        A :class:`Recording`, or topic -> dict of arrays (or one of the data classes).
        Fields per topic as in the module docstring; optional everywhere: ``t_recv``
        (bag time, default ``t``) and ``frame_id``.  JointState topics take ``name``
        (a string or a list of ``k`` joint names, default ``joint_name``) with 1-D
        arrays or ``(n, k)`` arrays for ``k`` joints; ``/joint_command`` without
        ``q_d``/``qd_d`` has empty position/velocity.  NaN is written as is.
    joint_name : str, optional
        Joint name of JointState topics without ``name``; default the recording's joint
        name, else ``'joint'``.

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    RecordingError
        ``path`` exists, a topic is not a contract topic, fields are unknown, missing or
        of the wrong length.

    Notes
    -----
    The bag is written into a temporary directory next to ``path`` and renamed at the
    end, so a failure leaves nothing at ``path``.  Messages are written in order of
    ``t_recv``.
    """
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    path = os.fspath(path)
    if isinstance(topics, Recording):
        joint_name = joint_name or topics.joint_name
        topics = topics.series()
    joint_name = 'joint' if joint_name is None else joint_name
    if os.path.lexists(path):
        raise RecordingError(f'{path} exists already, not overwriting')
    unknown = [t for t in topics if t not in _WRITE_FIELDS]
    if unknown:
        raise RecordingError(f'cannot write topic(s) {", ".join(unknown)}: not contract '
                             f'topics ({", ".join(_WRITE_FIELDS)})')
    typestore = get_typestore(Stores.ROS2_JAZZY)
    blocks = {t: _topic_block(typestore, t, spec, joint_name) for t, spec in topics.items()}

    parent = os.path.dirname(os.path.abspath(path))
    os.makedirs(parent, exist_ok=True)
    base = os.path.basename(os.path.normpath(path))
    tmp = tempfile.mkdtemp(prefix=f'.{base}.', suffix='.tmp', dir=parent)
    try:
        bagdir = os.path.join(tmp, base[:-5] if base.endswith('.mcap') else base)
        with Writer(bagdir, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
            conns, recvs, which, rows = [], [], [], []
            for i, (topic, (_, recv, block, msgtype)) in enumerate(blocks.items()):
                conns.append((writer.add_connection(topic, msgtype, typestore=typestore),
                              block))
                recvs.append(recv)
                which.append(np.full(len(recv), i, dtype=np.int64))
                rows.append(np.arange(len(recv), dtype=np.int64))
            if recvs:
                recvs, which, rows = (np.concatenate(x) for x in (recvs, which, rows))
                for j in np.lexsort((which, recvs)):   # by receive time, then topic
                    conn, block = conns[which[j]]
                    writer.write(conn, int(recvs[j]), block[rows[j]].tobytes())
        if base.endswith('.mcap'):
            made = [f for f in os.listdir(bagdir) if f.endswith('.mcap')]
            os.rename(os.path.join(bagdir, made[0]), path)
        else:
            os.rename(bagdir, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path
