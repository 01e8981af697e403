# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Realtime pacing of a simulated joint: wait for a lagging controller instead of losing the joint.

A simulator, unlike hardware, can slow its clock.  When the machine cannot hold
the publish rate for every process of the loop, the controller falls behind
and its commands answer ever older states; a real drive would apply them late
(and a watchdog would end it).  :class:`Pacing` lets the simulation run at
most ``lead`` steps past the newest state a valid command has answered and
then wait for the controller, up to ``patience`` wall seconds, after which
it runs on without it (the command watchdog decides) until an answer to a
recent state arrives.  The waits are counted and reported.
"""

__all__ = ['Pacing']


class Pacing:
    """
    Realtime pacing: how far the simulation may run ahead of the controller's answers.

    Parameters
    ----------
    lead : int
        Steps the simulation may run past the newest state a valid command answered
        (0: never wait, as hardware does).
    patience : float
        Wall seconds to wait for the controller before running on without it.

    """

    def __init__(self, lead: int, patience: float) -> None:
        self.lead = lead
        self.patience = patience
        self.newest: int | None = None      # the newest step a valid command answered
        self.count = 0              # states answered by a valid command
        self.active = True          # False after a give-up, until a recent answer
        self.since: float | None = None     # wall time the current wait began
        self.waited = 0.0           # wall seconds spent waiting
        self.pauses = 0
        self.given_up = 0

    def expect(self, k: int) -> None:
        """
        Pace from step ``k`` on before any answer (a controller is known to be there).

        Parameters
        ----------
        k : int
            The step the first answer is awaited for.

        """
        if self.newest is None:
            self.newest = k

    def answered(self, k: int) -> None:
        """
        Take a valid command answering the state of step ``k``.

        Parameters
        ----------
        k : int
            The step of the state the command answers.

        """
        if self.newest is None or k > self.newest:
            self.newest = k
            self.count += 1
            self.active = True

    def hold(self, k_next: int, now: float) -> tuple[bool, float, bool]:
        """
        Return whether the tick that would reach step ``k_next`` waits.

        Parameters
        ----------
        k_next : int
            The step the next tick would reach.
        now : float
            The wall time, s (monotonic).

        Returns
        -------
        held : bool
            Whether the tick waits for the controller.
        waited : float
            The length of a wait that ends now, s (0 otherwise).
        gave_up : bool
            Whether the wait ended because ``patience`` ran out.

        """
        if (not self.lead or self.newest is None or not self.active
                or k_next - self.newest <= self.lead):
            return False, self._end(now), False
        if self.since is None:
            self.since = now
            self.pauses += 1
        if now - self.since <= self.patience:
            return True, 0.0, False
        self.active = False
        self.given_up += 1
        return False, self._end(now), True

    def describe(self, states: int) -> str:
        """
        Return the pacing part of a run's closing line.

        Parameters
        ----------
        states : int
            The states published.

        Returns
        -------
        str
            Answered share, waits and give-ups.

        """
        share = self.count / states if states else 0.0
        return (f'answered by a valid command: {self.count} ({100 * share:.1f} %); waited '
                f'{self.waited:.2f} s for the controller ({self.pauses} pauses, '
                f'{self.given_up} given up)')

    def _end(self, now):
        if self.since is None:
            return 0.0
        waited, self.since = now - self.since, None
        self.waited += waited
        return waited
