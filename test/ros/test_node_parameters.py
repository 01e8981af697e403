# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The nodes read a gear file as the command line does; bad files and parameters end in one line.

``prepare_ros_args`` reads every ``--params-file`` with the package's reader and
hands rcl a normalized copy, so rcl (which reads ``2e4`` as a number and
refuses ``[2, 0.01]``) sees exactly what :func:`load_gear` read.  The in-process
tests parse the prepared arguments with rcl itself (``rclpy.init`` on a
private context); the process tests run ``joint_sim``.
"""
import contextlib
import os
import sys

from friction_joint import GearConfigError, load_gear
import pytest

pytestmark = pytest.mark.ros

PY = sys.executable
HEAD = '/**:\n  ros__parameters:\n'
BODY = """\
    joint_name: j1
    gear_ratio: 80
    inertia: .25
    friction:
      model: lugre
      fc: [2, 0.01]
      fv: [0.4, 1e-3]
      fs: [3]
      vs: [5e-2]
      fc_load: []
      delta_v: [1, 0]
      lugre:
        sigma0: 2e4
        sigma1: 0.5
      gms:
        k: [1e4, 5000]
        c: 4E2
      position_ripple:
        cycles_per_rev: 160
        amplitude: [0.05, 1e-2]
    lever:
      mass: 8
      length: ~
    simulation:
      seed: 3
