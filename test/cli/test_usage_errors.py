# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

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
