# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The YAML reader of gear and ROS 2 parameter files: strict, bounded, one-line errors.

What it reads differently from ``yaml.safe_load`` (PyYAML implements YAML 1.1):

* plain scalars are resolved by the YAML 1.2 core schema: ``2e4``, ``1e-3``,
  ``.5`` and ``5.`` are floats (YAML 1.1 reads ``2e4`` as a string, while
  rcl reads it as a number), ``0x1F`` and ``0o17`` are integers, only
  ``true``/``false`` (any case as written by the spec) are booleans, ``~``,
  ``null`` and an empty value are null; everything else is a string
  (``yes``, ``1_000``, ``1:30``);
* a key given twice in one mapping is an error naming it and both lines (YAML
  readers keep the last value silently);
* aliases (``*name``) are an error, as rcl refuses them;
* integers must fit in 64 bits (ROS 2 parameter integers); a nonzero float
  whose magnitude is below the smallest normal double is an error (rcl reads
  such a literal as a string);
* a file larger than :data:`MAX_FILE_BYTES` is rejected before it is parsed,
  as are bytes that are not UTF-8 text and NUL bytes; a sequence longer than
  :data:`MAX_SEQUENCE` items or nesting deeper than :data:`MAX_DEPTH` is
  rejected by a first pass over the parser's events, before a tree is built
  (libyaml's composer recurses: 100 000 nested ``[`` crashed the interpreter;
  a 1 MB list of 490 000 zeros took 3.4 s and 240 MB to build).

