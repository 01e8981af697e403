# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Usage errors are one line with exit 2, as every other error; help texts print as written."""
from friction_joint.cli import main
import pytest


@pytest.mark.parametrize('argv', [['identify'], ['bogus'], ['import', 'x.csv'],
                                  ['replay', 'bag', '--rate'], ['classic', 'nope', '--out', 'd'],
                                  ['diagnose', 'r', '--model', 'm', '--out', 'o', '--bogus']])
def test_usage_error_is_one_line(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2
    assert len(err) == 1 and ': error: ' in err[0] and '--help' in err[0], err


def test_help_text_with_a_percent_sign_prints(capsys):
    with pytest.raises(SystemExit) as exc:
        main(['experiment', '--help'])
    out = capsys.readouterr().out
    assert exc.value.code == 0
    assert '29-35 %' in ' '.join(out.split()) and 'option_strings' not in out


@pytest.mark.parametrize('argv, value', [
    (['fleet', '--manifest', 'm.csv', '--model', 'g.yaml', '--out', 'o', '--workers'], '\u0662'),
    (['fleet', '--manifest', 'm.csv', '--model', 'g.yaml', '--out', 'o', '--workers'], '1_0'),
    (['experiment', 'fleet', '--out', 'o', '--joints'], '\uff13'),
    (['experiment', 'chirp', '--out', 'o', '--duration-scale'], '1_0'),
    (['experiment', 'chirp', '--out', 'o', '--duration-scale'], '\u0660.\u0665'),
    (['import', 'x.csv', '--out', 'o', '--radius'], '\u0661e-3'),
])
def test_numbers_in_other_digits_are_usage_errors(argv, value, capsys, tmp_path, monkeypatch):
    """int() and float() read '\u0662' as 2 and '1_0' as 10: options take ASCII digits only."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main([*argv, value])
    err = capsys.readouterr().err.strip().splitlines()
    assert exc.value.code == 2 and len(err) == 1, err
    assert 'invalid' in err[0] and repr(value) in err[0], err
    assert list(tmp_path.iterdir()) == []
