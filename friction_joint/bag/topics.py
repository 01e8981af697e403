# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The topics of a recording and the numpy arrays they are read into.

A recording is a rosbag2 directory (``metadata.yaml`` + ``.mcap``, CDR, ROS 2
Jazzy message definitions) or a single ``.mcap`` file, with the topics of the
docs/interfaces.md (topics and recordings).  Only ``/joint_states`` is
required (:data:`REQUIRED_TOPICS`); every other topic, ``/joint_temperature``
included, is optional and its attribute of :class:`Recording` is None when the
recording lacks it (or has no message on it).
:func:`~friction_joint.bag.read_recording` turns one into a :class:`Recording`
of per-topic arrays; :func:`~friction_joint.bag.write_recording` writes one
from arrays (tests, offline simulator runs, identification experiments).

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
Messages are returned sorted by header stamp; the stamps are checked on reading
(:mod:`~friction_joint.bag.stamps`: stamps that go backwards are an error, a
message delivered late is sorted into place, a message sent twice is read
once).  ``q_d``/``qd_d`` are NaN where a command message carries no reference;
everything else must be finite and plausible (:mod:`~friction_joint.bag.plausible`).

Decoding does not go through a generic deserializer: the messages of one
topic nearly always share one byte layout (same frame id, joint names and
array lengths), so each layout is parsed once and all messages sharing it are
decoded as columns of one numpy array (about 3 µs per message in total,
dominated by reading the file).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..exceptions import MissingTopicError, RecordingError

__all__ = ['CONTRACT_TYPES', 'REQUIRED_TOPICS', 'NS', 'JointStates', 'Temperature', 'LinkTorque',
           'JointCommand', 'ExternalTorque', 'Recording', 'zero_order_hold']

#: topic -> message type of the contract (section 2)
CONTRACT_TYPES = {
    '/joint_states': 'sensor_msgs/msg/JointState',
    '/joint_temperature': 'sensor_msgs/msg/Temperature',
    '/link_torque': 'geometry_msgs/msg/WrenchStamped',
    '/joint_command': 'sensor_msgs/msg/JointState',
    '/external_torque': 'sensor_msgs/msg/JointState',
    '/clock': 'rosgraph_msgs/msg/Clock',
}

#: topics every recording has (section 3); ``/joint_temperature`` is optional
REQUIRED_TOPICS = ('/joint_states',)

#: nanoseconds per second
NS = 1_000_000_000


# --------------------------------------------------------------------------- data classes

@dataclass(frozen=True)
class JointStates:
    """
    ``/joint_states`` of one joint.

    Attributes
    ----------
    t, t_recv : numpy.ndarray
        Header and receive stamps (s).
    q : numpy.ndarray
        Position (rad).
    qd : numpy.ndarray
        Velocity (rad/s).
    effort : numpy.ndarray
        Drive torque τ (N m).
    skipped : int
        Messages that did not name the joint.

    """

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
    """
    ``/joint_temperature``: housing temperature ``xi`` (°C).

    Attributes
    ----------
    t, t_recv : numpy.ndarray
        Header and receive stamps (s).
    xi : numpy.ndarray
        Housing temperature (°C).
    variance : numpy.ndarray
        The sensor's variance.

    """

    t: np.ndarray
    t_recv: np.ndarray
    xi: np.ndarray
    variance: np.ndarray

    def __len__(self):
        return len(self.t)


@dataclass(frozen=True)
class LinkTorque:
    """
    ``/link_torque``: the measured τ_ext.

    Attributes
    ----------
    t, t_recv : numpy.ndarray
        Header and receive stamps (s).
    tau : numpy.ndarray
        Measured τ_ext (N m).

    """

    t: np.ndarray
    t_recv: np.ndarray
    tau: np.ndarray

    def __len__(self):
        return len(self.t)


@dataclass(frozen=True)
class JointCommand:
    """
    ``/joint_command``: commanded ``effort`` (N m), desired ``q_d``, ``qd_d``.

    Attributes
    ----------
    t, t_recv : numpy.ndarray
        Header and receive stamps (s).
    effort : numpy.ndarray
        Commanded torque (N m).
    q_d, qd_d : numpy.ndarray
        Desired position (rad) and velocity (rad/s); NaN where the message has
        no reference.
    skipped : int
        Messages that did not name the joint.

    """

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
    """
    ``/external_torque``: estimated τ̂_ext ``effort`` (N m).

    Attributes
    ----------
    t, t_recv : numpy.ndarray
        Header and receive stamps (s).
    effort : numpy.ndarray
        Estimated τ̂_ext (N m).
    skipped : int
        Messages that did not name the joint.

    """

    t: np.ndarray
    t_recv: np.ndarray
    effort: np.ndarray
    skipped: int = 0

    def __len__(self):
        return len(self.t)


