"""Exceptions raised by friction_joint, named for the problem they report."""

__all__ = ['FrictionJointError', 'GearConfigError', 'GearConfigWarning',
           'RecordingError', 'ExcitationError', 'PreslidingDataError', 'ExperimentError',
           'SimulationError']


class FrictionJointError(Exception):
    """Base class of every error this package raises on bad input."""


class GearConfigError(FrictionJointError, ValueError):
    """A gear parameter file (or dict) is malformed: the message names the key."""


class GearConfigWarning(UserWarning):
    """A gear parameter set loads but is physically questionable."""


class RecordingError(FrictionJointError):
    """A recording is missing, truncated, corrupt or lacks a required topic."""


class ExcitationError(FrictionJointError):
    """Data do not contain the experiment needed to determine a quantity."""


class SimulationError(FrictionJointError):
    """The simulated state left the finite range (an unstable loop or a runaway command)."""


class PreslidingDataError(FrictionJointError, ValueError):
    """Arrays given to the pre-sliding fit are malformed (lengths, NaN, time axis)."""


class ExperimentError(FrictionJointError, ValueError):
    """An experiment cannot run with the options given (e.g. a run too short to evaluate)."""
