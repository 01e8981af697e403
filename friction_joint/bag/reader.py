# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Reading recordings (rosbag2 directory or single ``.mcap`` file) into numpy arrays.

See :mod:`friction_joint.bag.topics` for the topics and fields.  What is checked on
reading: every file of the recording before anything opens it
(:mod:`~friction_joint.bag.gate`: no FIFO, device or unreadable file, a
``metadata.yaml`` that parses; one-line errors), that the file is not cut short
(a recorder killed before it finished: the error names the ``friction_joint recover``
command,
:func:`~friction_joint.bag.staging.partial_recording_error`), the file's
checksums (:mod:`~friction_joint.bag.checksums`), the message types, NaN/inf,
the header stamps of every topic (:mod:`~friction_joint.bag.stamps`; a nanosecond
field of 1e9 or more, or a negative stamp, is an error), absurd values
(:mod:`~friction_joint.bag.plausible`) and, across topics and signals
(:mod:`~friction_joint.bag.consistency`), one clock for every topic, a velocity that is
the derivative of the position and temperatures within physical bounds.
"""
from __future__ import annotations

from collections.abc import Iterable, Iterator
import os
from pathlib import Path
import struct

import numpy as np

from ._cdr import f64_columns, layout_groups, stamps_ns, walk_joint_state
from .checksums import mcap_files, verify_checksums
from .consistency import check_contents, check_negative_stamps, position_derivative
from .gate import check_recording_files, read_metadata
from .staging import partial_recording_error
from .stamps import stamp_order
from .topics import (CONTRACT_TYPES, ExternalTorque, JointCommand, JointStates, LinkTorque, NS,
                     Recording, REQUIRED_TOPICS, Temperature)
from ..exceptions import MissingTopicError, RecordingError
from ..inputs import open_input

__all__ = ['recording_custom_data', 'read_recording', 'recording_topics', 'iter_messages']


def _decode_joint_state(raws, topic, joint, required):
    """
    Stamps (ns), columns, kept-message mask and joint names seen, of ``joint``.

    ``topic`` names the recording and topic in errors.  ``required`` names the fields
    that must be present; others are NaN where absent.
    """
    n = len(raws)
    stamp = np.zeros(n, dtype=np.int64)
    keep = np.zeros(n, dtype=bool)
    cols = {k: np.full(n, np.nan) for k in ('position', 'velocity', 'effort')}
    missing = dict.fromkeys(required, 0)
    seen = {}
    for idx, layout, block in layout_groups(raws, 'sensor_msgs/msg/JointState', topic):
        names = layout.names
        seen.update(dict.fromkeys(names))
        if joint in names:
            j = names.index(joint)
        elif not names and all(c <= 1 for _, c in layout.fields.values()):
            j = 0                                  # anonymous single-joint message
        else:
            continue
        stamp[idx] = stamps_ns(block, topic, idx)
        keep[idx] = True
        for name, (off, count) in layout.fields.items():
            if count == 0:
                if name in missing:
                    missing[name] += len(idx)
                continue
            if count != max(len(names), 1):
                raise RecordingError(f'{topic}: malformed JointState: {count} {name} values '
                                     f'for {len(names)} names')
            cols[name][idx] = f64_columns(block, off + 8 * j, 1)[:, 0]
    for name, k in missing.items():
        if k:
            raise RecordingError(f'{topic}: {k} messages have no {name} for joint {joint!r}')
    return stamp, cols, keep, list(seen)


def _decode_fixed(raws, topic, msgtype, picks):
    """Stamps and ``picks`` (out name -> (field, index)) of fixed-layout messages."""
    n = len(raws)
    stamp = np.zeros(n, dtype=np.int64)
    cols = {k: np.full(n, np.nan) for k in picks}
    for idx, layout, block in layout_groups(raws, msgtype, topic):
        stamp[idx] = stamps_ns(block, topic, idx)
        for out, (name, i) in picks.items():
            off, _ = layout.fields[name]
            cols[out][idx] = f64_columns(block, off + 8 * i, 1)[:, 0]
    return stamp, cols


def _check_finite(topic, cols):
    bad = {k: int(np.count_nonzero(~np.isfinite(v))) for k, v in cols.items()}
    bad = {k: v for k, v in bad.items() if v}
    if bad:
        total = sum(bad.values())
        detail = ', '.join(f'{k} {v}' for k, v in bad.items())
        raise RecordingError(f'{topic}: {total} NaN/inf values ({detail})')


def _ordered(stamp, recv, cols, check):
    """
    Put one topic in stamp order; return t, t_recv, columns, late and duplicate counts.

    ``check``: ``(label, same(i, j), message indices)`` for :func:`stamp_order`; None
    only sorts (counting the backward steps as late).
    """
    if check is None:
        order = np.argsort(stamp, kind='stable')
        late, dups = int(np.count_nonzero(np.diff(stamp) < 0)), 0
    else:
        label, same, index = check
        order, late, dups = stamp_order(stamp, same, index, label)
    return (stamp[order] / NS, recv[order] / NS, {k: v[order] for k, v in cols.items()},
            late, dups)


def _verify(path):
    """Check the checksums of the recording's MCAP files (CRC 0: none recorded)."""
    for f in mcap_files(path):
        try:
            verify_checksums(f, label=path)
        except OSError as exc:
            raise RecordingError(f'{path}: cannot read {f.name}: {exc}') from None


