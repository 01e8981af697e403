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

"""
Every Python file carries the copyright notice and the Apache-2.0 licence header.

The ament_copyright linter is not installable here (no wheel); this test
applies its rule for this package's one licence: a Copyright <year> <holder>
line followed by the Apache-2.0 header, at the top of the file (after a
shebang line, if any), and a LICENSE file with the licence text.
"""
import os
import re

import pytest

from sourcetree import python_files, ROOT, SOURCE_DIRS

COPYRIGHT = re.compile(r'^# Copyright (\d{4})(-\d{4})? \S.*$')
LICENSE_LINES = [
    '# Licensed under the Apache License, Version 2.0 (the "License");',
    '# you may not use this file except in compliance with the License.',
    '# You may obtain a copy of the License at',
    '#     http://www.apache.org/licenses/LICENSE-2.0',
    '# limitations under the License.',
]


def _header_problems(path):
    with open(path, encoding='utf-8') as fh:
        lines = fh.read().splitlines()
    if lines and lines[0].startswith('#!'):
        lines = lines[1:]
    head = lines[:14]
    if not head or not COPYRIGHT.match(head[0]):
        return 'no "# Copyright <year> <holder>" on the first line'
    missing = [ln for ln in LICENSE_LINES if ln not in head]
    return f'licence header lacks {missing[0]!r}' if missing else None


@pytest.mark.copyright
@pytest.mark.linter
def test_copyright():
    files = [p for d in SOURCE_DIRS for p in python_files(os.path.join(ROOT, d))]
    assert len(files) > 50
    problems = [f'{os.path.relpath(p, ROOT)}: {why}' for p in files
                if (why := _header_problems(p))]
    assert not problems, '\n'.join(problems)


@pytest.mark.copyright
@pytest.mark.linter
def test_license_file_is_apache_2():
    with open(os.path.join(ROOT, 'LICENSE'), encoding='utf-8') as fh:
        text = fh.read()
    assert 'Apache License' in text and 'Version 2.0, January 2004' in text
    assert 'END OF TERMS AND CONDITIONS' in text
