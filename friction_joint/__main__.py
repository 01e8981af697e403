"""``python -m friction_joint ...`` is the ``friction_joint`` command."""
import sys

from .cli import main

sys.exit(main())
