# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Warm-up of the simulated test bed: operating temperatures reached by self-heating.

The paper runs its compensation experiments "at three different temperature
values" of the same gear; a gear reaches them by its own friction losses.
:func:`warm_up` runs the closed loop on a fast sinusoid (2.4 rad at
1.5 rad/s, the paper's high-velocity trajectory) from the plant's present
state until the *true* gear temperature reaches the target, finishes the
half period it is in (the joint at a turning point), then brings the joint
to rest at ``q = 0`` on a minimum-jerk move and holds it there.  The plant
is left in that state; the temperature is whatever the thermal model made
of it (it keeps rising slightly during the return).  Nothing is imposed.
"""
import math

from ..control.controller import SineTrajectory
from ..exceptions import ExperimentError

__all__ = ['WARM_UP', 'warm_up']

WARM_UP = {
    'amplitude': 2.4,       # rad
    'omega': 1.5,           # rad/s
    'return_time': 2.0,     # s, minimum-jerk move from the turning point to q = 0
    'hold': 0.5,            # s at rest before the experiment starts
    'max_time': 3600.0,     # s of simulated time before giving up
}


def _min_jerk(q0, q1, duration):
    """Rest-to-rest minimum-jerk move from q0 to q1; returns reference(t) from t = 0."""
    dq = q1 - q0

    def ref(t):
        s = min(max(t / duration, 0.0), 1.0)
        p = 10 * s ** 3 - 15 * s ** 4 + 6 * s ** 5
        v = (30 * s ** 2 - 60 * s ** 3 + 30 * s ** 4) / duration
        a = (60 * s - 180 * s ** 2 + 120 * s ** 3) / duration ** 2
        return q0 + dq * p, dq * v, dq * a
    return ref


def warm_up(plant, controller, target):
    """
    Heat ``plant`` by running ``controller`` until its true temperature reaches ``target``.

    Parameters
    ----------
    plant : Plant
        The test bed, in any state; it is advanced in place.
    controller : Controller
        Eq. 17 controller used for the warm-up motion.
    target : float
        Gear temperature to reach, degC.  A plant already at or above it is
        only brought to rest at q = 0.

    Returns
    -------
    dict
        ``target``, ``reached`` (true temperature at the end, degC),
        ``duration_s`` (simulated warm-up time including the return to rest),
        ``heating_s`` (time on the sinusoid).

    """
    c = WARM_UP
    t_start = plant.t
    s = plant.last
    if s.xi_true < target:
        sine = SineTrajectory(c['amplitude'], omega=c['omega'])
        half = math.pi / c['omega']
        ref = sine(s.t - t_start)
        end = None
        while end is None or s.t < end:
            tau = controller(s.q, s.qd, s.xi, *ref)
            s = plant.step(tau)
            ref = sine(s.t - t_start)
            if end is None and s.xi_true >= target:
                # finish at the next turning point of the sinusoid (zero velocity)
                phase = (s.t - t_start) * c['omega'] - 0.5 * math.pi
                end = t_start + (math.ceil(phase / math.pi) + 0.5) * half
            if s.t - t_start > c['max_time']:
                raise ExperimentError(
                    f'warm-up did not reach {target:g} degC in {c["max_time"]:g} s of '
                    f'simulated time (at {s.xi_true:.2f} degC): the thermal model of the '
                    'truth gear heats too little for this target')
    heating = s.t - t_start
    move = _min_jerk(s.q, 0.0, c['return_time'])
    t0 = s.t
    n = int(round((c['return_time'] + c['hold']) / plant.dt))
    for _ in range(n):
        tau = controller(s.q, s.qd, s.xi, *move(s.t - t0))
        s = plant.step(tau)
    return {'target': float(target), 'reached': float(s.xi_true),
            'duration_s': float(s.t - t_start), 'heating_s': float(heating)}
