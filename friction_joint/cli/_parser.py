# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The argument parser of every command: a usage error is one line, as every other error."""
import argparse
from typing import Any, NoReturn

__all__ = ['Parser']


def _ascii(kind):
    """Return ``kind`` (int or float) reading ASCII digits only, without ``_`` separators."""
    def parse(text: str) -> Any:
        if not text.isascii() or '_' in text:     # int('٢') is 2, float('1_0') is 10.0
            raise ValueError(text)
        return kind(text)
    parse.__name__ = kind.__name__               # argparse: "invalid int value: ..."
    return parse


_ASCII = {int: _ascii(int), float: _ascii(float)}


class Parser(argparse.ArgumentParser):
    """
    An :class:`argparse.ArgumentParser` whose errors are one line and exit status 2.

    argparse prints the whole usage before its error; here the error names the
    problem and points at ``--help``, as the commands' other errors do.  Help
    texts may contain ``%`` (argparse would read it as a format).
    """

    def error(self, message: str) -> NoReturn:
        """Print ``PROG: error: MESSAGE (see PROG --help)`` on stderr and exit with 2."""
        self.exit(2, f'{self.prog}: error: {message} (see {self.prog} --help)\n')

    def add_argument(self, *args: Any, **kwargs: Any) -> argparse.Action:
        """Add an argument; a ``%`` in its help is literal text; numbers in ASCII digits."""
        if kwargs.get('type') in _ASCII:
            kwargs['type'] = _ASCII[kwargs['type']]
        if isinstance(kwargs.get('help'), str) and '%' in kwargs['help'] \
                and '%(' not in kwargs['help']:
            kwargs['help'] = kwargs['help'].replace('%', '%%')
        return super().add_argument(*args, **kwargs)
