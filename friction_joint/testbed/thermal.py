# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Lumped thermal model of the gear: the housing temperature as a signal.

    C dxi/dt = P - (xi - xi_amb) / R,      P = |tau_r qd|   (friction losses)

C is the heat capacity of gear and housing (J/K), R the thermal resistance to
ambient (K/W); the time constant is R C.  For a constant power over a step
the solution is exact:  xi+ = xi_inf + (xi - xi_inf) exp(-h / (R C)),
xi_inf = xi_amb + P R.

Default values (``thermal`` section of a gear file) are plausible for a
CSD-25 unit in its housing: about 1 kg of steel and aluminium,
C = 450 J/K, R = 1.2 K/W (time constant 9 min; 10 W of losses warm it by 12 K).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..gear import GearParams

__all__ = ['ThermalModel']


class ThermalModel:
    """
    First-order thermal model.

    Parameters
    ----------
    capacity : float
        Heat capacity C, J/K.
    resistance : float
        Thermal resistance R to ambient, K/W.
    ambient : float
        Ambient temperature, degC.
    initial : float, optional
        Initial temperature, degC (default ambient).

    """

    def __init__(self, capacity: float, resistance: float, ambient: float, *,
                 initial: float | None = None) -> None:
        if capacity <= 0 or resistance <= 0:
            raise ValueError('thermal capacity and resistance must be > 0')
        self.capacity = float(capacity)
        self.resistance = float(resistance)
        self.ambient = float(ambient)
        self.xi = float(ambient if initial is None else initial)

    @classmethod
    def from_gear(cls, gear: GearParams, *, initial: float | None = None) -> ThermalModel:
        """
        Return the model of a gear's ``thermal`` section.

        Parameters
        ----------
        gear : GearParams
            The gear.
        initial : float, optional
            Initial temperature, degC (default the section's ``initial``).

        Returns
        -------
        ThermalModel

        """
        th = gear.section('thermal')
        assert th is not None  # a section with defaults
        return cls(th['capacity'], th['resistance'], th['ambient'],
                   initial=th['initial'] if initial is None else initial)

    @property
    def time_constant(self):
        return self.resistance * self.capacity

    def step(self, power: float, dt: float) -> float:
        """
        Advance by dt with loss power ``power`` held.

        Parameters
        ----------
        power : float
            Loss power (W), held over the step.
        dt : float
            Step (s).

        Returns
        -------
        float
            The temperature (degC) at the end of the step.

        """
        xi_inf = self.ambient + power * self.resistance
        self.xi = xi_inf + (self.xi - xi_inf) * math.exp(-dt / self.time_constant)
        return self.xi
