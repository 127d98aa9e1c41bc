"""Pacer: runs fixed simulation steps at ``speed`` x real time, slowing down (never skipping
steps) when the machine cannot keep up, and measures the factor it achieves."""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable

__all__ = ["Pacer"]


class Pacer:
    """Wall-clock schedule for steps of ``dt`` sim seconds at ``speed`` x real time.

    ``speed <= 0`` means as fast as possible. When a step is due more than ``max_lag``
    *sim* seconds ago (``max_lag / speed`` wall seconds), the schedule restarts from now: the
    sim runs slower instead of bursting to catch up, and `factor` reports what it achieved.
    The bound is in sim time so that a burst never outruns the robot's controllers: at 10x a
    0.1 s wall stall caught up would be a second of robot time driven on the last command,
    with no control tick in between (the nodes following ``/clock`` were stalled too).
    """

    def __init__(self, dt: float, speed: float, *, max_lag: float = 0.1,
                 window: float = 1.0, clock: Callable[[], float] = time.monotonic) -> None:
        if dt <= 0:
            raise ValueError(f"step must be > 0, got {dt}")
        self.dt = dt
        self.speed = speed
        self.max_lag = max_lag / speed if speed > 0 else max_lag  # wall seconds
        self.window = window
        self._clock = clock
        self._anchor = clock()
        self._steps = 0
        self._marks: deque[tuple[float, int]] = deque()
        self.total_steps = 0

    @property
    def period(self) -> float:
        """Wall seconds per step (0 when unthrottled)."""
        return self.dt / self.speed if self.speed > 0 else 0.0

    def delay(self) -> float:
        """Wall seconds to wait before the next step is due (0 if due or late)."""
        if self.speed <= 0:
            return 0.0
        now = self._clock()
        due = self._anchor + self._steps * self.period
        if now - due > self.max_lag:
            self._anchor, self._steps = now, 0
            return 0.0
        return max(0.0, due - now)

    def stepped(self) -> None:
        """Record that one step ran."""
        self._steps += 1
        self.total_steps += 1
        now = self._clock()
        self._marks.append((now, self.total_steps))
        while len(self._marks) > 2 and now - self._marks[1][0] >= self.window:
            self._marks.popleft()

    @property
    def factor(self) -> float:
        """Sim seconds per wall second over the last ``window`` (0 until two steps ran)."""
        if len(self._marks) < 2:
            return 0.0
        (t0, n0), (t1, n1) = self._marks[0], self._marks[-1]
        return (n1 - n0) * self.dt / (t1 - t0) if t1 > t0 else 0.0