def _corrupt(path, exc):
    """Return the RecordingError for an exception rosbags raised while reading messages."""
    text = ' '.join(f'{type(exc).__name__}: {exc}'.split())
    if 'checksum' in str(exc).lower():
        return RecordingError(f'{path}: truncated or corrupt recording: a chunk fails its '
                              f'checksum, the file changed after it was written ({text})')
    return RecordingError(f'{path}: truncated or corrupt recording ({text})')


def _open_reader(path, verify=False):
    try:
        from rosbags.rosbag2 import Reader
    except ImportError as exc:                    # pragma: no cover - packaging problem
        raise RecordingError(f'reading recordings needs the rosbags package ({exc})') from None
    p = Path(path)
    check_recording_files(path)                   # FIFOs, devices, unreadable files: refused
    partial = partial_recording_error(path)       # a killed recorder's file: how to recover
    if partial is not None:
        raise partial
    if p.is_dir():
        if not (p / 'metadata.yaml').exists():
            raise RecordingError(f'{path} is not a rosbag2 recording: no metadata.yaml '
                                 '(pass the .mcap file itself to read a bare MCAP file)')
    elif p.suffix not in ('.mcap', '.db3'):
        raise RecordingError(f'{path} is not a recording: expected a rosbag2 directory or '
                             'a .mcap file')
    if verify:
        _verify(path)
    try:
        reader = Reader(p)
        reader.open()
    except Exception as exc:                       # rosbags raises various types
        text = ' '.join(f'{type(exc).__name__}: {exc}'.split())
        raise RecordingError(f'{path}: cannot open recording, truncated or corrupt '
                             f'({text})') from None
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
    reader = _open_reader(path, verify=True)
    try:
        topics = _topic_table(reader, path)
        for topic, (msgtype, _) in topics.items():
            expected = CONTRACT_TYPES.get(topic)
            if expected and msgtype != expected:
                raise RecordingError(f'{path}: {topic} has message type {msgtype}, '
                                     f'expected {expected}')
        for topic in REQUIRED_TOPICS:
            if topic not in topics:
                raise MissingTopicError(f'{path}: no {topic} topic (topics: '
                                        f'{", ".join(sorted(topics)) or "none"})',
                                        topic=topic, path=os.fspath(path))
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
            raise _corrupt(path, exc) from None
        for topic, (raws, _recv) in data.items():
            topics[topic] = (topics[topic][0], len(raws))
        return topics, {k: (v[0], np.asarray(v[1], dtype=np.int64)) for k, v in data.items()}
    finally:
        _close(reader)


def recording_topics(path: str | os.PathLike) -> dict[str, tuple[str, int]]:
    """
    Return ``{topic: (message type, count)}`` of a recording, reading no messages.

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 directory or a single ``.mcap`` file.

    Returns
    -------
    dict
        Topic -> ``(message type, message count)``.

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


def iter_messages(path: str | os.PathLike, *, topics: Iterable[str] | None = None
                  ) -> Iterator[tuple[str, str, int, bytes]]:
    """
    Yield the serialized messages of a recording in bag-time order.

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
    reader = _open_reader(path, verify=True)
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
                raise _corrupt(path, exc) from None
            yield con.topic, con.msgtype, stamp, bytes(raw)
    finally:
        _close(reader)


