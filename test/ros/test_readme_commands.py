# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The README's command blocks, extracted from the README and run on a fresh copy of the tree.

Every fenced ``sh`` block of README.md is meant to be copied.  The HTML
comment on the line before a block says how a reader runs it:

* none: in a terminal, to the end; it must exit 0;
* ``<!-- readme-test: terminal -->``: in a terminal of its own, running until
  Ctrl-C; it is started in the background and stopped with SIGINT (Ctrl-C)
  once the next plain block has ended, recorders last;
* ``<!-- readme-test: skip, REASON -->``: not run here (it needs minutes:
  the demo, the test suite itself); its syntax and executables are checked.

The blocks run in README order in one copy of the git-tracked files (what a
fresh clone has), with ``.venv`` linked from this tree, in a ROS domain of
their own.  What they write is then checked: a block that breaks, or writes
something other than what the README says, fails the test.  The links of
README.md and docs/ are checked too.
"""
import json
import os
import re
import shutil
import signal
import subprocess

from friction_joint.bag import check_lockstep, read_recording
from friction_joint.gear import load_gear
import numpy as np
import pytest
import roshelpers

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
README = os.path.join(ROOT, 'README.md')
_BLOCK = re.compile(r'(?:^<!-- readme-test: ([^>]*?) -->\n)?^```sh\n(.*?)^```$',
                    re.MULTILINE | re.DOTALL)
_LINK = re.compile(r'\]\(([^)#\s]+)(?:#[^)]*)?\)')


def readme_blocks(path=README):
    """Return ``(kind, text)`` of every ``sh`` block: kind ``run``, ``terminal`` or ``skip``."""
    with open(path, encoding='utf-8') as fh:
        text = fh.read()
    blocks = []
    for match in _BLOCK.finditer(text):
        marker = (match.group(1) or 'run').strip()
        kind = marker.split(',')[0].strip()
        assert kind in ('run', 'terminal', 'skip'), f'unknown readme-test marker {marker!r}'
        if kind == 'skip':
            assert ',' in marker, f'a skipped block says why: {marker!r}'
        blocks.append((kind, match.group(2)))
    return blocks


def test_readme_blocks_are_marked_and_well_formed():
    """Every block parses as shell, names executables that exist, and few are skipped."""
    blocks = readme_blocks()
    kinds = [kind for kind, _ in blocks]
    assert kinds.count('run') >= 5 and kinds.count('terminal') >= 3, kinds
    assert kinds.count('skip') <= 2, kinds            # only the two commands that need minutes
    scripts = set()
    with open(os.path.join(ROOT, 'setup.py'), encoding='utf-8') as fh:
        scripts.update(re.findall(r"'([a-z_]+) = friction_joint", fh.read()))
    for _kind, text in blocks:
        check = subprocess.run(['bash', '-n'], input=text, text=True, capture_output=True)
        assert check.returncode == 0, (text, check.stderr)
        for name in re.findall(r'\.venv/bin/([A-Za-z_]+)', text):
            assert name in scripts | {'python'}, f'README names .venv/bin/{name}: not installed'


def test_readme_and_docs_links_point_at_files():
    """Relative links of README.md and docs/*.md (figures too) name files that exist."""
    pages = [README] + [os.path.join(ROOT, 'docs', f)
                        for f in sorted(os.listdir(os.path.join(ROOT, 'docs')))
                        if f.endswith('.md')]
    for page in pages:
        with open(page, encoding='utf-8') as fh:
            targets = _LINK.findall(fh.read())
        for target in targets:
            if '://' in target:
                continue
            path = os.path.normpath(os.path.join(os.path.dirname(page), target))
            assert os.path.exists(path), f'{os.path.relpath(page, ROOT)} links {target}'


def fresh_copy(dest):
    """Copy the git-tracked files of this tree (as they are now) to ``dest``; link .venv."""
    listed = subprocess.run(['git', 'ls-files', '-z'], cwd=ROOT, capture_output=True)
    if listed.returncode != 0:
        pytest.skip('not a git checkout: no list of tracked files to copy')
    for rel in listed.stdout.decode().split('\0'):
        if rel and os.path.lexists(os.path.join(ROOT, rel)):
            os.makedirs(os.path.join(dest, os.path.dirname(rel)), exist_ok=True)
            shutil.copy2(os.path.join(ROOT, rel), os.path.join(dest, rel), follow_symlinks=False)
    os.symlink(os.path.join(ROOT, '.venv'), os.path.join(dest, '.venv'))


def run_beside(proc, terminals, timeout=600.0):
    """Wait for ``proc`` to end; a background block that ends first fails the test at once."""
    def settled():
        return proc.popen.poll() is not None or any(p.popen.poll() is not None
                                                    for p in terminals)
    roshelpers.wait_until(settled, timeout=timeout, poll=0.1)
    for other in terminals:
        assert other.popen.poll() is None, 'a terminal block ended early\n' + other.describe()
    return proc.wait(timeout=5)


def stop_terminals(terminals):
    """Ctrl-C every background block, recorders last; each must end cleanly."""
    ordered = sorted(terminals, key=lambda p: 'bin/record' in ' '.join(p.cmd))
    for proc in ordered:
        rc = proc.stop(timeout=roshelpers.DEADLINE)
        assert rc in (0, 130, -signal.SIGINT), proc.describe()


@pytest.mark.ros
@pytest.mark.slow
def test_readme_command_blocks_run_on_a_fresh_copy(ros_env, tmp_path):
    """Run every README block not marked skip, in order; then check what they wrote."""
    if not os.path.exists(os.path.join(ROOT, '.venv', 'bin', 'friction_joint')):
        pytest.skip('the README commands run from .venv (bash .ci/setup)')
    clone = tmp_path / 'friction_joint'
    fresh_copy(str(clone))
    env = ros_env
    terminals = []
    try:
        for kind, text in readme_blocks():
            if kind == 'skip':
                continue
            cmd = ['bash', '-e', '-c', text]
            if kind == 'terminal':
                terminals.append(roshelpers.Proc(cmd, env, cwd=str(clone)))
                continue
            proc = roshelpers.Proc(cmd, env, cwd=str(clone))
            try:
                rc = run_beside(proc, terminals)
            finally:
                proc.stop()
            assert rc == 0, proc.describe() + ''.join(p.describe() for p in terminals)
            stop_terminals(terminals)
            terminals = []
    finally:
        for proc in terminals:
            proc.stop()
    check_outputs(clone)


def check_outputs(clone):
    """Check what the README says its blocks write, in the copy they ran in."""
    # the hand-started realtime loop with a recorder: every message from the first state
    run1 = read_recording(str(clone / 'bags' / 'run1'))
    k = np.round(np.asarray(run1.joint_states.t) * 1000.0).astype(np.int64)
    assert len(k) >= 1000 and np.all(np.diff(k) == 1)        # no state missing
    first = {topic: np.round(np.asarray(getattr(run1, topic).t) * 1000.0).astype(np.int64)[0]
             for topic in ('link_torque', 'joint_command', 'external_torque')}
    assert first['link_torque'] == first['external_torque'] == k[0], (first, k[0])
    # the realtime controller answers the newest state: under load it may skip a few, but
    # the simulation waits for its answers (at most max_lead, 0.02 s, ahead of them)
    assert k[0] <= first['joint_command'] <= k[0] + 20, (first, k[0])
    q = np.asarray(run1.joint_states.q)
    assert np.all(np.abs(q) < 1.0) and np.ptp(q) > 0.2, (q.min(), q.max())
    # bringup in lockstep: every step on every loop topic
    run2 = check_lockstep(read_recording(str(clone / 'bags' / 'run2')))
    assert run2.complete and run2.steps == 3 * 3000 + 1, run2.describe()
    # the replay into a fresh estimator: its answers on the recorded time of run1
    replayed = read_recording(str(clone / 'bags' / 'replayed'))
    t = np.asarray(replayed.external_torque.t)
    assert len(t) > 100 and np.all(np.isin(t, run1.joint_states.t)), len(t)
    # diagnose names the sample's hidden effect; identify writes a loadable gear file
    with open(clone / 'sample_diagnosis' / 'report.json') as fh:
        assert json.load(fh)['named_causes'] == ['thermal']
    assert (clone / 'sample_diagnosis' / 'report.html').stat().st_size > 10000
    assert load_gear(str(clone / 'sample_identified.yaml')).friction.fc
    # the imported tribometer log: pre-sliding named, temperature untestable
    with open(clone / 'tribometer_diagnosis' / 'report.json') as fh:
        report = json.load(fh)
    assert 'presliding' in report['named_causes'] and 'thermal' in report['untestable']
    # the fleet monitor flags exactly the joints the simulated fleet made wear
    with open(clone / 'fleet' / 'truth.json') as fh:
        truth = {j: d['wear'] for j, d in json.load(fh)['joints'].items()}
    with open(clone / 'fleet_report' / 'fleet.json') as fh:
        flagged = {j: d['wear'] for j, d in json.load(fh)['joints'].items()}
    assert flagged == truth and any(truth.values()), (flagged, truth)
    assert (clone / 'fleet_report' / 'report.html').stat().st_size > 10000
