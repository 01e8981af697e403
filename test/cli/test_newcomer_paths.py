# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Paths the commands print are normalised (issue 22): --out DIR/ printed DIR//report.json.

The work is stubbed: only what the command prints is under test.
"""
import json
import os
import types

from friction_joint.cli import main
import friction_joint.jobs.diagnose as diagnosis_report
import friction_joint.jobs.identify as identification_pipeline
from friction_joint.jobs.runs import IdentifyRun
import pytest

MODEL = os.path.join(os.path.dirname(__file__), '..', '..', 'config', 'csd25.yaml')


def _no_doubled_separator(text):
    return not any('//' in word for word in text.split())


@pytest.mark.parametrize('suffix', ['/', '//', ''])
def test_diagnose_prints_normal_paths(tmp_path, capsys, monkeypatch, suffix):
    def run_diagnose(recordings, model, out, **options):
        os.makedirs(out, exist_ok=True)
        path = os.path.join(out, 'report.json')
        with open(path, 'w', encoding='utf-8') as fh:
            json.dump({'named_causes': ['thermal']}, fh)
        diag = types.SimpleNamespace(named_causes=('thermal',))
        return diagnosis_report.DiagnoseRun(diagnosis=diag, written=[path])
    monkeypatch.setattr(diagnosis_report, 'run_diagnose', run_diagnose)
    out = str(tmp_path / 'report') + suffix
    assert main(['diagnose', 'rec.mcap', '--model', MODEL, '--out', out, '--quiet']) == 0
    printed = capsys.readouterr().out
    assert _no_doubled_separator(printed), printed
    assert os.path.join(str(tmp_path), 'report', 'report.json') in printed
    assert printed.startswith('named causes: thermal; wrote ')


def test_identify_prints_normal_paths(tmp_path, capsys, monkeypatch):
    def run_identify(paths, model, out, **options):
        report = options['report_dir']
        return IdentifyRun(None, {}, [os.path.join(report, 'identification.json'), out])
    monkeypatch.setattr(identification_pipeline, 'run_identify', run_identify)
    out = str(tmp_path) + '//gear.yaml'
    assert main(['identify', 'rec.mcap', '--model', MODEL, '--out', out, '--report',
                 str(tmp_path) + '/rep/', '--quiet']) == 0
    printed = capsys.readouterr().out
    assert _no_doubled_separator(printed), printed
    assert os.path.join(str(tmp_path), 'gear.yaml') in printed
