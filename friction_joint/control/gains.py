# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Gain design of the eq. 17 controller, separate from the plant it runs on.

The paper designs k_p and k_d "to respect the transient time requirements of
rise time 0.04 s and a maximum overshoot of 6 %" without saying for which
inertia.  :class:`GainDesign` makes that inertia explicit (the *design
inertia*), or takes k_p and k_d directly.  The loop the gains really make on
a plant of inertia J is reported by :func:`loop_metrics`:

    omega_n = sqrt(k_p / J),   zeta = k_d / (2 sqrt(k_p J)),
    overshoot = exp(-pi zeta / sqrt(1 - zeta^2))   (zeta < 1)

(the error dynamics J e'' + k_d e' + k_p e = 0 of eq. 17 with exact inertia
and gravity feed-forward and no friction).

Presets (:data:`GAIN_PRESETS`):

``paper``
    gains designed for 0.016 kg m^2, about 1/14 of the CSD-25 test bed's
    joint inertia.  This is an inference, not a number of the paper: it is
    the design inertia at which the uncompensated tracking error of
    ``q_d = 0.4 sin(1.5 t)`` falls in the paper's 29-35 % band (Fig. 7), and
    the order of the drive's own inertia (Section V-B builds the model from
    "the torque constant and the motor inertia").  On the full joint inertia
    these gains make a soft, lightly damped loop (omega_n about 14 rad/s,
    zeta about 0.18), which is what lets friction produce errors of a third
    of the amplitude.
``full-inertia``
    gains designed for the model gear's joint inertia: the stiff loop the
    specification would give with the whole joint's J (errors of a few %
    without compensation).
