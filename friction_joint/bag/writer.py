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
Writing recordings from numpy arrays (tests, offline simulator runs, experiments).

See :mod:`friction_joint.bag.topics` for the topics and fields.
"""
from dataclasses import fields
import os
import shutil
import tempfile

import numpy as np

from ._cdr import WALKERS
from .checksums import seal_recording
from .topics import CONTRACT_TYPES, NS, Recording
from ..exceptions import RecordingError

__all__ = ['write_recording']


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


def _stamp_ns(topic, name, t, n=None):
    t = np.asarray(t, dtype=float).reshape(-1)
    if n is not None and len(t) != n:
        raise RecordingError(f'{topic}: {name} has {len(t)} values for {n} messages')
    if not np.all(np.isfinite(t)) or np.any(t < 0) or np.any(t >= 2**31):
        raise RecordingError(f'{topic}: {name} must be finite times in [0, 2^31) s')
    return np.round(t * NS).astype(np.int64)


def _column(topic, name, x, n, k):
    x = np.asarray(x, dtype=float)
    if x.ndim == 1 and k == 1:
        x = x[:, None]
    if x.shape != (n, k):
        raise RecordingError(f'{topic}: {name} has shape {x.shape}, expected ({n},)'
                             + (f' or ({n}, {k})' if k > 1 else ''))
    return x


def _encode(typestore, msgtype, template, n, stamp, columns):
    """
    Serialize ``n`` messages: ``template`` with stamps and float64 ``columns`` replaced.

    ``columns`` maps a layout field to an ``(n, count)`` array.
    """
    raw = typestore.serialize_cdr(template, msgtype)
    layout = WALKERS[msgtype](raw)
    block = np.tile(np.frombuffer(raw, dtype=np.uint8), (n, 1))
    block[:, 4:8] = (stamp // NS).astype('<i4').view(np.uint8).reshape(n, 4)
    block[:, 8:12] = (stamp % NS).astype('<u4').view(np.uint8).reshape(n, 4)
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


def write_recording(path, topics, joint_name=None, *, custom_data=None):
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
    ``t_recv`` (then topic) by rosbags' writer, and the MCAP file is then sealed
    (:func:`~friction_joint.bag.checksums.seal_recording`: zstd-compressed chunks with
    CRCs, data-section and summary CRCs), so a flipped bit is found on reading.

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
            for key, value in (custom_data or {}).items():
                writer.set_custom_data(str(key), str(value))
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
        seal_recording(bagdir)
        if base.endswith('.mcap'):
            made = [f for f in os.listdir(bagdir) if f.endswith('.mcap')]
            os.rename(os.path.join(bagdir, made[0]), path)
        else:
            os.rename(bagdir, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return path
