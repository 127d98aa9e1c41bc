"""`ReplayClock`: the simulated clock of a deterministic run, which says when it is next due."""

from __future__ import annotations

import heapq

from ..clock import ManualClock, Time

__all__ = ["ReplayClock"]


class ReplayClock(ManualClock):
    """A `ManualClock` moved only by the run that owns it (`DeterministicRun`).

    `next_due` is the earliest time an asyncio sleeper (a timer) waits for, so the run can
    stop the clock at each timer's exact deadline instead of jumping past it. Nothing moves
    this clock but the run, on the run's own thread, so `sleep_until` never blocks: a
    thread that waited on it would wait for ever.
    """

    def next_due(self) -> int | None:
        """The nanoseconds of the earliest pending deadline, or None."""
        with self._cond:
            while self._waiters and self._waiters[0][3].done():  # cancelled sleepers
                heapq.heappop(self._waiters)
            return self._waiters[0][0] if self._waiters else None

    def sleep_until(self, t: Time, timeout: float | None = None) -> bool:
        """True if ``t`` has come, else False at once (the run's thread never blocks)."""
        return self._now.nanoseconds >= t.nanoseconds
