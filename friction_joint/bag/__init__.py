# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Recordings (rosbag2 / MCAP) as numpy arrays, without ROS.

* :mod:`~friction_joint.bag.topics`: the contract topics and their array classes
  (:class:`Recording`, :class:`JointStates`, ...);
* :mod:`~friction_joint.bag.reader`: :func:`read_recording`, :func:`iter_messages`;
* :mod:`~friction_joint.bag.writer`: :func:`write_recording`;
* :mod:`~friction_joint.bag.importer`: :func:`import_logs`, CSV/TSV/NPZ logs -> the topics
  of a recording (``friction_joint import``); :mod:`~friction_joint.bag.tables`:
  :func:`read_table` (delimited text or ``.npz``); :mod:`~friction_joint.bag.mapping`:
  :func:`load_mapping`, a motor current -> the torque, :func:`torque_from_current`;
* :mod:`~friction_joint.bag.checksums`: :func:`seal_recording` (CRCs into what rosbags
  wrote), :func:`verify_checksums`;
* :mod:`~friction_joint.bag.stamps`: the header-stamp rules of reading;
* :mod:`~friction_joint.bag.plausible`: :func:`check_values`, absurd samples;
* :mod:`~friction_joint.bag.lockstep`: :func:`check_lockstep`, every step on every loop topic;
* :mod:`~friction_joint.bag.recover`: :func:`recover_recording`, a truncated MCAP file (a
  killed recorder's) -> a recording (``friction_joint recover``);
  :mod:`~friction_joint.bag.staging`: the recorder's staging directory (marker, lock,
  periodic flush), :func:`partial_recording_error`, the readers' error for a
  truncated file, and :func:`missing_recording_error`, theirs for a missing one (naming
  a killed recorder's staging directory and the command that recovers it).
"""
from .checksums import seal_recording, verify_checksums
from .importer import import_logs, ImportedLog, load_mapping, parse_column, QUANTITIES
from .lockstep import check_lockstep, LockstepCheck, LoopTopicCount
from .mapping import check_motor, torque_from_current
from .plausible import check_samples, check_values
from .reader import iter_messages, read_recording, recording_custom_data, recording_topics
from .recover import recover_recording, RecoveredRecording
from .staging import missing_recording_error, partial_recording_error
from .topics import (CONTRACT_TYPES, ExternalTorque, JointCommand, JointStates, LinkTorque,
                     Recording, REQUIRED_TOPICS, Temperature, zero_order_hold)
from .writer import write_recording

__all__ = ['CONTRACT_TYPES', 'REQUIRED_TOPICS', 'JointStates', 'Temperature', 'LinkTorque',
           'JointCommand', 'ExternalTorque', 'Recording', 'read_recording', 'write_recording',
           'zero_order_hold', 'recording_topics', 'iter_messages', 'seal_recording',
           'verify_checksums', 'check_values', 'check_samples', 'check_lockstep',
           'LockstepCheck', 'LoopTopicCount', 'import_logs', 'ImportedLog', 'load_mapping',
           'parse_column', 'QUANTITIES', 'recover_recording', 'RecoveredRecording',
           'partial_recording_error', 'missing_recording_error', 'check_motor',
           'torque_from_current', 'recording_custom_data']