Errors are :class:`~friction_joint.exceptions.GearConfigError` with a
one-line message naming the file and, where known, the line.
"""
import os
import re
import sys
from typing import Any

import yaml
from yaml.constructor import SafeConstructor
from yaml.events import Event
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode
from yaml.resolver import BaseResolver

from .schema import INT64_RANGE
from ..exceptions import GearConfigError
from ..inputs import LIMITS, read_input

__all__ = ['MAX_FILE_BYTES', 'MAX_SEQUENCE', 'MAX_DEPTH', 'read_yaml_document', 'parse_yaml_text',
           'Yaml12Resolver']

#: largest gear / parameter file read (bytes, 1 MiB); the shipped gear files are about 2 kB
MAX_FILE_BYTES = LIMITS['gear']
#: longest sequence built (the schema's list limits are far lower)
MAX_SEQUENCE = 10_000
#: deepest nesting of mappings and lists (a gear file needs 5, node sections add a few)
MAX_DEPTH = 32


class Yaml12Resolver(BaseResolver):
    """Implicit tags of plain scalars by the YAML 1.2 core schema (also used for writing)."""


for _tag, _pattern, _first in (
        ('bool', r'true|True|TRUE|false|False|FALSE', 'tTfF'),
        ('int', r'[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+', '-+0123456789'),
        ('float', r'[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?'
                  r'|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN)', '-+.0123456789'),
        ('null', r'~|null|Null|NULL|', ['~', 'n', 'N', ''])):
    Yaml12Resolver.add_implicit_resolver(f'tag:yaml.org,2002:{_tag}',
                                         re.compile(f'^(?:{_pattern})$'), list(_first))


_CORE_TAGS = frozenset(f'tag:yaml.org,2002:{t}'
                       for t in ('str', 'int', 'float', 'bool', 'null', 'seq', 'map'))
_INT = re.compile(r'([-+]?)(0x[0-9a-fA-F]+|0o[0-7]+|[0-9]+)')


_NODE_EVENTS = (yaml.ScalarEvent, yaml.SequenceStartEvent, yaml.MappingStartEvent)
_ALIASES = 'YAML aliases (*name) are not supported in ROS 2 parameter files; write the value out'


class _Refused(Exception):
    """Content the reader refuses; carries the YAML node (or event) for its line."""

    def __init__(self, message: str, node: Node | Event) -> None:
        super().__init__(message)
        self.node = node


def _head(text: str, n: int = 24) -> str:
    return text if len(text) <= n else text[:n] + f'... ({len(text)} characters)'


class _StrictConstructor(SafeConstructor):
    """SafeConstructor with YAML 1.2 numbers, duplicate/alias checks and bounds."""

    def __init__(self) -> None:
        super().__init__()
        self._visited: set[int] = set()

    def construct_object(self, node: Node, deep: bool = False) -> Any:
        if id(node) in self._visited:
            raise _Refused(_ALIASES, node)
        self._visited.add(id(node))
        if node.tag not in _CORE_TAGS:
            raise _Refused(f'the tag {_head(node.tag, 60)} is not supported; write a plain value',
                           node)
        return super().construct_object(node, deep)

    def construct_yaml_int(self, node: Node) -> int:
        match = _INT.fullmatch(node.value) if isinstance(node, ScalarNode) else None
        if match is None:
            raise _Refused(f'{_head(str(node.value))} is not an integer', node)
        sign, digits = match.groups()
        base = {'0x': 16, '0o': 8}.get(digits[:2], 10)
        digits = digits[2:] if base != 10 else digits
        value = None                                 # more than 64 bits in any base here:
        if len(digits.lstrip('0')) <= 22:            # not converted at all
            value = (-1 if sign == '-' else 1) * int(digits, base)
        if value is None or not INT64_RANGE[0] <= value <= INT64_RANGE[1]:
            raise _Refused(f'integer {_head(node.value)} is outside the 64-bit range of ROS 2 '
                           'parameters', node)
        return value

    def construct_yaml_float(self, node: Node) -> float:
        text = node.value.lower() if isinstance(node, ScalarNode) else ''
        try:
            value = float(text.replace('.inf', 'inf').replace('.nan', 'nan'))
        except ValueError:
            raise _Refused(f'{_head(str(node.value))} is not a number', node) from None
        if value != 0.0 and abs(value) < sys.float_info.min:
            raise _Refused(f'{_head(node.value)} is below the smallest normal double '
                           f'({sys.float_info.min:.4g}), which ROS 2 reads as a string; '
                           'write 0.0', node)
        return value

    def construct_sequence(self, node: SequenceNode, deep: bool = False) -> list[Any]:
        if isinstance(node, SequenceNode) and len(node.value) > MAX_SEQUENCE:
            raise _Refused(f'a list of {len(node.value)} items (at most {MAX_SEQUENCE})', node)
        return super().construct_sequence(node, deep=deep)

    def construct_mapping(self, node: MappingNode,
                          deep: bool = False) -> dict[Any, Any]:
        if not isinstance(node, MappingNode):
            raise _Refused('expected a mapping', node)
        out: dict[Any, Any] = {}
        lines: dict[str, int] = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, ScalarNode):
                raise _Refused('a key must be a name, not a list or mapping', key_node)
            self._visited.add(id(key_node))
            key = key_node.value                      # the text, as rcl takes it
            line = key_node.start_mark.line + 1
            if key in lines:
                raise _Refused(f'duplicate key {key!r} at line {line} (first given at line '
                               f'{lines[key]}); a key may appear once per mapping', key_node)
            lines[key] = line
            out[key] = self.construct_object(value_node, deep=deep)
        return out


for _tag, _method in (('int', 'construct_yaml_int'), ('float', 'construct_yaml_float')):
    _StrictConstructor.add_constructor(f'tag:yaml.org,2002:{_tag}',
                                       getattr(_StrictConstructor, _method))


if getattr(yaml, '__with_libyaml__', False):
    from yaml._yaml import CParser

    class _Loader(CParser, _StrictConstructor, Yaml12Resolver):
        def __init__(self, stream: str) -> None:
            CParser.__init__(self, stream)
            _StrictConstructor.__init__(self)
            Yaml12Resolver.__init__(self)
else:                                                   # pragma: no cover - without libyaml
    from yaml.composer import Composer
    from yaml.parser import Parser
    from yaml.reader import Reader
    from yaml.scanner import Scanner

    # one of the two definitions, by whether PyYAML was built with libyaml
    class _Loader(Reader, Scanner, Parser, Composer,  # type: ignore[no-redef]
                  _StrictConstructor, Yaml12Resolver):
        def __init__(self, stream: str) -> None:
            Reader.__init__(self, stream)
            Scanner.__init__(self)
            Parser.__init__(self)
            Composer.__init__(self)
            _StrictConstructor.__init__(self)
            Yaml12Resolver.__init__(self)


def _one_line(exc: yaml.YAMLError, text: str) -> str:
    """Return a YAML error as 'line N, column M: problem' on one line."""
    mark = getattr(exc, 'problem_mark', None)
    problem = getattr(exc, 'problem', None)
    position = getattr(exc, 'position', None)
    character = getattr(exc, 'character', None)
    if mark is None and position is not None:                          # ReaderError
        line = text.count('\n', 0, position) + 1
        return f'line {line}: unacceptable character #x{int(character):04x}' \
            if isinstance(character, int) else f'line {line}: ' + ' '.join(str(exc).split())
    where = f'line {mark.line + 1}, column {mark.column + 1}: ' if mark is not None else ''
    what = ' '.join(str(problem if problem else exc).split())
    context = getattr(exc, 'context', None)
    return where + what + (f' ({" ".join(str(context).split())})' if context else '')


def _check_shape(events: _Loader) -> None:
    """Walk the parser's events (no tree, no recursion): refuse deep nesting and long lists."""
    open_seqs: list[int | None] = []            # item counts of the open lists, or None
    try:
        while events.check_event():
            event = events.get_event()
            if isinstance(event, yaml.AliasEvent):
                raise _Refused(_ALIASES, event)
            if isinstance(event, _NODE_EVENTS) and open_seqs and open_seqs[-1] is not None:
                open_seqs[-1] += 1
                if open_seqs[-1] > MAX_SEQUENCE:
                    raise _Refused(f'a list of more than {MAX_SEQUENCE} items', event)
            if isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
                open_seqs.append(0 if isinstance(event, yaml.SequenceStartEvent) else None)
                if len(open_seqs) > MAX_DEPTH:
                    raise _Refused(f'nested deeper than {MAX_DEPTH} levels', event)
            elif isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
                open_seqs.pop()
    finally:
        events.dispose()


