# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
Completeness of a lockstep recording: every loop topic has every step.

In lockstep the simulator publishes, for each step k, ``/joint_states``,
``/joint_temperature``, ``/link_torque`` and ``/clock`` with stamp k dt; the
controller answers each state with a ``/joint_command`` and the estimator with
an ``/external_torque`` of the same stamp.  A complete recording therefore has
the same set of stamps on every loop topic, and as many ``/clock`` messages as
``/joint_states`` messages (the simulator re-sends the first state, with its
``/clock``, until the first command arrives).  :func:`check_lockstep` counts
what is there and names what is missing.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .topics import Recording

__all__ = ['LOOP_TOPICS', 'LoopTopicCount', 'LockstepCheck', 'check_lockstep']

#: topic -> Recording attribute of the topics that carry every step
LOOP_TOPICS = {'/joint_states': 'joint_states', '/joint_temperature': 'temperature',
               '/link_torque': 'link_torque', '/joint_command': 'joint_command',
               '/external_torque': 'external_torque'}


@dataclass
class LoopTopicCount:
    """
    One loop topic of a lockstep recording.

    Attributes
    ----------
    topic : str
        Topic name.
    count : int
        Messages recorded (repeats of the same message included).
    steps : int
        Distinct stamps among them.
    missing : int
        Steps of ``/joint_states`` without a message on this topic (for
        ``/clock``: ``/joint_states`` messages minus ``/clock`` messages).
    first_missing : float or None
        Stamp (s) of the first missing step.

    """

    topic: str
    count: int
    steps: int
    missing: int
    first_missing: float | None = None


@dataclass
class LockstepCheck:
    """
    Result of :func:`check_lockstep`.

    Attributes
    ----------
    steps : int
        Distinct ``/joint_states`` stamps (the steps recorded).
    topics : list of LoopTopicCount
        One entry per loop topic present, ``/clock`` last if recorded.
    absent : list of str
        Loop topics the recording does not have.

    """

    steps: int
    topics: list[LoopTopicCount] = field(default_factory=list)
    absent: list[str] = field(default_factory=list)

    @property
    def complete(self):
        """Whether no loop topic misses a step and none is absent."""
        return not self.absent and all(t.missing == 0 for t in self.topics)

    def to_dict(self) -> dict:
        """Return a plain JSON-able dict (``complete`` included)."""
        return {'steps': self.steps, 'complete': self.complete, 'absent': list(self.absent),
                'topics': [asdict(t) for t in self.topics]}

    def describe(self) -> str:
        """Return one line: counts per topic and what is missing."""
        parts = []
        for t in self.topics:
            where = f' from {t.first_missing:.4f} s' if t.first_missing is not None else ''
            lost = f' ({t.missing} missing{where})' if t.missing else ''
            parts.append(f'{t.topic} {t.count}{lost}')
        parts += [f'{topic} absent' for topic in self.absent]
        state = 'complete' if self.complete else 'INCOMPLETE'
        return f'{self.steps} steps, {state}: ' + ', '.join(parts)


def check_lockstep(recording: Recording) -> LockstepCheck:
    """
    Check that every loop topic of a lockstep ``recording`` has every step.

    Parameters
    ----------
    recording : Recording
        A recording read with :func:`~friction_joint.bag.read_recording`.

    Returns
    -------
    LockstepCheck

    """
    raw = {topic: count for topic, (_, count) in recording.topics.items()}
    steps = np.unique(np.round(recording.joint_states.t * 1e9).astype(np.int64))
    result = LockstepCheck(steps=int(steps.size))
    for topic, attr in LOOP_TOPICS.items():
        data = getattr(recording, attr)
        if data is None:
            result.absent.append(topic)
            continue
        have = np.unique(np.round(data.t * 1e9).astype(np.int64))
        lost = np.setdiff1d(steps, have)
        result.topics.append(LoopTopicCount(
            topic, int(raw.get(topic, len(data))), int(have.size), int(lost.size),
            float(lost[0] * 1e-9) if lost.size else None))
    if '/clock' in raw:
        short = max(0, raw.get('/joint_states', 0) - raw['/clock'])
        result.topics.append(LoopTopicCount('/clock', int(raw['/clock']), int(raw['/clock']),
                                            int(short), None))
    return result
