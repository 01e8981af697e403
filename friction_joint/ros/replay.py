# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint replay BAG``: publish a recording again, with its timing and a ``/clock``.

Messages are published in bag order as the serialized bytes stored in the bag
(no deserialization), spaced by their bag (receive) times divided by
``--rate`` (at least :data:`MIN_RATE`); ``--rate max`` publishes as fast as
possible, still in order (``rate=0`` in :func:`replay`).  ``--rate 0`` is
refused: a time scale of 0 would never reach the second message.

``/clock`` (``rosgraph_msgs/msg/Clock``) is published so that nodes with
``use_sim_time`` run unchanged on recorded data: before each message whose
header stamp is ahead of the clock, the clock is advanced to that stamp (the
clock follows the data's own time base, which is simulated time for simulator
recordings).  The bag's own ``/clock`` is then not replayed; with
``--no-clock`` nothing is generated and the bag's ``/clock`` (if any) is
replayed like any topic.  With ``--loop`` the data start over and so does the
clock (time jumps back, as with ``ros2 bag play --loop``).

Before playing, the publishers wait up to ``--wait`` seconds until every topic
has a subscriber (DDS drops what is published before a subscriber is matched),
then ``--settle`` seconds for the subscribers' side of the match; at the end
they wait until reliable subscribers have acknowledged everything.  The
publishers are reliable with keep-all history: a sample a subscriber has not
acknowledged yet (lost in transport on a busy machine, say) stays queued until
DDS has repaired it, instead of being pushed out by newer ones.  A subscriber
that stops taking messages altogether ends the replay with an error once its
queue is full.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import math
import os
import struct
import sys
import threading
import time

from ._rclpy import RCLError
from .qos import dds_environ, replay_qos
from .record import install_signals, message_class
from .startup import check_domain_id, init_context
from ..bag import iter_messages, recording_topics
from ..exceptions import RecordingError

__all__ = ['replay', 'parse_rate', 'MIN_RATE', 'MAX_WAIT']

#: the slowest replay: a thousand times slower than recorded
MIN_RATE = 1.0e-3
#: s: the longest --wait / --settle (an hour)
MAX_WAIT = 3600.0


def parse_rate(text: str) -> float:
    """
    Return the time scale of ``--rate TEXT``: a number >= :data:`MIN_RATE`, or 0 for ``max``.

    Raises
    ------
    RecordingError
        Not a number, not finite, or below :data:`MIN_RATE` (0 included).

    """
    if str(text).strip().lower() == 'max':
        return 0.0
    try:
        rate = float(text)
    except ValueError:
        rate = math.nan
    if not MIN_RATE <= rate < math.inf:
        hint = ' (--rate max publishes as fast as possible)' if rate == 0 else ''
        raise RecordingError(f"--rate must be a time scale >= {MIN_RATE:g} or 'max', got "
                             f'{text!r}{hint}')
    return rate


_STAMP = struct.Struct('<iI')
_CLOCK_TYPE = 'rosgraph_msgs/msg/Clock'


def _has_header(cls):
    items = list(cls.get_fields_and_field_types().items())
    return bool(items) and items[0] == ('header', 'std_msgs/Header')