"""
from __future__ import annotations

import dataclasses
import math

from .controller import PAPER_OVERSHOOT, PAPER_RISE_TIME, pd_gains
from ..exceptions import ArgumentError

__all__ = ['GainDesign', 'GAIN_PRESETS', 'gain_design', 'loop_metrics']


@dataclasses.dataclass(frozen=True)
class GainDesign:
    """
    How the PD gains of eq. 17 are chosen.

    Parameters
    ----------
    name : str
        Name in reports (a preset name, or a description).
    design_inertia : float or None
        Inertia the gains are designed for, kg m^2; None: the model gear's
        joint inertia.
    rise_time, overshoot : float
        10-90 % rise time (s) and maximum overshoot (fraction) of the design
        (default: the paper's, :data:`~friction_joint.control.controller.PAPER_RISE_TIME`
        and :data:`~friction_joint.control.controller.PAPER_OVERSHOOT`).
    kp, kd : float or None
        Gains given directly (both or neither); then the design fields are
        not used.

    """

    name: str = 'full-inertia'
    design_inertia: float | None = None
    rise_time: float = PAPER_RISE_TIME
    overshoot: float = PAPER_OVERSHOOT
    kp: float | None = None
    kd: float | None = None

    def __post_init__(self) -> None:
        if (self.kp is None) != (self.kd is None):
            raise ArgumentError('give both kp and kd, or neither')
        if self.kp is not None and self.kd is not None and not (
                self.kp > 0 and self.kd >= 0 and math.isfinite(self.kp + self.kd)):
            raise ArgumentError(f'gains must be finite, kp > 0 and kd >= 0, got kp={self.kp}'
                                f', kd={self.kd}')
        if self.design_inertia is not None and not (math.isfinite(self.design_inertia)
                                                    and self.design_inertia > 0):
            raise ArgumentError(f'design inertia must be > 0 kg m^2, '
                                f'got {self.design_inertia}')

    def gains(self, model_inertia: float) -> tuple[float, float]:
        """
        Return ``(kp, kd)`` for a model gear of joint inertia ``model_inertia``.

        Direct gains are returned as given; otherwise :func:`pd_gains` of the
        design inertia (the model's joint inertia when it is None).

        Parameters
        ----------
        model_inertia : float
            The model gear's joint inertia (kg m^2).

        Returns
        -------
        kp, kd : float
            Nm/rad and Nm s/rad.

        """
        if self.kp is not None and self.kd is not None:         # both or neither
            return float(self.kp), float(self.kd)
        inertia = model_inertia if self.design_inertia is None else self.design_inertia
        return pd_gains(inertia, rise_time=self.rise_time, overshoot=self.overshoot)

    def to_dict(self, model_inertia: float) -> dict[str, object]:
        """
        Return a plain description with the gains it gives (for summary files).

        Parameters
        ----------
        model_inertia : float
            The model gear's joint inertia (kg m^2).

        Returns
        -------
        dict
            ``preset``, ``design_inertia``, ``rise_time``, ``overshoot``, ``kp``, ``kd``.

        """
        kp, kd = self.gains(model_inertia)
        return {'preset': self.name, 'design_inertia': (None if self.kp is not None else
                                                        self.design_inertia or model_inertia),
                'rise_time': None if self.kp is not None else self.rise_time,
                'overshoot': None if self.kp is not None else self.overshoot,
                'kp': kp, 'kd': kd}


#: named gain designs; ``paper`` is the default of the test-bed experiments
GAIN_PRESETS = {
    'paper': GainDesign('paper', design_inertia=0.016),
    'full-inertia': GainDesign('full-inertia'),
}


def gain_design(spec: GainDesign | str) -> GainDesign:
    """
    Return the :class:`GainDesign` named or described by ``spec``.

    Parameters
    ----------
    spec : GainDesign or str
        A :class:`GainDesign`, a preset name (``paper``, ``full-inertia``),
        ``J=<kg m^2>`` (design inertia) or ``kp=<Nm/rad>,kd=<Nm s/rad>``.

    Returns
    -------
    GainDesign

    """
    if isinstance(spec, GainDesign):
        return spec
    text = str(spec).strip()
    if text in GAIN_PRESETS:
        return GAIN_PRESETS[text]
    fields = {}
    for part in text.split(','):
        key, sep, value = part.partition('=')
        key = key.strip().lower()
        if not sep or key not in ('j', 'kp', 'kd') or key in fields:
            raise ArgumentError(
                f'gains {spec!r}: expected a preset ({", ".join(GAIN_PRESETS)}), J=<kg m^2> '
                'or kp=<Nm/rad>,kd=<Nm s/rad>')
        try:
            fields[key] = float(value)
        except ValueError:
            raise ArgumentError(f'gains {spec!r}: {key} is not a number') from None
    if set(fields) == {'j'}:
        return GainDesign(f'J={fields["j"]:g}', design_inertia=fields['j'])
    if set(fields) == {'kp', 'kd'}:
        return GainDesign(f'kp={fields["kp"]:g},kd={fields["kd"]:g}', kp=fields['kp'],
                          kd=fields['kd'])
    raise ArgumentError(f'gains {spec!r}: give J=<kg m^2> alone, or kp and kd together')


def loop_metrics(kp: float, kd: float, inertia: float) -> dict[str, float]:
    """
    Return natural frequency, damping ratio and overshoot of the PD loop on ``inertia``.

    Parameters
    ----------
    kp, kd : float
        Gains, Nm/rad and Nm s/rad.
    inertia : float
        The plant's joint inertia, kg m^2.

    Returns
    -------
    dict
        ``omega_n`` (rad/s), ``zeta``, ``overshoot`` (fraction of a step;
        0 for zeta >= 1), ``rise_time`` (s, 10-90 %, of the linear loop),
        ``inertia`` (the plant inertia they hold for).

    """
    wn = math.sqrt(kp / inertia)
    zeta = kd / (2.0 * math.sqrt(kp * inertia))
    over = math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta ** 2)) if zeta < 1.0 else 0.0
    return {'omega_n': wn, 'zeta': zeta, 'overshoot': over,
            'rise_time': _rise_time(wn, zeta), 'inertia': float(inertia)}


def _rise_time(wn: float, zeta: float) -> float:
    """10-90 % rise time of wn^2 / (s^2 + 2 zeta wn s + wn^2), by bisection on its step."""
    def y(t: float) -> float:
        x = wn * t
        if zeta < 1.0:
            wd = math.sqrt(1.0 - zeta ** 2)
            return 1.0 - math.exp(-zeta * x) * (math.cos(wd * x) + zeta / wd * math.sin(wd * x))
        if zeta == 1.0:
            return 1.0 - math.exp(-x) * (1.0 + x)
        r = math.sqrt(zeta ** 2 - 1.0)
        p1, p2 = zeta - r, zeta + r
        return 1.0 - (p2 * math.exp(-p1 * x) - p1 * math.exp(-p2 * x)) / (p2 - p1)

    def cross(level: float) -> float:
        lo, hi = 0.0, 1.0 / wn
        while y(hi) < level:
            lo, hi = hi, 2.0 * hi
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if y(mid) < level else (lo, mid)
        return 0.5 * (lo + hi)

    return cross(0.9) - cross(0.1)
