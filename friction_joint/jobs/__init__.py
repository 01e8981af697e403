# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The commands' work: load the inputs, compute with the subpackages, write one output set.

The subpackages compute (and draw, in memory); a job reads the files a
command names, calls them, and writes the command's outputs all or nothing
(:class:`~friction_joint.output.OutputSet`).  The command line
(:mod:`friction_joint.cli`) parses arguments and calls a job.  Every
``run_*`` returns a ``...Run`` (:mod:`~friction_joint.jobs.runs`): what it
computed, and ``written``, the paths it wrote.

* :mod:`~friction_joint.jobs.diagnose`: ``friction_joint diagnose``
  (:func:`run_diagnose`, returning a :class:`DiagnoseRun`);
* :mod:`~friction_joint.jobs.identify`: ``friction_joint identify``
  (:func:`run_identify`, returning an :class:`IdentifyRun`);
* :mod:`~friction_joint.jobs.experiment`: ``friction_joint experiment``
  (:func:`run_experiment`, returning an :class:`ExperimentRun`);
* :mod:`~friction_joint.jobs.fleet_simulation`: ``friction_joint experiment fleet``
  (:func:`run_fleet_simulation`, returning a :class:`FleetSimulationRun`);
* :mod:`~friction_joint.jobs.classic`: ``friction_joint classic``
  (:func:`run_classic`, :func:`write_experiment`, returning a :class:`ClassicRun`);
* :mod:`~friction_joint.jobs.fleet`: ``friction_joint fleet`` (:func:`run_fleet`,
  returning a :class:`FleetRun`; the recordings' cache);
* :mod:`~friction_joint.jobs.demo`: ``friction_joint demo``, the main job
  (:func:`run_demo`, returning a :class:`DemoRun`).
"""
from .classic import run_classic, write_experiment
from .diagnose import DiagnoseRun, run_diagnose
from .experiment import run_experiment
from .identify import run_identify
from .runs import ClassicRun, DemoRun, ExperimentRun, FleetRun, FleetSimulationRun, IdentifyRun

__all__ = ['DiagnoseRun', 'ClassicRun', 'ExperimentRun', 'IdentifyRun', 'DemoRun', 'FleetRun',
           'FleetSimulationRun', 'run_diagnose', 'run_identify', 'run_experiment', 'run_classic',
           'write_experiment', 'run_fleet', 'run_fleet_simulation', 'run_demo']


def __getattr__(name):
    """Load :func:`run_demo`, :func:`run_fleet` and :func:`run_fleet_simulation` on first use."""
    if name == 'run_demo':                  # every experiment
        from .demo import run_demo
        return run_demo
    if name == 'run_fleet':                 # Dask, the per-recording analysis
        from .fleet import run_fleet
        return run_fleet
    if name == 'run_fleet_simulation':      # the fleet's simulator
        from .fleet_simulation import run_fleet_simulation
        return run_fleet_simulation
    raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
