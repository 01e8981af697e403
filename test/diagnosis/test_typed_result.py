# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The diagnosis result is typed: no string-key access into it outside ``to_dict``/``from_dict``.

The result of :func:`friction_joint.diagnosis.diagnose` is a tree of frozen
dataclasses (:mod:`friction_joint.diagnosis.result`,
:mod:`friction_joint.diagnosis.verdicts`) whose field names are the keys of
``report.json``.  The rule, read from the source (the AST): in the modules that
build or read a diagnosis result, no key of the result (a field name of those
classes) is used as a string -- ``x['named_causes']``, ``x.get('gain_raw')``,
``x.pop(...)``, ``x.setdefault(...)``, ``'note' in x`` -- except inside a
function named ``to_dict`` or ``from_dict``.  Records other modules own and the
result carries as they came (the fitted coefficients, a scan row) are read by
their own keys, which are not the result's.  Before the result was typed the
scan found the report dict read and written by key in every one of these
modules (``diag.report['data']['gaps'] = ...`` in the job, ``rep['candidates']``
in the findings, ...).
"""
import ast
import dataclasses
import json
import os

from friction_joint.diagnosis import result, verdicts
from friction_joint.diagnosis.result import DiagnosisResult
import pytest
from sourcetree import ROOT

#: the modules that build or read a diagnosis result
SCANNED = [os.path.join('friction_joint', 'diagnosis', f'{m}.py') for m in (
    'pipeline', 'greedy', 'result', 'verdicts', 'findings', 'criterion', 'report',
    'next_step')] + [os.path.join('friction_joint', 'jobs', 'diagnose.py')]
#: functions that may use the keys: the JSON is built and read there only
ALLOWED = ('to_dict', 'from_dict')
#: the methods of a dict that take a key first
KEYED = ('get', 'pop', 'setdefault')


def _result_classes():
    return [getattr(mod, name) for mod in (result, verdicts) for name in mod.__all__
            if dataclasses.is_dataclass(getattr(mod, name))]


def result_keys():
    """Return the keys of a diagnosis result: the fields of its classes written to JSON."""
    return {f.name for cls in _result_classes() if hasattr(cls, 'to_dict')
            for f in dataclasses.fields(cls)} - {'record'}


def _key(node):
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    return None


def keyed_access(tree, keys):
    """Return ``[(line, text)]`` of string-key uses of ``keys`` outside the allowed functions."""
    found = []

    def visit(node, allowed):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            allowed = allowed or node.name in ALLOWED
        if not allowed:
            key = None
            if isinstance(node, ast.Subscript):
                key = _key(node.slice)
            elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                  and node.func.attr in KEYED and node.args):
                key = _key(node.args[0])
            elif (isinstance(node, ast.Compare) and
                  any(isinstance(op, (ast.In, ast.NotIn)) for op in node.ops)):
                key = _key(node.left)
            if key in keys:
                found.append((node.lineno, ast.unparse(node)[:80]))
        for child in ast.iter_child_nodes(node):
            visit(child, allowed)

    visit(tree, False)
    return found


def scan_source(text, keys=None):
    """Return the string-key uses of the result's keys in one module's source ``text``."""
    return keyed_access(ast.parse(text), result_keys() if keys is None else keys)


def test_the_result_keys_are_its_json_keys():
    """The vocabulary the scan looks for covers report.json's own keys."""
    keys = result_keys()
    assert {'named_causes', 'candidates', 'adequacy', 'rounds', 'data', 'gaps', 'timing',
            'gain_raw', 'p_holm', 'significant', 'note', 'reason', 'xi_range',
            'v_stick', 'total_s', 'headline', 'extended_fit'} <= keys


@pytest.mark.parametrize('path', SCANNED)
def test_no_string_key_access_into_a_diagnosis_result(path):
    """Before: 324 such uses in these modules (the report dict read and written by key)."""
    with open(os.path.join(ROOT, path), encoding='utf-8') as f:
        found = scan_source(f.read())
    assert not found, f'{path}: ' + '; '.join(f'line {n}: {t}' for n, t in found)


def test_the_scan_finds_what_it_must():
    """The report dict read and written by key, as the job and the findings did."""
    old = '\n'.join(['def _into(diag, rep):',
                     "    diag.report['data']['gaps'] = 1",
                     "    rep['timing']['total_s'] = 2",
                     "    c = rep.get('diagnosed')",
                     "    return 'note' in c",
                     'def to_dict(self):',
                     "    return {'named_causes': self.named_causes['x']}"])
    lines = [n for n, _ in scan_source(old)]
    assert lines == [2, 2, 3, 3, 4, 5], scan_source(old)


