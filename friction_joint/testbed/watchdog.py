# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The drive's command watchdog: the torque a drive applies when commands stop or are refused.

A real servo drive does not hold the last accepted torque forever: after a
command timeout it takes a safe reaction.  :class:`CommandWatchdog` counts
simulated steps since the newest valid command (refused commands do not
count) and, after ``timeout`` s, applies the reaction:

* ``zero``: torque off (safe torque off; the joint coasts and hangs);
* ``brake``: a damping torque ``-J q̇ / BRAKE_TIME`` within the plausible
  torque, which stops the joint (a holding brake's effect).

Before the first valid command the drive applies the (zero) initial command.
"""

__all__ = ['CommandWatchdog', 'REACTIONS', 'BRAKE_TIME']

#: the safe reactions
REACTIONS = ('zero', 'brake')
#: s: time constant of the ``brake`` reaction
BRAKE_TIME = 0.05


class CommandWatchdog:
    """
    Decide the drive torque from the newest valid command and its age.

    Parameters
    ----------
    rate : float
        Simulation steps per second.
    timeout : float
        Seconds of simulated time after which a command is stale (0: never).
    reaction : {'zero', 'brake'}
        What the drive applies once the command is stale.
    inertia, torque_limit : float
        Joint inertia (kg m^2) and the largest torque the brake may apply (Nm).

    Attributes
    ----------
    trips : int
        Times the watchdog has tripped.
    tripped : bool
        Whether the drive applies the reaction now.

    """

    def __init__(self, rate: float, timeout: float, reaction: str, *, inertia: float,
                 torque_limit: float) -> None:
        if reaction not in REACTIONS:
            raise ValueError(f'reaction must be one of {", ".join(REACTIONS)}, got {reaction!r}')
        self.timeout_steps = timeout * rate
        self.reaction = reaction
        self.damping = inertia / BRAKE_TIME
        self.torque_limit = torque_limit
        self.valid_k: int | None = None
        self.trips = 0
        self.tripped = False

    def command(self, k: int) -> None:
        """
        Note a valid command taken at step ``k``.

        Parameters
        ----------
        k : int
            The simulation step.

        """
        self.valid_k = k

    def torque(self, k: int, tau_cmd: float, qd: float) -> tuple[float, str | None]:
        """
        Return ``(torque, event)`` at step ``k``; event is 'tripped', 'resumed' or None.

        Parameters
        ----------
        k : int
            The simulation step.
        tau_cmd : float
            The newest valid command (Nm).
        qd : float
            The measured velocity (rad/s).

        Returns
        -------
        torque : float
            The drive torque (Nm).
        event : str or None
            ``'tripped'``, ``'resumed'`` or None.

        """
        if self.valid_k is None:
            return tau_cmd, None
        stale = k - self.valid_k > self.timeout_steps > 0
        event = None
        if stale != self.tripped:
            event = 'tripped' if stale else 'resumed'
            self.trips += stale
            self.tripped = stale
        if not stale:
            return tau_cmd, event
        if self.reaction == 'zero':
            return 0.0, event
        brake = -self.damping * qd
        return max(-self.torque_limit, min(self.torque_limit, brake)), event
