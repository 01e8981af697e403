# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The nodes, one executable per module: ``joint_sim``, ``controller``, ``estimator``."""
__all__ = []
