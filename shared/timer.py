"""`Timer`: a periodic callback on the executor, following the node's clock (sim time too)."""

from __future__ import annotations

import asyncio
import inspect
import logging
from collections.abc import Callable
from typing import Any

from .clock import Clock, Duration, Time
from .errors import NodeClosedError
from .executor import CallbackGroup, Executor
from .gate import DeliveryGate

__all__ = ["Timer"]


class Timer:
    """Calls ``callback()`` every ``period`` seconds of ``clock`` time, without drift.

    Deadlines are start + k * period; if the callback overruns, missed ticks are skipped
    (not bunched). With a simulated clock, ticks follow /clock, so a simulation running 10x
    faster fires timers 10x as often in wall time.
    """

    def __init__(
        self,
        period: float,
        callback: Callable[[], Any],
        clock: Clock,
        executor: Executor,
        logger: logging.Logger,
        group: CallbackGroup | None = None,
        autostart: bool = True,
        gate: DeliveryGate | None = None,
    ) -> None:
        if not period > 0:
            raise ValueError(f"timer period must be positive, got {period}")
        self.period = Duration.from_seconds(period)
        self.callback = callback
        self.clock = clock
        self._executor = executor
        self._logger = logger
        self._group = group
        self._gate = gate  # ticks before the node's setup() returned are skipped
        self._is_async = inspect.iscoroutinefunction(callback)
        self._future: Any = None
        self._canceled = True
        self.calls = 0
        if autostart:
            self.reset()

    def reset(self) -> None:
        """(Re)start the timer: the next tick is one period from now.

        "Now" is read here, on the caller's thread, not when the executor first runs the
        timer: with a simulated clock, /clock may move in between, and the first tick would
        then land up to a period late."""
        self.cancel()
        self._canceled = False
        self._future = self._executor.submit(self._run(self.clock.now() + self.period))

    def cancel(self) -> None:
        self._canceled = True
        if self._future is not None:
            self._executor.call_soon(self._future.cancel)
            self._future = None

    def is_canceled(self) -> bool:
        """True once `cancel` was called (or before `reset` without autostart), as rclpy."""
        return self._canceled

    async def _run(self, due: Time) -> None:
        while not self._canceled:
            await self.clock.async_sleep_until(due)
            if self._canceled:
                return
            await self._fire()
            now = self.clock.now()
            due = due + self.period
            if now >= due:  # overran or the clock jumped: skip the missed ticks
                behind = (now - due).nanoseconds // self.period.nanoseconds + 1
                due = due + self.period * behind

    async def _fire(self) -> None:
        if self._gate is not None and not self._gate.is_open:
            return
        self.calls += 1
        try:
            if self._is_async:
                await self.callback()
            elif self._group is not None:
                self._group.run(self.callback)
            else:
                self.callback()
        except asyncio.CancelledError:
            raise
        except NodeClosedError:
            if not self._canceled:  # in flight when the node closed: shutdown, not a fault
                self._logger.exception("timer callback raised")
        except Exception:
            self._logger.exception("timer callback raised")
        self._executor.mark_work()
