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
Recordings (rosbag2 / MCAP) as numpy arrays, without ROS.

* :mod:`~friction_joint.bag.topics`: the contract topics and their array classes
  (:class:`Recording`, :class:`JointStates`, ...);
* :mod:`~friction_joint.bag.reader`: :func:`read_recording`, :func:`iter_messages`;
* :mod:`~friction_joint.bag.writer`: :func:`write_recording`;
* :mod:`~friction_joint.bag.importer`: :func:`import_logs`, CSV/TSV/NPZ logs -> the topics
  of a recording (``friction_joint import``); :mod:`~friction_joint.bag.tables`:
  :func:`read_table` (delimited text or ``.npz``);
* :mod:`~friction_joint.bag.checksums`: :func:`seal_recording` (CRCs into what rosbags
  wrote), :func:`verify_checksums`;
* :mod:`~friction_joint.bag.stamps`: the header-stamp rules of reading;
* :mod:`~friction_joint.bag.plausible`: :func:`check_values`, absurd samples;
* :mod:`~friction_joint.bag.lockstep`: :func:`check_lockstep`, every step on every loop topic;
* :mod:`~friction_joint.bag.recover`: :func:`recover_recording`, a truncated MCAP file (a
  killed recorder's) -> a recording (``friction_joint recover``);
  :mod:`~friction_joint.bag.staging`: the recorder's staging directory (marker, lock,
  periodic flush) and :func:`partial_recording_error`, the readers' error for a
  truncated file.
"""
from .checksums import seal_recording, verify_checksums
from .importer import import_logs, ImportedLog, load_mapping, parse_column, QUANTITIES
from .lockstep import check_lockstep, LockstepCheck, LoopTopicCount
from .plausible import check_samples, check_values
from .reader import iter_messages, read_recording, recording_topics
from .recover import recover_recording, RecoveredRecording
from .staging import partial_recording_error
from .topics import (CONTRACT_TYPES, ExternalTorque, JointCommand, JointStates, LinkTorque,
                     Recording, REQUIRED_TOPICS, Temperature, zero_order_hold)
from .writer import write_recording

__all__ = ['CONTRACT_TYPES', 'REQUIRED_TOPICS', 'JointStates', 'Temperature', 'LinkTorque',
           'JointCommand', 'ExternalTorque', 'Recording', 'read_recording', 'write_recording',
           'zero_order_hold', 'recording_topics', 'iter_messages', 'seal_recording',
           'verify_checksums', 'check_values', 'check_samples', 'check_lockstep',
           'LockstepCheck', 'LoopTopicCount', 'import_logs', 'ImportedLog', 'load_mapping',
           'parse_column', 'QUANTITIES', 'recover_recording', 'RecoveredRecording',
           'partial_recording_error']
