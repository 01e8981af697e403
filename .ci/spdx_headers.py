#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Replace the 13-line Apache-2.0 comment atop Python files by the two-line SPDX header.

    python .ci/spdx_headers.py [PATH ...]    (default: the git-tracked *.py files)

The header becomes ``# SPDX-License-Identifier: Apache-2.0`` and the file's own
``# Copyright <year> <holder>`` line (after a shebang line, if any); nothing else
in the file changes, so the module docstring follows right after.  Files that
already have the short header are left alone (a second run changes nothing);
test/test_copyright.py checks the result.
"""
import pathlib
import re
import subprocess
import sys

SPDX = '# SPDX-License-Identifier: Apache-2.0\n'
COPYRIGHT = re.compile(r'# Copyright \d{4}(-\d{4})? \S.*\n\Z')
#: the 12 lines that follow the copyright line in the long header
APACHE_BODY = [
    '#\n',
    '# Licensed under the Apache License, Version 2.0 (the "License");\n',
    '# you may not use this file except in compliance with the License.\n',
    '# You may obtain a copy of the License at\n',
    '#\n',
    '#     http://www.apache.org/licenses/LICENSE-2.0\n',
    '#\n',
    '# Unless required by applicable law or agreed to in writing, software\n',
    '# distributed under the License is distributed on an "AS IS" BASIS,\n',
    '# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.\n',
    '# See the License for the specific language governing permissions and\n',
    '# limitations under the License.\n',
]


def shorten(text):
    """Return text with its long header replaced, or None if it has none."""
    lines = text.splitlines(keepends=True)
    start = 1 if lines and lines[0].startswith('#!') else 0
    head = lines[start:start + 1 + len(APACHE_BODY)]
    if len(head) < 1 + len(APACHE_BODY) or not COPYRIGHT.match(head[0]):
        return None
    if head[1:] != APACHE_BODY:
        return None
    rest = lines[start + len(head):]
    return ''.join(lines[:start] + [SPDX, head[0]] + rest)


def main(argv):
    """Shorten the headers of the files named in argv (default: every tracked .py file)."""
    root = pathlib.Path(__file__).resolve().parent.parent
    if argv:
        paths = [pathlib.Path(p) for p in argv]
    else:
        out = subprocess.run(['git', 'ls-files', '*.py'], cwd=root, check=True,
                             capture_output=True, text=True).stdout
        paths = [root / p for p in out.split()]
    changed = 0
    for path in paths:
        with open(path, encoding='utf-8', newline='') as fh:
            new = shorten(fh.read())
        if new is not None:
            with open(path, 'w', encoding='utf-8', newline='') as fh:
                fh.write(new)
            changed += 1
    print(f'spdx_headers: {changed} of {len(paths)} file(s) shortened')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