def recording_custom_data(path: str | os.PathLike) -> dict[str, str]:
    """
    Return the custom data of a recording's rosbag2 metadata (e.g. how a log was imported).

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 directory (its ``metadata.yaml``) or a single ``.mcap`` file (its
        ``rosbag2`` metadata record).

    Returns
    -------
    dict
        ``custom_data`` (key -> str); empty when there is none or it cannot be read
        (reading the recording itself reports a broken file).

    """
    path = os.fspath(path)
    meta = os.path.join(path, 'metadata.yaml')
    try:                                            # through the input gate: no FIFO, no device
        if os.path.isdir(path):
            doc = read_metadata(meta) if os.path.isfile(meta) else None
        else:
            doc = _mcap_rosbag2_metadata(path)
        custom = doc.get('custom_data') if isinstance(doc, dict) else None
    except Exception:                               # any unreadable file: no custom data
        return {}
    return {str(k): str(v) for k, v in custom.items()} if isinstance(custom, dict) else {}


def _mcap_rosbag2_metadata(path):
    """Return rosbag2's metadata kept in a single ``.mcap`` file's metadata record (or None)."""
    import yaml
    from mcap.reader import make_reader
    with open_input(path, kind='recording', error=RecordingError) as fh:
        for record in make_reader(fh).iter_metadata():
            if record.name == 'rosbag2':
                doc = yaml.safe_load(record.metadata.get('serialized_metadata', ''))
                if isinstance(doc, dict):
                    return doc.get('rosbag2_bagfile_information', doc)
                return None
    return None


