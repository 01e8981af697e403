# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The assertion every refusal test makes: one stderr line, the exit status, no traceback."""

__all__ = ['one_line']


def one_line(capsys, rc, *words, status=2):
    """
    Assert exit ``status`` and one stderr line holding ``words``; return the line.

    Parameters
    ----------
    capsys : pytest.CaptureFixture
        The test's captured output (read and reset here).
    rc : int
        The command's exit status.
    *words : str
        What the line must contain.
    status : int
        The expected exit status (2: bad input).

    Returns
    -------
    str
        The line.

    """
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert rc == status, err
    assert len(lines) == 1 and 'Traceback' not in err, err
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]
