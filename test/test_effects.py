# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The effects registry is the one list the diagnosis, the experiments and the docs use."""
import os

from friction_joint import ArgumentError
from friction_joint.diagnosis import base_structure, EFFECTS as DIAGNOSED, extend
from friction_joint.effects import effect, EFFECTS, HIDEABLE, REGISTRY, UNREPRESENTABLE
from friction_joint.experiments.hidden import EFFECT_RANGES
from friction_joint.gear import load_gear
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_every_effect_is_diagnosed_hidden_or_said_why_not():
    """The diagnosis extends a structure by every effect; the experiments hide the hideable."""
    assert DIAGNOSED is EFFECTS
    base = base_structure(load_gear(os.path.join(ROOT, 'config', 'csd25_base.yaml')))
    for name in EFFECTS:
        assert extend(base, name) is not None, name        # the base lacks each of them
    assert set(EFFECT_RANGES) == set(HIDEABLE)
    for name, eff in REGISTRY.items():
        assert eff.representable == (name not in UNREPRESENTABLE)
        assert eff.hideable or not eff.representable or name in HIDEABLE
    with pytest.raises(ArgumentError, match='effects: thermal, load'):
        effect('wear')
    with pytest.raises(ArgumentError):
        extend(base, 'wear')


def test_docs_list_every_effect():
    """docs/interfaces.md names every effect of the registry under ``diagnose`` outputs."""
    with open(os.path.join(ROOT, 'docs', 'interfaces.md'), encoding='utf-8') as fh:
        text = fh.read()
    for name in EFFECTS:
        assert f'* `{name}`:' in text, name