def parse_yaml_text(text: str, where: str) -> Any:
    """
    Parse one YAML document with the strict reader; errors name ``where``.

    Parameters
    ----------
    text : str
        The document.
    where : str
        The file (or argument) it came from, the start of every error message.

    Returns
    -------
    object
        The document: dicts, lists, str, int, float, bool, None.

    Raises
    ------
    GearConfigError
        Not valid YAML, a duplicate key, an alias, a number out of range.

    """
    loader = _Loader(text)
    try:
        _check_shape(_Loader(text))
        return loader.get_single_data()
    except _Refused as exc:
        mark = exc.node.start_mark
        assert mark is not None                 # the parser marks every node and event
        line = mark.line + 1
        msg = str(exc) if str(exc).startswith('duplicate key') else f'line {line}: {exc}'
        raise GearConfigError(f'{where}: {msg}') from None
    except yaml.YAMLError as exc:
        raise GearConfigError(f'{where}: not valid YAML at {_one_line(exc, text)}') from None
    except RecursionError:
        raise GearConfigError(f'{where}: nested too deeply') from None
    finally:
        loader.dispose()


def read_yaml_document(path: str | os.PathLike[str]) -> Any:
    """
    Read a YAML file with the strict reader, after checking its size and encoding.

    Parameters
    ----------
    path : str or os.PathLike
        The file.

    Returns
    -------
    object
        The document (None for an empty file).

    Raises
    ------
    GearConfigError
        Unreadable, larger than :data:`MAX_FILE_BYTES`, not UTF-8 text, binary,
        or refused by :func:`parse_yaml_text`.

    """
    path = str(path)
    # the input gate: a FIFO, a device or a directory is refused before any read (a FIFO
    # blocked open() forever), and never more than the limit is read
    data = read_input(path, kind='gear', what='a gear or ROS 2 parameter',
                      limit=MAX_FILE_BYTES, error=GearConfigError)
    try:
        text = data.decode('utf-8')
    except UnicodeDecodeError as exc:
        line = data.count(b'\n', 0, exc.start) + 1
        raise GearConfigError(f'{path}: not UTF-8 text (byte 0x{data[exc.start]:02x} at line '
                              f'{line}); a gear file is a YAML text file') from None
    if '\x00' in text:
        raise GearConfigError(f'{path}: a binary file (NUL bytes), not a YAML gear file')
    return parse_yaml_text(text[1:] if text.startswith('\ufeff') else text, path)
