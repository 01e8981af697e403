# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
ROS parameters of the nodes: the gear file through the package's schema, the nodes' own.

Every gear key (``friction.fc``, ``lever.mass``, ...) is declared read-only
with a description, so ``ros2 param describe`` documents it and the values
go through the same schema as the command line's (:mod:`friction_joint.gear`).
A node's own parameters are declared with a description, their range where
one applies, and read-only unless the node accepts them at run time
(:func:`parameter_guard`).  ``use_sim_time`` and the standard
``qos_overrides.*`` parameters are accepted besides.

rcl parses ``--params-file`` itself, with other rules than the command line's
reader (``2e4`` a number, ``[2, 0.01]`` an error at ``rclpy.init``, a
duplicate key the last value).  :func:`prepare_ros_args` therefore reads every
params file with the package's reader before ``rclpy.init`` and hands rcl a
normalized copy, so a node and the command line read a gear file alike and a
bad file is a :class:`~friction_joint.exceptions.GearConfigError` naming it.
"""
from __future__ import annotations

import array
from collections.abc import Callable, Mapping, Sequence
import math
import os
import shutil
import sys
import tempfile
import time
from typing import Any, TYPE_CHECKING

from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
from rclpy.exceptions import InvalidParameterValueException
from rclpy.parameter import Parameter

from ._rclpy import parameter_override_names, parameter_overrides
from .startup import check_qos_overrides, check_ros_args, ros_flags
from ..exceptions import GearConfigError
from ..gear import gear_from_flat, SCHEMA, Section
from ..gear.files import format_ros_params, read_ros_params_file
from ..gear.strict_yaml import parse_yaml_text

if TYPE_CHECKING:
    from rclpy.node import Node

    from ..gear import GearParams

__all__ = ['gear_keys', 'declare_gear', 'declare_node_params', 'parameter_guard', 'describe',
           'prepare_ros_args', 'REJECT_LOG_PERIOD', 'MODES', 'declare_follower_params']

#: seconds between two log lines about refused input or parameter changes (per node)
REJECT_LOG_PERIOD = 2.0

#: parameter names accepted besides the gear keys and a node's own
STANDARD = ('use_sim_time',)
#: prefix of the standard QoS override parameters (rclpy QosOverridingOptions)
QOS_OVERRIDES = 'qos_overrides.'


def gear_keys(schema: Mapping[str, Any] = SCHEMA, prefix: str = '') -> list[str]:
    """Dotted names of every leaf key of the gear schema."""
    out = []
    for key, spec in schema.items():
        if isinstance(spec, Section):
            out += gear_keys(spec.fields, prefix + key + '.')
        else:
            out.append(prefix + key)
    return out


def _plain(value):
    if isinstance(value, (array.array, tuple)):
        return list(value)
    return value


def declare_gear(node: Node, own: Sequence[str] = ()) -> GearParams:
    """
    Declare every gear key (dynamically typed) and build the GearParams.

    Parameters come from ``--params-file`` (the gear file) and ``-p``
    overrides.  Empty lists in a file arrive unset and count as absent (the
    same meaning).  Any override that is neither a gear key nor one of the
    node's own parameters ``own`` is an error, as unknown keys are in a gear
    file.

    Raises
    ------
    GearConfigError

    """
    check_qos_overrides(node)                # before any publisher or subscription exists
    keys = gear_keys()
    flat = {}
    for name in keys:
        desc = ParameterDescriptor(description=f'gear file key {name} (docs/interfaces.md)',
                                   dynamic_typing=True, read_only=True)
        p = node.declare_parameter(name, None, desc)
        if p.type_ != Parameter.Type.NOT_SET:
            flat[name] = _plain(p.value)
    overrides = parameter_override_names(node)
    unknown = sorted(n for n in overrides - set(keys) - set(own) - set(STANDARD)
                     if not n.startswith(QOS_OVERRIDES))
    if unknown:
        raise GearConfigError(f'unknown parameter {unknown[0]}' +
                              (f' (and {len(unknown) - 1} more)' if len(unknown) > 1 else '') +
                              ' for this node; gear keys and the node parameters '
                              f'{", ".join(sorted(own))} are accepted')
    return gear_from_flat(flat, source=f'parameters of {node.get_name()}')


def describe(description: str, *, read_only: bool = True, low: float | None = None,
             high: float | None = None, integer: bool = False) -> ParameterDescriptor:
    """
    Return a ParameterDescriptor with a description and, given ``low``/``high``, a range.

    The range is documentation for ``ros2 param describe`` and is enforced by
    rclpy on later changes; values are validated by the node's validators too.
    """
    desc = ParameterDescriptor(description=description, read_only=read_only,
                               dynamic_typing=True)
    if low is not None and high is not None:
        if integer:
            desc.integer_range = [IntegerRange(from_value=int(low), to_value=int(high), step=0)]
        else:
            desc.floating_point_range = [FloatingPointRange(from_value=float(low),
                                                            to_value=float(high), step=0.0)]
    return desc


def declare_node_params(node: Node, defaults: Mapping[str, Any],
                        validators: Mapping[str, Callable[[Any], str | None]] | None = None,
                        descriptors: Mapping[str, ParameterDescriptor] | None = None,
                        ) -> dict[str, Any]:
    """
    Declare the node's own parameters; return {name: value}.

    ``defaults`` maps names to default values (their type is the parameter's
    type; ints are accepted where a float is expected, a float where an int
    is expected is an error, and a NaN default accepts NaN as "unset").  A
    value of the wrong type is a :class:`GearConfigError` naming the
    parameter (one line, exit 2 from the node).  ``validators`` maps
    names to ``f(value) -> error message or None``; ``descriptors`` names to
    :class:`ParameterDescriptor` (:func:`describe`).
    """
    validators = validators or {}
    descriptors = descriptors or {}
    values = {}
    for name, default in defaults.items():
        desc = descriptors.get(name) or describe(f"{name} (see the node's docstring)")
        try:
            value = _plain(node.declare_parameter(name, default, desc).value)
        except InvalidParameterValueException as exc:       # out of the descriptor's range
            given = parameter_overrides(node).get(name)
            err = given is not None and _check(name, _plain(given.value), default, validators)
            raise GearConfigError(f'parameter {name}: {err or " ".join(str(exc).split())}') \
                from None
        if isinstance(default, float) and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        err = _check(name, value, default, validators)
        if err:
            raise GearConfigError(f'parameter {name}: {err}')
        values[name] = value
    return values


#: the loop modes of the simulator; controller and estimator take the same parameter
MODES = ('realtime', 'lockstep')
_MODE_DESCRIPTOR = ('loop mode of the simulator this node runs with: realtime (answer the '
                    'newest state, sync off) or lockstep (answer every state, sync on); '
                    'decides sync unless sync is set')


def declare_follower_params(node: Node, defaults: Mapping[str, Any],
                            validators: Mapping[str, Callable[[Any], str | None]],
                            descriptors: Mapping[str, ParameterDescriptor]) -> dict[str, Any]:
    """
    Declare ``mode`` and then a controller's or estimator's own parameters.

    ``sync`` defaults to ``mode == 'lockstep'``: a node started by hand with
    its defaults next to a realtime simulator answers the newest state (a
    synchronised node would hold every state until the temperature of its
    stamp arrives, which a realtime simulator sends at the sensor's rate: a
    delay that destabilises the loop).  A ``sync`` the user sets wins.
    Returns ``{name: value}`` including ``mode``.
    """
    mode = declare_node_params(
        node, {'mode': 'realtime'},
        {'mode': lambda v: None if v in MODES else f'must be {" or ".join(MODES)}'},
        {'mode': describe(_MODE_DESCRIPTOR)})['mode']
    values = declare_node_params(node, dict(defaults, sync=mode == 'lockstep'), validators,
                                 descriptors)
    values['mode'] = mode
    return values


def _short(value):
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + '...'


def _check(name, value, default, validators):
    if isinstance(default, bool) != isinstance(value, bool):
        return f'expected {type(default).__name__}, got {_short(value)}'
    if isinstance(default, float):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return f'expected a number, got {_short(value)}'
        if not math.isfinite(value) and not (math.isnan(default) and math.isnan(value)):
            return f'must be finite, got {value}'          # a NaN default: NaN means unset
    elif isinstance(default, int) and not isinstance(default, bool):
        if isinstance(value, bool) or not isinstance(value, int):
            return f'expected an integer, got {_short(value)}'
    elif isinstance(default, str) and not isinstance(value, str):
        return f'expected a string, got {_short(value)}'
    v = validators.get(name)
    return v(value) if v else None


def parameter_guard(node: Node, defaults: Mapping[str, Any],
                    validators: Mapping[str, Callable[[Any], str | None]],
                    apply: Callable[[str, Any], None] | None) -> None:
    """
    Install a set-parameters callback validating the node's own parameters.

    A bad value is rejected with a reason and the node keeps running; good
    values are handed to ``apply(name, value)`` after acceptance.  Every
    parameter not in ``defaults`` (``use_sim_time`` too) is read-only.  Rejections
    are counted and logged at most once per ``REJECT_LOG_PERIOD`` s, so a flood of
    requests cannot keep the node busy logging.
    """
    rejected = [0, -math.inf]                    # count, monotonic time of the last log line

    def refuse(reason):
        rejected[0] += 1
        now = time.monotonic()
        if now - rejected[1] >= REJECT_LOG_PERIOD:   # a flood of requests logs once a period
            rejected[1] = now
            node.get_logger().warning(f'rejected a parameter change: {reason} '
                                      f'({rejected[0]} rejected so far)')
        return SetParametersResult(successful=False, reason=reason)

    def callback(params):
        for p in params:
            if p.name not in defaults:
                return refuse(f'{p.name} cannot be changed at run time')
            value = _plain(p.value)
            if isinstance(defaults[p.name], float) and isinstance(value, int) and \
                    not isinstance(value, bool):
                value = float(value)
            err = _check(p.name, value, defaults[p.name], validators)
            if err:
                return refuse(f'{p.name}={_short(value)}: {err}')
        for p in params:
            value = _plain(p.value)
            if isinstance(defaults[p.name], float) and isinstance(value, int):
                value = float(value)
            apply(p.name, value)
        return SetParametersResult(successful=True)
    node.add_on_set_parameters_callback(callback)


_PARAM_FLAGS = ('-p', '--param')


def _one_type_list(assignment):
    """``-p name:=[2, 0.01]`` -> ``name:=[2.0, 0.01]`` (rcl refuses a list of int and float)."""
    name, sep, text = assignment.partition(':=')
    if not sep or not text.lstrip().startswith('['):
        return assignment
    try:
        value = parse_yaml_text(text, f'-p {name}')
    except GearConfigError:
        return assignment                               # rcl reports its own syntax errors
    numbers = isinstance(value, list) and value and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
    if not numbers or not any(isinstance(v, float) for v in value) or all(
            isinstance(v, float) for v in value):
        return assignment
    return f'{name}:=[{", ".join(repr(float(v)) for v in value)}]'


def prepare_ros_args(args: list[str] | None = None) -> tuple[list[str] | None, Callable[[], None]]:
    """
    Read every ``--params-file`` with the package's reader; return rcl-ready args and a cleanup.

    Each ``--params-file PATH`` inside ``--ros-args`` is read with
    :func:`~friction_joint.gear.files.read_ros_params_file` (the command
    line's YAML reader and gear schema) and replaced by a normalized copy in
    a temporary directory, written so that rcl parses exactly what the reader
    read (floats as floats, strings quoted).  ``-p name:=[...]`` lists of
    integers and floats become float lists.  Call before ``rclpy.init``; call
    ``cleanup()`` once ``rclpy.init`` has parsed the files (it removes the
    copies).

    Parameters
    ----------
    args : list of str, optional
        The command line (default ``sys.argv``), as ``rclpy.init`` takes it.

    Returns
    -------
    (list of str, callable)
        The arguments to give ``rclpy.init`` (``args`` itself when there is
        nothing to change) and the cleanup function.

    Raises
    ------
    GearConfigError
        A params file is missing, unreadable, a FIFO or a device, not UTF-8 YAML, too large, has
        a duplicate key, or a gear key it gives is invalid; the message names
        the file.  Nothing is left behind.

    """
    argv = list(sys.argv if args is None else args)
    check_ros_args(argv)                     # the files rcl opens, -p syntax; before rcl
    found = list(ros_flags(argv))
    files = [i for flag, i in found if flag == '--params-file']
    params = [i for flag, i in found if flag in _PARAM_FLAGS and i < len(argv)]
    if any(i >= len(argv) for i in files):
        raise GearConfigError('--params-file needs a file path after it')
    out = list(argv)
    for i in params:
        out[i] = _one_type_list(argv[i])
    if not files:
        return (args if out == argv else out), (lambda: None)
    tmpdir = None

    def cleanup():
        if tmpdir is not None:
            shutil.rmtree(tmpdir, ignore_errors=True)

    try:
        texts = [format_ros_params(read_ros_params_file(argv[i])) for i in files]
        tmpdir = tempfile.mkdtemp(prefix='friction_joint-params-')
        for n, (i, text) in enumerate(zip(files, texts, strict=True)):
            path = os.path.join(tmpdir, f'{n}-{os.path.basename(argv[i]) or "params"}')
            with open(path, 'w', encoding='utf-8') as fh:
                fh.write(text)
            out[i] = path
    except BaseException:
        cleanup()
        raise
    return out, cleanup
