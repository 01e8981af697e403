# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
ruff's flake8-bugbear rules (``B``) over the package, the tests and the benchmarks: zero findings.

The bugs ament_flake8 does not look for: a closure that reads a loop variable late
(B023), a ``zip`` of sequences whose lengths must match without ``strict=True``
(B905; ``strict=False`` where a shorter one ends it on purpose), mutable defaults
(B006/B008), ``raise ... from`` inside ``except`` (B904), unused loop variables
(B007), ``warnings.warn`` without ``stacklevel`` (B028).  The settings are given
here on the command line (``--isolated``: no configuration file is read), with the
project's line length and its oldest Python (3.11, so B905 applies).  ruff is
pinned in requirements.txt; the version run must be that one, since new versions
add rules.
"""
import os
import re
import subprocess
import sys

import pytest

from sourcetree import ROOT

DIRS = ('friction_joint', 'test', 'benchmarks')
ARGS = ['check', '--isolated', '--no-cache', '--select', 'B', '--line-length', '99',
        '--target-version', 'py311', '--output-format', 'concise']


def _ruff(*args, cwd=ROOT):
    return subprocess.run([sys.executable, '-m', 'ruff', *args], capture_output=True,
                          text=True, cwd=cwd, timeout=300)


def _pinned():
    with open(os.path.join(ROOT, 'requirements.txt'), encoding='utf-8') as fh:
        return re.search(r'^ruff==(\S+)', fh.read(), re.M).group(1)


@pytest.fixture(scope='module')
def ruff_version():
    done = _ruff('--version')
    assert done.returncode == 0, ('ruff is not installed in this environment: run .ci/setup '
                                  '(requirements.txt pins it)\n' + done.stderr)
    return done.stdout.split()[-1]


@pytest.mark.linter
def test_ruff_is_the_pinned_version(ruff_version):
    assert ruff_version == _pinned()


@pytest.mark.linter
def test_ruff_bugbear(ruff_version):
    done = _ruff(*ARGS, *DIRS)
    assert done.returncode == 0, f'ruff --select B found:\n{done.stdout}{done.stderr}'


@pytest.mark.linter
def test_ruff_finds_a_late_binding_closure(ruff_version, tmp_path):
    """The check can fail: a lambda reading the loop variable after the loop is B023."""
    (tmp_path / 'late.py').write_text('fs = []\nfor i in range(3):\n'
                                      '    fs.append(lambda: i)\n')
    done = _ruff(*ARGS, 'late.py', cwd=tmp_path)
    assert done.returncode == 1 and 'B023' in done.stdout, done.stdout + done.stderr
