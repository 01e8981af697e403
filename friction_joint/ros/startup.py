# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
A node's start-up: its ROS arguments checked before rcl sees them, every failure one line.

rcl reads files named on the command line (``--params-file``,
``--log-config-file``) in ``rclpy.init``, before any code of the package runs:
a FIFO there blocks it forever, so :func:`check_ros_args` puts every such path
through the input gate (:mod:`friction_joint.inputs`) first, and refuses
``-p`` assignments rcl would misread or report on several lines (an empty
name, an empty list, which rcl drops without a word).  :func:`rcl_init` runs
``rclpy.init`` with rcl's own error lines held back, so a failure is the one
line :func:`one_line` makes of the exception.

The standard parameters rclpy declares itself are checked as the node's own
are: ``qos_overrides.<topic>.<publisher|subscription>.<policy>`` given for a
node must name a policy the node lets be overridden (:data:`QOS_POLICIES`)
with a valid value (:func:`check_qos_overrides`, before the publishers are
created) and an entity the node has (:func:`check_overrides_used`, after).
"""
from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
import math
import os
import re
from typing import Any, TYPE_CHECKING

from rclpy.exceptions import (InvalidParameterTypeException, InvalidParameterValueException,
                              ParameterException)
from rclpy.parameter import Parameter
from rclpy.utilities import remove_ros_args as _remove_ros_args

from ._rclpy import held_stderr, parameter_overrides, RCLError
from ..exceptions import FrictionJointError, GearConfigError, RecordingError
from ..gear.strict_yaml import parse_yaml_text
from ..inputs import check_input

if TYPE_CHECKING:
    from rclpy.context import Context
    from rclpy.node import Node

__all__ = ['ros_flags', 'check_ros_args', 'remove_ros_args',
           'check_domain_id', 'MAX_DOMAIN_ID', 'rcl_init', 'init_context',
           'one_line', 'check_qos_overrides',
           'check_overrides_used', 'QOS_POLICIES', 'MAX_QOS_DEPTH', 'QOS_PREFIX']

#: prefix of the standard QoS override parameters (rclpy QosOverridingOptions)
QOS_PREFIX = 'qos_overrides.'
#: the policies a node lets be overridden (rclpy's default policies) and their values
QOS_POLICIES = {'history': ('keep_last', 'keep_all', 'system_default'),
                'depth': None,
                'reliability': ('reliable', 'best_effort', 'system_default')}
#: the largest keep-last depth: 1000 s of a 1 kHz stream queued per entity (a replayed
#: recording answered in sync holds that many)
MAX_QOS_DEPTH = 1_000_000
_WHY_NOT = {'durability': 'the streams are volatile (transient_local would keep samples of a '
                          'keep-all topic for late joiners without bound)'}

#: the largest ROS_DOMAIN_ID: Fast DDS's ports (7400 + 250 id + offsets) stay below 65536
MAX_DOMAIN_ID = 232

#: ROS arguments followed by a value
_VALUE_FLAGS = ('-r', '--remap', '-e', '--enclave', '--log-level', '--log-file-name', '-p',
                '--param', '--params-file', '--log-config-file')
#: a parameter name as rcl accepts it: tokens of letters, digits and _ separated by dots
_NAME = re.compile(r'^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_/][A-Za-z0-9_/]*)*$')


def ros_flags(argv: Sequence[str]) -> Iterator[tuple[str, int]]:
    """Yield (flag, index of its value) of the flags with a value in ``--ros-args ... [--]``."""
    i, inside = 0, False
    while i < len(argv):
        arg = argv[i]
        if arg == '--ros-args':
            inside = True
        elif inside and arg == '--':
            inside = False
        elif inside and arg in _VALUE_FLAGS:
            yield arg, i + 1
            i += 1
        i += 1


def _flags(argv):
    """Yield (flag, value or None) for the flags inside ``--ros-args ... [--]``."""
    for flag, i in ros_flags(argv):
        yield flag, (argv[i] if i < len(argv) else None)


def _check_assignment(text):
    """Return why ``-p text`` is refused, or None."""
    name, sep, value = text.partition(':=')
    if not sep:
        return f'-p {text}: expected NAME:=VALUE'
    param = name.rpartition(':')[2]            # -p node:name:=value names one node
    if not param:
        return f'-p {text}: the parameter name is empty'
    if not _NAME.match(param) and not param.startswith(QOS_PREFIX):
        return f'-p {text}: {param!r} is not a parameter name'
    if value.strip().replace(' ', '') == '[]':
        return (f'-p {text}: an empty list cannot be given with -p (rcl ignores it and keeps '
                "the file's value)")
    return None


#: the ``-p`` assignments of the last :func:`check_ros_args`: (node or '', name, text)
_ASSIGNED: list[tuple[str, str, str]] = []


def check_ros_args(argv: Sequence[str]) -> None:
    """
    Check the ROS arguments of ``argv`` before ``rclpy.init`` reads them.

    Every ``--params-file`` must be a readable regular gear-sized file (a FIFO
    would block rcl forever), every ``--log-config-file`` a readable regular
    text file, and every ``-p`` a ``NAME:=VALUE`` with a name and not an
    empty list.

    Raises
    ------
    GearConfigError
        One line naming the argument or file and the problem.

    """
    _ASSIGNED.clear()
    for flag, value in _flags(list(argv)):
        if value is None:
            raise GearConfigError(f'{flag} needs a value after it')
        if flag == '--params-file':
            check_input(value, kind='gear', what='a ROS 2 parameter', error=GearConfigError)
        elif flag == '--log-config-file':
            check_input(value, kind='text', what='a log configuration', error=GearConfigError)
        elif flag in ('-p', '--param'):
            why = _check_assignment(value)
            if why:
                raise GearConfigError(why)
            name, _, text = value.partition(':=')
            node, _, name = name.rpartition(':')
            _ASSIGNED.append((node, name, text))


def remove_ros_args(args: Sequence[str]) -> list[str]:
    """
    Return ``args`` without the ROS arguments (rclpy's); malformed ones raise an error.

    rcl parses them to find their end (reading every ``--params-file``: a
    FIFO blocked it, so :func:`check_ros_args` checks them first) and raised
    ``RCLInvalidROSArgsError`` (after logging a line of its own) on, e.g., ``-p :=1``.

    Raises
    ------
    GearConfigError
        A file named by a ROS argument is no readable regular file.
    RecordingError
        rcl cannot parse the ROS arguments.

    """
    check_ros_args(args)                         # rcl reads --params-file here: no FIFO
    try:
        return held_stderr(lambda: _remove_ros_args(args))
    except RCLError as exc:
        text = ' '.join(str(exc).split()).split(', at /')[0]
        raise RecordingError(f'ROS arguments: {text}') from None


def check_domain_id(environ: Mapping[str, str] | None = None,
                    error: type[FrictionJointError] = GearConfigError) -> None:
    """
    Check ``ROS_DOMAIN_ID`` (unset or an integer 0-232); Fast DDS exits on a larger one.

    Raises
    ------
    error
        One line naming the variable and its value.

    """
    text = (os.environ if environ is None else environ).get('ROS_DOMAIN_ID', '').strip()
    if text and not (text.isdigit() and int(text) <= MAX_DOMAIN_ID):
        raise error(f'ROS_DOMAIN_ID={text!r}: must be an integer from 0 to {MAX_DOMAIN_ID} '
                    '(the DDS ports of larger ids do not exist)')


def rcl_init(init: Callable[[], Any]) -> Any:
    """
    Call ``init()`` (``rclpy.init``) with what rcl writes to stderr held back.

    On success the held-back output is written to stderr; on failure it is
    dropped (the caller reports the exception in one line).
    """
    return held_stderr(init)


def init_context(args: list[str] | None, context: Context,
                 error: type[FrictionJointError]) -> None:
    """
    ``rclpy.init`` of ``context`` with ``args`` (checked first); a failure raises ``error``.

    For the commands that run a node of their own (record, replay): a bad ROS
    argument is one line naming it, rcl's own lines are dropped.
    """
    import rclpy
    from rclpy.signals import SignalHandlerOptions
    try:
        check_ros_args(args or [])
        rcl_init(lambda: rclpy.init(args=args, context=context,
                                    signal_handler_options=SignalHandlerOptions.NO))
    except Exception as exc:                     # noqa: BLE001 - one line, never a traceback
        raise error(one_line(exc)) from None


_TYPE_ERROR = re.compile(r"parameter '([^']*)' to '(.*)' of type '(\w+)', expecting type '(\w+)'",
                         re.S)


def one_line(exc: BaseException) -> str:
    """Return the one-line message of an exception ending a node's start-up."""
    text = ' '.join(str(exc).split()) or type(exc).__name__
    if isinstance(exc, FrictionJointError):
        return text
    if isinstance(exc, InvalidParameterTypeException):
        m = _TYPE_ERROR.search(str(exc))
        if m:
            value = m.group(2) if len(m.group(2)) <= 60 else m.group(2)[:57] + '...'
            return (f'parameter {m.group(1)}: expected a {m.group(4).lower()}, got '
                    f'{value!r} ({m.group(3).lower()})')
    if isinstance(exc, (InvalidParameterValueException, ParameterException)):
        return f'parameter: {text}'
    if isinstance(exc, RCLError):
        return f'ROS: {text.split(", at /")[0]}'
    return f'cannot start: {type(exc).__name__}: {text}'


def _qos_problem(name, value):
    rest = name[len(QOS_PREFIX):]
    parts = rest.rsplit('.', 2)
    if len(parts) != 3 or not parts[0] or not re.match(r'^(publisher|subscription)(_\w+)?$',
                                                       parts[1]):
        return ('expected qos_overrides.<topic>.<publisher|subscription>.<policy>, e.g. '
                'qos_overrides./joint_states.publisher.depth')
    policy = parts[2]
    if policy not in QOS_POLICIES:
        why = _WHY_NOT.get(policy, 'not a policy this node lets be overridden')
        return (f'{policy} cannot be overridden: {why} (overridable: '
                f'{", ".join(QOS_POLICIES)})')
    allowed = QOS_POLICIES[policy]
    if allowed is None:
        if isinstance(value, bool) or not isinstance(value, int):
            return f'expected an integer, got {value!r}'
        if not 1 <= value <= MAX_QOS_DEPTH:
            return f'must be in [1, {MAX_QOS_DEPTH}], got {value}'
        return None
    if not isinstance(value, str) or value.lower() not in allowed:
        return f'must be one of {", ".join(allowed)}, got {value!r}'
    return None


def check_qos_overrides(node: Node) -> None:
    """
    Check the ``qos_overrides.*`` parameters given for ``node`` (before its entities exist).

    Raises
    ------
    GearConfigError
        ``parameter NAME: problem`` for the first bad one (name form, policy, value).

    """
    for name, param in sorted(parameter_overrides(node).items()):
        if not name.startswith(QOS_PREFIX):
            continue
        value = None if param.type_ == Parameter.Type.NOT_SET else param.value
        why = _qos_problem(name, value)
        if why:
            raise GearConfigError(f'parameter {name}: {why}')


def _given(text):
    """Return the value of ``-p name:=text`` as rcl reads it (YAML; ``nan``, ``1e5`` numbers)."""
    try:
        value = parse_yaml_text(text, '-p')
    except GearConfigError:
        return text
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            return value
    if isinstance(value, list):
        return [_given(v) if isinstance(v, str) else v for v in value]
    return value


def _same(given, held):
    if isinstance(held, (list, tuple)) or type(held).__name__ == 'array':
        return (isinstance(given, list) and len(given) == len(held)
                and all(_same(a, b) for a, b in zip(given, held, strict=True)))
    numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (given, held))
    if numbers:
        return (given != given and held != held) or math.isclose(given, held, rel_tol=1e-12)
    return type(given) is type(held) and given == held


