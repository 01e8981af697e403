# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
The commands' work: load the inputs, compute with the subpackages, write one output set.

The subpackages compute (and draw, in memory); a job reads the files a
command names, calls them, and writes the command's outputs all or nothing
(:class:`~friction_joint.output.OutputSet`).  The command line
(:mod:`friction_joint.cli`) parses arguments and calls a job.

* :mod:`~friction_joint.jobs.diagnose`: ``friction_joint diagnose``
  (:func:`run_diagnose`, returning a :class:`DiagnoseRun`);
* :mod:`~friction_joint.jobs.identify`: ``friction_joint identify``
  (:func:`run_identify`);
* :mod:`~friction_joint.jobs.experiment`: ``friction_joint experiment``
  (:func:`run_experiment`);
* :mod:`~friction_joint.jobs.classic`: ``friction_joint classic``
  (:func:`run_classic`, :func:`write_experiment`);
* :mod:`~friction_joint.jobs.fleet`: ``friction_joint fleet`` (:func:`run_fleet`,
  returning a :class:`~friction_joint.fleet.FleetRun`; the recordings' cache);
* :mod:`~friction_joint.jobs.demo`: ``friction_joint demo``, the main job
  (:func:`run_demo`).
"""
from .classic import run_classic, write_experiment
from .diagnose import DiagnoseRun, run_diagnose
from .experiment import run_experiment
from .identify import run_identify

__all__ = ['DiagnoseRun', 'run_diagnose', 'run_identify', 'run_experiment', 'run_classic',
           'write_experiment', 'run_fleet', 'run_demo']


def __getattr__(name):
    """Load :func:`run_demo` (every experiment) and :func:`run_fleet` (the fleet) on first use."""
    if name == 'run_demo':
        from .demo import run_demo
        return run_demo
    if name == 'run_fleet':
        from .fleet import run_fleet
        return run_fleet
    raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
