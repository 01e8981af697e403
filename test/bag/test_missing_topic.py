# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""A missing topic is a :class:`MissingTopicError` naming it in a field, not only in its text."""
import pickle

from friction_joint.bag import read_recording, write_recording
from friction_joint.exceptions import MissingTopicError, RecordingError
from friction_joint.identification import identify_recordings
import friction_joint.identification.pipeline as pipeline
import numpy as np
import pytest


def _states(n=200):
    t = 1e-3 * np.arange(n)
    return {'t': t, 'q': 0.1 * t, 'qd': np.full(n, 0.1), 'effort': np.ones(n)}


def test_no_joint_states_names_the_topic_in_a_field(tmp_path):
    bag = write_recording(tmp_path / 'bag', {
        '/joint_temperature': {'t': np.array([0.0, 0.1]), 'xi': np.array([30.0, 30.0])}})
    with pytest.raises(MissingTopicError) as info:
        read_recording(bag)
    assert info.value.topic == '/joint_states'
    assert info.value.path == str(bag)
    assert isinstance(info.value, RecordingError) and '/joint_states' in str(info.value)


def test_no_temperature_names_the_topic_in_a_field(tmp_path):
    rec = read_recording(write_recording(tmp_path / 'bag', {'/joint_states': _states()}))
    with pytest.raises(MissingTopicError) as info:
        rec.temperature_at()
    assert info.value.topic == '/joint_temperature'
    back = pickle.loads(pickle.dumps(info.value))      # a Dask worker's error survives the trip
    assert (back.topic, back.path, str(back)) == (info.value.topic, info.value.path,
                                                  str(info.value))


def test_identification_says_why_it_needs_the_temperature_topic(tmp_path, monkeypatch):
    """The reader's missing /joint_temperature is told by its field (no text is parsed)."""
    def reader(path, **kwargs):
        raise MissingTopicError(f'{path}: gone', topic='/joint_temperature', path=str(path))

    monkeypatch.setattr(pipeline, 'read_recording', reader)
    with pytest.raises(RecordingError, match='gone: the identification needs the gear housing '
                                             'temperature'):
        identify_recordings([tmp_path / 'x'], 'config/csd25_base.yaml')


def test_identification_passes_another_missing_topic_unchanged(tmp_path, monkeypatch):
    def reader(path, **kwargs):
        raise MissingTopicError(f'{path}: no /joint_states topic (the temperature)',
                                topic='/joint_states', path=str(path))

    monkeypatch.setattr(pipeline, 'read_recording', reader)
    with pytest.raises(MissingTopicError) as info:
        identify_recordings([tmp_path / 'x'], 'config/csd25_base.yaml')
    assert 'housing' not in str(info.value)
