# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The QoS profiles of this package, defined once.

* :func:`stream_qos`: the contract topics between the nodes (reliable,
  volatile; keep-last :data:`QOS_DEPTH`, or keep-all where nothing may be lost);
* :func:`recorder_qos`: what the recorder subscribes with;
* :func:`replay_qos`: what replay publishes with;
* :data:`READY_TOPIC` / :data:`READY_QOS`: the recorder's readiness
  announcement (``std_msgs/String``, the sorted comma-separated topics on which
  it has matched a publisher; transient-local, so a late joiner gets the
  newest), which ``joint_sim``'s ``wait_recorder`` waits for;
* :data:`DDS_PROFILE` / :func:`dds_environ`: the Fast DDS profile every
  process of the package uses unless the environment names one (a larger
  shared-memory segment and 20 ms heartbeats: a recorder taking 18 000
  messages/s keeps up; see the file ``fastdds.xml``);
* :func:`overridable`: the standard ``qos_overrides.<topic>.<entity>.<policy>``
  parameters for a node's publishers and subscriptions (users retune a
  topic's QoS with ``-p qos_overrides./joint_states.publisher.depth:=100``).
"""
from __future__ import annotations

from collections.abc import Mapping, MutableMapping, Sequence
import os

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import QoSOverridingOptions

__all__ = ['DDS_PROFILE', 'dds_environ', 'QOS_DEPTH', 'CLOCK_QOS', 'READY_TOPIC', 'READY_QOS',
           'stream_qos', 'recorder_qos',
           'replay_qos', 'overridable']

#: the Fast DDS profile of the package's processes (shared-memory segment, heartbeats)
DDS_PROFILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'fastdds.xml')
_PROFILE_VARIABLES = ('FASTRTPS_DEFAULT_PROFILES_FILE', 'FASTDDS_DEFAULT_PROFILES_FILE')


def dds_environ(env: Mapping[str, str] | None = None) -> MutableMapping[str, str]:
    """
    Return ``env`` with :data:`DDS_PROFILE` as the Fast DDS profile; ``None``: set it here.

    An environment that names a profile already (``FASTRTPS_DEFAULT_PROFILES_FILE``
    or ``FASTDDS_DEFAULT_PROFILES_FILE``) is left as it is.  With ``env=None``
    the variable is set in ``os.environ`` (call before ``rclpy.init``) and
    ``os.environ`` is returned.
    """
    target = os.environ if env is None else dict(env)
    if not set(_PROFILE_VARIABLES) & set(target):
        target['FASTRTPS_DEFAULT_PROFILES_FILE'] = DDS_PROFILE
    return target


#: keep-last depth of the topics' QoS (and of the recorder's /clock subscription)
QOS_DEPTH = 1000

#: /clock as published by the simulator (rclpy's use_sim_time subscriber is best effort)
#: the lockstep simulator's /clock: reliable keep-all, so a recorder loses no tick
#: (rclpy's own time source subscribes best effort and never slows it down)
CLOCK_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.VOLATILE)

#: the recorder's readiness topic (relative: follows the recorder's namespace)
READY_TOPIC = 'recorder_ready'
#: its QoS: reliable, transient-local keep-last 1 (a subscriber joining late gets the newest)
READY_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                       reliability=ReliabilityPolicy.RELIABLE,
                       durability=DurabilityPolicy.TRANSIENT_LOCAL)


def stream_qos(lossless: bool = False) -> QoSProfile:
    """
    Reliable, volatile QoS of the contract topics.

    Parameters
    ----------
    lossless : bool
        Keep-all history (for publishers in lockstep / synchronised runs): a sample
        that a subscriber (the recorder, say) has not acknowledged stays queued until
        DDS has repaired it.  The default keep-last ``QOS_DEPTH`` lets a publisher run
        in real time past a stalled subscriber, which then loses the samples pushed
        out of the queue before they were repaired.

    """
    if lossless:
        return QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.VOLATILE)
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=QOS_DEPTH,
                      reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)


def recorder_qos(topic: str, offered: Sequence[QoSProfile] = ()) -> QoSProfile:
    """
    Return the recorder's QoS for ``topic``.

    Reliable keep-all for every topic (a recorder that falls behind for a
    moment must not let its queue overwrite messages it has acknowledged).
    For ``/clock``, whose publishers differ (rclpy's time source and some
    simulators publish it best effort), the reliability follows ``offered``
    (the :class:`rclpy.qos.QoSProfile` of the publishers seen at subscription
    time): best effort, keep-last :data:`QOS_DEPTH`, if any of them is best
    effort (a reliable subscription would not match it), else reliable keep-all.
    """
    best_effort = any(q.reliability == ReliabilityPolicy.BEST_EFFORT for q in offered)
    if topic == '/clock' and best_effort:
        return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=QOS_DEPTH,
                          reliability=ReliabilityPolicy.BEST_EFFORT,
                          durability=DurabilityPolicy.VOLATILE)
    return QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)


def replay_qos() -> QoSProfile:
    """Return replay's publisher QoS: reliable keep-all, so no sample is pushed out unrepaired."""
    return QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.VOLATILE)


def overridable() -> QoSOverridingOptions:
    """Return the options that declare the standard ``qos_overrides.*`` parameters of an entity."""
    return QoSOverridingOptions.with_default_policies()
