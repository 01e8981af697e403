# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The demo says what it is doing and names paths that exist (issue 22).

It printed nothing for about 3.5 minutes, then a bag path inside the
temporary directory it had been built in (gone by then).  Now every stage
prints a line to stderr as it starts and as it ends (its duration, the time
elapsed), --quiet silences them, and the last lines name what was
written at its final place.  The long stages are stubbed (the test bed is
left out, one classic experiment runs at low resolution).
"""
import os
from pathlib import Path
import re

from friction_joint.cli import main
from friction_joint.exceptions import FrictionJointError
from friction_joint.experiments import classic
from friction_joint.jobs import demo
import pytest


@pytest.fixture
def stubbed(monkeypatch):
    """Stub the ROS run and the identification; one fast classic experiment; no test bed."""
    def ros_run(out, model, truth, duration):
        Path(out, 'ros_run.png').write_bytes(b'png')
        Path(out, 'bag').mkdir()
        return ['ros run (stub)', '']

    def identification(out, model, truth, duration_scale, **options):
        options['progress']('block 1/1: 22.0 degC')            # a step within the stage
        Path(out, 'identification').mkdir()
        Path(out, 'identification', 'identified.yaml').write_text('joint_name: j\n')
        return ['identification (stub)', '']
    monkeypatch.setattr(demo, '_ros_run', ros_run)
    monkeypatch.setattr(demo, '_identification', identification)
    monkeypatch.setattr(demo, 'CLASSIC', ('lag',))
    monkeypatch.setattr(demo, 'TESTBED', ())
    monkeypatch.setitem(classic.CLASSIC_EXPERIMENTS, 'lag',
                        lambda: classic.frictional_lag(samples_per_period=2000))


def test_demo_prints_a_line_as_each_stage_starts_and_ends(stubbed, tmp_path, capsys):
    out = tmp_path / 'demo_out'
    assert main(['demo', '--out', f'{out}/']) == 0
    captured = capsys.readouterr()
    err = captured.err.splitlines()
    started = [m.group(1) for m in map(re.compile(r'demo: (.*) \.\.\. \(\d+:\d\d elapsed\)$')
                                       .match, err) if m]
    ended = [m.group(1) for m in map(re.compile(
        r'demo: (.*): done in \d+\.\d s \(\d+:\d\d elapsed\)$').match, err) if m]
    assert started == ended and len(started) >= 4, err
    assert any('ROS 2' in s for s in started) and any('identification' in s for s in started)
    assert 'classic experiment lag' in started
    assert 'demo:   block 1/1: 22.0 degC' in err              # a step, indented
    assert len(err) == 2 * len(started) + 1, err       # nothing else on stderr


def test_demo_last_lines_name_what_exists(stubbed, tmp_path, capsys):
    out = tmp_path / 'demo_out'
    assert main(['demo', '--out', f'{out}//', '--quiet']) == 0
    captured = capsys.readouterr()
    assert captured.err == ''                          # --quiet: no progress
    last = captured.out.splitlines()
    assert last[0] == f'report: {out / "report.md"}'
    named = [ln.split(':')[0].strip() for ln in last[1:]]
    assert named == [str(out / 'report.html'), str(out / 'bag'),
                     str(out / 'identification' / 'identified.yaml')]
    for path in [last[0].split(' ', 1)[1]] + named:
        assert os.path.exists(path), path


def test_demo_runs_bringup_quietly(monkeypatch, tmp_path):
    """The demo silences bringup, whose lines named the bag in the staging directory."""
    import friction_joint.ros.bringup as ros_bringup
    seen = {}

    def bringup(model, truth, duration, **options):
        seen.update(options)
        raise FrictionJointError('stop here (stub)')
    monkeypatch.setattr(ros_bringup, 'bringup', bringup)
    with pytest.raises(FrictionJointError):
        demo._ros_run(str(tmp_path), 'model.yaml', 'truth.yaml', 1.0)
    assert seen['quiet'] is True and seen['record'] == os.path.join(str(tmp_path), 'bag')
