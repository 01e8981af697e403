# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Shared fixtures: isolated ROS 2 domains and process handling (see ``roshelpers.py``)."""
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import roshelpers  # noqa: E402


@pytest.fixture
def ros_env(monkeypatch):
    """Environment dict of a fresh ROS domain (no other test's); also in ``os.environ``."""
    env = roshelpers.ros_environ()
    for key in ('ROS_DOMAIN_ID', 'ROS_AUTOMATIC_DISCOVERY_RANGE'):
        monkeypatch.setenv(key, env[key])
    monkeypatch.delenv('ROS_LOCALHOST_ONLY', raising=False)
    yield env
    roshelpers.release_domain(env['ROS_DOMAIN_ID'])     # after spawn / ros_node have stopped


@pytest.fixture
def spawn(ros_env):
    """
    Yield a callable ``(cmd, env=None)`` -> :class:`roshelpers.Proc`.

    Used as ``spawn(cmd, env=None)``; each Proc is stopped at the end of the test.
    """
    procs = []

    def start(cmd, env=None, cwd=None):
        proc = roshelpers.Proc(cmd, ros_env if env is None else env, cwd)
        procs.append(proc)
        return proc

    yield start
    for proc in reversed(procs):
        proc.stop()


@pytest.fixture
def ros_node(ros_env):
    """Yield an in-test :class:`roshelpers.TestNode` in the test's domain."""
    with roshelpers.ros_node('test_node', ros_env['ROS_DOMAIN_ID']) as node:
        yield node
