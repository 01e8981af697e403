# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Fleet friction monitoring: which joints wear, since when, how fast (docs/fleet.md).

* :mod:`~friction_joint.fleet.manifest`: the manifest (recording, joint, time);
* :mod:`~friction_joint.fleet.recording`: the per-recording task (static curve
  around the model gear file, friction at the reference point);
* :mod:`~friction_joint.fleet.trend`: the per-joint wear test (hinge vs no
  wear, bootstrap-calibrated);
* :mod:`~friction_joint.fleet.assess`: reference point, trends, verdict;
* :mod:`~friction_joint.fleet.cluster`: the tasks on Dask distributed (the only
  module that imports Dask, lazily);
* :mod:`~friction_joint.fleet.plots`, :mod:`~friction_joint.fleet.report`: the
  trend plots and the output files' content.

The ``fleet`` command's load, compute, write (manifest, cache, Dask tasks,
DIR) is :func:`friction_joint.jobs.fleet.run_fleet`; its result, a
:class:`~friction_joint.jobs.runs.FleetRun`
(:meth:`~friction_joint.jobs.runs.FleetRun.plot`: the trend plots in memory).
"""
from .assess import assess_fleet, FleetAssessment, reference_point
from .cluster import default_workers, local_cluster, map_recordings
from .manifest import ManifestEntry, read_manifest
from .recording import analyse_recording, recording_task, RecordingResult, reference_friction
from .trend import extra_variance, trend_test, TrendResult

__all__ = ['read_manifest', 'ManifestEntry', 'analyse_recording', 'recording_task',
           'RecordingResult', 'reference_friction', 'assess_fleet', 'FleetAssessment',
           'reference_point', 'trend_test', 'TrendResult', 'extra_variance', 'map_recordings',
           'default_workers', 'local_cluster']
