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

"""
Writing results: figures rendered in memory, files replaced atomically.

Every command that writes results renders them completely first, writes them
to temporary files next to their destination, and only then renames them
into place (:func:`os.replace`), in the order given (put the JSON summary
last: its presence means the files before it belong to it).  An error leaves
no partial result behind.
"""
import dataclasses
import io
import json
import math
import os
import secrets

import numpy as np

from .exceptions import FrictionJointError

__all__ = ['json_clean', 'json_bytes', 'render_png', 'write_files', 'ExperimentResult',
           'write_results']


@dataclasses.dataclass
class ExperimentResult:
    """
    Numbers and figures of one experiment run.

    Attributes
    ----------
    summary : dict
        Plain numbers (written as JSON).
    figures : dict
        File name -> ``(draw(fig), (width, height))``: the figures drawn from
        the run, rendered by :func:`write_results` (or :func:`render_png`).

    """

    summary: dict
    figures: dict = dataclasses.field(default_factory=dict)

    def to_dict(self):
        """Return the summary as plain JSON types."""
        return json_clean(self.summary)


def json_clean(obj):
    """Plain JSON types; non-finite floats become null."""
    if isinstance(obj, dict):
        return {str(k): json_clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [json_clean(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, (np.integer, np.bool_)):
        return obj.item()
    return obj


def json_bytes(obj):
    """``obj`` as indented JSON (UTF-8 bytes)."""
    return (json.dumps(json_clean(obj), indent=2, allow_nan=False) + '\n').encode('utf-8')


def render_png(draw, size, dpi=100):
    """Render ``draw(fig)`` on a new Agg figure of ``size`` inches; returns PNG bytes."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fig = Figure(figsize=size)
    FigureCanvasAgg(fig)
    draw(fig)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format='png', dpi=dpi)
    return buf.getvalue()


def write_files(out_dir, targets, error=FrictionJointError):
    """
    Write ``[(file name, bytes), ...]`` into ``out_dir`` atomically, in order.

    ``out_dir`` is created if missing.  Files get the usual permissions (the
    umask applies).  Raises ``error`` naming the directory if it cannot be
    written; no partial file is left.

    Returns
    -------
    list of str
        The paths written.

    """
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as exc:
        raise error(f'cannot create output directory {out_dir}: {exc.strerror}') from None
    temps = []
    try:
        for name, data in targets:
            tmp = os.path.join(out_dir, f'.{name}-{os.getpid()}-{secrets.token_hex(4)}.tmp')
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            temps.append(tmp)
            with os.fdopen(fd, 'wb') as fh:
                fh.write(data)
        paths = []
        for (name, _), tmp in zip(targets, temps):
            path = os.path.join(out_dir, name)
            os.replace(tmp, path)
            paths.append(path)
    except OSError as exc:
        raise error(f'cannot write to {out_dir}: {exc.strerror}') from None
    finally:
        for tmp in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return paths


def write_results(result, out_dir, json_name='summary.json', error=FrictionJointError):
    """
    Write the figures and ``summary.json`` of ``result`` into ``out_dir`` atomically.

    ``result`` is an :class:`ExperimentResult` (or anything with ``summary`` and
    ``figures``); ``json_name`` names the JSON file (default ``summary.json``);
    ``error`` is the exception class raised when writing fails.

    Everything is rendered in memory, written to temporary files in
    ``out_dir`` (created if missing), then renamed into place with
    :func:`os.replace`, ``summary.json`` last: a ``summary.json`` present
    means the figures next to it belong to it.

    Returns
    -------
    list of str
        The paths written.

    """
    targets = [(name, render_png(draw, size)) for name, (draw, size) in result.figures.items()]
    targets.append((json_name, json_bytes(result.summary)))
    return write_files(out_dir, targets, error)
