# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Every input of every command, replaced by a special file: refused at once, in one line.

The inputs (a log and a mapping of ``import``; a recording directory, its
``metadata.yaml`` and its ``.mcap``, a bare ``.mcap`` and the gear file of
``identify`` and ``diagnose``; the path of ``recover``; the gear files of
``experiment``) are each replaced by a FIFO (whose ``open`` blocks forever),
a symlink to ``/dev/zero`` or ``/dev/urandom`` (endless), a socket, a dangling
symlink, a symlink loop, an empty file or a directory.  Every combination must
end with exit 2 and one line naming the special file, with nothing written,
under a time guard: a blocking read or an endless one fails the case instead
of hanging the suite.
"""
import os
import shutil
import socket

from friction_joint.bag import write_recording
import numpy as np
import pytest

from test_fuzz_inputs import guarded

BASE = 'config/csd25_base.yaml'
KINDS = ('fifo', 'zero', 'urandom', 'socket', 'dangling', 'loop', 'empty', 'directory')


def _recording(path):
    t = np.arange(2000) * 1e-3
    q = 0.5 * np.sin(2 * np.pi * t)
    return write_recording(path, {
        '/joint_states': {'t': t, 'q': q, 'qd': np.gradient(q, t), 'effort': np.sign(q)},
        '/joint_temperature': {'t': t[::100], 'xi': np.full(20, 30.0)}})


def _log(path):
    t = np.arange(100) * 1e-3
    np.savetxt(path, np.column_stack([t, np.sin(t), np.cos(t)]), delimiter=',',
               header='time,position,torque', comments='')


def _special(path, kind, holder):
    """Make ``path`` a special file of ``kind``."""
    if os.path.isdir(path) and not os.path.islink(path):
        shutil.rmtree(path)
    elif os.path.lexists(path):
        os.remove(path)
    if kind == 'fifo':
        os.mkfifo(path)
    elif kind == 'zero':
        os.symlink('/dev/zero', path)
    elif kind == 'urandom':
        os.symlink('/dev/urandom', path)
    elif kind == 'socket':
        s = socket.socket(socket.AF_UNIX)
        s.bind(path)
        holder.append(s)
    elif kind == 'dangling':
        os.symlink(path + '.missing', path)
    elif kind == 'loop':
        os.symlink(os.path.basename(path), path)
    elif kind == 'empty':
        open(path, 'wb').close()
    else:
        os.mkdir(path)


def _argv(where, d):
    """Return (argv, path to make special, outputs) of one input position."""
    rec, out = os.path.join(d, 'rec'), os.path.join(d, 'out')
    mcap = os.path.join(rec, 'rec_0.mcap')
    gear = os.path.join(d, 'gear.yaml')
    ident = ['identify', rec, '--model', gear, '--out', out + '.yaml', '--quiet',
             '--presliding', 'skip']
    diag = ['diagnose', rec, '--model', gear, '--out', out, '--quiet']
    log, mapping = os.path.join(d, 'log.csv'), os.path.join(d, 'map.yaml')
    imp = ['import', log, '--out', out, '--mapping', mapping, '--quiet']
    table = {
        'import_log': (imp, log), 'import_mapping': (imp, mapping),
        'identify_recording': (ident, rec), 'identify_metadata': (ident, os.path.join(
            rec, 'metadata.yaml')), 'identify_mcap': (ident, mcap),
        'identify_model': (ident, gear), 'diagnose_recording': (diag, rec),
        'diagnose_mcap': (diag, mcap), 'diagnose_model': (diag, gear),
        'recover_path': (['recover', mcap, out], mcap),
        'experiment_model': (['experiment', 'chirp', '--model', gear, '--truth', BASE,
                              '--out', out], gear),
        'experiment_truth': (['experiment', 'chirp', '--model', BASE, '--truth', gear,
                              '--out', out], gear),
    }
    argv, special = table[where]
    return argv, special, [out, out + '.yaml', out + '_report']


WHERE = ('import_log', 'import_mapping', 'identify_recording', 'identify_metadata',
         'identify_mcap', 'identify_model', 'diagnose_recording', 'diagnose_mcap',
         'diagnose_model', 'recover_path', 'experiment_model', 'experiment_truth')
# a directory where a directory is expected is not a special case
CASES = [(w, k) for w in WHERE for k in KINDS
         if not (k == 'directory' and w in ('identify_recording', 'diagnose_recording'))]


@pytest.mark.parametrize('where,kind', CASES)
def test_special_file_refused(where, kind, tmp_path, capsys):
    d = str(tmp_path)
    _recording(os.path.join(d, 'rec'))
    shutil.copy(BASE, os.path.join(d, 'gear.yaml'))
    _log(os.path.join(d, 'log.csv'))
    with open(os.path.join(d, 'map.yaml'), 'w', encoding='utf-8') as fh:
        fh.write('time: time\nposition: position\ntorque: torque\n')
    argv, special, outputs = _argv(where, d)
    holder = []
    _special(special, kind, holder)
    try:
        rc = guarded(argv)
    finally:
        for s in holder:
            s.close()
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert rc == 2, f'exit {rc}: {err}'
    assert len(lines) == 1 and ': error: ' in lines[0], err
    assert os.path.basename(special) in lines[0], f'the special file is not named: {err}'
    for out in outputs:
        assert not os.path.lexists(out), f'{out} written'
    assert not [p for p in os.listdir(d) if p.endswith('.tmp')], 'temporary left'
