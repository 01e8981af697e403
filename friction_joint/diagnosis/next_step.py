# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers


"""
Whether the next step a diagnosis suggests can run: ``identify`` with the extended file.

The report suggests identifying the extended model's coefficients on the same
recordings (``friction_joint identify RECORDINGS --model extended.yaml``).  That
command needs constant-velocity plateaus in both directions and a temperature
signal; :func:`identify_refusal` runs the checks it runs before its fit (the
plateaus found with the extended gear, the structure lowered to what they carry,
:func:`~friction_joint.identification.check_excitation` as ``identify`` calls it)
and returns its one-line reason when it would refuse, so the report suggests
recording an identification run instead of a command that fails.
"""
from __future__ import annotations

from collections.abc import Sequence
import os
from typing import TYPE_CHECKING

from ..bag import read_recording
from ..exceptions import ExcitationError, RecordingError
from ..identification import check_excitation, find_plateaus, Plateaus, StaticStructure
from ..identification.static_structure import carry_structure

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['identify_refusal']


def identify_refusal(paths: Sequence[str | os.PathLike[str]], gear: GearParams,
                     joint_name: str | None = None) -> str | None:
    """
    Return why ``identify`` would refuse ``paths`` with ``gear`` as its structure, or None.

    Parameters
    ----------
    paths : sequence of str
        The recordings.
    gear : GearParams
        The extended gear (the structure ``identify`` would be given).
    joint_name : str, optional
        The joint read (default the gear's).

    Returns
    -------
    str or None
        The reason ``identify`` would give (None: it would run).

    """
    try:
        parts = []
        for path in paths:
            rec = read_recording(path, joint_name=joint_name or gear.joint_name)
            if rec.temperature is None or len(rec.temperature) == 0:
                return (f'{path} has no /joint_temperature: the identification needs the '
                        'housing temperature during the plateaus')
            parts.append(find_plateaus(rec, gear))
        plateaus = Plateaus.concatenate(parts)
        fixed = ('delta_v',) if tuple(gear.friction.delta_v) == (1.0,) else ()
        s = StaticStructure.from_gear(gear, fixed=fixed)
        if len(plateaus) == 0:
            check_excitation(plateaus, s)               # names what to record
        s, _ = carry_structure(plateaus, s, prior=gear.friction)
        check_excitation(plateaus, s, stribeck=False, temperature=False, load=False)
    except (ExcitationError, RecordingError) as exc:
        return str(exc)
    return None
