# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""Exceptions raised by friction_joint, named for the problem they report."""

__all__ = ['FrictionJointError', 'ArgumentError', 'InputFileError', 'OutputError',
           'GearConfigError', 'GearConfigWarning', 'RecordingError', 'MissingTopicError',
           'ExcitationError',
           'PreslidingDataError', 'ExperimentError', 'SimulationError', 'InputRejected',
           'NodeError', 'CacheWarning', 'StallWarning', 'UnitsWarning']


class FrictionJointError(Exception):
    """
    Base class of every error this package raises on bad input.

    Never raised itself: each problem has its class below, so a caller can
    catch exactly it (``except ArgumentError``) or any of them
    (``except FrictionJointError``); the command line turns every one into
    one line and exit status 2.
    """


class ArgumentError(FrictionJointError, ValueError):
    """An argument or option has a value the call cannot take; the message names it."""


class InputFileError(FrictionJointError):
    """An input file is refused before it is read: missing, special, unreadable or too large."""


class OutputError(FrictionJointError):
    """An output cannot be written: it exists (without ``force``), overlaps an input, ..."""


class GearConfigError(FrictionJointError, ValueError):
    """A gear parameter file (or dict) is malformed: the message names the key."""


class GearConfigWarning(UserWarning):
    """A gear parameter set loads but is physically questionable."""


class CacheWarning(UserWarning):
    """A cached result is unusable (unreadable, malformed, out of bounds) and is recomputed."""


class StallWarning(UserWarning):
    """No task of a cluster finished for the stall guard's time: the pending ones failed."""


class UnitsWarning(UserWarning):
    """A result's scale suggests a column of the log was imported in other units."""


class RecordingError(FrictionJointError):
    """A recording is missing, truncated, corrupt or lacks a required topic."""


class MissingTopicError(RecordingError):
    """
    A recording lacks a topic, or has no message on it.

    Parameters
    ----------
    message : str
        The one-line error (names the file and the topic).
    topic : str
        The topic missing, e.g. ``/joint_temperature`` (a default, for unpickling only:
        the attributes come back with the state).
    path : str
        The recording.

    Attributes
    ----------
    topic : str
        The topic missing.
    path : str
        The recording.

    """

    def __init__(self, message: str, *, topic: str = '', path: str = '') -> None:
        super().__init__(message)
        self.topic = topic
        self.path = path


class ExcitationError(FrictionJointError):
    """Data do not contain the experiment needed to determine a quantity."""


class SimulationError(FrictionJointError):
    """The simulated state left the finite range (an unstable loop or a runaway command)."""


class PreslidingDataError(FrictionJointError, ValueError):
    """Arrays given to the pre-sliding fit are malformed (lengths, NaN, time axis)."""


class ExperimentError(FrictionJointError, ValueError):
    """An experiment cannot run with the options given (e.g. a run too short to evaluate)."""


class InputRejected(FrictionJointError, ValueError):
    """
    A sample given to a controller or observer is refused (not finite, overflowing).

    The object's state is left as it was before the call, so a node can log
    and count the sample and go on with the next.
    """


class NodeError(FrictionJointError, RuntimeError):
    """A node process started by ``bringup`` ended early or failed."""
