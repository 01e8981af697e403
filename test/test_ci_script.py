# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""`.ci/run` runs both of its checks and reports both, whatever the first said."""

import os
from pathlib import Path
import shutil
import subprocess

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _stub(path, body):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text('#!/usr/bin/env bash\n' + body + '\n')
    path.chmod(0o755)


@pytest.mark.parametrize('pytest_rc, colcon_rc', [(1, 0), (0, 3), (0, 0), (2, 5)])
def test_ci_runs_colcon_even_when_pytest_fails(tmp_path, pytest_rc, colcon_rc):
    """A red suite still runs the colcon step; the exit status is the first failure's."""
    shutil.copytree(ROOT / '.ci', tmp_path / '.ci')
    log = tmp_path / 'log'
    _stub(tmp_path / '.ci' / 'setup', f'echo setup >> {log}')
    _stub(tmp_path / '.ci' / 'colcon', f'echo colcon >> {log}; exit {colcon_rc}')
    _stub(tmp_path / '.venv' / 'bin' / 'python', f'echo pytest >> {log}; exit {pytest_rc}')
    env = {k: v for k, v in os.environ.items() if k != 'BASH_ENV'}
    done = subprocess.run(['bash', str(tmp_path / '.ci' / 'run')], env=env,
                          capture_output=True, text=True, timeout=60)
    assert log.read_text().split() == ['setup', 'pytest', 'colcon']
    assert done.returncode == (pytest_rc or colcon_rc)
    assert f'pytest exit {pytest_rc}, colcon exit {colcon_rc}' in done.stdout


def test_ci_stops_when_setup_fails(tmp_path):
    """Without an environment nothing else runs, and the failure is the exit status."""
    shutil.copytree(ROOT / '.ci', tmp_path / '.ci')
    log = tmp_path / 'log'
    _stub(tmp_path / '.ci' / 'setup', f'echo setup >> {log}; exit 7')
    _stub(tmp_path / '.ci' / 'colcon', f'echo colcon >> {log}')
    done = subprocess.run(['bash', str(tmp_path / '.ci' / 'run')],
                          capture_output=True, text=True, timeout=60)
    assert log.read_text().split() == ['setup']
    assert done.returncode == 7


def _fake_python(tmp_path, pip_rc):
    """Return a ``python3`` whose ``-m venv`` makes a ``.venv`` whose pip talks like pip."""
    venv_python = ('#!/usr/bin/env bash\n'
                   'if [[ " $* " == *" -r requirements.txt "* ]]; then\n'
                   '  echo "Collecting numpy==2.0"; echo "  Downloading numpy.whl (18 MB)"\n'
                   '  echo "Installing collected packages: numpy"\n'
                   f'  echo "Successfully installed numpy-2.0"; exit {pip_rc}\n'
                   'fi\n')
    fake = tmp_path / 'fake-python3'
    _stub(fake, 'if [[ "$1 $2" == "-m venv" ]]; then\n'
                '  mkdir -p "$3/bin"\n'
                f"  cat > \"$3/bin/python\" <<'PY'\n{venv_python}PY\n"
                '  chmod +x "$3/bin/python"\n'
                'else echo "Python 3.11.9"; fi')
    return fake


def test_setup_says_what_it_does_step_by_step(tmp_path):
    """A first run prints a line per step with its time, and pip's per-package lines."""
    shutil.copytree(ROOT / '.ci', tmp_path / '.ci')
    (tmp_path / 'requirements.txt').write_text('numpy==2.0\n')
    env = dict(os.environ, PYTHON=str(_fake_python(tmp_path, 0)))
    done = subprocess.run(['bash', str(tmp_path / '.ci' / 'setup')], env=env,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    for what in ('creating .venv', 'upgrading pip', 'installing requirements.txt',
                 'installing friction_joint'):
        assert any(line.startswith(f'setup: {what}') and line.endswith(' ...')
                   for line in lines), (what, lines)
        assert any(line.startswith(f'setup: {what}') and 'done in' in line
                   for line in lines), (what, lines)
    assert 'Collecting numpy==2.0' in lines and 'Successfully installed numpy-2.0' in lines
    assert not any('Downloading' in line for line in lines)      # one line per package


def test_setup_fails_when_pip_fails(tmp_path):
    """A failing install is the setup's failure, whatever the progress filter saw."""
    shutil.copytree(ROOT / '.ci', tmp_path / '.ci')
    (tmp_path / 'requirements.txt').write_text('numpy==2.0\n')
    env = dict(os.environ, PYTHON=str(_fake_python(tmp_path, 1)))
    done = subprocess.run(['bash', str(tmp_path / '.ci' / 'setup')], env=env,
                          capture_output=True, text=True, timeout=60)
    assert done.returncode != 0
    assert not any('installing friction_joint' in line for line in done.stdout.splitlines())
