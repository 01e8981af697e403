# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""The source tree the convention tests check: its root, its Python files, its modules."""
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
#: directories (and files) of Python sources the linters check
SOURCE_DIRS = ('friction_joint', 'test', 'benchmarks', 'launch', 'setup.py')
PACKAGE = 'friction_joint'


def python_files(path):
    """Every .py file under path (or path itself), sorted."""
    if os.path.isfile(path):
        return [path]
    out = []
    for dirpath, dirnames, filenames in os.walk(path):
        dirnames[:] = sorted(d for d in dirnames if not d.startswith(('.', '__pycache__')))
        out += [os.path.join(dirpath, f) for f in sorted(filenames) if f.endswith('.py')]
    return out


def package_modules():
    """(dotted name, path) of every module of the package, sorted."""
    out = []
    for path in python_files(os.path.join(ROOT, PACKAGE)):
        rel = os.path.relpath(path, ROOT)[:-3].replace(os.sep, '.')
        if rel.endswith('.__init__'):
            rel = rel[:-len('.__init__')]
        out.append((rel, path))
    return out


#: ``../shared`` beside the clone (CI puts it there): real data and the MCAP CLI;
#: FRICTION_JOINT_SHARED points elsewhere (e.g. from a colcon workspace's src/)
SHARED = (os.environ.get('FRICTION_JOINT_SHARED')
          or os.path.join(os.path.dirname(ROOT), 'shared'))
#: the upstream MCAP CLI (``mcap doctor``); FRICTION_JOINT_MCAP_CLI overrides
MCAP_CLI = os.environ.get('FRICTION_JOINT_MCAP_CLI') or os.path.join(SHARED, 'tools', 'mcap')