def _clock_bytes(ns):
    return b'\x00\x01\x00\x00' + _STAMP.pack(ns // 1_000_000_000, ns % 1_000_000_000)


def replay(bag: str | os.PathLike[str], *, rate: float = 1.0, topics: Sequence[str] | None = None,
           clock: bool = True, loop: bool = False, wait: float = 2.0, settle: float = 0.5,
           args: list[str] | None = None, log: Callable[[str], None] | None = None,
           stop: threading.Event | None = None) -> dict[str, int]:
    """
    Publish the messages of ``bag`` with their original timing.

    Parameters
    ----------
    bag : str
        rosbag2 directory or ``.mcap`` file.
    rate : float
        Time scale: 2 plays twice as fast; 0 publishes without waiting.
    topics : list of str, optional
        Topics to replay (default: all).
    clock : bool
        Publish ``/clock`` from the header stamps (and skip the bag's own ``/clock``).
    loop : bool
        Start over at the end until stopped.
    wait : float
        Seconds to wait for a subscriber on every topic before playing.
    settle : float
        Seconds to wait after that: the publisher's side of a match comes first,
        and a volatile subscriber drops (and DDS then marks as lost) what arrives
        before its own side has matched.
    args : list of str, optional
        Command line for ``rclpy`` (``--ros-args ...``).
    log : callable, optional
        Progress lines (default: stderr).
    stop : threading.Event, optional
        Set it to stop (besides SIGINT/SIGTERM).

    Returns
    -------
    dict
        Topic -> number of messages published (``/clock`` included when generated).

    Raises
    ------
    RecordingError
        The bag is missing, unreadable, lacks a requested topic, or a type is not installed.

    """
    import rclpy
    from rclpy.context import Context
    from rclpy.duration import Duration

    log = log or (lambda line: print(line, file=sys.stderr, flush=True))
    if not (rate == 0 or MIN_RATE <= rate < math.inf):
        raise RecordingError(f'--rate must be at least {MIN_RATE:g} (or max: as fast as '
                             f'possible), got {rate}')
    for option, value in (('--wait', wait), ('--settle', settle)):
        if not 0 <= value <= MAX_WAIT:
            raise RecordingError(f'{option} must be in [0, {MAX_WAIT:g}] s, got {value}')
    check_domain_id(error=RecordingError)
    available = recording_topics(bag)
    if topics:
        missing = [t for t in topics if t not in available]
        if missing:
            raise RecordingError(f'{bag}: no {", ".join(missing)} topic (topics: '
                                 f'{", ".join(sorted(available)) or "none"})')
        selected = list(dict.fromkeys(topics))
    else:
        selected = list(available)
    if clock:
        selected = [t for t in selected if t != '/clock']
    if not selected:
        raise RecordingError(f'{bag}: nothing to replay')
    classes = {t: message_class(t, available[t][0]) for t in selected}
    header = {t for t, cls in classes.items() if _has_header(cls)}

    stop = stop or threading.Event()
    restore = install_signals(stop)
    context = Context()
    node = None
    counts = dict.fromkeys(selected, 0)
    if clock:
        counts['/clock'] = 0
    try:
        dds_environ()                     # the package's DDS profile, unless one is set
        init_context(args, context, RecordingError)     # a bad ROS argument: one line
        node = rclpy.create_node('friction_joint_replay', context=context,
                                 start_parameter_services=False)
        qos = replay_qos()
        pubs = {t: node.create_publisher(cls, t, qos) for t, cls in classes.items()}
        clock_pub = None
        if clock:
            clock_pub = node.create_publisher(message_class('/clock', _CLOCK_TYPE), '/clock',
                                              qos)
        every = list(pubs.values()) + ([clock_pub] if clock_pub else [])
        t_wait = time.monotonic() + wait
        while not stop.is_set() and time.monotonic() < t_wait and \
                any(p.get_subscription_count() == 0 for p in every):
            time.sleep(0.01)
        if settle > 0 and all(p.get_subscription_count() > 0 for p in every):
            stop.wait(settle)
        log(f'replaying {", ".join(selected)}{" + /clock" if clock else ""} from {bag} '
            f'at rate {rate:g}')

        t_start = time.monotonic()
        while not stop.is_set():
            now_clock = -1
            t0_bag: int | None = None
            t0_wall = 0.0                   # set with t0_bag
            for topic, _, bag_ns, raw in iter_messages(bag, topics=selected):
                if stop.is_set():
                    break
                if rate > 0:
                    if t0_bag is None:
                        t0_bag, t0_wall = bag_ns, time.monotonic()
                    due = t0_wall + (bag_ns - t0_bag) * 1e-9 / rate
                    while not stop.is_set() and time.monotonic() < due:
                        stop.wait(min(due - time.monotonic(), 1.0))     # any gap, in steps
                    if stop.is_set():
                        break
                if clock_pub is not None and topic in header and len(raw) >= 12:
                    sec, nsec = _STAMP.unpack_from(raw, 4)
                    ns = sec * 1_000_000_000 + nsec
                    if ns > now_clock:
                        now_clock = ns
                        clock_pub.publish(_clock_bytes(ns))
                        counts['/clock'] += 1
                try:
                    pubs[topic].publish(raw)
                except RCLError as exc:
                    raise RecordingError(f'{topic}: publishing failed after {counts[topic]} '
                                         f'messages ({exc}); a subscriber has stopped taking '
                                         'messages') from None
                counts[topic] += 1
            if not loop:
                break
        elapsed = time.monotonic() - t_start
        for p in every:
            p.wait_for_all_acked(Duration(seconds=5))
        log(f'replay took {elapsed:.3f} s')
        return counts
    finally:
        if node is not None:
            node.destroy_node()
        if context.ok():
            context.try_shutdown()
        restore()
