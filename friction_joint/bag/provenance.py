# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Where an imported recording's numbers came from: the import's column mapping, and SI back to it.

``friction_joint import`` writes the mapping (each quantity's column, unit and
conversion, the radius of a linear device) into the recording's
``metadata.yaml`` (custom data ``friction_joint.import``).  A result in SI
(N m, rad/s, degC) can then be quoted in the units the user logged:
:class:`ImportedUnits` converts back, e.g. a friction level of 2.26 N m of a
tribometer logged in uN with radius 1 m is 2.26e+06 uN.
"""
from __future__ import annotations

import json
import math
import os

from .reader import recording_custom_data
from .units import SI, UNITS

__all__ = ['import_mapping', 'ImportedUnits']

#: quantities that are torques (a linear device: forces times the radius)
_TORQUES = ('torque', 'friction', 'load')


def import_mapping(path: str | os.PathLike) -> dict | None:
    """
    Return the import mapping of the recording at ``path`` (None: not imported, or unreadable).

    Parameters
    ----------
    path : str or os.PathLike
        A rosbag2 recording directory.

    """
    text = recording_custom_data(path).get('friction_joint.import')
    if not text:
        return None
    try:
        mapping = json.loads(text)
    except ValueError:
        return None
    return mapping if isinstance(mapping, dict) else None


class ImportedUnits:
    """
    Quote SI numbers in the units of an import mapping.

    Parameters
    ----------
    mapping : dict
        An import mapping (:func:`import_mapping`).

    """

    def __init__(self, mapping: dict) -> None:
        columns = mapping.get('columns')
        if not isinstance(columns, dict):
            columns = {}
        self.units = {q: c.get('unit') for q, c in columns.items()
                      if isinstance(c, dict) and c.get('unit') in UNITS.get(q, {})}
        radius = mapping.get('radius_m')
        self.radius = (float(radius) if isinstance(radius, (int, float))
                       and math.isfinite(radius) and radius > 0 else None)

    def _scale(self, quantity):
        """Return ``(unit, SI per unit)`` of ``quantity`` as logged, or None."""
        unit = self.units.get(quantity)
        if unit is None and quantity == 'velocity' and 'position' in self.units:
            unit = self.units['position']            # derived from the position: its unit / s
            factor, linear = UNITS['position'][unit]
            return unit + '/s', (factor / self.radius if linear else factor)
        if unit is None and quantity == 'torque':
            for other in _TORQUES[1:]:               # friction logged directly, or the load
                if other in self.units:
                    return self._scale(other)
        if unit is None or quantity == 'temperature':
            return None if unit is None else (unit, None)
        factor, linear = UNITS[quantity][unit]
        if linear and self.radius is None:
            return None
        if linear:
            factor = factor / self.radius if quantity in ('position', 'velocity') else (
                factor * self.radius)
        return unit, factor

    def quote(self, quantity: str, value: float) -> str | None:
        """
        Return ``value`` (SI) in the logged unit of ``quantity``, e.g. ``'2.26e+06 uN'``.

        Parameters
        ----------
        quantity : str
            time, position, velocity, torque, friction, load or temperature.
        value : float
            The value in SI (:data:`~friction_joint.bag.units.SI`).

        Returns
        -------
        str or None
            None when the quantity was not logged, or was logged in SI.

        """
        scale = self._scale(quantity)
        if scale is None or scale[0] == SI.get(quantity) or not math.isfinite(value):
            return None
        unit, factor = scale
        if quantity == 'temperature':
            logged = {'K': value + 273.15, 'degF': value * 9.0 / 5.0 + 32.0}.get(unit, value)
        else:
            logged = value / factor
        return f'{logged:.4g} {unit}'
