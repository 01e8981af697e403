# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Physical ranges of the nodes' own parameters and the check that enforces them.

The bounds come from physics and from what ROS can carry, not from one gear:
a time a stamp can hold, a wait a person would make, a rate a device can
sample at.  :func:`between` is the validator the nodes' tables use.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
import math
from typing import Any, TYPE_CHECKING

from ...exceptions import GearConfigError
from ...gear.schema import RATE_BOUNDS

if TYPE_CHECKING:
    from ...gear import GearParams

__all__ = ['between', 'DURATION_BOUNDS', 'WAIT_BOUNDS', 'RESEND_BOUNDS', 'RISE_TIME_BOUNDS',
           'INERTIA_FACTOR', 'MIN_RISE_STEPS', 'PUBLISH_RATE_BOUNDS', 'SAMPLE_RATE_BOUNDS',
           'BETA_BOUNDS', 'sample_rate', 'warm_up_temperature', 'check_controller_params',
           'check_estimator_params', 'topics_problem']

#: simulated or recorded time, s: ROS stamps carry int32 seconds (2.1e9 s, of which the
#: wall clock has used 1.8e9): 1e8 s (3 years) leaves room for any start time
DURATION_BOUNDS = (0.0, 1.0e8, 'ROS stamps hold int32 seconds')
#: a wait before a start or a reaction, s
WAIT_BOUNDS = (0.0, 3600.0, 'an hour; longer is a wait nobody makes')
#: period of a repeated message while a peer is missing, s
RESEND_BOUNDS = (1.0e-3, 60.0, 'from a millisecond (a timer the machine can keep) to a minute')
#: rise time of the controller, s, besides its lower bound of MIN_RISE_STEPS samples
RISE_TIME_BOUNDS = (1.0e-6, 1000.0, 'a rise time beyond 1000 s controls nothing; below '
                    '1 us no sample rate resolves it')
#: the simulator's publish rate, Hz (also at most simulation.rate)
PUBLISH_RATE_BOUNDS = (RATE_BOUNDS[0], RATE_BOUNDS[1], 'the rates a device samples at')
#: a node's sample rate, Hz (0: simulation.rate)
SAMPLE_RATE_BOUNDS = PUBLISH_RATE_BOUNDS
#: observer cut-off, rad/s, besides its upper bound of the Nyquist frequency pi rate
BETA_BOUNDS = (1.0e-3, math.pi * RATE_BOUNDS[1], 'a time constant of at most 1000 s, a '
               'cut-off below the Nyquist frequency')
#: the inertia a controller is designed for lies within this factor of the gear's
INERTIA_FACTOR = 1000.0
#: samples per rise time: a discrete PD designed faster than this is unstable
MIN_RISE_STEPS = 10


def topics_problem(text: str, allow: Sequence[str] = ()) -> str | None:
    """
    Return why the comma-separated topic names ``text`` are not valid ROS topic names, or None.

    An empty ``text`` is valid (no topics); the words in ``allow`` (e.g.
    ``'loop'``) are accepted as they are.
    """
    from rclpy.expand_topic_name import expand_topic_name
    from rclpy.validate_full_topic_name import validate_full_topic_name
    if not text.strip() or text.strip() in allow:
        return None
    for name in (t.strip() for t in text.split(',')):
        try:
            validate_full_topic_name(expand_topic_name(name, 'node', '/'))
        except Exception as exc:             # noqa: BLE001 - rclpy's ValueError or its own
            why = ' '.join(str(exc).split()).split(', at /')[0]
            return f'{name!r} is not a topic name: {why}'
    return None


def between(value: float, bounds: tuple[float, float, str], unit: str,
            zero: str | None = None) -> str | None:
    """
    Return why ``value`` is outside ``bounds = (lo, hi, why)``, or None.

    ``zero`` names what 0 means when 0 is allowed besides the range (e.g.
    ``'no watchdog'``).
    """
    lo, hi, why = bounds
    if zero is not None and value == 0:
        return None
    if isinstance(value, float) and not math.isfinite(value):
        return f'must be finite, got {value}'
    if lo <= value <= hi:
        return None
    unit = f' {unit}' if unit else ''
    alt = f' or 0 ({zero})' if zero is not None else ''
    return f'must be in [{lo:g}, {hi:g}]{unit}{alt} ({why}), got {value:g}'


def _fail(name, why):
    raise GearConfigError(f'parameter {name}: {why}')


def sample_rate(p: Mapping[str, Any], gear: GearParams) -> float:
    """Return the sample rate of a controller or estimator: ``rate``, or ``simulation.rate``."""
    if p['rate']:
        return p['rate']
    sim = gear.section('simulation')
    assert sim is not None  # a section with defaults
    return sim['rate']


def warm_up_temperature(gear: GearParams) -> float:
    """
    Return the temperature a node's first, compiling call uses: the middle of the gear's range.

    Any temperature of the gear's ``friction.temperature_range`` works (the call only
    compiles the kernels before data flows); the middle is one for every gear.
    """
    lo, hi = gear.friction.temperature_range
    return 0.5 * (lo + hi)


def check_controller_params(p: Mapping[str, Any], gear: GearParams) -> None:
    """
    Check a controller's gains against its gear and sample rate, before anything is built.

    The rise time must span at least :data:`MIN_RISE_STEPS` samples (a PD loop
    designed faster than its sampling is unstable), and ``design_inertia``
    lie within :data:`INERTIA_FACTOR` of the gear's inertia (0: the gear's).

    Raises
    ------
    GearConfigError

    """
    rate = sample_rate(p, gear)
    if p['rise_time'] < MIN_RISE_STEPS / rate:
        _fail('rise_time', f"{p['rise_time']:g} s is shorter than {MIN_RISE_STEPS} samples at "
              f'{rate:g} Hz ({MIN_RISE_STEPS / rate:g} s): the loop would be unstable')
    j = gear.inertia
    design = p['design_inertia']
    if design and not j / INERTIA_FACTOR <= design <= j * INERTIA_FACTOR:
        _fail('design_inertia', f'{design:g} kg m^2 is not within a factor {INERTIA_FACTOR:g} of '
              f"the gear's inertia {j:g} kg m^2 (0: the gear's)")


def check_estimator_params(p: Mapping[str, Any], gear: GearParams) -> None:
    """
    Check an observer's cut-off against its sample rate (below Nyquist, ``pi rate``).

    Raises
    ------
    GearConfigError

    """
    rate = sample_rate(p, gear)
    if p['beta'] > math.pi * rate:
        _fail('beta', f"{p['beta']:g} rad/s is above the Nyquist frequency of {rate:g} Hz "
              f'({math.pi * rate:.6g} rad/s)')
