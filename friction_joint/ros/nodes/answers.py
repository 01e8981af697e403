# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""The closing summary of a node that answers states: how many, how fast, how many skipped."""
import time

__all__ = ['Answers']


class Answers:
    """
    Mixin: count the states a node answers and say so when it ends (``run_summary``).

    The node calls :meth:`count_answer` for every new answer; a ``stale``
    attribute (states skipped to answer the newest) is reported when set.
    """

    answers = 0                         # states answered (a new answer each)
    _answer_span = None                 # wall times of the first and the last answer

    def count_answer(self) -> None:
        """Count a state answered now (the closing summary's rate and count)."""
        now = time.monotonic()
        first = now if self._answer_span is None else self._answer_span[0]
        self._answer_span = (first, now)
        self.answers += 1

    def run_summary(self) -> str:
        """Return the closing line: states answered, over how long, skipped as stale."""
        first, last = self._answer_span or (0.0, 0.0)
        span = last - first
        rate = (self.answers - 1) / span if span > 0 else 0.0
        stale = getattr(self, 'stale', 0)
        return (f'answered {self.answers} states in {span:.2f} s of wall time ({rate:.0f} Hz)'
                + (f'; skipped {stale} stale states (answering the newest)' if stale else ''))
