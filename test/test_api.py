# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
The public names: every module declares ``__all__`` and every name in it exists.

Imports between the package's modules use only names the imported module exports
(or its submodules), so a module's ``__all__`` is its whole interface.
"""
import ast
import importlib

import pytest

from sourcetree import package_modules

MODULES = [(m, p) for m, p in package_modules() if not m.endswith('__main__')]


def _resolve(module, is_package, node):
    """Absolute name of the module an ``ImportFrom`` node imports from (None: not ours)."""
    if node.level == 0:
        return node.module if (node.module or '').split('.')[0] == 'friction_joint' else None
    base = module.split('.') if is_package else module.split('.')[:-1]
    base = base[:len(base) - (node.level - 1)]
    return '.'.join(base + ([node.module] if node.module else []))


def _internal_imports():
    for module, path in MODULES:
        with open(path, encoding='utf-8') as fh:
            tree = ast.parse(fh.read(), filename=path)
        is_package = path.endswith('__init__.py')
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                target = _resolve(module, is_package, node)
                if target:
                    yield module, node.lineno, target, [a.name for a in node.names]


@pytest.mark.parametrize('module', [m for m, _ in MODULES])
def test_all_names_exist(module, request):
    if '.ros' in module:
        pytest.importorskip('rclpy')
    mod = importlib.import_module(module)
    assert hasattr(mod, '__all__'), f'{module} has no __all__'
    missing = [n for n in mod.__all__ if not hasattr(mod, n)]
    assert not missing, f'{module}.__all__ names missing objects: {missing}'
    assert len(set(mod.__all__)) == len(mod.__all__), f'{module}.__all__ has duplicates'


def test_imports_between_modules_use_exported_names():
    pytest.importorskip('rclpy')
    bad = []
    for module, line, target, names in _internal_imports():
        mod = importlib.import_module(target)
        exported = set(getattr(mod, '__all__', ()))
        for name in names:
            if name in exported:
                continue
            try:
                importlib.import_module(f'{target}.{name}')     # a submodule
            except ImportError:
                bad.append(f'{module}:{line} imports {name} from {target}, which does not '
                           'export it')
    assert not bad, '\n'.join(bad)


def test_the_top_level_docstring_maps_every_subpackage():
    import friction_joint
    subpackages = sorted({m.split('.')[1] for m, p in MODULES
                          if p.endswith('__init__.py') and m.count('.') == 1})
    assert len(subpackages) >= 8
    missing = [s for s in subpackages if f'friction_joint.{s}' not in friction_joint.__doc__]
    assert not missing, f'friction_joint docstring does not mention {missing}'


def _is_overload(node):
    """Return whether ``node`` is a function decorated ``@overload`` / ``@typing.overload``."""
    return isinstance(node, ast.FunctionDef) and any(
        (isinstance(d, ast.Name) and d.id == 'overload')
        or (isinstance(d, ast.Attribute) and d.attr == 'overload') for d in node.decorator_list)


def test_one_public_class_per_name():
    """No two modules define a public class or function of the same name."""
    seen, dup = {}, []
    for module, path in MODULES:
        with open(path, encoding='utf-8') as fh:
            tree = ast.parse(fh.read(), filename=path)
        for node in tree.body:
            if _is_overload(node):
                continue                      # a typing.overload signature, not a definition
            if isinstance(node, (ast.ClassDef, ast.FunctionDef)) and \
                    not node.name.startswith('_') and node.name not in ('main', 'run',
                                                                        'add_arguments'):
                if node.name in seen:
                    dup.append(f'{node.name}: {seen[node.name]} and {module}')
                seen.setdefault(node.name, module)
    assert not dup, '\n'.join(dup)


def test_result_objects_give_plain_json():
    """Result objects return plain JSON types from ``to_dict()`` (python-control's pattern)."""
    import json

    import numpy as np

    from friction_joint.identification import pattern_search
    from friction_joint.output import ExperimentResult

    res = pattern_search(lambda x: np.sum((x - 0.25) ** 2, axis=1), [1.0], [-2.0], [2.0],
                         min_step=1e-4)
    doc = json.loads(json.dumps(res.to_dict(), allow_nan=False))
    assert doc['x'] == [pytest.approx(0.25, abs=1e-3)] and doc['success'] is True
    summary = {'rmse': np.float64(0.5), 'bad': float('nan'), 'n': np.int64(3)}
    assert json.dumps(ExperimentResult('x', summary).to_dict(), allow_nan=False) == \
        '{"rmse": 0.5, "bad": null, "n": 3}'


def test_every_job_returns_a_run_with_what_it_wrote():
    """Every ``jobs.run_*`` is annotated to return a ``...Run`` that has ``written``."""
    import dataclasses
    import typing

    import friction_joint.jobs as jobs

    runs = [name for name in jobs.__all__ if name.startswith('run_')]
    assert {'run_diagnose', 'run_identify', 'run_experiment', 'run_classic', 'run_fleet',
            'run_fleet_simulation', 'run_demo'} <= set(runs)
    bad = []
    for name in runs:
        returned = typing.get_type_hints(getattr(jobs, name)).get('return')
        fields = {f.name for f in dataclasses.fields(returned)} \
            if dataclasses.is_dataclass(returned) else set()
        if not (isinstance(returned, type) and returned.__name__.endswith('Run')
                and 'written' in fields):
            bad.append(f'{name} -> {returned!r}')
        elif returned.__module__.split('.')[:2] != ['friction_joint', 'jobs']:
            bad.append(f'{name} -> {returned.__module__}.{returned.__name__}: not in jobs/')
    assert not bad, 'jobs that do not return a ...Run with written:\n' + '\n'.join(bad)