def test_every_result_class_is_frozen():
    """The job builds a new result (dataclasses.replace); nothing writes into one."""
    loose = [cls.__name__ for cls in _result_classes()
             if not cls.__dataclass_params__.frozen]
    assert not loose, loose


#: a report.json with every kind of candidate entry, read back and written again
SAMPLE = {
    'named_causes': ['thermal'],
    'candidates': [
        {'effect': 'thermal', 'applicable': True, 'gain': 0.5, 'gain_raw': 0.5, 'p_value': 1e-4,
         'explained_torque': 0.1, 'blocks_improved': 10, 'blocks': 10,
         'heldout_torque_rmse': 0.01, 'mean_log_mse_ratio': 1.0, 'median_log_mse_ratio': 1.0,
         'confounded_with': {'drift': {'rank_correlation': 0.95, 'separate_by': 'x'}},
         'p_holm': 1e-3, 'significant': True, 'round': 1, 'testable': True, 'physical': True},
        {'effect': 'stribeck', 'applicable': False, 'gain': 0.0, 'significant': False,
         'p_value': 1.0, 'note': 'already in the model structure', 'testable': True},
        {'effect': 'gravity', 'testable': False, 'reason': 'too short', 'gain': 0.0,
         'significant': False}],
    'baseline': {'torque_rmse': 0.2, 'velocity_rmse': 0.01},
    'extended': {'torque_rmse': 0.1, 'velocity_rmse': None},
    'criterion': {'statistic': 's', 'test': 't', 'multiplicity': 'm', 'alpha': 0.05,
                  'min_gain': 0.03, 'min_explained': 0.01, 'blocks': 10, 'gain': 'g',
                  'selection': 'greedy', 'confound_rank_correlation': 0.9},
    'adequacy': {k: {'r2': 0.9, 'rmse': 0.1, 'friction_level': 2.0, 'rmse_over_level': 0.05,
                     'explains': True} for k in ('base', 'extended')},
    'confounds': [{'effects': ['thermal', 'drift'], 'rank_correlation': 0.95,
                   'separate_by': 'x'}],
    'rounds': [{'round': 1, 'model_torque_rmse': 0.2, 'candidates': []}],
    'data': {'recordings': ['rec'], 'bins': 100, 'bin_s': 0.01, 'sliding_s': 1.0,
             'xi_range': [20.0, 30.0], 'torque_source': 'none', 'velocity_windows': 0,
             'window_s': 0.5, 'has_temperature': True,
             'scales': {'v_stick': 0.01, 'resolution': 1e-5, 'friction_level': 2.0,
                        'stroke': 1.0, 'velocity_noise': None, 'quantisation_noise': None,
                        'standstill_noise': None, 'standstill_fraction': None,
                        'cutoff': None},
             'velocity_from_position': False,
             'torque_from_current': [{'recording': 'rec', 'k': 1.0, 'text': 'from current'}],
             'in_logged_units': [],
             'gaps': {'bridged': 1, 'longest_bridged_s': 0.01, 'longest_bridged_samples': 2.0,
                      'split': 0, 'bridge_limit_s': None, 'rule': 'r'}},
    'base_fit': {'fc': [1.0]}, 'extended_fit': {'fc': [1.0, 0.1]},
    'extended_effects': ['thermal'],
    'residual_scan': [{'variable': 'time', 'explained': 0.1, 'p_value': 0.5, 'note': '',
                       'untestable': '', 'flagged': False}],
    'untestable': {'gravity': 'too short'}, 'notes': ['n'],
    'timing': {'read_s': 1.0, 'base_fit_s': 1.0, 'candidates_s': 1.0, 'extended_fit_s': 1.0,
               'velocity_sim_s': 1.0, 'residual_scan_s': 1.0, 'report_s': 1.0,
               'total_s': 6.0},
    'identify': {'ready': False, 'reason': 'no plateaus'},
    'diagnosed': {'effects': ['thermal'], 'torque_rmse': 0.1, 'fit': {'fc': [1.0]}},
    'headline': 'Missing effects: thermal.', 'model_file': '/m.yaml',
    'extended_file': '/out/extended.yaml'}


def test_report_json_read_back_is_written_the_same():
    """from_dict then to_dict gives report.json back, its keys in their order."""
    again = DiagnosisResult.from_dict(json.loads(json.dumps(SAMPLE))).to_dict()
    assert json.dumps(again) == json.dumps(SAMPLE)
