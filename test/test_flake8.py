# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""ament_flake8 over the whole tree: the ament linters' rules, 99-column lines, zero findings."""
import os

from ament_flake8.main import main_with_errors
import pytest

from sourcetree import ROOT, SOURCE_DIRS


@pytest.mark.flake8
@pytest.mark.linter
def test_flake8():
    rc, errors = main_with_errors(argv=[os.path.join(ROOT, d) for d in SOURCE_DIRS])
    assert rc == 0, f'Found {len(errors)} code style errors / warnings:\n' + '\n'.join(errors)