def zero_order_hold(t_src: ArrayLike, x_src: ArrayLike, t: ArrayLike) -> np.ndarray:
    """
    Sample ``x_src(t_src)`` at ``t`` holding the last value (zero-order hold).

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
    """
    A recording of one joint as numpy arrays (see the module docstring for the fields).

    Attributes
    ----------
    path : str
        Where it was read from.
    joint_name : str
        The joint picked from the JointState topics.
    joint_states : JointStates
        Always present.
    temperature : Temperature or None
        ``/joint_temperature``; None when the recording has no temperature messages
        (measured data without a temperature sensor, imported logs).
    link_torque, joint_command, external_torque : LinkTorque, JointCommand, ExternalTorque or None
        Present if the recording has the topic.
    topics : dict
        Every topic of the bag -> ``(message type, message count)``, including ones not read.
    unordered : dict
        Topic -> number of messages delivered late (their header stamp is older than one
        before them in bag order; they fill a hole in the stamps and are sorted into
        place).
    duplicates : dict
        Topic -> number of repeated copies of a message (same stamp, same bytes, one
        after the other) left out.

    """

    path: str
    joint_name: str
    joint_states: JointStates
    temperature: Temperature | None = None
    link_torque: LinkTorque | None = None
    joint_command: JointCommand | None = None
    external_torque: ExternalTorque | None = None
    topics: dict[str, tuple[str, int]] = field(default_factory=dict)
    unordered: dict[str, int] = field(default_factory=dict)
    duplicates: dict[str, int] = field(default_factory=dict)

    @property
    def t0(self):
        """First joint-state stamp (s)."""
        return float(self.joint_states.t[0])

    @property
    def duration(self):
        """Joint-state time span (s)."""
        return float(self.joint_states.t[-1] - self.joint_states.t[0])

    def temperature_at(self, *, t: ArrayLike | None = None) -> np.ndarray:
        """
        Return the housing temperature ξ at ``t``, zero-order hold.

        Parameters
        ----------
        t : array_like, optional
            Times (s); default the joint-state stamps.

        Returns
        -------
        numpy.ndarray
            Temperature (°C) at each time.

        Raises
        ------
        MissingTopicError
            The recording has no ``/joint_temperature`` messages (``temperature`` is None);
            its ``topic`` is ``/joint_temperature``.

        """
        if self.temperature is None or len(self.temperature) == 0:
            raise MissingTopicError(f'{self.path}: no /joint_temperature topic: the recording '
                                    'has no gear housing temperature', topic='/joint_temperature',
                                    path=str(self.path))
        t = self.joint_states.t if t is None else t
        return zero_order_hold(self.temperature.t, self.temperature.xi, t)

    def series(self) -> dict[str, JointStates | Temperature | LinkTorque | JointCommand
                             | ExternalTorque]:
        """Return topic -> data class of every topic present (:func:`write_recording` takes it)."""
        pairs = (('/joint_states', self.joint_states), ('/joint_temperature', self.temperature),
                 ('/link_torque', self.link_torque), ('/joint_command', self.joint_command),
                 ('/external_torque', self.external_torque))
        return {k: v for k, v in pairs if v is not None}

    def summary(self) -> dict:
        """Return duration, counts, mean rates and largest gaps per topic, as a JSON-able dict."""
        topics = {}
        for topic, data in self.series().items():
            entry = _span_stats(data.t)
            skipped = getattr(data, 'skipped', 0)
            if skipped:
                entry['skipped'] = int(skipped)
            if self.unordered.get(topic):
                entry['unordered'] = int(self.unordered[topic])
            if self.duplicates.get(topic):
                entry['duplicates'] = int(self.duplicates[topic])
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
            extra = ''.join(f', {k} {e[k]}' for k in ('skipped', 'unordered', 'duplicates')
                            if k in e)
            lines.append(f'  {topic}: {e["count"]} messages, {rate}{gap}{extra}')
        for topic, e in s['other_topics'].items():
            lines.append(f'  {topic}: {e["count"]} messages ({e["type"]}, not read)')
        return '\n'.join(lines)
