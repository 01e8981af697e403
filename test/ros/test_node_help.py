# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``--help`` of every executable works without a gear file (issue 22).

``joint_sim --help`` printed ``missing required key gear_ratio`` and exited 2.
Now each node prints what it does, its own parameters (from its DEFAULTS and
DESCRIPTORS) and how to pass a gear file, and exits 0, before rclpy.init.
"""
import os
import subprocess
import sys

from friction_joint.ros.nodes.usage import help_requested
import pytest

pytestmark = pytest.mark.ros

PY = sys.executable
BIN = os.path.dirname(PY)
NODES = ('joint_sim', 'controller', 'estimator')


def _run(cmd):
    env = dict(os.environ, ROS_DOMAIN_ID='0')
    return subprocess.run(cmd, capture_output=True, text=True, timeout=60, env=env,
                          stdin=subprocess.DEVNULL)


def _defaults(node):
    if node == 'joint_sim':
        from friction_joint.ros.nodes.sim_params import DEFAULTS
        return list(DEFAULTS)
    module = __import__(f'friction_joint.ros.nodes.{node}', fromlist=['DEFAULTS'])
    return list(module.DEFAULTS) + ['mode']


@pytest.mark.parametrize('node', NODES)
@pytest.mark.parametrize('how', ['script --help', 'module -h'])
def test_node_help_without_a_gear_file(node, how):
    script = os.path.join(BIN, node)
    if how.startswith('script'):
        if not os.path.exists(script):
            pytest.skip(f'no {script} (not an editable install with scripts)')
        cmd = [script, '--help']
    else:
        cmd = [PY, '-m', f'friction_joint.ros.nodes.{node}', '-h']
    res = _run(cmd)
    assert res.returncode == 0, res.stderr
    assert res.stderr == ''
    out = res.stdout
    assert out.startswith(f'usage: {node} ')
    assert 'gear_ratio' not in out                       # no attempt to read a gear
    assert '--params-file config/' in out and '-p NAME:=VALUE' in out
    for name in _defaults(node):                         # every own parameter, with a meaning
        line = next((ln for ln in out.splitlines() if ln.startswith(f'  {name} (')), None)
        assert line is not None, f'{name} missing from {node} --help'
    assert max(len(ln) for ln in out.splitlines() if not ln.startswith('    ')) <= 100


def test_help_lists_defaults_and_ranges():
    res = _run([PY, '-m', 'friction_joint.ros.nodes.controller', '--help'])
    out = res.stdout
    assert '  amplitude (0.4)\n' in out and '[-3.2, 3.2]' in out
    assert '  sync (false)\n' in out and 'changeable at run time' in out
    res = _run([PY, '-m', 'friction_joint.ros.nodes.joint_sim', '--help'])
    assert '  seed (-1)\n' in res.stdout
    assert '[-1, 9223372036854775807]' in ' '.join(res.stdout.split())


def test_composed_help_points_at_the_nodes():
    res = _run([PY, '-m', 'friction_joint.ros.nodes.composed', '--help'])
    assert res.returncode == 0, res.stderr
    assert 'joint_sim --help' in res.stdout and 'section' in res.stdout


@pytest.mark.parametrize('tool', ['record', 'replay'])
def test_record_replay_help(tool):
    res = _run([PY, '-m', 'friction_joint', tool, '--help'])
    assert res.returncode == 0 and res.stdout.startswith('usage: ')


def test_help_only_before_ros_args():
    assert help_requested(['joint_sim', '--help'])
    assert help_requested(['joint_sim', '-h', '--ros-args', '-p', 'a:=1'])
    assert not help_requested(['joint_sim', '--ros-args', '-p', 'follow:=--help'])
    assert not help_requested(['joint_sim', '--ros-args', '-h'])
    assert not help_requested(['joint_sim'])


def test_ros_args_help_is_not_taken_for_ours():
    """``-p x:=--help`` after --ros-args is rcl's: the node starts (and refuses the value)."""
    res = _run([PY, '-m', 'friction_joint.ros.nodes.joint_sim', '--ros-args', '-p',
                'follow:=--help'])
    assert res.returncode == 2 and 'usage:' not in res.stdout
    assert res.stderr.startswith('joint_sim: error: ')


def test_help_into_a_closed_pipe_is_quiet():
    """``estimator --help | head -1`` printed a BrokenPipeError traceback."""
    res = subprocess.run(f'"{PY}" -m friction_joint.ros.nodes.estimator --help | true',
                         shell=True, capture_output=True, text=True, timeout=60)
    assert res.stderr == ''


@pytest.mark.parametrize('node', NODES)
def test_help_points_at_documents_that_exist(node):
    """Every document and README section a node's help names exists (and has the recipe)."""
    import re
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = ' '.join(_run([PY, '-m', f'friction_joint.ros.nodes.{node}', '--help']).stdout.split())
    docs = re.findall(r'\b(docs/[\w./-]+\.md)', out)
    assert docs and all(os.path.exists(os.path.join(root, d)) for d in docs), docs
    with open(os.path.join(root, 'README.md'), encoding='utf-8') as fh:
        readme = fh.read()
    sections = re.findall(r'README \("([^"]+)"\)', out)
    assert sections, out
    for section in sections:
        assert f'## {section}\n' in readme, section
        body = readme.split(f'## {section}\n', 1)[1].split('\n## ', 1)[0]
        assert f'{node} ' in body or f'/{node}' in body, (node, section)
