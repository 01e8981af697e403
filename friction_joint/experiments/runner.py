# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The paper's evaluation experiments on the simulated test bed (seed Section V B-D).

Each experiment runs the simulated hardware (:class:`~friction_joint.testbed.plant.Plant`
with the **truth** gear file) and the identified **model** gear file the way
the paper runs its test bed and its model:

* :func:`chirp` -- dynamic simulation (Section V-B, Fig. 5).  Two chirp
  torque commands with the same rising frequency and a low and a high
  constant amplitude drive the plant open loop against the lever's gravity.
  The LuGre and GMS models are then simulated open loop with the measured
  applied torque (effort) as input and the measured temperature fed in, and
  their velocity and friction torque are compared with the measurement.
* :func:`compensation` -- friction compensation (Section V-C, Fig. 6-7).
  q_d = a sin(1.5 t), a in {0.4, 2.4} rad, the plant started at 27 and at
  35 degC, controller eq. 17 with gains for 0.04 s rise time and 6 %
  overshoot, friction feed-forward none / LuGre / GMS (same gains for all).
* :func:`estimation` -- external torque estimation (Section V-D, Fig. 8).
  Closed-loop motion with variable velocity over most of the lever's
  gravity range; the disturbance observer (eq. 15) leaves the gravity out,
  so the lever load is the unknown external torque it has to estimate,
  with and without the friction model.

Every experiment function takes ``(model, truth, duration_scale=1.0)`` (two
:class:`~friction_joint.gear.GearParams`) and returns an
:class:`~friction_joint.results.ExperimentResult`: ``summary``
(plain numbers for ``summary.json``), ``series`` (the signals its figures
are drawn from) and ``figures``, drawn by :mod:`~friction_joint.experiments.plots`.
:data:`EXPERIMENTS` maps the command-line names to them; adding an
experiment is adding an entry (and its figures to ``plots.TESTBED_FIGURES``).

The command ``friction_joint experiment NAME --model M.yaml --truth T.yaml
--out DIR [--duration-scale X] [--force]`` runs one and writes its PNG figures
and ``DIR/summary.json``: DIR is the command's output as a whole (built next
to it and renamed into place; an existing non-empty DIR is an error unless
``--force``, which replaces it, see :class:`~friction_joint.output.OutputSet`).
``--duration-scale`` multiplies every duration (settling, evaluation window,
chirp length) and is meant for quick test runs.

``identification`` (Section V-A) is different: it only needs ``--truth`` and
writes a *recording* (``--out BAG``, a rosbag2 MCAP directory or ``.mcap``
file) of the identification excitation of :mod:`friction_joint.experiments.excitation`
for ``friction_joint identify``, under the same rules (``--force`` replaces an
existing recording as a whole).
"""
import math

from ._common import check_scale, Experiment
from .catalogue import EXPERIMENT_HELP
from .chirp import chirp
from .compensation import compensation
from .estimation import estimation
from .gain_sweep import gain_sweep
from ..exceptions import ExperimentError

__all__ = ['check_gains', 'EXPERIMENTS', 'CLOSED_LOOP', 'identification']


# --------------------------------------------------------- identification ---

def identification(model, truth, duration_scale=1.0, progress=None):
    """
    Identification excitation (paper Section V-A): a recording for ``friction_joint identify``.

    Constant-velocity plateaus 0.01..3.5 rad/s in both directions at four
    temperatures across the truth's range, the lever at different angles,
    and slow pre-sliding sinusoids; see :mod:`friction_joint.experiments.excitation`.
    ``model`` is not used; ``progress(message)`` is called once per
    temperature block.

    Returns
    -------
    topics : dict
        Contract topics, the input of :func:`friction_joint.bag.write_recording`.
    summary : dict
        Plan and run facts (block temperatures, planned plateaus, duration).

    """
    from .excitation import simulate_identification
    return simulate_identification(truth, duration_scale=check_scale(duration_scale),
                                   progress=progress)


#: experiments whose closed loop takes a gain design (``gains=``)
CLOSED_LOOP = ('compensation', 'estimation')

#: command-line name -> experiment
EXPERIMENTS = {
    'chirp': Experiment(chirp, EXPERIMENT_HELP['chirp']),
    'compensation': Experiment(compensation, EXPERIMENT_HELP['compensation']),
    'estimation': Experiment(estimation, EXPERIMENT_HELP['estimation']),
    'gain_sweep': Experiment(gain_sweep, EXPERIMENT_HELP['gain_sweep']),
    'identification': Experiment(identification, EXPERIMENT_HELP['identification'],
                                 'recording', False),
}


def check_gains(design, model, truth):
    """
    Check that a gain design gives a PD loop the simulated plant can run.

    The loop is integrated at the truth's ``simulation.rate``: with step ``h`` and joint
    inertia ``J`` it is stable only for ``(kp h**2 + 2 kd h) / J < 4``; gains beyond
    (or not finite) are refused before the run.

    Raises
    ------
    ExperimentError
        One line with the gains and the limit.

    """
    kp, kd = design.gains(model.inertia)
    h = 1.0 / truth.section('simulation')['rate']
    margin = (kp * h * h + 2.0 * kd * h) / truth.inertia
    if not (math.isfinite(kp) and math.isfinite(kd) and math.isfinite(margin)) or margin >= 4.0:
        raise ExperimentError(
            f'--gains {design.name}: kp {kp:.4g} Nm/rad, kd {kd:.4g} Nm s/rad make the loop '
            f'unstable at simulation.rate {1.0 / h:g} Hz on the joint inertia '
            f'{truth.inertia:g} kg m^2 ((kp h^2 + 2 kd h) / J = {margin:.3g}, must be < 4)')
