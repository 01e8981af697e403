# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Hostile node parameters (issue 23): one line and exit 2 at start-up, a reason at run time.

A node started with a bad parameter (on the command line, in a params file,
the standard ``use_sim_time`` and ``qos_overrides.*`` included) must end by
itself with exit status 2 and one line on stderr naming the parameter and the
problem; before, these cases ended in tracebacks, hung (a FIFO as params file,
``publish_rate:=1e-300``) or ran with a value silently ignored or absurd.  A
bad value set at run time is refused with a reason and the node keeps running.
"""
import os
import signal
import sys

import pytest
from roshelpers import DEADLINE, wait_until

pytestmark = pytest.mark.ros

PY = sys.executable
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TRUTH = os.path.join(ROOT, 'config', 'csd25_truth.yaml')
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
QOS = 'qos_overrides./joint_states.'
CLI = [PY, '-m', 'friction_joint']


def node_cmd(node, *ros_args, gear=None):
    """Return the command starting ``node`` with its gear file and more ROS arguments."""
    gear = gear or (TRUTH if node == 'joint_sim' else MODEL)
    return [PY, '-m', f'friction_joint.ros.nodes.{node}', '--ros-args', '--params-file',
            gear] + list(ros_args)


def gear_with(tmp_path, old, new):
    """Return a copy of the truth gear with ``old`` replaced by ``new``."""
    with open(TRUTH, encoding='utf-8') as fh:
        text = fh.read()
    assert old in text
    path = tmp_path / 'gear.yaml'
    path.write_text(text.replace(old, new), encoding='utf-8')
    return str(path)


def one_line_exit_2(proc, name, words):
    """Wait for ``proc`` to end by itself; assert exit 2 and one stderr line with ``words``."""
    try:
        rc = proc.wait(DEADLINE)                 # a hang fails here, it does not block the run
    except Exception:                           # noqa: BLE001 - TimeoutExpired: describe it
        pytest.fail(f'{name} did not end within {DEADLINE} s:\n{proc.describe()}')
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert rc == 2, proc.describe()
    assert len(lines) == 1, proc.describe()
    assert lines[0].startswith(f'{name}: error: '), proc.describe()
    for word in words:
        assert word in lines[0], proc.describe()


# the start-up cases of issue 23: node, ROS arguments, words the one line must hold
STARTUP = [
    ('joint_sim', ['-p', 'use_sim_time:=abc'], ['use_sim_time', "'abc'"]),
    ('joint_sim', ['-p', QOS + 'publisher.depth:=abc'], [QOS + 'publisher.depth', 'integer']),
    ('joint_sim', ['-p', QOS + 'publisher.depth:=-5'], [QOS + 'publisher.depth', '-5']),
    ('joint_sim', ['-p', QOS + 'publisher.reliability:=bogus'], ['reliability', 'bogus']),
    ('joint_sim', ['-p', QOS + 'publisher.durability:=transient_local'],
     ['durability', 'volatile']),
    ('joint_sim', ['-p', 'qos_overrides./joint_statez.publisher.depth:=5'],
     ['/joint_statez', 'no such publisher']),
    ('estimator', ['-p', QOS + 'subscription.depth:=0'], ['subscription.depth', '0']),
    ('joint_sim', ['-p', 'xi0:=1e308'], ['xi0', 'temperature']),
    ('joint_sim', ['-p', 'xi0:=-300.0'], ['xi0', 'temperature']),
    ('joint_sim', ['-p', 'publish_rate:=1e-300'], ['publish_rate', '1e-300']),
    ('joint_sim', ['-p', 'publish_rate:=5000.0'], ['publish_rate', 'simulation.rate']),
    ('joint_sim', ['-p', 'seed:=-2'], ['seed', '-1']),
    ('joint_sim', ['-p', 'start_delay:=1e308'], ['start_delay', '3600']),
    ('joint_sim', ['-p', 'duration:=1e308'], ['duration']),
    ('joint_sim', ['-p', 'resend_period:=1e-300'], ['resend_period']),
    ('joint_sim', ['-p', 'command_timeout:=1e-9'], ['command_timeout', 'step']),
    ('joint_sim', ['-p', 'q0:=1e300'], ['q0', 'position']),
    ('joint_sim', ['-p', 'friction.fc:=[]'], ['friction.fc', 'empty list']),
    ('joint_sim', ['-p', ':=1'], ['-p :=1', 'name is empty']),
    ('joint_sim', ['--log-level', 'bogus'], ['log level']),
    ('joint_sim', ['-p', 'mode:=lockstep', '-p', 'follow:=a b'], ['parameter follow', "'a b'"]),
    ('joint_sim', ['-p', 'wait_recorder:=1abc'], ['parameter wait_recorder', "'1abc'"]),
    ('controller', ['-p', 'rise_time:=1e-300'], ['rise_time', '1e-300']),
    ('controller', ['-p', 'rise_time:=0.001'], ['rise_time', 'samples']),
    ('controller', ['-p', 'design_inertia:=1e308'], ['design_inertia', 'inertia']),
    ('controller', ['-p', 'rate:=-3.0'], ['parameter rate']),
    ('estimator', ['-p', 'beta:=1e308'], ['beta', '1e+308']),
    ('estimator', ['-p', 'beta:=20000.0'], ['beta', 'Nyquist']),
    ('joint_sim', ['-p', 'lever.angle_offset:=1e308'], ['lever.angle_offset', 'turn']),
    ('controller', ['-p', 'lever.angle_offset:=1e308'], ['lever.angle_offset', 'turn']),
    ('estimator', ['-p', 'lever.angle_offset:=-90.0'], ['lever.angle_offset', 'degrees']),
]


@pytest.mark.parametrize('node, args, words', STARTUP,
                         ids=[f'{n}:{" ".join(a)}' for n, a, _ in STARTUP])
def test_bad_parameter_at_start_up_is_one_line(node, args, words, spawn):
    """Tracebacks (exit 1), a hang, or a value silently ignored or absurd before."""
    one_line_exit_2(spawn(node_cmd(node, *args)), node, words)


@pytest.mark.parametrize('rate', ['1.0e15', '1.0e-300'])
def test_truth_gear_with_an_absurd_rate_is_one_line(rate, spawn, tmp_path):
    """A ``simulation.rate`` of 1e15 ended in a LinAlgError traceback, 1e-300 in another."""
    gear = gear_with(tmp_path, '      rate: 3000.0', f'      rate: {rate}')
    one_line_exit_2(spawn(node_cmd('joint_sim', gear=gear)), 'joint_sim', ['rate'])


def test_params_file_fifo_missing_or_oversized_is_one_line(spawn, tmp_path):
    """A FIFO named by --params-file was opened by rcl before any code of ours: a hang."""
    fifo = tmp_path / 'fifo.yaml'
    os.mkfifo(fifo)
    big = tmp_path / 'big.yaml'
    big.write_text('/**:\n  ros__parameters:\n    joint_name: j\n' + '#' * (2 << 20) + '\n')
    cases = [(['--params-file', str(fifo)], ['fifo.yaml', 'FIFO']),
             (['--params-file', str(tmp_path / 'missing.yaml')], ['missing.yaml']),
             (['--params-file', str(big)], ['big.yaml', 'limit']),
             (['--log-config-file', str(fifo)], ['fifo.yaml', 'FIFO'])]
    for args, words in cases:
        one_line_exit_2(spawn(node_cmd('joint_sim', *args)), 'joint_sim', words)


@pytest.mark.parametrize('domain', ['233', 'abc'])
def test_domain_id_beyond_the_dds_ports_is_one_line(domain, spawn, ros_env, tmp_path):
    """Fast DDS printed two lines to stdout and the node exited 1 with nothing on stderr."""
    env = dict(ros_env, ROS_DOMAIN_ID=domain)
    one_line_exit_2(spawn(node_cmd('joint_sim'), env=env), 'joint_sim', ['ROS_DOMAIN_ID'])
    one_line_exit_2(spawn(CLI + ['record', str(tmp_path / 'rec')], env=env),
                    'friction_joint record', ['ROS_DOMAIN_ID'])
    assert not (tmp_path / 'rec').exists()


def _set(ros_node, client, name, value):
    from rcl_interfaces.srv import SetParameters
    from rclpy.parameter import Parameter
    req = SetParameters.Request()
    req.parameters = [Parameter(name, value=value).to_parameter_msg()]
    fut = client.call_async(req)
    assert ros_node.spin_until(fut.done), f'no answer to setting {name}'
    return fut.result().results[0]


def test_bad_parameter_set_at_run_time_is_refused_with_a_reason(spawn, ros_node):
    """Run-time values go through the same ranges as start-up values; the nodes keep running."""
    from rcl_interfaces.srv import SetParameters
    ctrl = spawn(node_cmd('controller'))
    est = spawn(node_cmd('estimator'))
    assert ctrl.wait_for('eq. 17 controller') and est.wait_for('external torque'), \
        ctrl.describe() + est.describe()
    clients = {n: ros_node.node.create_client(SetParameters, f'/{n}/set_parameters')
               for n in ('controller', 'estimator')}
    for client in clients.values():
        assert client.wait_for_service(timeout_sec=DEADLINE)
    refused = [('controller', 'amplitude', 1e308), ('controller', 'omega', -1.0),
               ('controller', 'omega', 'fast'), ('controller', 'offset', float('nan')),
               ('controller', 'rise_time', 1e-300), ('controller', 'use_sim_time', True),
               ('controller', QOS + 'subscription.depth', 5),
               ('estimator', 'beta', 1e308), ('estimator', 'friction', 'coulomb'),
               ('estimator', 'use_sim_time', 'abc')]
    for node, name, value in refused:
        result = _set(ros_node, clients[node], name, value)
        assert not result.successful and result.reason, (node, name, value)
    assert _set(ros_node, clients['controller'], 'amplitude', 0.2).successful
    assert _set(ros_node, clients['estimator'], 'friction', 'static').successful
    assert ctrl.popen.poll() is None and est.popen.poll() is None, \
        ctrl.describe() + est.describe()


# ---------------------------------------------------------------- replay and record


@pytest.mark.parametrize('args, words', [
    (['--rate', '0'], ['--rate', 'max']),
    (['--rate', '-1'], ['--rate']),
    (['--rate', 'nan'], ['--rate']),
    (['--wait', '-5'], ['--wait', '-5']),
    (['--settle', '1e308'], ['--settle']),
])
def test_replay_refuses_a_bad_rate_or_wait(args, words, spawn, tmp_path):
    """``--rate 0`` and ``--wait -5`` were accepted."""
    proc = spawn(CLI + ['replay', str(tmp_path / 'bag')] + args)
    one_line_exit_2(proc, 'friction_joint replay', words)


def test_record_into_a_path_through_a_file_is_one_line(spawn, tmp_path):
    """``record out/afile/x`` with ``afile`` a file ended in a NotADirectoryError traceback."""
    (tmp_path / 'afile').write_text('x')
    proc = spawn(CLI + ['record', str(tmp_path / 'afile' / 'x')])
    one_line_exit_2(proc, 'friction_joint record', [str(tmp_path / 'afile'), 'not a directory'])
    assert (tmp_path / 'afile').read_text() == 'x'


@pytest.mark.parametrize('script', ['record', 'replay'])
def test_record_and_replay_with_bad_ros_arguments_are_one_line(script, spawn, tmp_path):
    """A FIFO as --params-file blocked rcl's argument parser; ``-p :=1`` was a traceback."""
    fifo = tmp_path / 'fifo.yaml'
    os.mkfifo(fifo)
    exe = os.path.join(os.path.dirname(PY), script)
    for ros_args, words in ((['--params-file', str(fifo)], ['FIFO']),
                            (['-p', ':=1'], ['-p :=1']),
                            (['--log-level', 'bogus'], ['log level'])):
        proc = spawn([exe, str(tmp_path / 'rec'), '--ros-args'] + ros_args)
        one_line_exit_2(proc, script, words)
    assert not (tmp_path / 'rec').exists()


def _maps_rclpy(pid):
    try:
        with open(f'/proc/{pid}/maps', encoding='utf-8', errors='replace') as fh:
            return '_rclpy_pybind11' in fh.read()
    except OSError:
        return False


@pytest.mark.parametrize('script', ['friction_joint record', 'record'])
def test_ctrl_c_while_record_starts_is_quiet(script, spawn, tmp_path):
    """
    Ctrl-C while ``record`` loads ROS (its first 2-3 s) ends it without a traceback.

    The signal goes out once rclpy is loaded (``/proc/PID/maps``): the moment
    the command is inside its own code, loading ROS and the bag writer.
    """
    out = tmp_path / 'rec'
    cmd = (CLI + ['record', str(out)] if script != 'record'
           else [os.path.join(os.path.dirname(PY), 'record'), str(out)])
    proc = spawn(cmd)
    assert wait_until(lambda: _maps_rclpy(proc.popen.pid) or proc.popen.poll() is not None), \
        proc.describe()
    os.killpg(proc.popen.pid, signal.SIGINT)
    rc = proc.wait(DEADLINE)
    assert 'Traceback' not in proc.stderr and 'KeyboardInterrupt' not in proc.stderr, \
        proc.describe()
    assert rc in (0, 130), proc.describe()
