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
