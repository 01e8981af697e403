# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``-h`` / ``--help`` of the node executables, answered without a gear file and before rclpy.init.

``joint_sim --help`` (also ``controller``, ``estimator``, ``python -m
friction_joint.ros.nodes.<node> --help``) prints what the node does (the
summary and first paragraph of the node module's docstring), its own
parameters with their defaults, meaning and ranges, and how to pass the gear
file, then exits 0.  The parameter list is built by the node's own declare
function (:func:`~friction_joint.ros.parameters.declare_node_params` or
:func:`~friction_joint.ros.parameters.declare_follower_params`) on a
stand-in that records what is declared, from the module's ``DEFAULTS`` and
``DESCRIPTORS``: one source of truth for the node, ``ros2 param describe``
and this text.  Only the arguments before ``--ros-args`` are looked at (rcl
owns the rest); no argument parser is involved.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
import math
import os
import re
import sys
import textwrap
from types import ModuleType
from typing import Any

__all__ = ['help_requested', 'node_usage', 'exit_on_help', 'HELP_FLAGS', 'EXAMPLE_GEARS']

HELP_FLAGS = ('-h', '--help')
#: the shipped gear file each node is usually started with (the simulator runs the "truth")
EXAMPLE_GEARS = {'joint_sim': 'config/csd25_truth.yaml', 'controller': 'config/csd25.yaml',
                 'estimator': 'config/csd25.yaml'}
_WIDTH = 79


def help_requested(args: Sequence[str] | None = None) -> bool:
    """Return True if ``-h`` or ``--help`` comes before ``--ros-args`` in ``args`` (sys.argv)."""
    argv = list(sys.argv if args is None else args)
    if '--ros-args' in argv:
        argv = argv[:argv.index('--ros-args')]
    return any(a in HELP_FLAGS for a in argv)


class _Value:
    def __init__(self, value):
        self.value = value


class _Declared:
    """Stands in for a node: records the parameters declared on it, with their defaults."""

    def __init__(self):
        self.declared = []

    def declare_parameter(self, name, value, descriptor):
        self.declared.append((name, value, descriptor))
        return _Value(value)


def _plain(text):
    """Return reStructuredText ``text`` as plain text (roles and literals unmarked)."""
    text = re.sub(r':\w+:`~[\w.]*?(\w+)`', r'\1', text)
    text = re.sub(r':\w+:`([^`]*)`', r'\1', text)
    return ' '.join(text.replace('``', '').split())


def _paragraphs(doc, count):
    """Return the summary and the first ``count`` plain (not indented) paragraphs after it."""
    paras = [p for p in re.split(r'\n\s*\n', textwrap.dedent(doc or '').strip()) if p.strip()]
    plain = [p for p in paras[1:] if not p.startswith((' ', '\t'))]
    return [_plain(p) for p in paras[:1] + plain[:count]]


def _default(value):
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float) and math.isnan(value):
        return 'nan'
    if value == '':
        return "''"
    return f'{value:g}' if isinstance(value, float) else str(value)


def _range(descriptor):
    if descriptor.integer_range:
        low, high = descriptor.integer_range[0].from_value, descriptor.integer_range[0].to_value
        return f' [{low}, {high}]'
    ranges = descriptor.floating_point_range
    return f' [{ranges[0].from_value:g}, {ranges[0].to_value:g}]' if ranges else ''


def _parameters(module, name):
    """Return [(name, default, description)] of the node's own parameters."""
    from ..parameters import declare_follower_params, declare_node_params
    defaults = getattr(module, 'DEFAULTS', None)
    if defaults is None:
        return []
    stand_in = _Declared()
    if 'mode' in defaults:
        declare_node_params(stand_in, defaults, module.VALIDATORS, module.DESCRIPTORS)
    else:                                   # a follower: mode first, sync defaults from it
        declare_follower_params(stand_in, defaults, module.VALIDATORS, module.DESCRIPTORS)
    rows = []
    for pname, value, desc in stand_in.declared:
        note = '' if desc.read_only else ' (changeable at run time)'
        rows.append((pname, _default(value), _plain(desc.description) + _range(desc) + note))
    return rows


def node_usage(module: ModuleType, name: str) -> str:
    """Return the ``--help`` text of the node ``name`` defined in ``module``."""
    fill = textwrap.TextWrapper(width=_WIDTH, break_on_hyphens=False)
    indent = textwrap.TextWrapper(width=_WIDTH, initial_indent='    ',
                                  subsequent_indent='    ', break_on_hyphens=False)
    rows = _parameters(module, name)
    lines = [f'usage: {name} [-h] --ros-args --params-file FILE.yaml [-p NAME:=VALUE ...]'
             ' [-r __ns:=/NS]', '']
    for para in _paragraphs(module.__doc__, 1 if rows else 2):
        lines += fill.wrap(para) + ['']
    if not rows:                            # a composition: the nodes' parameters
        return '\n'.join(lines + fill.wrap(
            f'Each section of the params file takes a gear and the parameters of its node: see '
            f'{", ".join(n + " --help" for n in EXAMPLE_GEARS)}.'))
    lines += ['parameters (-p NAME:=VALUE; default in parentheses):']
    for pname, default, text in rows:
        lines += [f'  {pname} ({default})'] + indent.wrap(text)
    gear = EXAMPLE_GEARS.get(name, 'config/csd25.yaml')
    example = f'--ros-args --params-file {gear} -p {rows[0][0]}:={rows[0][1]}'
    lines += ['', 'gear file (required to run; not needed for --help):']
    lines += fill.wrap(
        'Every gear file key is a parameter of the node too: pass the gear file with '
        '--params-file and override a key or a parameter with -p NAME:=VALUE. '
        'config/csd25.yaml is the model gear, config/csd25_truth.yaml and '
        "config/csd25_truth_gms.yaml the simulated hardware; 'friction_joint identify' writes "
        'one from a recording. For example:')
    lines += ['', f'    {name} {example}',
              f'    python -m friction_joint.ros.nodes.{name} {example}', '']
    lines += fill.wrap('Remap the namespace with -r __ns:=/arm1; see docs/ros.md for the '
                       'topics and the loop modes, and the README ("Run the nodes '
                       'yourself") for the recipe, one terminal per node.')
    return '\n'.join(lines)


def exit_on_help(factory: Callable[[], Any], name: str,
                 args: Sequence[str] | None = None) -> None:
    """
    Print the usage of the node and exit 0 if the command line asks for help.

    ``factory`` is what the node's ``main()`` runs (the node class, or a
    composition); its module supplies the docstring and parameter tables.
    """
    if help_requested(args):
        try:
            print(node_usage(sys.modules[factory.__module__], name), flush=True)
        except BrokenPipeError:             # `joint_sim --help | head`: no traceback at exit
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        raise SystemExit(0)
