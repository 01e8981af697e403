# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Gear files and ROS 2 parameter files: the one reader of the command line and the nodes.

:func:`load_gear` reads a gear file for the command line.
:func:`read_ros_params_file` reads any ``--params-file`` of a node with the
same reader (:mod:`.strict_yaml`) and schema, and returns it normalized, so
that :func:`format_ros_params` can write a copy rcl parses exactly as the
command line read the original: every gear key checked and coerced by its
spec (integers in float keys and lists become floats), the other parameters
(a node's own, ``qos_overrides``, ...) passed through with numeric lists made
one type, nulls and empty sections dropped (rcl has no null), and strings
quoted.
"""
from __future__ import annotations

import json
import os
import re
import secrets
from typing import Any
import warnings

import yaml

from .params import expand_dotted, gear_from_dict, gear_from_flat, GearParams
from .schema import key_specs, required_keys, SCHEMA, Section
from .strict_yaml import parse_yaml_text, read_yaml_document, Yaml12Resolver
from ..exceptions import GearConfigError

__all__ = ['load_gear', 'parse_gear', 'format_gear', 'save_gear', 'read_ros_params_file',
           'format_ros_params']

_SPECS = key_specs()
_REQUIRED = required_keys()
_PLAIN_KEY = re.compile(r'[A-Za-z0-9_/][A-Za-z0-9_./*~-]*')


def load_gear(path: str | os.PathLike[str]) -> GearParams:
    """
    Load and validate a gear parameter file.

    Parameters
    ----------
    path : str or os.PathLike
        The gear parameter file.

    Returns
    -------
    GearParams

    Raises
    ------
    GearConfigError
        The file is missing, too large, not UTF-8 YAML (or has a duplicate
        key), not a ROS 2 parameter file, or invalid.

    """
    path = str(path)
    return _gear_from_document(read_yaml_document(path), path)


def parse_gear(text: str, where: str) -> GearParams:
    """
    Validate the text of a gear parameter file as :func:`load_gear` validates a file.

    Parameters
    ----------
    text : str
        The file's content (e.g. from :func:`format_gear`).
    where : str
        Its name in error messages.

    Returns
    -------
    GearParams

    Raises
    ------
    GearConfigError
        Anything :func:`load_gear` rejects.

    """
    return _gear_from_document(parse_yaml_text(text, where), where)


def _gear_from_document(doc: object, path: str) -> GearParams:
    if not isinstance(doc, dict) or '/**' not in doc:
        raise GearConfigError(f'{path}: not a gear parameter file: expected a top-level '
                              '"/**:" key with "ros__parameters:" below it')
    extra = sorted(set(doc) - {'/**'})
    if extra:
        raise GearConfigError(f'{path}: unexpected top-level key {extra[0]!r}; '
                              'put every parameter under "/**: ros__parameters:"')
    node = doc['/**']
    if not isinstance(node, dict) or set(node) != {'ros__parameters'} or not isinstance(
            node['ros__parameters'], dict):
        raise GearConfigError(f'{path}: "/**" must contain exactly one mapping "ros__parameters"')
    try:
        params = expand_dotted(node['ros__parameters'])
    except GearConfigError as exc:
        raise GearConfigError(f'{path}: {exc}') from None
    return gear_from_dict(params, source=path)


class _Dumper(yaml.SafeDumper):
    """SafeDumper that quotes a string YAML 1.1 or 1.2 would read as something else."""


for _first, _resolvers in Yaml12Resolver.yaml_implicit_resolvers.items():
    for _tag, _regexp in _resolvers:
        _Dumper.add_implicit_resolver(_tag, _regexp, [_first])


def format_gear(gear: GearParams, *, header: str | None = None) -> str:
    """
    Return the text of ``gear`` as a ROS 2 parameter file, ``header`` lines as comments.

    Parameters
    ----------
    gear : GearParams
        The gear.
    header : str, optional
        Lines written as ``#`` comments at the top.

    Returns
    -------
    str

    """
    text = yaml.dump(gear.to_dict(), Dumper=_Dumper, sort_keys=False, default_flow_style=None)
    if header:
        text = ''.join(f'# {line}\n' if line else '#\n' for line in header.splitlines()) + text
    return text


def save_gear(gear: GearParams, path: str | os.PathLike[str], *,
              header: str | None = None) -> None:
    """
    Write ``gear`` as a ROS 2 parameter file (atomically), with an optional comment header.

    Parameters
    ----------
    gear : GearParams
        The gear to write.
    path : str or os.PathLike
        The file; replaced only once the new content is complete.
    header : str, optional
        Lines written as ``#`` comments at the top.

    """
    text = format_gear(gear, header=header)
    path = str(path)
    d = os.path.dirname(os.path.abspath(path))
    tmp = os.path.join(d, f'.gear-{secrets.token_hex(6)}.yaml')
    # a new file of the normal mode (0666 less the umask), not mkstemp's 0600
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, 'w', encoding='utf-8') as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def read_ros_params_file(path: str | os.PathLike[str]) -> dict[str, Any]:
    """
    Read a ROS 2 parameter file (``--params-file``) with the gear reader; return it normalized.

    Parameters
    ----------
    path : str or os.PathLike
        The file: node names (``/**``, ``joint_sim``, namespaces) with
        ``ros__parameters:`` mappings below them.

    Returns
    -------
    dict
        The same tree, values normalized (see the module docstring).  A
        ``ros__parameters`` mapping that holds a whole gear (every required
        key) has been validated as :func:`load_gear` validates a gear file.

    Raises
    ------
    GearConfigError
        Anything :func:`load_gear` rejects in a gear key, a list of mixed
        types, or a file that is no ROS 2 parameter file; the message names
        the file.

    """
    path = str(path)
    doc = read_yaml_document(path)
    if not isinstance(doc, dict) or not doc:
        raise GearConfigError(f'{path}: not a ROS 2 parameter file: expected node names '
                              '(e.g. "/**:") with "ros__parameters:" below them')
    try:
        return _nodes(doc, '')
    except GearConfigError as exc:
        raise GearConfigError(f'{path}: {exc}') from None


def _nodes(doc: dict[Any, Any], trail: str) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, val in doc.items():
        if key == 'ros__parameters':
            if not isinstance(val, dict):
                raise GearConfigError(f'{trail}ros__parameters: expected a mapping of '
                                      'parameters')
            out[key] = _parameters(val, '')
            _check_whole_gear(out[key])
        elif isinstance(val, dict):
            sub = _nodes(val, f'{trail}{key}: ')
            if sub:
                out[key] = sub
        else:
            raise GearConfigError(f'{trail}{key}: not under "ros__parameters:" (a ROS 2 '
                                  'parameter file has node names, then "ros__parameters:", '
                                  'then the parameters)')
    return out


def _parameters(params: dict[str, Any], prefix: str) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, val in params.items():
        name = prefix + key
        spec = _SPECS.get(name)
        if val is None:
            continue
        if isinstance(spec, Section) and not isinstance(val, dict) and name in SCHEMA:
            out[key] = _other(val, name)        # e.g. the estimator's own ``friction``
        elif spec is not None and not isinstance(spec, Section):
            out[key] = spec.check(val, name)
        elif isinstance(val, dict):
            _unknown_gear_key(name, spec)
            sub = _parameters(val, name + '.')
            if sub:
                out[key] = sub
        elif spec is not None:
            spec.check(val, name)               # a gear section given a value: the error
        else:
            _unknown_gear_key(name, spec)
            out[key] = _other(val, name)
    return out


def _unknown_gear_key(name: str, spec: object) -> None:
    """Raise for a dotted name below a gear section that the schema does not know."""
    head = name.rpartition('.')[0]
    if spec is not None or not head or head.split('.')[0] not in SCHEMA:
        return
    parent = _SPECS.get(head)
    known = (f'; known keys here: {", ".join(sorted(parent.fields))}'
             if isinstance(parent, Section) else f' ({head} is not a section)')
    raise GearConfigError(f'unknown key {name}{known}')


def _other(value: object, name: str) -> object:
    """Return a parameter that is not a gear key as rcl takes it (lists of one type)."""
    if not isinstance(value, list):
        return value
    kinds = {bool if isinstance(v, bool) else float if isinstance(v, (int, float))
             else type(v) for v in value}
    if len(kinds) > 1 or kinds - {bool, float, str}:
        names = ', '.join(sorted(k.__name__ for k in kinds))
        raise GearConfigError(f'{name}: a list that mixes {names}; a ROS 2 parameter list '
                              'holds numbers, booleans or strings, one type')
    if kinds == {float} and any(isinstance(v, float) for v in value):
        return [float(v) for v in value]
    return list(value)


def _flatten(tree: dict[str, Any], prefix: str = '') -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, val in tree.items():
        if isinstance(val, dict):
            out.update(_flatten(val, f'{prefix}{key}.'))
        else:
            out[prefix + key] = val
    return out


def _check_whole_gear(params: dict[str, Any]) -> None:
    """Validate a ros__parameters mapping that holds a whole gear, as load_gear would."""
    flat = {k: v for k, v in _flatten(params).items() if k in _SPECS}
    if all(k in flat for k in _REQUIRED):
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')            # the node warns once, when it loads
            gear_from_flat(flat)


def _key(key: str) -> str:
    return key if _PLAIN_KEY.fullmatch(key) else _string(key)


def _string(text: str) -> str:
    return (json.dumps(text, ensure_ascii=False)
            .replace('\u2028', '\\L').replace('\u2029', '\\P').replace('\x85', '\\N'))


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)                 # 2.0, 1e-05, nan, inf: each a double for rcl
    if isinstance(value, str):
        return _string(value)
    return '[' + ', '.join(_value(v) for v in value) + ']'


def format_ros_params(tree: dict[str, Any]) -> str:
    """
    Return the text of a ROS 2 parameter file holding ``tree`` (from :func:`read_ros_params_file`).

    Floats are written so rcl reads doubles (``2.0``, ``1e-05``), strings
    double-quoted so rcl reads strings, lists in flow style.

    Parameters
    ----------
    tree : dict
        Node names -> ... -> ``ros__parameters`` -> parameters.

    Returns
    -------
    str

    """
    lines: list[str] = []

    def emit(d: dict[str, Any], indent: int) -> None:
        for key, val in d.items():
            if isinstance(val, dict):
                lines.append(f'{" " * indent}{_key(key)}:')
                emit(val, indent + 2)
            else:
                lines.append(f'{" " * indent}{_key(key)}: {_value(val)}')
    emit(tree, 0)
    return '\n'.join(lines) + '\n'