def _check_applied(node):
    """Check that every ``-p`` given to ``node`` holds the value given (rcl may drop one)."""
    for target, name, text in _ASSIGNED:
        if target not in ('', node.get_name()) or not node.has_parameter(name):
            continue
        held = node.get_parameter(name).value
        if not _same(_given(text), held):
            raise GearConfigError(
                f'parameter {name}: -p {name}:={text} was not applied ({node.get_name()} holds '
                f'{held!r}): its type differs from the value in the params file, which rcl '
                f'keeps; give a value of type {type(held).__name__}')


def check_overrides_used(node: Node) -> None:
    """
    Check that every ``qos_overrides.*`` given for ``node`` names an entity it has.

    Also that every ``-p name:=value`` of the command line (:func:`check_ros_args`)
    is what the node holds: rcl keeps a params file's value over a ``-p`` of
    another type without a word.

    rclpy declares the QoS parameters as the publishers and subscriptions are
    created and ignores the others: a mistyped topic would be dropped silently.

    Raises
    ------
    GearConfigError

    """
    _check_applied(node)
    unused = sorted(n for n in parameter_overrides(node)
                    if n.startswith(QOS_PREFIX) and not node.has_parameter(n))
    if unused:
        declared = node.list_parameters([QOS_PREFIX.rstrip('.')], 0).names
        entities = sorted({n[len(QOS_PREFIX):].rsplit('.', 1)[0] for n in declared})
        raise GearConfigError(f'parameter {unused[0]}: {node.get_name()} has no such publisher '
                              f'or subscription (overridable: {", ".join(entities) or "none"})')
