# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The input gate of a recording: every file of it checked before anything opens one.

A recording is a rosbag2 directory or a single ``.mcap`` (or ``.db3``) file.
Before the reader, rosbags or the recovery code reads a byte of it,
:func:`check_recording_files` checks (:mod:`friction_joint.inputs`) that

* a file recording is a readable regular file (not a FIFO, which blocks
  ``open()`` forever, nor a device such as ``/dev/zero``, which never ends);
* a directory can be listed and entered; its ``metadata.yaml`` is a readable
  regular file within the size limit of its kind, valid YAML with a
  ``rosbag2_bagfile_information`` mapping (errors are one line: the YAML
  parser's multi-line message is folded);
* every storage file the directory holds (``*.mcap``, ``*.db3``) and every file
  ``metadata.yaml`` lists (``relative_file_paths``) is a readable regular file.

Symlinks are followed: what they point to counts.
"""
import os

from .staging import missing_recording_error
from ..exceptions import RecordingError
from ..inputs import check_input, check_input_dir, read_input

__all__ = ['check_recording_files', 'read_metadata', 'STORAGE_SUFFIXES']

#: suffixes of rosbag2 storage files
STORAGE_SUFFIXES = ('.mcap', '.db3')


def _one_line(text):
    return ' '.join(str(text).split())


def read_metadata(path, *, label=None):
    """
    Read and parse a rosbag2 ``metadata.yaml`` through the input gate.

    Parameters
    ----------
    path : str or os.PathLike
        The ``metadata.yaml`` file.
    label : str, optional
        How to name the recording in errors (default: the file).

    Returns
    -------
    dict
        The ``rosbag2_bagfile_information`` mapping.

    Raises
    ------
    RecordingError
        One line naming the file: not a readable regular file, too large, not UTF-8,
        not YAML, or without a ``rosbag2_bagfile_information`` mapping.

    """
    import yaml

    path = os.fspath(path)
    inside = label and os.path.dirname(os.path.abspath(path)) == os.path.abspath(label)
    prefix = f'{label}: ' if label and not inside and label != path else ''
    data = read_input(path, kind='metadata', what='a rosbag2 metadata.yaml',
                      error=RecordingError)
    try:
        text = data.decode('utf-8')
    except UnicodeDecodeError as exc:
        raise RecordingError(f'{prefix}{path}: not UTF-8 text (byte {exc.start}); a corrupt '
                             'metadata.yaml') from None
    try:
        info = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, 'problem_mark', None)
        where = f' at line {mark.line + 1}, column {mark.column + 1}' if mark else ''
        problem = getattr(exc, 'problem', None) or _one_line(exc)
        raise RecordingError(f'{prefix}{path}: not valid YAML{where} ({_one_line(problem)}); '
                             'a corrupt metadata.yaml') from None
    except RecursionError:
        raise RecordingError(f'{prefix}{path}: nested too deeply; a corrupt metadata.yaml'
                             ) from None
    info = info.get('rosbag2_bagfile_information') if isinstance(info, dict) else None
    if not isinstance(info, dict):
        raise RecordingError(f'{prefix}{path}: no rosbag2_bagfile_information mapping; not '
                             'a rosbag2 metadata.yaml')
    return info


def _listed_files(info, meta_path, label):
    files = info.get('relative_file_paths')
    if files is None:
        return []
    if not isinstance(files, list) or not all(isinstance(f, str) and f for f in files):
        raise RecordingError(f'{label}: {meta_path}: relative_file_paths must be a list of '
                             'file names; a corrupt metadata.yaml')
    return files


def check_recording_files(path):
    """
    Check every file of a recording before it is opened (module docstring).

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 directory or a single ``.mcap``/``.db3`` file.

    Returns
    -------
    dict or None
        The parsed ``rosbag2_bagfile_information`` of a directory with a
        ``metadata.yaml``, else None.

    Raises
    ------
    RecordingError
        One line naming the file at fault.

    """
    path = os.fspath(path)
    if not os.path.lexists(path):
        raise missing_recording_error(path)         # a killed recorder's: how to recover
    if not os.path.isdir(path):
        check_input(path, kind='recording', what='a recording', error=RecordingError)
        return None
    check_input_dir(path, what='a recording', error=RecordingError)
    try:
        names = sorted(os.listdir(path))
    except OSError as exc:
        raise RecordingError(f'{path}: cannot read a recording directory: '
                             f'{exc.strerror or exc}') from None
    for name in names:
        if name.endswith(STORAGE_SUFFIXES) and not name.startswith('.'):
            check_input(os.path.join(path, name), kind='recording',
                        what='a recording storage', error=RecordingError)
    meta_path = os.path.join(path, 'metadata.yaml')
    if not os.path.lexists(meta_path):
        return None
    info = read_metadata(meta_path, label=path)
    for name in _listed_files(info, meta_path, path):
        f = os.path.join(path, name)
        if os.path.lexists(f):                    # a missing one: rosbags names it
            try:
                check_input(f, kind='recording', what='a recording', error=RecordingError)
            except RecordingError as exc:
                raise RecordingError(f'{meta_path} lists {name}: {exc}') from None
    return info
