# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Writing recordings from numpy arrays (tests, offline simulator runs, experiments).

See :mod:`friction_joint.bag.topics` for the topics and fields.

The recording is written in one pass with memory bounded by a block, whatever its
length: the topics are merged by receive time (then topic) :data:`WRITE_BLOCK` messages at
a time (a k-way merge over windows of each topic's stamps), each block is encoded
(a template message with stamps and float64 fields replaced, numpy) and appended to
the MCAP file by :class:`~friction_joint.bag.mcap_stream.McapStream` (zstd chunks
with CRCs, data-section and summary CRCs: what rosbags' writer followed by
:func:`~friction_joint.bag.checksums.seal_recording` gave, byte for byte), and
``metadata.yaml`` is written as rosbags writes it.
"""
from __future__ import annotations

from dataclasses import fields
import io
import os
import shutil
import tempfile

import numpy as np

from ._cdr import WALKERS
from .mcap_stream import McapStream, MESSAGE_HEADER
from .topics import CONTRACT_TYPES, NS, Recording
from ..exceptions import RecordingError

__all__ = ['write_recording', 'WRITE_BLOCK', 'BLOCK_BYTES']

#: at most this many messages are merged and encoded at a time
WRITE_BLOCK = 65536
#: and at most this many bytes of message records (large JointStates)
BLOCK_BYTES = 16 << 20
#: stamps checked this many at a time
_CHECK = 1 << 20
#: rosbag2 ``metadata.yaml`` version
_VERSION = 9


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
    """Return a mapping of arrays from a dict or one of the data classes."""
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


def _ns(t):
    return np.round(t * NS).astype(np.int64)


def _times(topic, name, t, n=None):
    """Return ``t`` as float seconds, checked (a slice at a time) to be stamps."""
    t = np.asarray(t, dtype=float).reshape(-1)
    if n is not None and len(t) != n:
        raise RecordingError(f'{topic}: {name} has {len(t)} values for {n} messages')
    for a in range(0, len(t), _CHECK):
        x = t[a:a + _CHECK]
        if not np.all(np.isfinite(x)) or np.any(x < 0) or np.any(x >= 2**31):
            raise RecordingError(f'{topic}: {name} must be finite times in [0, 2^31) s')
    return t


def _column(topic, name, x, n, k):
    x = np.asarray(x, dtype=float)
    if x.ndim == 1 and k == 1:
        x = x[:, None]
    if x.shape != (n, k):
        raise RecordingError(f'{topic}: {name} has shape {x.shape}, expected ({n},)'
                             + (f' or ({n}, {k})' if k > 1 else ''))
    return x


def _encode(raw, layout, stamp, columns):
    """
    Serialize ``len(stamp)`` messages: ``raw`` with stamps and float64 ``columns`` replaced.

    ``columns`` maps a layout field to an ``(n, count)`` array.
    """
    n = len(stamp)
    block = np.tile(np.frombuffer(raw, dtype=np.uint8), (n, 1))
    block[:, 4:8] = (stamp // NS).astype('<i4').view(np.uint8).reshape(n, 4)
    block[:, 8:12] = (stamp % NS).astype('<u4').view(np.uint8).reshape(n, 4)
    for name, x in columns.items():
        off, count = layout.fields[name]
        block[:, off:off + 8 * count] = np.ascontiguousarray(x, dtype='<f8').view(
            np.uint8).reshape(n, 8 * count)
    return block


class _Topic:
    """One topic to write: template, checked arrays, and its messages in receive order."""

    def __init__(self, typestore, topic, spec, joint_name):
        T = typestore.types
        spec = _as_fields(topic, spec)
        self.topic = topic
        self.msgtype = msgtype = CONTRACT_TYPES[topic]
        self.t = t = _times(topic, 't', spec['t'])
        self.n = n = len(t)
        self.t_recv = (None if spec.get('t_recv') is None
                       else _times(topic, 't_recv', spec['t_recv'], n))
        self.columns, self.raw, self.order = {}, b'', None
        if n == 0:                                 # a channel without messages
            return
        header = T['std_msgs/msg/Header'](stamp=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0),
                                          frame_id=str(spec.get('frame_id') or ''))
        if topic == '/clock':
            template = T[msgtype](clock=T['builtin_interfaces/msg/Time'](sec=0, nanosec=0))
        elif topic == '/joint_temperature':
            var = spec.get('variance')
            self.columns = {
                'temperature': _column(topic, 'xi', spec['xi'], n, 1),
                'variance': _column(topic, 'variance', np.broadcast_to(
                    np.asarray(0.0 if var is None else var, dtype=float), (n,)), n, 1)}
            template = T[msgtype](header=header, temperature=0.0, variance=0.0)
        elif topic == '/link_torque':
            self.columns = {'torque': _column(topic, 'tau', spec['tau'], n, 1)}
            V = T['geometry_msgs/msg/Vector3']
            template = T[msgtype](header=header, wrench=T['geometry_msgs/msg/Wrench'](
                force=V(x=0.0, y=0.0, z=0.0), torque=V(x=0.0, y=0.0, z=0.0)))
        else:                                              # JointState topics
            names = spec.get('name', joint_name)
            names = [names] if isinstance(names, str) else [str(x) for x in names]
            k = len(names)
            src = {'/joint_states': {'position': 'q', 'velocity': 'qd', 'effort': 'effort'},
                   '/joint_command': {'position': 'q_d', 'velocity': 'qd_d', 'effort': 'effort'},
                   '/external_torque': {'effort': 'effort'}}[topic]
            self.columns = {f: _column(topic, key, spec[key], n, k) for f, key in src.items()
                            if spec.get(key) is not None}
            template = T[msgtype](header=header, name=names,
                                  **{f: np.zeros(k if f in self.columns else 0)
                                     for f in ('position', 'velocity', 'effort')})
        self.raw = bytes(typestore.serialize_cdr(template, msgtype))
        self.layout = WALKERS[msgtype](self.raw)
        recv = self.t if self.t_recv is None else self.t_recv
        last = None
        for a in range(0, n, _CHECK):
            r = _ns(recv[a:a + _CHECK])
            if np.any(np.diff(r) < 0) or (last is not None and r[0] < last):
                r = _ns(recv)                              # out of order: sort (O(n))
                self.order = np.argsort(r, kind='stable')
                self.recv_sorted = r[self.order]
                break
            last = r[-1]

    def rows(self, lo, hi):
        """Return the rows of the ``lo:hi`` messages in receive order (a slice or indices)."""
        return slice(lo, hi) if self.order is None else self.order[lo:hi]

    def recv_ns(self, lo, hi):
        """Return the receive stamps (ns) of messages ``lo:hi`` in receive order."""
        if self.order is not None:
            return self.recv_sorted[lo:hi]
        return _ns((self.t if self.t_recv is None else self.t_recv)[lo:hi])

    def encode(self, lo, hi):
        """Return messages ``lo:hi`` in receive order, encoded: ``(hi - lo, size)`` uint8."""
        rows = self.rows(lo, hi)
        stamp = _ns(self.t[rows])
        cols = {f: x[rows] for f, x in self.columns.items()}
        if self.topic == '/link_torque':
            torque = np.zeros((hi - lo, 3))
            torque[:, 2] = cols['torque'][:, 0]
            cols = {'force': np.zeros((hi - lo, 3)), 'torque': torque}
        return _encode(self.raw, self.layout, stamp, cols)


def _merged(topics, block):
    """
    Yield ``(recvs, which)``: the next messages of all topics, at most ``block``.

    The messages of all topics in order of receive time, then topic, then their order
    within the topic (the stable sort of everything at once), ``block`` at a time: each
    round takes a window of ``block`` stamps of every topic, keeps what is at or before
    the smallest last stamp of the windows that do not reach their topic's end (all of
    the smallest keys, so the order is that of one global sort), sorts it and yields its
    first ``block``: ``recvs[k]``, the receive stamps of the next messages of topic ``k``
    (from where the last round stopped), and ``which``, the topic of each in file order.
    """
    pos = [0] * len(topics)
    while True:
        live = [k for k, tp in enumerate(topics) if pos[k] < tp.n]
        if not live:
            return
        wins = {k: topics[k].recv_ns(pos[k], min(topics[k].n, pos[k] + block)) for k in live}
        cut = min(((int(w[-1]), k, len(w) - 1) for k, w in wins.items()
                   if pos[k] + len(w) < topics[k].n), default=None)
        recv = np.concatenate([wins[k] for k in live])
        topic = np.concatenate([np.full(len(wins[k]), k, dtype=np.int64) for k in live])
        local = np.concatenate([np.arange(len(wins[k]), dtype=np.int64) for k in live])
        if cut is not None:
            r, k, i = cut
            keep = (recv < r) | ((recv == r) & ((topic < k) | ((topic == k) & (local <= i))))
            recv, topic, local = recv[keep], topic[keep], local[keep]
        order = np.lexsort((local, topic, recv))[:block]
        which = topic[order]
        counts = np.bincount(which, minlength=len(topics))
        yield {k: wins[k][:counts[k]] for k in live if counts[k]}, which
        for k in live:
            pos[k] += int(counts[k])


def _dump_yaml(data):
    from ruamel.yaml import YAML

    yaml = YAML(typ='safe')
    yaml.default_flow_style = False
    stream = io.StringIO()
    yaml.dump(data, stream)
    return stream.getvalue()


def _write_mcap(fh, typestore, topics, info):
    """Write the MCAP file of ``topics`` to ``fh``; return rosbag2's metadata of it."""
    from importlib.metadata import version

    out = McapStream(fh)
    out.start('ros2', f'rosbags-{version("rosbags")}')
    schemas = {}
    for tp in topics:                          # schemas first, then channels (as sealed)
        if tp.msgtype not in schemas:
            msgdef, _ = typestore.generate_msgdef(tp.msgtype, ros_version=2)
            fmt = 'ros2idl' if msgdef.startswith('=' * 80 + '\nIDL: ') else 'ros2msg'
            schemas[tp.msgtype] = out.register_schema(tp.msgtype, fmt, msgdef.encode())
    qos = _dump_yaml([]).strip()
    channels = [out.register_channel(tp.topic, 'cdr', schemas[tp.msgtype],
                                     {'offered_qos_profiles': qos}) for tp in topics]
    width = max((MESSAGE_HEADER + len(tp.raw) for tp in topics), default=1)
    block = max(1, min(WRITE_BLOCK, BLOCK_BYTES // width))
    pos = [0] * len(topics)
    lo, hi = 2**63 - 1, 0
    for recvs, which in _merged(topics, block):
        groups, remap = [], np.zeros(len(topics), dtype=np.intp)
        for k, r in recvs.items():
            data = topics[k].encode(pos[k], pos[k] + len(r))
            remap[k] = len(groups)
            groups.append((channels[k], r, r, data))
            pos[k] += len(r)
            lo, hi = min(lo, int(r.min())), max(hi, int(r.max()))
        out.add_messages(groups, remap[which])
    meta = info(pos, lo, hi)
    out.add_metadata('rosbag2', {'serialized_metadata': _dump_yaml(meta).strip()})
    out.finish()
    return meta


def _bagfile_information(typestore, topics, name, custom_data):
    """Return ``info(counts, first, last)``: rosbag2's metadata as rosbags writes it."""
    def info(counts, first, last):
        duration = max(0, last - first)
        count = int(sum(counts))
        return {
            'version': _VERSION,
            'storage_identifier': 'mcap',
            'relative_file_paths': [name],
            'duration': {'nanoseconds': duration},
            'starting_time': {'nanoseconds_since_epoch': first},
            'message_count': count,
            'topics_with_message_count': [
                {'topic_metadata': {'name': tp.topic, 'type': tp.msgtype,
                                    'serialization_format': 'cdr',
                                    'offered_qos_profiles': [],
                                    'type_description_hash': typestore.hash_rihs01(tp.msgtype)},
                 'message_count': int(c)}
                for tp, c in zip(topics, counts, strict=True)],
            'compression_format': '',
            'compression_mode': '',
            'files': [{'path': name, 'starting_time': {'nanoseconds_since_epoch': first},
                       'duration': {'nanoseconds': duration}, 'message_count': count}],
            'custom_data': {str(k): str(v) for k, v in custom_data.items()} or None,
            'ros_distro': 'rosbags',
        }
    return info


def write_recording(path: str | os.PathLike, topics: Recording | dict, *,
                    joint_name: str | None = None,
                    custom_data: dict[str, str] | None = None) -> str:
    """
    Write a recording (rosbag2 directory, or a single ``.mcap`` file) from arrays.

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
    custom_data : dict, optional
        ``{key: str}`` written into ``metadata.yaml`` (rosbag2's ``custom_data``, e.g.
        how an imported log was converted); not kept in a bare ``.mcap`` file.

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
    ``t_recv`` (then topic), :data:`WRITE_BLOCK` at a time, into zstd-compressed chunks with
    CRCs, a data-section and a summary CRC (as
    :func:`~friction_joint.bag.checksums.seal_recording` seals a file), so a flipped bit
    is found on reading.  Memory beyond the arrays given stays at a few blocks, whatever
    the length (stamps out of receive order within a topic are sorted first: 16 bytes a
    message of that topic).

    """
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
    prepared = [_Topic(typestore, t, spec, joint_name) for t, spec in topics.items()]

    parent = os.path.dirname(os.path.abspath(path))
    os.makedirs(parent, exist_ok=True)
    base = os.path.basename(os.path.normpath(path))
    tmp = tempfile.mkdtemp(prefix=f'.{base}.', suffix='.tmp', dir=parent)
    try:
        single = base.endswith('.mcap')
        bagdir = os.path.join(tmp, base[:-5] if single else base)
        os.mkdir(bagdir, 0o755)
        name = f'{os.path.basename(bagdir)}.mcap'
        info = _bagfile_information(typestore, prepared, name, custom_data or {})
        with open(os.path.join(bagdir, name), 'xb') as fh:
            meta = _write_mcap(fh, typestore, prepared, info)
        if single:
            os.rename(os.path.join(bagdir, name), path)
        else:
            with open(os.path.join(bagdir, 'metadata.yaml'), 'x', encoding='utf8') as fh:
                fh.write(_dump_yaml({'rosbag2_bagfile_information': meta}))
            os.rename(bagdir, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path
