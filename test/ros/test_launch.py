# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Static check of ``launch/friction_joint.launch.py`` against the package and ``bringup``.

The ROS 2 ``launch`` and ``launch_ros`` packages are not installable here (they
have no PyPI wheels), so this is a stand-in check, not a launch: the launch
file is loaded with small stand-in modules for exactly the ``launch`` /
``launch_ros`` names it imports (injected into ``sys.modules``; they record
their constructor arguments and evaluate the substitutions the way launch
does), ``generate_launch_description()`` is called, and the recorded nodes are
checked: every executable is a console script of this package, every
parameter file exists under ``config/`` and is installed by ``setup.py``, each
node gets the parameters that ``friction_joint bringup`` gives it, and the
``namespace`` argument reaches every node.  The namespace alone moves a joint's
topics because the nodes use relative topic names (``/clock`` excepted); that is
checked on the nodes' source, and the launch file must not remap a topic to an
absolute name.  It starts no ROS process.
"""
import ast
import importlib.util
import os
import runpy
import sys
import types

import pytest
import setuptools
import yaml

# the module, not the function of the same name a package __init__ may re-export
bringup_module = importlib.import_module('friction_joint.ros.bringup')

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LAUNCH_FILE = os.path.join(ROOT, 'launch', 'friction_joint.launch.py')
PACKAGE = 'friction_joint'
SHARE = 'share/' + PACKAGE


# ------------------------------------------------------------------ stand-ins
class _Recorded:
    """Base of the stand-in actions: keeps the constructor arguments."""

    def __init__(self, *args, **kwargs):
        self.args = args
        self.kwargs = kwargs


class _Substitution:
    """Base of the stand-in substitutions: ``perform(context) -> str``."""

    def perform(self, context):
        raise NotImplementedError


def _evaluate(value, context):
    """Evaluate a substitution, a string or a list of them (concatenated) to a string."""
    if isinstance(value, str):
        return value
    if isinstance(value, _Substitution):
        return value.perform(context)
    if isinstance(value, (list, tuple)):
        return ''.join(_evaluate(item, context) for item in value)
    raise TypeError(f'not a substitution: {value!r}')


class LaunchConfiguration(_Substitution):
    """Stand-in for ``launch.substitutions.LaunchConfiguration``."""

    def __init__(self, name):
        self.name = name

    def perform(self, context):
        return context['configurations'][self.name]


class PathJoinSubstitution(_Substitution):
    """Stand-in for ``launch.substitutions.PathJoinSubstitution``."""

    def __init__(self, substitutions):
        self.substitutions = substitutions

    def perform(self, context):
        return os.path.join(*(_evaluate(part, context) for part in self.substitutions))


class PythonExpression(_Substitution):
    """Stand-in for ``launch.substitutions.PythonExpression``: ``str(eval(...))``."""

    def __init__(self, expression):
        self.expression = expression

    def perform(self, context):
        return str(eval(_evaluate(self.expression, context), {'__builtins__': {}}))


class FindPackageShare(_Substitution):
    """Stand-in for ``launch_ros.substitutions.FindPackageShare``: the source tree."""

    def __init__(self, package):
        self.package = package

    def perform(self, context):
        context['packages'].add(self.package)
        return ROOT


class LaunchDescription(_Recorded):
    """Stand-in for ``launch.LaunchDescription``."""


class DeclareLaunchArgument(_Recorded):
    """Stand-in for ``launch.actions.DeclareLaunchArgument``."""


class Shutdown(_Recorded):
    """Stand-in for ``launch.actions.Shutdown``."""


class Node(_Recorded):
    """Stand-in for ``launch_ros.actions.Node``."""


STAND_INS = {
    'launch': {'LaunchDescription': LaunchDescription},
    'launch.actions': {'DeclareLaunchArgument': DeclareLaunchArgument, 'Shutdown': Shutdown},
    'launch.substitutions': {'LaunchConfiguration': LaunchConfiguration,
                             'PathJoinSubstitution': PathJoinSubstitution,
                             'PythonExpression': PythonExpression},
    'launch_ros': {},
    'launch_ros.actions': {'Node': Node},
    'launch_ros.substitutions': {'FindPackageShare': FindPackageShare},
}


@pytest.fixture
def description(monkeypatch):
    """Load the launch file with the stand-ins; return its ``LaunchDescription``."""
    for name, attributes in STAND_INS.items():
        module = types.ModuleType(name)
        module.__dict__.update(attributes)
        monkeypatch.setitem(sys.modules, name, module)
    spec = importlib.util.spec_from_file_location('friction_joint_launch', LAUNCH_FILE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    result = module.generate_launch_description()
    assert isinstance(result, LaunchDescription)
    return result


def _launch(description, **arguments):
    """
    Evaluate the description with these launch arguments; returns (context, nodes).

    Each node is a dict of its evaluated ``package``, ``executable``, ``namespace``,
    ``files`` (parameter files), ``params`` (the parameter dict, values parsed as
    YAML as launch_ros does), ``remappings`` and ``on_exit``.
    """
    context = {'configurations': {}, 'packages': set()}
    (entities,) = description.args
    declared = [e for e in entities if isinstance(e, DeclareLaunchArgument)]
    unknown = set(arguments) - {e.args[0] for e in declared}
    assert not unknown, f'the launch file declares no argument {sorted(unknown)}'
    for action in declared:
        name = action.args[0]
        if name in arguments:
            value = arguments[name]
            assert action.kwargs.get('choices') in (None, []) or value in action.kwargs['choices']
        else:
            value = _evaluate(action.kwargs['default_value'], context)
        context['configurations'][name] = value
    nodes = []
    for action in entities:
        if not isinstance(action, Node):
            continue
        kw = action.kwargs
        files, params = [], {}
        for entry in kw.get('parameters', []):
            if isinstance(entry, dict):
                for key, value in entry.items():
                    if isinstance(value, (_Substitution, str, list)):
                        value = yaml.safe_load(_evaluate(value, context))
                    params[key] = value
            else:
                files.append(_evaluate(entry, context))
        nodes.append({
            'package': _evaluate(kw['package'], context),
            'executable': _evaluate(kw['executable'], context),
            'namespace': _evaluate(kw.get('namespace', ''), context),
            'files': files,
            'params': params,
            'remappings': [(_evaluate(a, context), _evaluate(b, context))
                           for a, b in kw.get('remappings', [])],
            'on_exit': kw.get('on_exit'),
        })
    return context, nodes


# ------------------------------------------------------------------ the package
@pytest.fixture(scope='module')
def setup_kwargs():
    """Run ``setup.py``; return the keyword arguments it gives ``setuptools.setup``."""
    captured = {}
    original, cwd = setuptools.setup, os.getcwd()
    setuptools.setup = captured.update
    try:
        os.chdir(ROOT)                # setup.py globs config/*.yaml relative to the cwd
        runpy.run_path(os.path.join(ROOT, 'setup.py'), run_name='__main__')
    finally:
        setuptools.setup = original
        os.chdir(cwd)
    return captured


def _console_scripts(setup_kwargs):
    scripts = {}
    for line in setup_kwargs['entry_points']['console_scripts']:
        name, target = (part.strip() for part in line.split('='))
        scripts[name] = target
    return scripts


def _installed(setup_kwargs, directory):
    """Source paths that ``data_files`` installs into ``directory``."""
    return {path for target, paths in setup_kwargs['data_files'] if target == directory
            for path in paths}


def _bringup_nodes(monkeypatch, scripts, **options):
    """
    Run ``bringup`` with fake processes; return {module name: (gear file, params)}.

    A node started as ``python -m MODULE`` or as a console script (``scripts``) is
    named by its module.
    """
    started = {}

    class FakeProcess:
        def __init__(self, name, argv, env=None, log_dir=None):
            self.name = name
            self.proc = types.SimpleNamespace(returncode=0)
            started[name] = argv

        def alive(self):
            return False

        def stop(self, timeout=45.0):
            return 0

    monkeypatch.setattr(bringup_module, 'NodeProcess', FakeProcess)
    bringup_module.bringup(os.path.join(ROOT, 'config', 'csd25.yaml'),
                           os.path.join(ROOT, 'config', 'csd25_truth.yaml'), quiet=True,
                           **options)
    nodes = {}
    for argv in started.values():
        if '-m' in argv:
            module = argv[argv.index('-m') + 1]
        else:
            module = scripts[os.path.basename(argv[0])].split(':')[0]
        rest = argv[argv.index('--ros-args') + 1:]
        assert rest[0] == '--params-file'
        params = {}
        for flag, assignment in zip(rest[2::2], rest[3::2], strict=True):
            assert flag == '-p'
            key, value = assignment.split(':=', 1)
            params[key] = yaml.safe_load(value)
        nodes[module] = (rest[1], params)
    return nodes


# ------------------------------------------------------------------ tests
def test_executables_are_console_scripts_of_this_package(description, setup_kwargs):
    context, nodes = _launch(description)
    scripts = _console_scripts(setup_kwargs)
    assert setup_kwargs['name'] == PACKAGE
    assert context['packages'] == {PACKAGE}
    assert sorted(n['executable'] for n in nodes) == ['controller', 'estimator', 'joint_sim']
    for node in nodes:
        assert node['package'] == PACKAGE
        assert node['executable'] in scripts, f'{node["executable"]} is no console script'
        module = scripts[node['executable']].split(':')[0]
        assert importlib.util.find_spec(module) is not None, f'{module} does not exist'


def test_parameter_files_exist_and_are_installed(description, setup_kwargs):
    _, nodes = _launch(description)
    installed = _installed(setup_kwargs, SHARE + '/config')
    named = set()
    for node in nodes:
        assert len(node['files']) == 1, node
        for path in node['files']:
            rel = os.path.relpath(path, ROOT)
            assert rel.startswith('config' + os.sep), path
            assert os.path.isfile(path), path
            assert rel.replace(os.sep, '/') in installed, f'setup.py does not install {rel}'
            named.add(rel)
    assert named == {os.path.join('config', 'csd25.yaml'),
                     os.path.join('config', 'csd25_truth.yaml')}


def test_launch_file_is_installed(setup_kwargs):
    assert 'launch/friction_joint.launch.py' in _installed(setup_kwargs, SHARE + '/launch')


@pytest.mark.parametrize('mode', ['lockstep', 'realtime'])
@pytest.mark.parametrize('friction', ['lugre', 'gms'])
def test_nodes_get_the_parameters_of_bringup(description, setup_kwargs, monkeypatch, mode,
                                             friction):
    duration = 10.0
    _, nodes = _launch(description, mode=mode, friction=friction, duration=str(duration))
    scripts = _console_scripts(setup_kwargs)
    expected = _bringup_nodes(monkeypatch, scripts, duration=duration, mode=mode,
                              friction=friction)
    assert len(nodes) == len(expected)
    for node in nodes:
        module = scripts[node['executable']].split(':')[0]
        assert module in expected, f'bringup does not start {module}'
        gear_file, params = expected[module]
        assert node['files'] == [gear_file]
        # an empty string is the nodes' default: bringup passes no override for it
        launched = {k: v for k, v in node['params'].items() if v not in ('', None)}
        if 'rate' not in params:
            # bringup leaves rate at the node's default, 0.0 = the gear's simulation.rate
            assert launched.pop('rate', 0.0) == 0.0
        assert launched == params
        for key, value in params.items():
            assert type(launched[key]) is type(value), (key, launched[key], value)


def test_simulator_end_shuts_the_launch_down(description):
    _, nodes = _launch(description)
    (sim,) = [n for n in nodes if n['executable'] == 'joint_sim']
    assert isinstance(sim['on_exit'], Shutdown)


def _topic_names(module):
    """Topic names given as string literals to ``create_publisher``/``create_subscription``."""
    with open(importlib.util.find_spec(module).origin, encoding='utf-8') as stream:
        tree = ast.parse(stream.read())
    names = []
    for call in ast.walk(tree):
        if (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)
                and call.func.attr in ('create_publisher', 'create_subscription')
                and len(call.args) >= 2 and isinstance(call.args[1], ast.Constant)
                and isinstance(call.args[1].value, str)):
            names.append(call.args[1].value)
    return names


@pytest.mark.parametrize('namespace', ['', 'joint1'])
def test_namespace_applies_to_every_node(description, namespace):
    _, nodes = _launch(description, namespace=namespace)
    assert len(nodes) == 3
    for node in nodes:
        assert node['namespace'] == namespace
        # a remapping to an absolute name would keep a topic out of the namespace
        pinned = [(a, b) for a, b in node['remappings'] if b.startswith('/')]
        assert not pinned, f'{node["executable"]} remaps to absolute names: {pinned}'


def test_node_topics_are_relative(description, setup_kwargs):
    _, nodes = _launch(description)
    scripts = _console_scripts(setup_kwargs)
    for node in nodes:
        module = scripts[node['executable']].split(':')[0]
        names = _topic_names(module)
        assert 'joint_states' in names, f'{module}: no joint_states topic found'
        absolute = [name for name in names if name.startswith('/') and name != '/clock']
        assert not absolute, f'{module} uses absolute topic names {absolute}'


def test_default_namespace_is_the_root(description):
    context, nodes = _launch(description)
    assert context['configurations']['namespace'] == ''
    assert {n['namespace'] for n in nodes} == {''}