"""
OWN = ['mode', 'seed', 'duration']


def write(path, text):
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding='utf-8')
    return str(path)


@contextlib.contextmanager
def rcl_node(args, domain):
    """Yield a node on a private context initialised with ``args`` (rcl parses the files)."""
    import rclpy
    from rclpy.context import Context
    from rclpy.signals import SignalHandlerOptions
    context = Context()
    rclpy.init(args=args, context=context, domain_id=int(domain),
               signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        node = rclpy.create_node('joint_sim', context=context, start_parameter_services=False)
        yield node
    finally:
        if node is not None:
            node.destroy_node()
        context.try_shutdown()


def node_gear(args, domain):
    from friction_joint.ros.parameters import declare_gear, prepare_ros_args
    prepared, cleanup = prepare_ros_args(args)
    try:
        with rcl_node(prepared, domain) as node:
            return declare_gear(node, own=OWN), {
                k: v.value for k, v in node._parameter_overrides.items()}
    finally:
        cleanup()


@pytest.mark.parametrize('gear', ['config/csd25.yaml', 'config/csd25_truth.yaml',
                                  'config/csd25_base.yaml', 'numbers'])
def test_node_reads_the_gear_file_as_the_cli_does(gear, tmp_path, ros_env):
    """``2e4`` (a string for the CLI, 20000 for rcl) and ``[2, 0.01]`` (an rcl error)."""
    if gear == 'numbers':
        gear = write(tmp_path / 'numbers.yaml', HEAD + BODY)
    cli = load_gear(gear)
    node, _ = node_gear(['x', '--ros-args', '--params-file', gear], ros_env['ROS_DOMAIN_ID'])
    assert node.friction == cli.friction
    assert node.data == cli.data
    if 'numbers' in gear:
        assert cli.friction.lugre.sigma0 == 20000.0 and cli.friction.fc == (2.0, 0.01)
        assert cli.inertia == 0.25 and cli.friction.gms.c == 400.0


def test_override_values_are_coerced_like_file_values(tmp_path, ros_env):
    """Ints for float keys and mixed lists in ``-p`` overrides (rcl refused the mixed list)."""
    gear = write(tmp_path / 'g.yaml', HEAD + BODY)
    args = ['x', '--ros-args', '--params-file', gear, '-p', 'friction.fc:=[3, 0.5]',
            '-p', 'inertia:=1', '-p', 'friction.lugre.sigma0:=3e4', '-p', 'mode:=lockstep']
    node, overrides = node_gear(args, ros_env['ROS_DOMAIN_ID'])
    assert node.friction.fc == (3.0, 0.5) and node.inertia == 1.0
    assert type(node.inertia) is float and node.friction.lugre.sigma0 == 30000.0
    assert overrides['mode'] == 'lockstep'


def test_other_params_files_and_arguments_pass_through(tmp_path, ros_env):
    """A launch-style file of node parameters and node-name sections keep their meaning."""
    gear = write(tmp_path / 'g.yaml', HEAD + BODY)
    own = write(tmp_path / 'own.yaml',
                '/**:\n  ros__parameters:\n    mode: lockstep\n    duration: 2\n'
                '    qos_overrides:\n      /joint_states:\n        publisher:\n'
                '          depth: 5\n'
                'other_node:\n  ros__parameters:\n    friction: lugre\n    rate: [1, 2.5]\n')
    from friction_joint.ros.parameters import prepare_ros_args
    args = ['prog', 'user', '--ros-args', '-r', '__ns:=/arm', '--params-file', gear,
            '--params-file', own, '-p', 'seed:=4', '--', '--params-file', 'user-arg']
    prepared, cleanup = prepare_ros_args(args)
    try:
        assert len(prepared) == len(args)
        changed = [i for i, (a, b) in enumerate(zip(args, prepared, strict=True)) if a != b]
        assert changed == [6, 8]                    # the two params files, nothing else
        files = [prepared[i] for i in changed]
        assert all(os.path.isfile(f) for f in files)
        with rcl_node(prepared, ros_env['ROS_DOMAIN_ID']) as node:
            values = {k: v.value for k, v in node._parameter_overrides.items()}
    finally:
        cleanup()
    assert not any(os.path.exists(f) for f in files)
    assert values['mode'] == 'lockstep' and values['duration'] == 2 and values['seed'] == 4
    assert values['qos_overrides./joint_states.publisher.depth'] == 5
    assert values['friction.lugre.sigma0'] == 20000.0 and values['inertia'] == 0.25
    assert list(values['friction.fc']) == [2.0, 0.01]


def test_without_params_files_the_arguments_are_unchanged():
    from friction_joint.ros.parameters import prepare_ros_args
    args = ['prog', '--ros-args', '-p', 'mode:=lockstep']
    prepared, cleanup = prepare_ros_args(args)
    assert prepared == args
    cleanup()


@pytest.mark.parametrize('content, words', [
    (b'\xff\xfe\x00\x01binary', ['UTF-8']),
    (HEAD + BODY.replace('seed: 3', 'seed: ' + '9' * 400), ['64-bit']),
    (HEAD + BODY.replace('mass: 8', 'mass: [1, 2: }'), ['not valid YAML', 'line']),
    (HEAD + BODY.replace('fv: [0.4, 1e-3]', 'fc: [1.0]'), ["duplicate key 'fc'", 'line 9']),
    (HEAD + BODY.replace('fc: [2, 0.01]', 'fc: [' + '0.0, ' * 9 + '1.0]'), ['at most 9']),
    (HEAD + BODY.replace('sigma1: 0.5', 'sigma1: "1"'), ['friction.lugre.sigma1', 'a number']),
    (HEAD + BODY.replace('fv: [0.4, 1e-3]', 'fv: [-1.0]'), ['friction.fv', 'evaluates to']),
    (HEAD + BODY + '    friction.fcc: [1.0]\n', ['unknown key friction.fcc']),
    (HEAD + '    mode: [1, true]\n', ['mode', 'mixes']),
    ('x' * 1_100_000, ['larger than']),
    (None, ['cannot read']),
])
def test_bad_params_files_are_one_line_errors(content, words, tmp_path, monkeypatch):
    from friction_joint.ros.parameters import prepare_ros_args
    scratch = tmp_path / 'tmp'
    scratch.mkdir()
    monkeypatch.setattr('tempfile.tempdir', str(scratch))
    missing = str(tmp_path / 'missing.yaml')
    path = missing if content is None else write(tmp_path / 'g.yaml', content)
    good = write(tmp_path / 'good.yaml', HEAD + BODY)
    with pytest.raises(GearConfigError) as err:
        prepare_ros_args(['x', '--ros-args', '--params-file', good, '--params-file', path])
    msg = str(err.value)
    assert '\n' not in msg and path in msg, msg
    for w in words:
        assert w in msg, msg
    assert list(scratch.iterdir()) == []            # nothing left behind


def test_params_file_without_path_is_an_error():
    from friction_joint.ros.parameters import prepare_ros_args
    with pytest.raises(GearConfigError, match='--params-file'):
        prepare_ros_args(['x', '--ros-args', '--params-file'])


# ---------------------------------------------------------------- processes

def joint_sim(gear, *params):
    cmd = [PY, '-m', 'friction_joint.ros.nodes.joint_sim', '--ros-args', '--params-file', gear]
    for p in params:
        cmd += ['-p', p]
    return cmd


@pytest.mark.parametrize('param, words', [
    ('seed:=abc', ['parameter seed', 'expected an integer', "'abc'"]),
    ('seed:=1.5', ['parameter seed', 'expected an integer', '1.5']),
    ('wait_subscribers:=abc', ['parameter wait_subscribers', 'expected an integer']),
    ('publish_rate:=fast', ['parameter publish_rate', 'expected a number']),
])
def test_node_parameter_of_the_wrong_type_is_one_line(param, words, spawn):
    """These ended in a TypeError traceback (exit 1) or ran with the wrong type."""
    proc = spawn(joint_sim('config/csd25_truth.yaml', param, 'mode:=lockstep'))
    assert proc.wait(60) == 2, proc.describe()
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert 'Traceback' not in proc.stderr, proc.describe()
    assert lines[-1].startswith('joint_sim: error: '), proc.describe()
    for w in words:
        assert w in lines[-1], proc.describe()


def test_node_runs_on_a_file_rcl_alone_refused(tmp_path, spawn):
    """``fc: [2, 0.01]`` ended every node in an RCLError traceback at rclpy.init."""
    gear = write(tmp_path / 'g.yaml', HEAD + BODY)
    proc = spawn(joint_sim(gear, 'duration:=0.05', 'publish_rate:=200.0',
                           'wait_subscribers:=0'))
    assert proc.wait(60) == 0, proc.describe()
    assert 'realtime simulation of j1' in proc.stdout + proc.stderr, proc.describe()


with open('config/csd25_truth.yaml', encoding='utf-8') as _fh:
    TRUTH = _fh.read()


@pytest.mark.parametrize('content, words', [
    (b'\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR', ['UTF-8']),
    (TRUTH.replace('seed: 0', 'seed: ' + '9' * 400), ['64-bit']),
    (TRUTH.replace('mass: 8.16', 'mass: [1, 2: }'), ['not valid YAML']),
    (None, ['cannot read']),
])
def test_node_with_a_bad_gear_file_is_one_line(content, words, tmp_path, spawn, ros_env):
    """Tracebacks (exit 1) before: UnicodeDecodeError, RCLError."""
    scratch = tmp_path / 'tmp'
    scratch.mkdir()
    env = dict(ros_env, TMPDIR=str(scratch))
    missing = str(tmp_path / 'missing.yaml')
    gear = missing if content is None else write(tmp_path / 'g.yaml', content)
    proc = spawn(joint_sim(gear), env=env)
    assert proc.wait(60) == 2, proc.describe()
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert 'Traceback' not in proc.stderr, proc.describe()
    assert lines[-1].startswith(f'joint_sim: error: {gear}: '), proc.describe()
    for w in words:
        assert w in lines[-1], proc.describe()
    assert list(scratch.iterdir()) == []


@pytest.mark.parametrize('param, error', [
    ('seed:=7', None), ('seed:=7.0', 'parameter seed: expected an integer, got 7.0'),
    ('seed:=true', 'parameter seed: expected int, got True'),
    ('xi0:=nan', None), ('xi0:=30', None), ('xi0:=abc', 'parameter xi0: expected a number'),
    ('xi0:=.inf', 'parameter xi0: must be finite'),
])
def test_declare_node_params_checks_types(param, error, ros_env):
    """An int parameter took any type (``seed:=abc`` reached the plant); NaN may mean unset."""
    from friction_joint.ros.parameters import declare_node_params
    defaults = {'seed': -1, 'xi0': float('nan')}
    with rcl_node(['x', '--ros-args', '-p', param], ros_env['ROS_DOMAIN_ID']) as node:
        if error is None:
            values = declare_node_params(node, defaults)
            assert type(values['seed']) is int and type(values['xi0']) is float
        else:
            with pytest.raises(GearConfigError, match=error):
                declare_node_params(node, defaults)
