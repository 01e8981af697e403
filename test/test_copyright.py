# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
The head of every Python file: the SPDX licence line, the copyright line, the module's purpose.

The rule (REUSE-style, replacing the 13-line Apache-2.0 comment that
ament_copyright's template writes; that linter has no wheel here): the first two
lines, after a shebang line if any, are ``# SPDX-License-Identifier: Apache-2.0``
and ``# Copyright <year> <holder>``; the licence text itself is in LICENSE
(``.ci/spdx_headers.py`` turns a long header into the short one).  Right after
them comes the module docstring, whose first line, for every module of the
package, is one sentence saying what the module is for: ending with a period, at
most 99 characters, words beyond a command line or a name.  Those first lines are
the package layout table of docs/design.md, the tree read as a table of contents
(regenerate it with ``python test/test_copyright.py --write``).
"""
import ast
import os
import re
import sys

import pytest

from sourcetree import PACKAGE, package_modules, python_files, ROOT, SOURCE_DIRS

SPDX = '# SPDX-License-Identifier: Apache-2.0'
COPYRIGHT = re.compile(r'^# Copyright (\d{4})(-\d{4})? \S.*$')
#: the docs file whose package layout table is generated from the first lines
LAYOUT_DOC = os.path.join(ROOT, 'docs', 'design.md')
TABLE_START = "<!-- package layout: generated from the modules' first docstring lines -->"
TABLE_END = '<!-- end of package layout -->'
SUMMARY_MAX = 99


def _header_problems(path):
    with open(path, encoding='utf-8') as fh:
        lines = fh.read().splitlines()
    if lines and lines[0].startswith('#!'):
        lines = lines[1:]
    if not lines or lines[0] != SPDX:
        return f'the first line is not {SPDX!r}'
    if len(lines) < 2 or not COPYRIGHT.match(lines[1]):
        return 'no "# Copyright <year> <holder>" on the second line'
    if len(lines) > 2 and lines[2].startswith('#'):
        return 'a comment continues the header (the licence text is in LICENSE)'
    return None


def summary_line(path):
    """Return the first line of the module docstring of path, or None without one."""
    with open(path, encoding='utf-8') as fh:
        doc = ast.get_docstring(ast.parse(fh.read()), clean=False)
    if doc is None:
        return None
    return doc.lstrip('\n').split('\n', 1)[0].strip()


def _summary_problems(path):
    with open(path, encoding='utf-8') as fh:
        doc = ast.get_docstring(ast.parse(fh.read()), clean=False)
    if not doc or not doc.strip():
        return 'no module docstring'
    lines = doc.lstrip('\n').split('\n')
    first = lines[0].strip()
    if len(lines) > 1 and lines[1].strip():
        return 'the first line is not a summary of its own (no blank line after it)'
    if not first.endswith('.'):
        return f'the first line does not end with a period: {first!r}'
    if len(first) > SUMMARY_MAX:
        return f'the first line has {len(first)} > {SUMMARY_MAX} characters'
    # a command line or a name alone does not say what the module is for
    words = re.findall(r'[A-Za-z]{2,}', re.sub(r'(:\w+:)?`+[^`]*`+', ' ', first))
    if len(words) < 3:
        return f'the first line does not say what the module is for: {first!r}'
    return None


def _markdown(summary):
    """Turn the reST of a summary (``x``, :mod:`~a.b`) into Markdown code spans."""
    def role(match):
        target = match.group(2)
        return f'`{target.rsplit(".", 1)[-1] if match.group(1) else target}`'

    summary = re.sub(r':\w+:`(~?)\.?([\w.]+)`', role, summary)
    return re.sub(r'``([^`]+)``', r'`\1`', summary).replace('|', '\\|')


def layout_table():
    """Return the package layout table: one row per module, its docstring's first line."""
    rows = ['| module | what it is for |', '|---|---|']
    base = os.path.join(ROOT, PACKAGE)
    for _, path in package_modules():
        rel = os.path.relpath(path, base).replace(os.sep, '/')
        if rel.endswith('/__init__.py'):
            name = f'**`{rel[:-len("__init__.py")]}`**'
        else:
            name = f'`{PACKAGE}/`' if rel == '__init__.py' else f'`{rel}`'
        rows.append(f'| {name} | {_markdown(summary_line(path) or "")} |')
    return '\n'.join(rows) + '\n\n'


def _split_doc(text):
    start = text.index(TABLE_START) + len(TABLE_START) + 1
    end = text.index(TABLE_END, start)
    return text[:start], text[start:end], text[end:]


@pytest.mark.copyright
@pytest.mark.linter
def test_copyright():
    files = [p for d in SOURCE_DIRS for p in python_files(os.path.join(ROOT, d))]
    assert len(files) > 50
    problems = [f'{os.path.relpath(p, ROOT)}: {why}' for p in files
                if (why := _header_problems(p))]
    assert not problems, ('\n'.join(problems)
                          + '\n(python .ci/spdx_headers.py shortens a long header)')


@pytest.mark.copyright
@pytest.mark.linter
def test_license_file_is_apache_2():
    with open(os.path.join(ROOT, 'LICENSE'), encoding='utf-8') as fh:
        text = fh.read()
    assert 'Apache License' in text and 'Version 2.0, January 2004' in text
    assert 'TERMS AND CONDITIONS FOR USE, REPRODUCTION, AND DISTRIBUTION' in text
    headings = re.findall(r'^\s+(\d)\. [A-Z]', text, re.MULTILINE)
    assert headings == [str(i) for i in range(1, 10)], 'the nine sections of the licence'
    assert 'END OF TERMS AND CONDITIONS' in text
    # the identifier the headers name is the one the package declares
    with open(os.path.join(ROOT, 'package.xml'), encoding='utf-8') as fh:
        assert '<license>Apache-2.0</license>' in fh.read()
    with open(os.path.join(ROOT, 'setup.py'), encoding='utf-8') as fh:
        assert "license='Apache-2.0'" in fh.read()


@pytest.mark.linter
def test_every_module_says_what_it_is_for():
    modules = package_modules()
    assert len(modules) > 100
    problems = [f'{name}: {why}' for name, path in modules if (why := _summary_problems(path))]
    assert not problems, '\n'.join(problems)


@pytest.mark.linter
def test_the_package_layout_table_is_the_modules_first_lines():
    with open(LAYOUT_DOC, encoding='utf-8') as fh:
        _, table, _ = _split_doc(fh.read())
    assert table == layout_table(), (
        "docs/design.md: the package layout table differs from the modules' first "
        'docstring lines; regenerate it with python test/test_copyright.py --write')


if __name__ == '__main__':
    if sys.argv[1:] != ['--write']:
        sys.exit('usage: python test/test_copyright.py --write  '
                 '(regenerates the package layout table of docs/design.md)')
    with open(LAYOUT_DOC, encoding='utf-8') as fh:
        head, _, tail = _split_doc(fh.read())
    with open(LAYOUT_DOC, 'w', encoding='utf-8') as fh:
        fh.write(head + layout_table() + tail)
    print(f'{os.path.relpath(LAYOUT_DOC, ROOT)}: package layout table written')
