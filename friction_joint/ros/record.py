# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint record OUT``: record topics into a rosbag2 recording without losing messages.

The recorder subscribes with ``raw=True`` (the serialized CDR bytes are written as received,
nothing is deserialized) and writes every message with the rosbags ``Writer`` (version 9, MCAP),
the DDS receive time as log (bag) time; with ``--use-sim-time`` (as ``ros2 bag record
--use-sim-time``) the log time is the ``/clock`` time current when the message was *sent* (the
newest ``/clock`` whose DDS source timestamp precedes the message's; a message waits until a later
``/clock`` has arrived, so neither the batching below nor a delay in delivery shifts it), and a
lockstep recording spans its simulated time, each message at the step that produced it: replay,
which follows log times, then plays it at its simulated speed. Each subscription callback also
takes whatever else is already queued on its subscription, and the spin loop pauses 2 ms between
rounds so that messages arrive in batches: at 3 kHz the recorder costs about a fifth of a core
instead of more than half. Every message is written in the callback that takes it, so the counts
received and written are the same number.

Stopping (SIGINT, SIGTERM or ``--duration``) first drains what DDS has already received, then
finalises the bag: every message received is written, the MCAP file is sealed (rewritten with
chunk, data and summary CRCs and zstd-compressed chunks, messages in log-time order across topics;
``metadata.yaml`` and the file's ``rosbag2`` record get ``ros_distro`` from ``ROS_DISTRO`` (default
``jazzy``) and, per topic, the ``offered_qos_profiles`` of the publishers the recorder matched, as
rosbag2 stores them: :func:`~friction_joint.bag.checksums.seal_rosbag2`; if that fails the bag is
kept as rosbags wrote it), and the counts are printed. A second signal skips the drain. The bag is
written into a hidden staging directory next to ``OUT`` (``.OUT.rec-XXXXXXXX.tmp``, marked and
locked: :class:`~friction_joint.bag.staging.RecorderStaging`) and renamed when complete, so ``OUT``
is either a complete recording or absent. Every :data:`~friction_joint.bag.staging.FLUSH_PERIOD` (1
s) the open MCAP chunk is closed and the file flushed and ``fsync``-ed
(:func:`~friction_joint.bag.staging.flush_chunks`), so a recorder killed without a chance to finish
(SIGKILL, power loss) leaves a truncated file holding all but the last second or so:
``friction_joint recover`` turns it into a recording (:mod:`~friction_joint.bag.recover`), and a
later ``record`` to the same ``OUT`` names the staging directory left behind and that command.

Readiness: the recorder publishes on ``READY_TOPIC`` (``recorder_ready``, relative, so
``/recorder_ready`` in the root namespace; ``std_msgs/msg/String``, ``READY_QOS``: reliable,
transient local, keep-last 1; both defined in :mod:`friction_joint.ros.qos` and exported here too)
the comma-separated, sorted fully-qualified names of the recorded topics on which it has matched at
least one publisher (``/external_torque,/joint_command,/joint_states``): once at start (possibly
the empty string) and again whenever that set changes, so a simulator can wait for it before its
first step (a late subscriber with transient-local durability gets the current set at once). The
log lines ``/topic: N publisher(s) matched`` stay.

