"""TimedLoop: the control loop of a deterministic run, a timer on the node's clock instead
of a thread of its own (docs/replay.md).

It keeps `ControlLoop`'s interface (``start``, ``wake``, ``stop``, ``calls``) and its rest
rule: while ``idle()`` holds, ticks are skipped until `wake` is called or ``idle_period``
seconds of the clock have passed since the last step. Each step runs on the timer's tick,
at an exact simulated time, to completion.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

__all__ = ["TimedLoop"]


class _TimerMaker(Protocol):
    def create_timer(self, period: float, callback: Callable[[], Any]) -> Any: ...

    def now(self) -> Any: ...


class TimedLoop:
    def __init__(self, node: _TimerMaker, period: float, step: Callable[[], None],
                 idle: Callable[[], bool] | None = None, idle_period: float = 1.0) -> None:
        if not period > 0:
            raise ValueError(f"control period must be positive, got {period}")
        self.node, self.period, self.step = node, period, step
        self.idle, self.idle_period = idle, idle_period
        self.calls = 0
        self._woken = True
        self._last = -float("inf")
        self._timer: Any = None

    def start(self) -> None:
        self._timer = self.node.create_timer(self.period, self._tick)

    def _tick(self) -> None:
        now = self.node.now().nanoseconds / 1e9
        if (self.idle is not None and self.idle() and not self._woken
                and now - self._last < self.idle_period):
            return
        self._woken = False
        self._last = now
        self.calls += 1
        self.step()

    def wake(self) -> None:
        """Step at the next tick even if idle (a goal started, a behaviour ended)."""
        self._woken = True

    def stop(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
