# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The self-contained HTML report: figures embedded as data URIs, links kept, written atomically.

A small Markdown report with two PNG figures (drawn here with matplotlib) is
converted; the figures must come back byte for byte from the page's data URIs,
no ``src`` may point outside the page, and a missing figure must be an error
that writes nothing.  With a Chromium on the PATH the page is also rendered
headless and the screenshot must show the solid red figure, after the figure
files have been deleted (so only the embedded copy can show it).
"""
import base64
import html
import os
from pathlib import Path
import re
import shutil
import subprocess

from friction_joint.exceptions import FrictionJointError
from friction_joint.report_html import markdown_to_html, write_html_report
import numpy as np
import pytest

#: the red figure, in pixels (4 x 3 in at 100 dpi)
RED_SIZE = (400, 300)

REPORT = """# Test report

A paragraph with inline math $a*b$ that Markdown must leave alone, and a
[summary](compensation/summary.json).

![red](figs/red.png)

| quantity | value |
|---|---|
| rmse | 1.5e-3 |
| samples | 1200 |

```python
x = 1  # <not a tag>
```

![sine](figs/sine.png)
"""


def _png_red(path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fig = Figure(figsize=(RED_SIZE[0] / 100, RED_SIZE[1] / 100), facecolor='#ff0000')
    FigureCanvasAgg(fig)
    fig.savefig(path, format='png', dpi=100, facecolor='#ff0000')


def _png_sine(path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fig = Figure(figsize=(5, 3))
    FigureCanvasAgg(fig)
    t = np.linspace(0.0, 2.0 * np.pi, 200)
    fig.add_subplot().plot(t, np.sin(t), color='tab:blue')
    fig.savefig(path, format='png', dpi=80)


@pytest.fixture
def report(tmp_path):
    """Write a report directory: ``report.md`` and ``figs/red.png``, ``figs/sine.png``."""
    (tmp_path / 'figs').mkdir()
    _png_red(tmp_path / 'figs' / 'red.png')
    _png_sine(tmp_path / 'figs' / 'sine.png')
    md = tmp_path / 'report.md'
    md.write_text(REPORT, encoding='utf-8')
    return md


def _sources(page):
    """Return every ``src`` attribute value in ``page``."""
    return [html.unescape(next(g for g in m.groups() if g is not None))
            for m in re.finditer(r"""\ssrc\s*=\s*(?:"([^"]*)"|'([^']*)'|([^\s>]+))""", page,
                                 re.IGNORECASE)]


def _decoded_images(page):
    """Return the bytes of every base64 PNG data URI of ``page``, in order."""
    out = []
    for src in _sources(page):
        m = re.fullmatch(r'data:image/png;base64,([A-Za-z0-9+/=]+)', src)
        assert m, f'src is not a PNG data URI: {src[:80]}'
        out.append(base64.b64decode(m.group(1), validate=True))
    return out


def _hidden_entries(folder):
    return sorted(p.name for p in Path(folder).iterdir() if p.name.startswith('.'))


def test_report_html_embeds_figures_and_keeps_links(report):
    written = write_html_report(report)
    assert written == str(report.with_suffix('.html'))
    page = Path(written).read_text(encoding='utf-8')
    assert page.startswith('<!DOCTYPE html>')
    assert '<h1' in page and '<table' in page and '<pre><code' in page
    assert '<title>Test report</title>' in page
    assert '&lt;not a tag&gt;' in page
    # math stays text: no emphasis made of the '*'
    assert '$a*b$' in page and '<em>b$' not in page
    assert re.search(r"""<a\s+href=["']compensation/summary\.json["']""", page)
    srcs = _sources(page)
    assert len(srcs) == 2
    assert all(s.startswith('data:') for s in srcs), [s[:60] for s in srcs]
    red = (report.parent / 'figs' / 'red.png').read_bytes()
    sine = (report.parent / 'figs' / 'sine.png').read_bytes()
    assert red != sine
    assert _decoded_images(page) == [red, sine]
    assert 'figs/red.png' not in page and 'figs/sine.png' not in page
    # numbers in table cells are marked for right alignment, words are not
    assert re.search(r'<td class="num">1\.5e-3</td>', page)
    assert re.search(r'<td>rmse</td>', page)
    # nothing but the inputs and the page, no temporary file left
    assert sorted(p.name for p in report.parent.iterdir()) == ['figs', 'report.html',
                                                               'report.md']


