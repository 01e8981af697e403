# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
friction_joint: a simulated Harmonic Drive joint with thermal- and load-dependent friction.

The subpackages, one concept each (the tree is the architecture):

* :mod:`~friction_joint.models`: static curve (seed eq. 1, 5-7), LuGre (eq. 10),
  GMS (eq. 11-13) and the joint they act in;
* :mod:`~friction_joint.testbed`: the simulated hardware (plant, sensors, thermal model);
* :mod:`~friction_joint.control`: the eq. 17 controller and the eq. 4/15 observer;
* :mod:`~friction_joint.identification`: the paper's three identification steps;
* :mod:`~friction_joint.diagnosis`: what a model gets wrong on measured data;
* :mod:`~friction_joint.fleet`: fleet friction monitoring, wear told apart from
  temperature and load (per-recording tasks on Dask);
* :mod:`~friction_joint.experiments`: the paper's experiments, the classic LuGre
  experiments, excitations and hidden-effect recordings;
* :mod:`~friction_joint.bag`: recordings (rosbag2 / MCAP) without ROS;
* :mod:`~friction_joint.ros`: the only place that imports rclpy (nodes, record,
  replay, bring-up);
* :mod:`~friction_joint.jobs`: the commands' work: load the inputs, compute with
  the subpackages above, write one output set;
* :mod:`~friction_joint.cli`: the only place that parses arguments;

and the modules shared by all of them: :mod:`~friction_joint.gear` (gear
parameter files), :mod:`~friction_joint.effects` (the friction effects a model may
lack, one registry), :mod:`~friction_joint.exceptions`, :mod:`~friction_joint.output`
(atomic result files), :mod:`~friction_joint.report_html` (a Markdown report as
one self-contained HTML file).
"""
import importlib

# first: importing _entry guards Ctrl-C while the package loads in a program of its own
from ._entry import GUARDED as _GUARDED  # noqa: F401
from ._version import __version__
from .exceptions import (ArgumentError, ExcitationError, ExperimentError, FrictionJointError,
                         GearConfigError, GearConfigWarning, InputFileError, InputRejected,
                         MissingTopicError, NodeError, OutputError, PreslidingDataError,
                         RecordingError, SimulationError)

__all__ = ['__version__', 'FrictionJointError', 'ArgumentError', 'InputFileError',
           'OutputError', 'GearConfigError', 'GearConfigWarning', 'RecordingError',
           'MissingTopicError', 'ExcitationError', 'PreslidingDataError', 'ExperimentError',
           'SimulationError', 'InputRejected', 'NodeError', 'FrictionParams', 'GearParams',
           'gear_from_dict', 'load_gear', 'save_gear', 'StaticFriction', 'LuGre', 'GMS', 'Joint']

# the gear and model names load on first use (PEP 562): ``import friction_joint.cli`` stays
# light, so the command line handles Ctrl-C from its first instants (numpy and numba load
# inside main())
_LAZY = {'FrictionParams': 'gear', 'GearParams': 'gear', 'gear_from_dict': 'gear',
         'load_gear': 'gear', 'save_gear': 'gear', 'StaticFriction': 'models',
         'LuGre': 'models', 'GMS': 'models', 'Joint': 'models'}


def __getattr__(name):
    """Return a gear or model name of :data:`__all__`, importing its subpackage once."""
    if name in _LAZY:
        value = getattr(importlib.import_module(f'.{_LAZY[name]}', __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f'module {__name__!r} has no attribute {name!r}')


def __dir__():
    """List the module's names, the lazy ones included."""
    return sorted(set(globals()) | set(__all__))
