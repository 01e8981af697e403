# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""``python -m friction_joint COMMAND``: the command line (see :mod:`friction_joint.cli`)."""
import sys

from .cli import main

sys.exit(main())