def test_report_html_replaces_an_existing_page_atomically(report, tmp_path, monkeypatch):
    target = tmp_path / 'out.html'
    target.write_text('old page', encoding='utf-8')
    real_replace = os.replace

    def failing_replace(src, dst):
        raise OSError(28, 'No space left on device')

    monkeypatch.setattr(os, 'replace', failing_replace)
    with pytest.raises(FrictionJointError, match='out.html'):
        write_html_report(report, html_path=target)
    assert target.read_text(encoding='utf-8') == 'old page'
    assert _hidden_entries(tmp_path) == []
    monkeypatch.setattr(os, 'replace', real_replace)
    assert write_html_report(str(report), html_path=str(target)) == str(target)
    assert '<table' in target.read_text(encoding='utf-8')
    assert _hidden_entries(tmp_path) == []
    assert not report.with_suffix('.html').exists()


def test_missing_image_is_an_error_that_writes_nothing(report, tmp_path):
    (tmp_path / 'figs' / 'sine.png').unlink()
    target = tmp_path / 'page.html'
    with pytest.raises(FrictionJointError) as err:
        write_html_report(report, html_path=target)
    msg = str(err.value)
    assert 'figs/sine.png' in msg and str(report) in msg and '\n' not in msg
    assert not target.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ['figs', 'report.md']
    with pytest.raises(FrictionJointError, match='sine.png') as err:
        markdown_to_html(REPORT, base_dir=tmp_path)
    assert str(tmp_path) in str(err.value)


def test_remote_and_data_images_are_left_alone(tmp_path):
    data = 'data:image/png;base64,iVBORw0KGgo='
    page = markdown_to_html(f'![w](https://example.com/a.png) ![d]({data})', base_dir=tmp_path,
                            title='a < b')
    assert _sources(page) == ['https://example.com/a.png', data]
    assert '<title>a &lt; b</title>' in page


def test_svg_and_jpeg_get_their_mime_types(tmp_path):
    (tmp_path / 'f.svg').write_text('<svg xmlns="http://www.w3.org/2000/svg"/>',
                                    encoding='utf-8')
    (tmp_path / 'g.jpeg').write_bytes(b'\xff\xd8\xff\xe0 not a real jpeg')
    srcs = _sources(markdown_to_html('![s](f.svg) ![j](g.jpeg)', base_dir=tmp_path))
    assert srcs[0].startswith('data:image/svg+xml;base64,')
    assert base64.b64decode(srcs[0].split(',', 1)[1]) == (tmp_path / 'f.svg').read_bytes()
    assert srcs[1].startswith('data:image/jpeg;base64,')


def _chromium():
    for name in ('chromium', 'chromium-browser', 'google-chrome'):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.mark.skipif(_chromium() is None, reason='no chromium / google-chrome on the PATH')
def test_report_html_renders_in_headless_chromium(report, tmp_path):
    import matplotlib.image

    page = Path(write_html_report(report))
    shutil.rmtree(report.parent / 'figs')     # only the embedded copies remain
    profile = tmp_path / 'profile'
    shot = tmp_path / 'shot.png'
    cmd = [_chromium(), '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic',
           '--no-first-run', '--disable-background-networking', '--disable-component-update',
           '--disable-sync', f'--user-data-dir={profile}', '--window-size=1200,2000',
           '--hide-scrollbars', f'--screenshot={shot}', page.as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0 and shot.is_file(), proc.stderr[-2000:]
    img = matplotlib.image.imread(shot)
    rgb = img[..., :3]
    assert rgb.shape[0] >= 1000 and rgb.shape[1] >= 1000
    assert float(rgb.std()) > 0.02          # not a blank page
    red = (rgb[..., 0] > 0.85) & (rgb[..., 1] < 0.15) & (rgb[..., 2] < 0.15)
    assert int(red.sum()) > 0.6 * RED_SIZE[0] * RED_SIZE[1], int(red.sum())


def test_code_blocks_wrap_on_screen_and_in_print(tmp_path):
    long_line = 'fc: [' + ', '.join(f'{0.1 * i:.6f}' for i in range(40)) + ']'
    page = markdown_to_html(f'```\n{long_line}\n```\n', base_dir=tmp_path)
    assert long_line in page                       # kept whole; the browser wraps it
    css = page[page.index('<style>'):page.index('</style>')]
    pre_rule = re.search(r'(?m)^pre \{([^}]*)\}', css).group(1)
    assert 'white-space: pre-wrap' in pre_rule and 'overflow-wrap: anywhere' in pre_rule
    print_rules = css[css.index('@media print'):]
    assert 'white-space: pre-wrap' in print_rules
