# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""ament_pep257 over the whole tree (docstring conventions, the ament ignore list)."""
import os

from ament_pep257.main import main
import pytest

from sourcetree import ROOT, SOURCE_DIRS


@pytest.mark.linter
@pytest.mark.pep257
def test_pep257():
    rc = main(argv=[os.path.join(ROOT, d) for d in SOURCE_DIRS])
    assert rc == 0, 'Found code style errors / warnings'
