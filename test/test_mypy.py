# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
mypy over the package with the project's configuration (setup.cfg ``[mypy]``): zero errors.

The configuration is strict (the per-module flags of ``--strict``) on the compute core
(``models``, ``control``, ``gear``, ``identification``, ``diagnosis``) and mypy's default
checks elsewhere; third-party libraries without types are listed one by one there.
mypy runs as ``python -m mypy`` from the source root with no targets (the
configuration names the package) and no cache (the source tree is only read).  mypy
and the PyYAML stubs are pinned in requirements.txt; the versions run must be those,
since new versions find new errors.
"""
from collections import Counter
from importlib import metadata
import os
import re
import shutil
import subprocess
import sys

import pytest

from sourcetree import PACKAGE, ROOT

STRICT = ('models', 'control', 'gear', 'identification', 'diagnosis')
ARGS = ['--config-file', 'setup.cfg', '--cache-dir', os.devnull, '--no-color-output',
        '--no-error-summary', '--show-error-codes']


def _mypy(*args, cwd=ROOT):
    return subprocess.run([sys.executable, '-m', 'mypy', *args], capture_output=True,
                          text=True, cwd=cwd, timeout=600)


def _pinned(name):
    with open(os.path.join(ROOT, 'requirements.txt'), encoding='utf-8') as fh:
        return re.search(rf'^{re.escape(name)}==(\S+)', fh.read(), re.M | re.I).group(1)


@pytest.fixture(scope='module')
def mypy_version():
    done = _mypy('--version')
    assert done.returncode == 0, ('mypy is not installed in this environment: run .ci/setup '
                                  '(requirements.txt pins it)\n' + done.stderr)
    return done.stdout.split()[1]


def _errors(stdout):
    return [line for line in stdout.splitlines() if ': error: ' in line]


@pytest.mark.linter
def test_mypy_and_stubs_are_the_pinned_versions(mypy_version):
    assert mypy_version == _pinned('mypy')
    assert metadata.version('types-PyYAML') == _pinned('types-PyYAML')


@pytest.mark.linter
def test_mypy(mypy_version):
    done = _mypy(*ARGS)
    errors = _errors(done.stdout)
    # where they are, per file, before the list itself
    where = Counter(line.split(':', 1)[0] for line in errors)
    summary = ''.join(f'{n:5d} {path}\n' for path, n in sorted(where.items()))
    assert done.returncode == 0 and not errors, (
        f'mypy found {len(errors)} error(s) in {len(where)} file(s):\n{summary}\n'
        f'{done.stdout}{done.stderr}')
    # every section of the configuration applies to a module (no misspelt name)
    assert 'unused section' not in done.stdout + done.stderr, done.stdout + done.stderr


@pytest.mark.linter
def test_mypy_is_strict_on_the_core_only(mypy_version, tmp_path):
    """The check can fail: an unannotated function is an error in the core, not elsewhere."""
    shutil.copy(os.path.join(ROOT, 'setup.cfg'), tmp_path / 'setup.cfg')
    body = 'def twice(x):\n    return 2 * x\n'
    for sub in (*STRICT, 'jobs'):
        pkg = tmp_path / PACKAGE / sub
        pkg.mkdir(parents=True)
        (pkg / '__init__.py').write_text('')
        (pkg / 'twice.py').write_text(body)
    (tmp_path / PACKAGE / '__init__.py').write_text('')
    done = _mypy(*ARGS, cwd=tmp_path)
    flagged = {line.split(os.sep)[1] for line in _errors(done.stdout)
               if '[no-untyped-def]' in line}
    assert done.returncode == 1 and flagged == set(STRICT), done.stdout + done.stderr