QoS (:func:`friction_joint.ros.qos.recorder_qos`): reliable with keep-all history for every topic
(a recorder that falls behind for a moment must not let its queue overwrite messages it has
acknowledged); ``/clock`` too unless a best-effort ``/clock`` publisher is there when the recorder
starts (then best effort, keep-last 1000). A reliable subscription does not match a best-effort
publisher; record such a topic from a reliable republisher.
"""
import bisect
import collections
from collections.abc import Callable, Iterable, Mapping, Sequence
import contextlib
import importlib
import os
import shutil
import signal
import struct
import sys
import tempfile
import threading
import time
from typing import Any, TYPE_CHECKING

from ._rclpy import take_all
from .qos import dds_environ, READY_QOS, READY_TOPIC, recorder_qos
from .startup import check_domain_id, init_context
from ..bag import CONTRACT_TYPES
from ..bag.checksums import seal_rosbag2
from ..bag.recover import salvage_recording
from ..bag.staging import (flush_chunks, FLUSH_PERIOD, killed_recordings, RecorderStaging,
                           recovery_command, STAGING_TAG)
from ..exceptions import RecordingError

if TYPE_CHECKING:
    from rclpy.node import Node
    from rclpy.qos import QoSProfile
    from rosbags.rosbag2 import Writer
    from rosbags.typesys.store import Typestore

__all__ = ['record', 'Recorder', 'parse_topics', 'message_class', 'install_signals',
           'format_counts', 'qos_dict', 'READY_TOPIC', 'READY_QOS']


_BATCH = 0.002      # s to let messages queue up between takes (bag time is DDS time)
_DRAIN_QUIET = 0.2     # s without a message that ends the drain
_DRAIN_MAX = 2.0       # s the drain may take at most (a publisher still flooding)
_CLOCK_TYPE = 'rosgraph_msgs/msg/Clock'
_CLOCK_KEEP = 100_000   # /clock samples kept for messages not taken yet (older ones folded)


def _clock_ns(raw):
    """Time (ns) in a serialized ``rosgraph_msgs/msg/Clock`` (CDR, either byte order)."""
    sec, nsec = struct.unpack_from('<iI' if raw[1] & 1 else '>iI', raw, 4)
    return sec * 1_000_000_000 + nsec


def _policy(value):
    return getattr(value, 'name', str(value)).lower()


def _duration(value):
    ns = value.nanoseconds
    return {'sec': ns // 1_000_000_000, 'nsec': ns % 1_000_000_000}


def qos_dict(profile: 'QoSProfile') -> dict[str, Any]:
    """
    Return an rclpy ``QoSProfile`` as a rosbag2 version 9 ``offered_qos_profiles`` entry.

    As ``ros2 bag record`` stores a matched publisher's profile: policy names in
    lower case (``keep_last``, ``reliable``, ...; ``unknown`` where DDS discovery
    does not tell, as the history of a remote publisher), durations as
    ``{sec, nsec}`` (infinite: ``{sec: 9223372036, nsec: 854775807}``).
    """
    return {'history': _policy(profile.history), 'depth': int(profile.depth),
            'reliability': _policy(profile.reliability),
            'durability': _policy(profile.durability),
            'deadline': _duration(profile.deadline), 'lifespan': _duration(profile.lifespan),
            'liveliness': _policy(profile.liveliness),
            'liveliness_lease_duration': _duration(profile.liveliness_lease_duration),
            'avoid_ros_namespace_conventions': bool(profile.avoid_ros_namespace_conventions)}


class _SimClock:
    """
    The ``/clock`` time at which a message was sent.

    Each ``/clock`` sample is kept with its DDS source timestamp (the wall time
    its publisher sent it).  A message sent at source time ``s`` gets the
    newest ``/clock`` sent before ``s``: the simulated time current when the
    message was published, whatever delays it met on the way to the recorder.
    It is known once a ``/clock`` sent after ``s`` has been received (reliable
    delivery is in order), so :meth:`at` answers None until then.
    """

    def __init__(self):
        self.sources = []                 # source timestamps of the kept samples, ascending
        self.values = []                  # their clock times (ns)
        self.before = 0                   # clock before the oldest kept sample (0: none yet)

    @property
    def newest_source(self):
        return self.sources[-1] if self.sources else -1

    def add(self, source, ns):
        if self.sources and source < self.sources[-1]:
            source = self.sources[-1]     # a second /clock publisher: keep the order
        self.sources.append(source)
        self.values.append(ns)
        if len(self.sources) > 2 * _CLOCK_KEEP:
            self.before = self.values[_CLOCK_KEEP - 1]
            del self.sources[:_CLOCK_KEEP], self.values[:_CLOCK_KEEP]

    def at(self, source, final=False):
        """Clock time (ns) when a message was sent at ``source``; None: not known yet."""
        if source >= self.newest_source and not final:
            return None
        i = bisect.bisect_right(self.sources, source)
        return self.values[i - 1] if i else self.before


def _source_ns(info):
    """Return the DDS source (send) timestamp of a taken message, else now."""
    return info.get('source_timestamp') or time.time_ns()


def parse_topics(specs: Sequence[str]) -> list[tuple[str, str]]:
    """``[(topic, msgtype)]`` from ``TOPIC`` (contract topics) or ``TOPIC:pkg/msg/Type``."""
    out: list[tuple[str, str]] = []
    for spec in specs:
        topic, _, msgtype = spec.partition(':')
        if not topic.startswith('/'):
            topic = '/' + topic
        if not msgtype:
            contract = CONTRACT_TYPES.get(topic)
            if contract is None:
                raise RecordingError(f'topic {topic} is not a contract topic: give its type '
                                     f'as {topic}:pkg/msg/Type')
            msgtype = contract
        if msgtype.count('/') != 2:
            raise RecordingError(f'{spec}: message type must look like pkg/msg/Type')
        if topic in dict(out):
            raise RecordingError(f'topic {topic} given twice')
        out.append((topic, msgtype))
    return out


def message_class(topic: str, msgtype: str) -> type:
    """Return the rclpy message class of ``msgtype`` (``pkg/msg/Type``) used on ``topic``."""
    try:
        pkg, kind, name = msgtype.split('/')
        return getattr(importlib.import_module(f'{pkg}.{kind}'), name)
    except (ImportError, AttributeError, ValueError):
        raise RecordingError(f'{topic}: message type {msgtype} is not installed') from None


class Recorder:
    """
    Subscriptions of one node that write every message into an open rosbags ``Writer``.

    Parameters
    ----------
    node : rclpy.node.Node
        Node to create the subscriptions on.
    writer : rosbags.rosbag2.Writer
        Open writer.
    topics : list of (str, str)
        ``(topic, msgtype)`` pairs.
    typestore : rosbags.typesys.store.Typestore
        Provides the message definitions stored in the bag.
    log : callable, optional
        Receives a line whenever the number of publishers matched on a topic changes
        (``'/topic: 1 publisher matched'``).  A publisher's messages are recorded only
        from the moment the recorder's side has matched it: DDS marks what a volatile
        reader missed before that as lost.
    sim_time : bool
        Log times from ``/clock`` instead of the receive (wall) time: each message
        gets the ``/clock`` time current when it was sent (by DDS source
        timestamps; 0 before the first), ``/clock`` messages their own time (not
        written unless it is one of ``topics``); call :meth:`flush` before
        closing.  ``/clock`` is subscribed reliable keep-all (nothing lost from
        the lockstep simulator), or best effort if a best-effort publisher is
        already there when the recorder starts (see
        :func:`~friction_joint.ros.qos.recorder_qos`).

    Attributes
    ----------
    matched : dict
        Recorded topic -> number of publishers matched now; the topics with one or more
        are announced on ``READY_TOPIC`` (see the module docstring).
    offered_qos : dict
        Topic -> list of the distinct QoS profiles (:func:`qos_dict`) of the
        publishers matched so far; see :meth:`update_offered_qos`.

    """

    def __init__(self, node: 'Node', writer: 'Writer', topics: Sequence[tuple[str, str]],
                 typestore: 'Typestore', log: Callable[[str], None] | None = None, *,
                 sim_time: bool = False) -> None:
        from rclpy.event_handler import SubscriptionEventCallbacks
        self.writer = writer
        self.node = node
        self.written = {t: 0 for t, _ in topics}
        self.offered_qos: dict[str, list[dict[str, Any]]] = {t: [] for t, _ in topics}
        self.last_message = time.monotonic()
        self.connections = {}
        self._clock = _SimClock() if sim_time else None
        self._clock_take: Callable[[], None] | None = None
        self._deferred: collections.deque[tuple[Any, str, bytes, int]] = collections.deque()
        # (conn, topic, raw, source ns) awaiting /clock
        self._subs = []
        self.matched = {t: 0 for t, _ in topics}
        from std_msgs.msg import String
        self._ready_msg = String
        self._ready = node.create_publisher(String, READY_TOPIC, READY_QOS)
        self._announced = None
        self._announce()
        pairs = list(topics)
        if sim_time and '/clock' not in dict(pairs):
            pairs.append(('/clock', _CLOCK_TYPE))
        for topic, msgtype in pairs:
            if msgtype not in typestore.types:
                raise RecordingError(f'{topic}: message type {msgtype} is unknown to the '
                                     'rosbags Jazzy typestore')
            cls = message_class(topic, msgtype)
            conn = None
            if topic in self.written:
                conn = writer.add_connection(topic, msgtype, typestore=typestore)
                self.connections[topic] = conn
            holder: list[Any] = []
            events = SubscriptionEventCallbacks(matched=self._matched(topic, log)) \
                if topic in self.written else None
            if sim_time and topic == '/clock':
                callback = self._clock_callback(conn, cls, holder)
            else:
                callback = self._callback(topic, cls, conn, holder)
            offered = [i.qos_profile for i in node.get_publishers_info_by_topic(topic)]
            sub = node.create_subscription(cls, topic, callback, recorder_qos(topic, offered),
                                           raw=True, event_callbacks=events)
            holder.append(sub)
            self._subs.append(sub)

    def _matched(self, topic, log):
        def callback(status):
            n = status.current_count
            self.matched[topic] = n
            self.update_offered_qos([topic])
            self._announce()
            if log is not None:
                log(f'{topic}: {n} publisher{"" if n == 1 else "s"} matched')
        return callback

    def ready_topics(self) -> str:
        """Return the recorded topics with a matched publisher, sorted, comma-separated."""
        return ','.join(sorted(t for t, n in self.matched.items() if n > 0))

    def _announce(self):
        """Publish :meth:`ready_topics` on ``READY_TOPIC`` if it changed."""
        text = self.ready_topics()
        if text != self._announced:
            self._announced = text
            self._ready.publish(self._ready_msg(data=text))

    def update_offered_qos(self, topics: Iterable[str] | None = None) -> None:
        """Add the QoS profiles of the publishers now on ``topics`` (default all)."""
        for topic in self.written if topics is None else topics:
            seen = self.offered_qos[topic]
            for info in self.node.get_publishers_info_by_topic(topic):
                profile = qos_dict(info.qos_profile)
                if profile not in seen:
                    seen.append(profile)

    def _clock_callback(self, conn, cls, holder):
        write = self.writer.write
        written = self.written
        clock = self._clock

        def take(raw, info):
            ns = _clock_ns(raw)
            clock.add(_source_ns(info), ns)
            if conn is not None:
                write(conn, ns, raw)
                written['/clock'] += 1

        def pull():
            for taken in take_all(holder[0], cls, raw=True):
                take(*taken)
            self._release()

        def callback(raw, info):
            take(raw, info)
            pull()
            self.last_message = time.monotonic()

        self._clock_take = pull
        return callback

    def _callback(self, topic, cls, conn, holder):
        write = self.writer.write
        written = self.written

        def callback(raw, info):
            batch = [(raw, info)]
            batch.extend(take_all(holder[0], cls, raw=True))   # the rest of a burst, now
            if self._clock is not None:
                self._deferred.extend((conn, topic, raw, _source_ns(info)) for raw, info in batch)
                self._clock_take()          # every /clock received so far; writes what it can
            else:
                for raw, info in batch:
                    write(conn, info.get('received_timestamp') or time.time_ns(), raw)
                written[topic] += len(batch)
            self.last_message = time.monotonic()

        return callback

    def _release(self, final=False):
        """Write the deferred messages whose send-time clock is known (all if ``final``)."""
        deferred, clock = self._deferred, self._clock
        final = final or len(deferred) > _CLOCK_KEEP      # no /clock coming: do not hoard
        keep = collections.deque()
        while deferred:
            conn, topic, raw, source = item = deferred.popleft()
            ns = clock.at(source, final)
            if ns is None:
                keep.append(item)
                continue
            self.writer.write(conn, ns, raw)
            self.written[topic] += 1
        self._deferred = keep

    def flush(self) -> None:
        """Write every message still waiting for its ``/clock`` (before closing the bag)."""
        if self._clock is not None and self._clock_take is not None:    # both with sim_time
            self._clock_take()
            self._release(final=True)


def _seal(bag, out, log, offered_qos):
    """
    Put CRCs, ``ros_distro`` and offered QoS into the closed bag; keep it as is on failure.

    rosbags writes CRC 0 and ``ros_distro: rosbags``;
    :func:`~friction_joint.bag.checksums.seal_rosbag2` writes the distribution
    (``ROS_DISTRO``, else ``jazzy``) and the publishers' QoS profiles into
    ``metadata.yaml`` and rewrites the ``.mcap`` beside itself (messages in log-time
    order, the same metadata in its ``rosbag2`` record and channels) and renames it
    over the original, so a failure (a full disk) leaves the complete unsealed
    recording, which is kept: nothing recorded is lost.
    """
    try:
        seal_rosbag2(bag, offered_qos=offered_qos)
    except (OSError, RecordingError, KeyError, ValueError) as exc:
        log(f'{out}: kept without checksums, sealing failed ({exc})')


def _qos_objects(dicts):
    """Return the rosbags ``Qos`` objects of :func:`qos_dict` entries."""
    from rosbags.rosbag2.metadata import parse_qos
    return parse_qos(list(dicts))


def _blocking(path):
    """Return ``'X is not a directory'`` for the existing ancestor of ``path`` that is a file."""
    while path and not os.path.lexists(path):
        path = os.path.dirname(path)
    return f'{path} is not a directory' if path and not os.path.isdir(path) else None


def install_signals(stop: threading.Event, force: threading.Event | None = None,
                    ) -> Callable[[], object]:
    """
    SIGINT/SIGTERM set ``stop`` (a second one also ``force``); returns a restore function.

    rclpy is initialised without its own handlers, which would shut the context down
    at once and leave no chance to drain and finalise.  Outside the main thread
    nothing is installed.
    """
    if threading.current_thread() is not threading.main_thread():
        return lambda: None

    def handler(signum, frame):
        if stop.is_set() and force is not None:
            force.set()
        stop.set()

    old = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    return lambda: [signal.signal(s, h) for s, h in old.items()]


def record(out: str | os.PathLike[str], *, topics: Sequence[str] | None = None,
           duration: float | None = None, args: list[str] | None = None,
           log: Callable[[str], None] | None = None, stop: threading.Event | None = None,
           use_sim_time: bool = False) -> dict[str, int]:
    """
    Record ``topics`` into ``out`` until a signal, ``duration`` or ``stop`` is set.

    Parameters
    ----------
    out : str
        Target rosbag2 directory; must not exist.
    topics : list of str, optional
        ``TOPIC`` or ``TOPIC:pkg/msg/Type``; default every contract topic.
    duration : float, optional
        Stop after this many seconds of recording.
    args : list of str, optional
        Command line for ``rclpy`` (``--ros-args ...``).
    log : callable, optional
        Progress lines (default: stderr).
    stop : threading.Event, optional
        Set it to stop recording (besides SIGINT/SIGTERM).
    use_sim_time : bool
        Log times from ``/clock`` (as ``ros2 bag record --use-sim-time``): each message
        is logged at the latest ``/clock`` time received before it, so a lockstep
        recording spans its simulated time and replays at its own speed.  Default:
        the receive (wall) time.

    Returns
    -------
    dict
        Topic -> number of messages received and written.

    Raises
    ------
    RecordingError
        ``out`` exists, a topic or type is unknown, or writing failed.

    """
    import rclpy
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    log = log or (lambda line: print(line, file=sys.stderr, flush=True))
    out = os.fspath(out)
    if os.path.lexists(out):
        raise RecordingError(f'{out} exists already, not overwriting')
    if duration is not None and not duration > 0:
        raise RecordingError(f'--duration must be positive, got {duration}')
    check_domain_id(error=RecordingError)
    pairs = parse_topics(topics if topics else list(CONTRACT_TYPES))
    for topic, msgtype in pairs:
        message_class(topic, msgtype)
    typestore = get_typestore(Stores.ROS2_JAZZY)

    parent = os.path.dirname(os.path.abspath(out))
    try:
        os.makedirs(parent, exist_ok=True)
    except OSError as exc:                 # a file on the way, no permission, a full disk
        raise RecordingError(f'cannot create the directory of {out}: '
                             f'{_blocking(parent) or exc.strerror or exc}') from None
    if not os.access(parent, os.W_OK | os.X_OK):
        raise RecordingError(f'cannot write {out}: {parent} is not writable')
    base = os.path.basename(os.path.normpath(out))
    for stale, state in killed_recordings(out):
        log(f'note: {stale} holds an earlier recording to {out} that did not finish (its '
            f'recorder was killed{"" if state == "killed" else ", or still runs"}); recover '
            f'it with: {recovery_command(stale, avoid=out)}')
    tmp = tempfile.mkdtemp(prefix=f'.{base}.{STAGING_TAG}', suffix='.tmp', dir=parent)
    staging = RecorderStaging(tmp, out, pairs, sim_time=use_sim_time)
    keep = told = False               # keep tmp: it holds messages that did not reach out
    stop = stop or threading.Event()
    force = threading.Event()
    restore = install_signals(stop, force)
    context = Context()
    node = executor = recorder = None
    try:
        dds_environ()                     # the package's DDS profile, unless one is set
        init_context(args, context, RecordingError)     # a bad ROS argument: one line
        node = rclpy.create_node('friction_joint_recorder', context=context,
                                 start_parameter_services=False)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        writer = Writer(os.path.join(tmp, base), version=9, storage_plugin=StoragePlugin.MCAP)
        writer.open()
        try:
            recorder = Recorder(node, writer, pairs, typestore, log=log, sim_time=use_sim_time)
            log(f'recording {", ".join(t for t, _ in pairs)} to {out} '
                f'({"for %g s" % duration if duration else "Ctrl-C to stop"}'
                f'{", log times from /clock" if use_sim_time else ""})')
            t_end = None if duration is None else time.monotonic() + duration
            t_flush = time.monotonic() + FLUSH_PERIOD
            while not stop.is_set() and (t_end is None or time.monotonic() < t_end):
                timeout = 0.1 if t_end is None else max(0.0, min(0.1, t_end - time.monotonic()))
                executor.spin_once(timeout_sec=timeout)
                time.sleep(_BATCH)
                if time.monotonic() >= t_flush:     # a SIGKILL loses at most this period
                    flush_chunks(writer)
                    staging.update(recorder.offered_qos)
                    t_flush = time.monotonic() + FLUSH_PERIOD
            # drain: take what is queued until the topics are quiet (or the drain takes too long)
            t_stop = time.monotonic()
            while not force.is_set():
                executor.spin_once(timeout_sec=0.02)
                now = time.monotonic()
                if now - max(recorder.last_message, t_stop) > _DRAIN_QUIET or \
                        now - t_stop > _DRAIN_MAX:
                    break
            recorder.flush()
            recorder.update_offered_qos()
            for i, conn in enumerate(writer.connections):   # into metadata.yaml at close
                profiles = _qos_objects(recorder.offered_qos.get(conn.topic, ()))
                writer.connections[i] = conn._replace(    # rosbags: ext of either format
                    ext=conn.ext._replace(offered_qos_profiles=profiles))  # type: ignore[call-arg]
        except BaseException:
            with contextlib.suppress(OSError):      # a full disk: its buffer cannot go
                writer.abort()
            keep = recorder is not None and any(recorder.written.values())
            raise
        keep = any(recorder.written.values())       # finishing can fail too (a full disk)
        try:
            writer.close()
        except BaseException:
            with contextlib.suppress(OSError):
                writer.abort()
            raise
        _seal(os.path.join(tmp, base), out, log, recorder.offered_qos)
        keep = True
        os.rename(os.path.join(tmp, base), out)
        keep = False
        return dict(recorder.written)
    except RecordingError:
        raise
    except OSError as exc:                # ENOSPC, EDQUOT, EROFS: stop, seal what fits, 1 line
        staging.close()                   # (its lock released: recover takes it)
        told = keep
        raise RecordingError(salvage_recording(tmp, out, exc) if keep else
                             f'cannot write {out}: {exc.strerror or exc}') from None
    finally:
        staging.close()
        if keep and not told:
            log(f'what was recorded is kept in {tmp}; recover it with: {recovery_command(tmp)}')
        if executor is not None:
            executor.shutdown(timeout_sec=1.0)
        if node is not None:
            node.destroy_node()
        if context.ok():
            context.try_shutdown()
        restore()
        if not keep:
            shutil.rmtree(tmp, ignore_errors=True)


def format_counts(counts: Mapping[str, int]) -> str:
    """``'N messages (/a: n1, /b: n2)'`` of a topic -> count dict."""
    detail = ', '.join(f'{t}: {n}' for t, n in counts.items())
    return f'{sum(counts.values())} messages ({detail})'
