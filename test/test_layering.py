# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
The layering rules of docs/development.md, checked on the source tree.

* only :mod:`friction_joint.ros` imports rclpy: every other module imports
  in a fresh interpreter in which importing rclpy (or a ROS message package)
  fails, and none names rclpy in an import statement, even a lazy one;
* only :mod:`friction_joint.cli` imports argparse;
* no module is longer than 600 lines; no public function or method takes more
  than 6 positional parameters (options are keyword-only).
"""
import ast
import json
import subprocess
import sys

import pytest

from sourcetree import package_modules, ROOT

ROS_ONLY = ('rclpy', 'rcl_interfaces', 'rosgraph_msgs', 'sensor_msgs', 'std_msgs',
            'geometry_msgs', 'builtin_interfaces')
MAX_LINES = 600
MAX_POSITIONAL = 6

BLOCKED_IMPORT = """
import importlib, importlib.abc, json, sys
BLOCKED = set(sys.argv[1].split(','))
class Blocker(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in BLOCKED:
            raise ImportError(f'{name} is blocked in this test')
        return None
sys.meta_path.insert(0, Blocker())
failed = {}
for name in json.loads(sys.stdin.read()):
    try:
        importlib.import_module(name)
    except Exception as exc:
        failed[name] = f'{type(exc).__name__}: {exc}'
print(json.dumps(failed))
"""


def _outside_ros():
    return [(m, p) for m, p in package_modules()
            if not (m == 'friction_joint.ros' or m.startswith('friction_joint.ros.'))]


def _imported_roots(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name.split('.')[0]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            yield node.lineno, node.module.split('.')[0]


def _parse(path):
    with open(path, encoding='utf-8') as fh:
        return ast.parse(fh.read(), filename=path)


def test_every_module_outside_ros_imports_without_rclpy():
    names = [m for m, _ in _outside_ros() if not m.endswith('__main__')]
    assert 'friction_joint.cli.record' in names and 'friction_joint.jobs.demo' in names
    proc = subprocess.run([sys.executable, '-c', BLOCKED_IMPORT, ','.join(ROS_ONLY)],
                          input=json.dumps(names), capture_output=True, text=True, cwd=ROOT,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    failed = json.loads(proc.stdout)
    assert not failed, '\n'.join(f'{k}: {v}' for k, v in failed.items())


def test_the_blocker_blocks():
    """The check above can fail: a ROS module does not import with rclpy blocked."""
    proc = subprocess.run([sys.executable, '-c', BLOCKED_IMPORT, ','.join(ROS_ONLY)],
                          input=json.dumps(['friction_joint.ros.nodes.estimator']),
                          capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert 'blocked' in json.loads(proc.stdout)['friction_joint.ros.nodes.estimator']


def test_no_ros_import_statement_outside_ros():
    bad = [f'{m}:{line} imports {root}' for m, p in _outside_ros()
           for line, root in _imported_roots(_parse(p)) if root in ROS_ONLY]
    assert not bad, '\n'.join(bad)


def test_argparse_only_in_cli():
    bad = [f'{m}:{line}' for m, p in package_modules()
           if not (m == 'friction_joint.cli' or m.startswith('friction_joint.cli.'))
           for line, root in _imported_roots(_parse(p)) if root == 'argparse']
    assert not bad, 'argparse imported outside friction_joint.cli: ' + ', '.join(bad)


def test_module_length():
    long = []
    for m, p in package_modules():
        with open(p, encoding='utf-8') as fh:
            n = sum(1 for _ in fh)
        if n > MAX_LINES:
            long.append(f'{m}: {n} lines')
    assert not long, '\n'.join(long)


def _public_functions(tree):
    """(qualified name, node) of public functions and methods of public classes."""
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            if not node.name.startswith('_'):
                yield node.name, node
        elif isinstance(node, ast.ClassDef) and not node.name.startswith('_'):
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and \
                        (not item.name.startswith('_') or item.name in ('__init__', '__call__')):
                    yield f'{node.name}.{item.name}', item


@pytest.mark.parametrize('limit', [MAX_POSITIONAL])
def test_public_functions_take_few_positional_parameters(limit):
    bad = []
    for m, p in package_modules():
        for name, fn in _public_functions(_parse(p)):
            args = fn.args.posonlyargs + fn.args.args
            n = len(args) - (1 if args and args[0].arg in ('self', 'cls') else 0)
            if n > limit:
                bad.append(f'{m}.{name}: {n} positional parameters')
    assert not bad, '\n'.join(bad)
