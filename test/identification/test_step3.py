# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Step 3's result is a frozen record whose ``to_dict`` is the ``presliding`` entry of the JSON.

A real run on the shipped sample (both pre-sliding fits rejected, explained) writes
``identification.json``; its ``presliding`` entry, read back, rebuilds the same record
and the record gives the same JSON text (same keys in the same order, same values).
"""
import dataclasses
import json
from pathlib import Path

from friction_joint.identification.step3 import PreslidingStep
from friction_joint.jobs import run_identify
import pytest

ROOT = Path(__file__).resolve().parents[2]
BASE = ROOT / 'config' / 'csd25_base.yaml'
SAMPLE = ROOT / 'bags' / 'csd25_sample'


@pytest.mark.parametrize('mode', ['auto', 'skip'])
def test_step_3_is_frozen_and_its_dict_is_the_json_of_a_real_run(tmp_path, mode):
    """The written ``presliding`` entry is ``to_dict()`` and round-trips through the record."""
    out = tmp_path / 'id.yaml'
    done = run_identify([str(SAMPLE)], str(BASE), str(out), presliding=mode)
    step = done.identification.presliding
    assert isinstance(step, PreslidingStep)
    with pytest.raises(dataclasses.FrozenInstanceError):
        step.status = 'failed'
    text = (tmp_path / 'id_report' / 'identification.json').read_text()
    written = json.loads(text)['presliding']
    assert json.dumps(step.to_dict()['status']) == json.dumps(written['status'])
    again = PreslidingStep(**written)
    assert json.dumps(again.to_dict()) == json.dumps(written)
    assert list(step.to_dict()) == list(written)
    if mode == 'skip':
        assert written == {'status': 'skipped', 'reason': '--presliding skip'}
        assert step == again
    else:
        assert step.status == 'done' and step.why and step.advice
        assert list(written) == ['status', 'models', 'excitation', 'why', 'advice']
        statuses = {m: r['status'] for m, r in step.models.items()}
        assert statuses == {'lugre': 'rejected', 'gms': 'rejected'}
        assert (step.why, step.advice) == (written['why'], written['advice'])
