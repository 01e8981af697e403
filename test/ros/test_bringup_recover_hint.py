# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""A recorder that ends early under ``bringup``: the error says how to recover what it staged."""
import types

from friction_joint.exceptions import NodeError
from friction_joint.ros.bringup import _check_alive
import pytest


def _ended(name, code):
    return types.SimpleNamespace(name=name, alive=lambda: False,
                                 proc=types.SimpleNamespace(returncode=code))


def test_a_killed_recorder_names_the_recover_command(tmp_path, monkeypatch):
    """Before: 'record ended early (exit -9)' and nothing about the staged data."""
    monkeypatch.chdir(tmp_path)
    record = tmp_path / 'run1'
    staged = tmp_path / '.run1.rec-abcd1234.tmp'
    (staged / 'run1').mkdir(parents=True)
    (staged / 'run1' / 'run1.mcap').write_bytes(b'\x89MCAP0\r\n')    # a killed recorder's
    with pytest.raises(NodeError) as err:
        _check_alive([_ended('record', -9)], None, str(tmp_path), False, str(record))
    text = str(err.value)
    assert '\n' not in text and 'record ended early (exit -9)' in text
    assert 'friction_joint recover .run1.rec-abcd1234.tmp run1' in text


def test_no_staged_data_no_recover_hint(tmp_path):
    """A recorder that staged nothing, or another node: no recover hint."""
    for name in ('record', 'controller'):
        with pytest.raises(NodeError) as err:
            _check_alive([_ended(name, 1)], None, str(tmp_path), False, str(tmp_path / 'r'))
        assert 'recover' not in str(err.value)
