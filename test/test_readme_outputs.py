# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""What the README's command blocks write in the repository does not show up in git status."""
from pathlib import Path
import re
import shutil
import subprocess

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: how a README command names what it writes: --out X, record X, cat > X, --record X
WRITES = re.compile(r'(?:--out|--record|/record|cat >)\s+([A-Za-z0-9_./-]+)')


def _written():
    text = (ROOT / 'README.md').read_text()
    blocks = re.findall(r'```sh\n(.*?)```', text, flags=re.S)
    return sorted({m for block in blocks for m in WRITES.findall(block)})


def test_readme_outputs_are_ignored_by_git():
    """Every path a README block writes is ignored (the README's runs leave git status clean)."""
    if shutil.which('git') is None or not (ROOT / '.git').exists():
        pytest.skip('not a git checkout')
    written = _written()
    assert {'demo_out', 'bags/run1', 'fleet_report'} <= set(written), written
    probe = [w.rstrip('/') + ('/x' if not w.endswith(('.yaml', '.mcap')) else '')
             for w in written]
    done = subprocess.run(['git', 'check-ignore', '--no-index', *probe], cwd=ROOT,
                          capture_output=True, text=True)
    ignored = set(done.stdout.split())
    assert not [p for p in probe if p not in ignored], (probe, ignored)