def read_recording(path: str | os.PathLike, *, joint_name: str | None = None,
                   check: bool = True, velocity_from_position: bool = False) -> Recording:
    """
    Read a recording into arrays.

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 directory (``metadata.yaml`` + ``.mcap``) or a single ``.mcap`` file.
    joint_name : str, optional
        Joint to pick from the JointState topics; default: the first name of the first
        ``/joint_states`` message.  Messages that do not name the joint are skipped and
        counted (``skipped``); messages without names (one anonymous joint) are taken.
    check : bool
        Check the header stamps of every topic (:mod:`~friction_joint.bag.stamps`), the
        values for absurd samples (:mod:`~friction_joint.bag.plausible`) and the topics
        against each other (:mod:`~friction_joint.bag.consistency`).  ``False``
        reads a broken recording for inspection: messages are only sorted by stamp.
    velocity_from_position : bool
        Replace the recorded velocity of ``/joint_states`` by the centred difference of
        its position (:func:`~friction_joint.bag.consistency.position_derivative`), e.g.
        for a velocity in other units than the position (``--velocity-from-position``).

    Returns
    -------
    Recording
        ``temperature`` is None when the recording has no ``/joint_temperature``
        messages (a log without a temperature sensor); likewise the other optional
        topics.

    Raises
    ------
    RecordingError
        The path is missing or not a recording, the file is truncated or corrupt or fails
        its checksums, the required topic ``/joint_states`` is missing or empty (the
        other topics are optional: ``temperature``, ``link_torque``, ... are None when
        the recording has no message on them), a contract topic has the wrong message
        type, no message names the joint (the message lists the joints the recording
        has), data are NaN/inf,
        header stamps go backwards (a reversed stretch, overlapping runs, a message too
        late), two different messages have the same stamp, a stamp is negative or
        malformed, a value is absurd, a topic is on another clock than ``/joint_states``,
        the velocity disagrees with the position, or a temperature is outside physical
        bounds (:mod:`~friction_joint.bag.consistency`).  The message names the file, the
        topic and where.

    """
    path = os.fspath(path)
    wanted = [t for t in CONTRACT_TYPES if t != '/clock']
    topics, data = _read_raw(path, wanted)
    for topic in REQUIRED_TOPICS:
        if not data[topic][0]:
            raise MissingTopicError(f'{path}: {topic} has no messages', topic=topic, path=path)

    js_raws, js_recv = data['/joint_states']
    if joint_name is None:
        try:
            names = walk_joint_state(js_raws[0]).names
        except (ValueError, struct.error) as exc:
            raise RecordingError(f'{path}: /joint_states: message 0 is not a valid '
                                 f'sensor_msgs/msg/JointState: {exc}') from None
        joint_name = names[0] if names else ''

    unordered, duplicates = {}, {}

    def order(topic, raws, keep, stamp, recv, cols):
        idx = np.flatnonzero(keep) if keep is not None else np.arange(len(raws))
        spec = None
        if check:
            check_negative_stamps(f'{path}: {topic}', stamp[idx] / NS, idx)
            spec = (f'{path}: {topic}', lambda a, b: raws[idx[a]] == raws[idx[b]], idx)
        t, t_recv, cols, late, dups = _ordered(stamp[idx], recv[idx],
                                               {k: v[idx] for k, v in cols.items()}, spec)
        if late:
            unordered[topic] = late
        if dups:
            duplicates[topic] = dups
        return t, t_recv, cols

    def joint_topic(topic, required, rename):
        raws, recv = data[topic]
        label = f'{path}: {topic}'
        stamp, cols, keep, seen = _decode_joint_state(raws, label, joint_name, required)
        skipped = int(len(raws) - np.count_nonzero(keep))
        cols = {rename[k]: v for k, v in cols.items() if k in rename}
        _check_finite(label, {k: v[keep] for k, v in cols.items()
                              if k in {rename[r] for r in required}})
        t, t_recv, cols = order(topic, raws, keep, stamp, recv, cols)
        return t, t_recv, cols, skipped, seen

    t, t_recv, c, skipped, seen = joint_topic(
        '/joint_states', ('position', 'velocity', 'effort'),
        {'position': 'q', 'velocity': 'qd', 'effort': 'effort'})
    if len(t) == 0:
        have = ', '.join(map(repr, seen))
        raise RecordingError(f'{path}: no /joint_states message names joint {joint_name!r}; '
                             f'the recording has joint(s) {have} (pass one as the joint name, '
                             '--joint on the command line)')
    qd = position_derivative(t, c['q']) if velocity_from_position else c['qd']
    joint_states = JointStates(t, t_recv, c['q'], qd, c['effort'], skipped)

    def fixed_topic(topic, picks):
        raws, recv = data[topic]
        stamp, cols = _decode_fixed(raws, f'{path}: {topic}', CONTRACT_TYPES[topic], picks)
        _check_finite(f'{path}: {topic}', cols)
        return order(topic, raws, None, stamp, recv, cols)

    temperature = link_torque = joint_command = external_torque = None
    if data.get('/joint_temperature', ((),))[0]:
        t, t_recv, c = fixed_topic('/joint_temperature', {'xi': ('temperature', 0),
                                                          'variance': ('variance', 0)})
        temperature = Temperature(t, t_recv, c['xi'], c['variance'])
    if data.get('/link_torque', ((),))[0]:
        t, t_recv, c = fixed_topic('/link_torque', {'tau': ('torque', 2)})
        link_torque = LinkTorque(t, t_recv, c['tau'])
    if data.get('/joint_command', ((),))[0]:
        t, t_recv, c, skipped, _ = joint_topic(
            '/joint_command', ('effort',),
            {'position': 'q_d', 'velocity': 'qd_d', 'effort': 'effort'})
        joint_command = JointCommand(t, t_recv, c['effort'], c['q_d'], c['qd_d'], skipped)
    if data.get('/external_torque', ((),))[0]:
        t, t_recv, c, skipped, _ = joint_topic('/external_torque', ('effort',),
                                               {'effort': 'effort'})
        external_torque = ExternalTorque(t, t_recv, c['effort'], skipped)

    rec = Recording(path=path, joint_name=joint_name, joint_states=joint_states,
                    temperature=temperature, link_torque=link_torque,
                    joint_command=joint_command, external_torque=external_torque,
                    topics=topics, unordered=unordered, duplicates=duplicates)
    if check:
        check_contents(rec)
    return rec
