# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Test-suite settings shared by every test directory.

Tests name the shipped files by their path in the source tree
(config/csd25.yaml), so the suite runs from the repository root whatever
directory pytest (or colcon test) was started in.
"""
import os

os.chdir(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
