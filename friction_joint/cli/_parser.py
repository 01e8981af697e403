# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""The argument parser of every command: a usage error is one line, as every other error."""
import argparse

__all__ = ['Parser']


class Parser(argparse.ArgumentParser):
    """
    An :class:`argparse.ArgumentParser` whose errors are one line and exit status 2.

    argparse prints the whole usage before its error; here the error names the
    problem and points at ``--help``, as the commands' other errors do.  Help
    texts may contain ``%`` (argparse would read it as a format).
    """

    def error(self, message):
        """Print ``PROG: error: MESSAGE (see PROG --help)`` on stderr and exit with 2."""
        self.exit(2, f'{self.prog}: error: {message} (see {self.prog} --help)\n')

    def add_argument(self, *args, **kwargs):
        """Add an argument; a ``%`` in its help is literal text."""
        if isinstance(kwargs.get('help'), str) and '%' in kwargs['help'] \
                and '%(' not in kwargs['help']:
            kwargs['help'] = kwargs['help'].replace('%', '%%')
        return super().add_argument(*args, **kwargs)
