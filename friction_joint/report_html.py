# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Markdown reports as self-contained HTML: one file that opens in a browser, figures inside.

The reports of ``friction_joint demo`` (``DIR/report.md``) and ``diagnose``
name their figures by relative paths (``![fig](classic/stick_slip.png)``).
:func:`markdown_to_html` renders such a report with Python-Markdown (tables,
fenced code, sane lists, heading anchors) into a complete HTML5 document with a
small inline style sheet, and replaces every local image by a ``data:`` URI of
the file's bytes (PNG, SVG, JPEG, GIF, WebP), so the page needs neither the
result directory nor the network:

* a local image is a ``src`` without a URL scheme (or a ``file:`` URL), taken
  relative to ``base_dir``; ``%20``-style escapes are decoded, a query or
  fragment is ignored; remote (``http(s):``, ``//host``) and ``data:image/``
  sources are left as they are;
* a missing or unreadable image, one of an unknown type, one outside
  ``base_dir`` (an absolute path, ``..``, a symlink leading out) or one that
  is not a regular file (a FIFO, ``/dev/zero``: read through the input gate,
  :func:`~friction_joint.inputs.read_input`) is a one-line
  :class:`~friction_joint.exceptions.InputFileError` naming the file and
  the Markdown file (or ``base_dir``) it was looked up from;
* a command that renders its own figures passes them as ``images`` (name ->
  bytes): then no file is opened at all, and any other image is dropped
  (its alt text kept);
* links (``[summary](compensation/summary.json)``) are kept as written: they
  resolve when the HTML file lies beside the Markdown file, as
  :func:`write_html_report` writes it by default;
* inline math ``$...$`` stays text (``<span class="math">``), protected from
  Markdown's emphasis (``$a*b$``), and a backslash before ``$`` makes it a plain
  dollar sign; no MathJax, nothing is loaded;
* table cells that hold a single number are right-aligned (class ``num``);
* code blocks wrap their long lines (``white-space: pre-wrap``) on screen and
  in print, so a wide gear file is never cut off on the right.

:func:`write_html_report` converts a Markdown file and writes the HTML
atomically (a hidden temporary sibling, then :func:`os.replace`), so a reader
sees the old file or the complete new one, never a part.

The page is inert, whatever the Markdown holds (a report quotes joint ids,
recording paths and metadata written by its users): raw HTML in the Markdown
is not passed through but shown as text (``<script>`` reads as
``&lt;script&gt;``); a link whose target has a scheme other than
:data:`SAFE_SCHEMES` (``javascript:``, ``data:``, ``vbscript:``, also spelt
with entities, blanks or control characters) loses its ``href`` and stays
text; no element has an ``on*`` handler, and ``script``, ``iframe``,
``object`` and the like never appear.  :func:`markdown_text` escapes a
user's text for Markdown, so that it shows as written.

This module imports Python-Markdown; :mod:`friction_joint` does not import
it, so ``import friction_joint`` does not load it.
"""
from __future__ import annotations

import base64
from collections.abc import Mapping
import html
import os
import re
import secrets
import unicodedata
from urllib.parse import unquote, urlsplit
from urllib.request import url2pathname
import xml.etree.ElementTree as etree

import markdown
from markdown.inlinepatterns import InlineProcessor
from markdown.treeprocessors import Treeprocessor
from markdown.util import AtomicString

from .exceptions import InputFileError, OutputError
from .inputs import read_input

__all__ = ['SAFE_SCHEMES', 'markdown_text', 'markdown_to_html', 'write_html_report']

#: Python-Markdown extensions the reports are written for
EXTENSIONS = ('tables', 'fenced_code', 'sane_lists', 'toc')

#: file suffix -> MIME type of the images that are embedded
IMAGE_TYPES = {'.png': 'image/png', '.svg': 'image/svg+xml', '.jpg': 'image/jpeg',
               '.jpeg': 'image/jpeg', '.gif': 'image/gif', '.webp': 'image/webp'}

DEFAULT_TITLE = 'friction_joint report'

CSS = """
body { margin: 0; background: #fff; color: #1f2328; font: 16px/1.5 -apple-system,
  'Segoe UI', Helvetica, Arial, sans-serif; }
main { max-width: 1100px; margin: 0 auto; padding: 1.5em 2em 4em; }
h1, h2, h3 { line-height: 1.25; margin: 1.4em 0 0.6em; }
h1 { border-bottom: 2px solid #d0d7de; padding-bottom: 0.3em; }
h2 { border-bottom: 1px solid #d0d7de; padding-bottom: 0.2em; }
img { max-width: 100%; height: auto; display: block; margin: 0.5em 0; }
table { border-collapse: collapse; margin: 1em 0; display: block; overflow-x: auto; }
th, td { border: 1px solid #d0d7de; padding: 0.3em 0.7em; }
th { background: #f6f8fa; }
tbody tr:nth-child(even) { background: #fafbfc; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
code, pre { font-family: ui-monospace, 'SFMono-Regular', Menlo, Consolas, monospace;
  font-size: 0.9em; }
code { background: #f6f8fa; padding: 0.1em 0.3em; border-radius: 4px; }
pre { background: #f6f8fa; padding: 0.8em 1em; border-radius: 6px; white-space: pre-wrap;
  overflow-wrap: anywhere; }
pre code { background: none; padding: 0; white-space: inherit; }
.math { font-family: 'Latin Modern Math', 'STIX Two Math', 'Cambria Math', serif; }
a { color: #0969da; }
@media print {
  main { max-width: none; padding: 0; }
  pre, code { white-space: pre-wrap; overflow-wrap: anywhere; }
  table { display: table; overflow: visible; }
  img, pre, tr { break-inside: avoid; }
}
"""

_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="friction_joint.report_html">
<title>{title}</title>
<style>{css}</style>
</head>
<body>
<main>
{body}
</main>
</body>
</html>
"""

# $$...$$, and $...$ as pandoc reads it: no blank right after the opening $ nor before
# the closing one, the closing $ not followed by a digit; an escaped \$ is no delimiter
_MATH = (r'(?<![\\$])(?:\$\$(?:[^$\\]|\\.)+?\$\$'
         r'|\$(?=[^\s$])(?:[^$\n\\]|\\.)*?[^\s\\$]\$(?!\d))')
_NUMBER = re.compile(r'[-+\u2212]?(?:\d[\d,_]*\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*%?')
#: URL schemes a link of a report may have (besides none: a relative link)
SAFE_SCHEMES = ('http', 'https', 'mailto')
#: elements that never appear in a report (raw HTML is not passed through: belt and braces)
_FORBIDDEN = frozenset({'script', 'iframe', 'frame', 'frameset', 'object', 'embed', 'applet',
                        'style', 'link', 'meta', 'base', 'form', 'input', 'button', 'textarea',
                        'select', 'svg', 'math', 'template', 'noscript', 'audio', 'video',
                        'source', 'track', 'portal'})
#: attributes that never appear (and every ``on*`` event handler)
_FORBIDDEN_ATTRS = frozenset({'style', 'srcdoc', 'srcset', 'formaction', 'action', 'background',
                              'dynsrc', 'lowsrc', 'ping', 'xlink:href'})
#: characters Markdown (or its tables, links, autolinks and math) gives a meaning
_MD_SPECIAL = re.compile(r'([\\`*_{}\[\]()#+\-.!|>~<&$])')
#: those escaped as an entity rather than a backslash
_MD_ENTITY = {'<': '&lt;', '&': '&amp;', '|': '&#124;', '$': '&#36;', '~': '&#126;'}
_CONTROL = re.compile(r'[\x00-\x1f\x7f\u2028\u2029]')


class _MathProcessor(InlineProcessor):
    """``$...$`` becomes a ``<span class="math">`` whose text Markdown leaves alone."""

    def handleMatch(self, m, data):  # noqa: N802 (Python-Markdown's name)
        span = etree.Element('span', {'class': 'math'})
        span.text = AtomicString(m.group(0))
        return span, m.start(0), m.end(0)


class _NumericCells(Treeprocessor):
    """Mark table cells that hold a single number (class ``num``, right-aligned)."""

    def run(self, root):
        for cell in root.iter('td'):
            text = (cell.text or '').strip()
            if len(cell) == 0 and text and _NUMBER.fullmatch(text):
                cell.set('class', 'num')


class _ReportExtension(markdown.Extension):
    """The report's additions to Python-Markdown: inline math as text, numeric cells."""

    def extendMarkdown(self, md):  # noqa: N802 (Python-Markdown's name)
        # after code spans (190), before backslash escapes (180)
        md.inlinePatterns.register(_MathProcessor(_MATH, md), 'friction_joint_math', 185)
        if '$' not in md.ESCAPED_CHARS:     # \$ is a literal dollar sign, as in pandoc
            md.ESCAPED_CHARS.append('$')
        # after the inline patterns (20), before prettify (10)
        md.treeprocessors.register(_NumericCells(md), 'friction_joint_numeric_cells', 15)


def _error_prefix(where):
    return f'{where}: ' if where else ''


def _inside(path, base_dir):
    """Return whether ``path`` (symlinks followed) lies inside ``base_dir``."""
    try:
        real, base = os.path.realpath(path), os.path.realpath(base_dir)
    except (OSError, ValueError):
        return False
    return real.startswith(base.rstrip(os.sep) + os.sep)


def _data_uri(src, base_dir, where):
    """``src`` as a ``data:`` URI if it names a local file, else None (left alone)."""
    parts = urlsplit(src)
    if parts.scheme.lower() == 'file':
        path = url2pathname(parts.path)
    elif parts.scheme or parts.netloc or not parts.path:
        return None
    else:
        path = os.path.join(base_dir, unquote(parts.path))
    suffix = os.path.splitext(path)[1].lower()
    mime = IMAGE_TYPES.get(suffix)
    if mime is None:
        raise InputFileError(
            f'{_error_prefix(where)}cannot embed image {src!r}: unknown image type '
            f'{suffix or "(no suffix)"!r} (known: {", ".join(sorted(IMAGE_TYPES))})')
    try:
        found = os.path.lexists(path)
    except ValueError:                        # a NUL byte
        found = False
    if not found:
        raise InputFileError(f'{_error_prefix(where)}image {src!r} not found: no file '
                             f'{path}')
    if not _inside(path, base_dir):
        raise InputFileError(f'{_error_prefix(where)}image {src!r} ({path}) lies outside '
                             f'{base_dir}: a report embeds only its own figures')
    try:
        data = read_input(path, kind='report', what='an image')
    except InputFileError as exc:
        raise InputFileError(f'{_error_prefix(where)}cannot embed image {src!r}: '
                             f'{exc}') from None
    return f'data:{mime};base64,{base64.b64encode(data).decode("ascii")}'


def _safe_href(href):
    """Return whether a link target is relative or has one of the :data:`SAFE_SCHEMES`."""
    text = html.unescape(href)
    # browsers skip ASCII whitespace and control characters in a URL's scheme
    text = ''.join(c for c in text if not (c.isspace() or unicodedata.category(c)[0] == 'C'))
    m = re.match(r'([^/?#]*?):', text)
    return m is None or m.group(1).lower() in SAFE_SCHEMES


class _Inert(Treeprocessor):
    """Make the page inert and its images self-contained (module docstring)."""

    def __init__(self, md, base_dir, where, images):
        super().__init__(md)
        self.base_dir, self.where, self.images = base_dir, where, images

    def _image(self, src):
        """Return the ``src`` to use for image ``src``; None drops the image."""
        src = html.unescape(src).strip()
        if self.images is not None:
            if src not in self.images:
                return None
            mime = IMAGE_TYPES.get(os.path.splitext(src)[1].lower(), 'image/png')
            return f'data:{mime};base64,{base64.b64encode(self.images[src]).decode("ascii")}'
        scheme = urlsplit(src).scheme.lower()
        if scheme == 'data':
            return src if src[5:].lower().startswith('image/') else None
        if scheme not in ('', 'http', 'https', 'file'):
            return None
        uri = _data_uri(src, self.base_dir, self.where)
        return src if uri is None else uri

    def run(self, root):
        """Strip handlers, scripts and unsafe links; embed or drop every image."""
        parents = {child: parent for parent in root.iter() for child in parent}
        for elem in list(root.iter()):
            if not isinstance(elem.tag, str):
                continue
            for key in list(elem.keys()):
                if key.lower().startswith('on') or key.lower() in _FORBIDDEN_ATTRS:
                    del elem.attrib[key]
            if elem.tag.lower() in _FORBIDDEN:
                if elem in parents:
                    parents[elem].remove(elem)
            elif elem.tag == 'a' and not _safe_href(elem.get('href') or ''):
                elem.tag = 'span'
                elem.attrib.clear()
            elif elem.tag == 'img':
                uri = self._image(elem.get('src') or '')
                if uri is None:
                    alt = elem.get('alt') or ''
                    elem.tag = 'span'
                    elem.attrib.clear()
                    elem.text = AtomicString(alt)
                else:
                    elem.set('src', uri)


def markdown_text(text: str) -> str:
    """
    Escape a user's text for Markdown: it shows as written, never as markup or a link.

    Parameters
    ----------
    text : str
        Any text (a joint id, a path, a metadata value, a reason).

    Returns
    -------
    str
        One line (line breaks and control characters become blanks, runs of
        blanks one, as a browser shows them) with every character that
        Markdown or its tables give a meaning escaped.

    """
    one = re.sub(' {2,}', ' ', _CONTROL.sub(' ', str(text))).strip(' ')     # never a code block
    return _MD_SPECIAL.sub(lambda m: _MD_ENTITY.get(m.group(1), '\\' + m.group(1)), one)


def _render(text, base_dir, title, where, images=None):
    """
    Render ``text``; ``title`` None takes the first level-1 heading (or the default).

    ``where`` names the Markdown file (or ``base_dir``) in error messages;
    ``images`` (name -> bytes), when given, are the page's only images.
    """
    md = markdown.Markdown(extensions=[*EXTENSIONS, _ReportExtension()],
                           output_format='html')
    md.preprocessors.deregister('html_block')      # raw HTML is text, never markup
    md.inlinePatterns.deregister('html')
    base = None if base_dir is None else os.fspath(base_dir)
    # after every other tree processor (unescape, at 0, restores escaped attributes)
    md.treeprocessors.register(_Inert(md, base, where, images), 'friction_joint_inert', -10)
    body = md.convert(text)
    if title is None:
        first = md.toc_tokens[0] if md.toc_tokens else None
        # toc's 'name' is already escaped for HTML
        shown = first['name'] if first and first['level'] == 1 and first['name'] else \
            html.escape(DEFAULT_TITLE)
    else:
        shown = html.escape(str(title))
    return _PAGE.format(title=shown, css=CSS.strip(), body=body)


def markdown_to_html(text: str, *, base_dir: str | os.PathLike[str] | None = None,
                     title: str = DEFAULT_TITLE,
                     images: Mapping[str, bytes] | None = None) -> str:
    """
    Render Markdown as a complete, self-contained, inert HTML5 document.

    Parameters
    ----------
    text : str
        The Markdown source (Python-Markdown with tables, fenced code, sane
        lists and heading anchors; ``$...$`` is kept as text; raw HTML is
        shown as text).
    base_dir : str or os.PathLike, optional
        Directory that relative image paths are taken from (the Markdown
        file's directory); required unless ``images`` is given.
    title : str
        The document's ``<title>`` (escaped here).
    images : mapping, optional
        The images the command rendered, name (as the Markdown gives it) ->
        bytes (type by the name's suffix).  When given they are the only
        images: no file is opened, any other image is dropped.

    Returns
    -------
    str
        The HTML document; every local image is a ``data:`` URI, remote and
        ``data:image/`` images are left as written; links of the
        :data:`SAFE_SCHEMES` or relative are kept, others become text.

    Raises
    ------
    InputFileError
        An image is missing, unreadable, of an unknown type, not a regular
        file or outside ``base_dir``; the message names it and ``base_dir``.

    """
    if base_dir is None and images is None:
        raise TypeError('markdown_to_html needs base_dir or images')
    where = f'base_dir {os.fspath(base_dir)}' if base_dir is not None else ''
    return _render(text, base_dir, title, where, images=images)


def _write_atomic(path, data):
    """Write ``data`` (bytes) to ``path`` via a hidden temporary sibling and a rename."""
    folder = os.path.dirname(os.path.abspath(path))
    name = os.path.basename(path)
    for _ in range(100):
        tmp = os.path.join(folder, f'.{name}.{secrets.token_hex(4)}.tmp')
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            break
        except FileExistsError:
            continue
        except OSError as exc:
            raise OutputError(f'cannot write {path}: {exc.strerror or exc}') from None
    else:
        raise OutputError(f'cannot write {path}: no free temporary name in {folder}')
    try:
        with os.fdopen(fd, 'wb') as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            raise OutputError(f'cannot write {path}: {exc.strerror or exc}') from None
        raise


def write_html_report(md_path: str | os.PathLike[str], *,
                      html_path: str | os.PathLike[str] | None = None) -> str:
    """
    Convert a Markdown report into a self-contained HTML file beside it.

    Images are taken relative to the Markdown file's directory and embedded
    (see :func:`markdown_to_html`); the ``<title>`` is the first level-1
    heading (else ``'friction_joint report'``).  Links are kept as written,
    so they resolve when ``html_path`` lies in the Markdown file's directory.

    Parameters
    ----------
    md_path : str or os.PathLike
        The Markdown file (UTF-8).
    html_path : str or os.PathLike, optional
        Where to write the HTML; default: ``md_path`` with the suffix
        ``.html``.  An existing file there is replaced (atomically: a
        temporary sibling renamed into place).

    Returns
    -------
    str
        The path of the HTML file written.

    Raises
    ------
    InputFileError, OutputError
        The Markdown file cannot be read, an image is missing, unreadable or
        of an unknown type, ``html_path`` is ``md_path`` or cannot be written;
        nothing is written then.

    """
    md_path = os.fspath(md_path)
    if html_path is None:
        html_path = os.path.splitext(md_path)[0] + '.html'
    html_path = os.fspath(html_path)
    if os.path.abspath(html_path) == os.path.abspath(md_path) or \
            (os.path.exists(html_path) and os.path.exists(md_path) and
             os.path.samefile(html_path, md_path)):
        raise OutputError(f'{md_path}: the HTML report would overwrite the Markdown '
                          'file; give another html_path')
    try:
        with open(md_path, encoding='utf-8') as fh:
            text = fh.read()
    except OSError as exc:
        raise InputFileError(f'cannot read {md_path}: {exc.strerror or exc}') from None
    except UnicodeDecodeError as exc:
        raise InputFileError(f'{md_path}: not UTF-8 ({exc.reason} at byte '
                             f'{exc.start})') from None
    page = _render(text, os.path.dirname(os.path.abspath(md_path)), None, md_path)
    _write_atomic(html_path, page.encode('utf-8'))
    return html_path
