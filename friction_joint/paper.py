# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
The seed paper's own numbers, in one table: what it reports and the set-up it reports it for.

Every figure and report text that sets our results beside the paper's reads
:data:`PAPER` (key -> :class:`PaperNumber`), and so do the controller's design
defaults (:mod:`friction_joint.control`: the rise time and overshoot the PD
gains are designed for); no module types these numbers in again.  The table
sits at the top of the package, below both :mod:`friction_joint.control` and
:mod:`friction_joint.experiments`, so that both can read it.

``where`` says where in the paper the number is stated, quoted where the
wording matters (e.g. "less than", "approximately").  The rows of kind
``'result'`` are the reference numbers our results are compared with; those
of kind ``'set-up'`` describe the experiment the paper ran and that ours
repeats.
"""
import dataclasses
import types

__all__ = ['PaperNumber', 'PAPER']


@dataclasses.dataclass(frozen=True)
class PaperNumber:
    """
    One number of the seed paper.

    Attributes
    ----------
    figure : str
        The figure (or section) the number belongs to, e.g. ``'Fig. 7'``.
    quantity : str
        What the number is.
    value : float or tuple of float
        The number; a range or a set as a tuple.
    unit : str
        Its unit (``'%'``, ``'Nm'``, ``'rad/s'``, ...).
    where : str
        Where the paper states it.
    kind : str
        ``'result'`` (a reference for our results) or ``'set-up'``.

    """

    figure: str
    quantity: str
    value: float | tuple[float, ...]
    unit: str
    where: str
    kind: str = 'result'


#: key -> the paper's number (read-only)
PAPER = types.MappingProxyType({
    'uncompensated_band': PaperNumber(
        'Fig. 7', 'maximum tracking error without friction compensation, a = 0.4 rad, '
        'over the temperatures', (29.0, 35.0), '% of a',
        'Section V-C: "an position error of 29 % to 35 % ... in low velocity case, '
        'depending on the temperature"'),
    'compensated_lugre': PaperNumber(
        'Fig. 7', 'maximum tracking error with LuGre friction compensation', 6.0, '% of a',
        'Section VI (conclusion): "dropped from 35 % ... to 6 % and 4 % with the LuGre and '
        'GMS model"'),
    'compensated_gms': PaperNumber(
        'Fig. 7', 'maximum tracking error with GMS friction compensation', 4.0, '% of a',
        'Section VI (conclusion), as compensated_lugre'),
    'estimation_max': PaperNumber(
        'Fig. 8', 'external torque estimation error, upper bound', 1.0, 'Nm',
        'Section V-D: "The estimated external toque error is less than 1 Nm"'),
    'estimation_pct': PaperNumber(
        'Fig. 8', 'external torque estimation error', 14.0, '%',
        'Section VI (conclusion): "approximately 14% error" (relative to what is not said)'),
    'peak_velocity_low': PaperNumber(
        'Fig. 6', 'peak velocity of the low-velocity case', 0.6, 'rad/s',
        'Fig. 6 caption: "low velocity (peak 0.6 rad/s)"', 'set-up'),
    'peak_velocity_high': PaperNumber(
        'Fig. 6', 'peak velocity of the high-velocity case', 3.5, 'rad/s',
        'Fig. 6 caption: "high velocity case (peak 3.5 rad/s)"', 'set-up'),
    'rise_time': PaperNumber(
        'Section V-C', 'rise time of the step response the PD gains are designed for', 0.04,
        's', 'Section V-C: "rise time 0.04 s"', 'set-up'),
    'overshoot': PaperNumber(
        'Section V-C', 'maximum overshoot of the step response the PD gains are designed for',
        6.0, '%', 'Section V-C: "a maximum overshoot of 6 %"', 'set-up'),
})
