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

    A plain callback on a real clock (system or steady) waits on the event loop's own timer,
    one handle a tick; an ``async def`` callback or a simulated clock waits in a coroutine.
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
        # a real clock's nanoseconds, when the loop's timer can do the waiting
        self._ns: Callable[[], int] | None = (
            None if self._is_async else getattr(clock, "ns", None))
        self._future: Any = None
        self._run_id: object | None = None  # the loop's ticks go on while it is theirs
        self._handle: asyncio.TimerHandle | None = None
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
        if self._ns is None:
            self._future = self._executor.submit(self._run(self.clock.now() + self.period))
        else:
            run = self._run_id = object()
            self._executor.call_soon(self._arm, run, self._ns() + self.period.nanoseconds)

    def cancel(self) -> None:
        self._canceled = True
        self._run_id = None  # a tick already due finds it is not its run's and ends it
        if self._future is not None:
            self._executor.call_soon(self._future.cancel)
            self._future = None
        handle, self._handle = self._handle, None
        if handle is not None:
            self._executor.call_soon(handle.cancel)

    def is_canceled(self) -> bool:
        """True once `cancel` was called (or before `reset` without autostart), as rclpy."""
        return self._canceled

    # ------------------------------------------------------------------ on the loop's timer

    def _arm(self, run: object, due_ns: int) -> None:
        assert self._ns is not None
        if self._run_id is run:
            loop = self._executor.loop
            self._handle = loop.call_at(loop.time() + (due_ns - self._ns()) / 1e9,
                                        self._tick, run, due_ns)

    def _tick(self, run: object, due_ns: int) -> None:
        assert self._ns is not None
        if self._run_id is not run:
            return
        self._call()
        period, now = self.period.nanoseconds, self._ns()
        due_ns += period
        if now >= due_ns:  # overran or the clock jumped: skip the missed ticks
            due_ns += period * ((now - due_ns) // period + 1)
        self._arm(run, due_ns)

    # ------------------------------------------------------------------ in a coroutine

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
        if not self._is_async:
            self._call()
            return
        if self._gate is not None and not self._gate.is_open:
            return
        self.calls += 1
        try:
            await self.callback()
        except asyncio.CancelledError:
            raise
        except Exception as exc:  # noqa: BLE001 a callback never stops its timer
            self._failed(exc)
        self._executor.mark_work()

    def _call(self) -> None:
        """One tick of a plain callback."""
        if self._gate is not None and not self._gate.is_open:
            return
        self.calls += 1
        try:
            if self._group is not None:
                self._group.run(self.callback)
            else:
                self.callback()
        except Exception as exc:  # noqa: BLE001 a callback never stops its timer
            self._failed(exc)
        self._executor.mark_work()

    def _failed(self, exc: Exception) -> None:
        """A tick raised ``exc`` (called in its ``except``): logged with its traceback, unless
        the node closed under a canceled timer while it ran (shutdown, not a fault)."""
        if not (isinstance(exc, NodeClosedError) and self._canceled):
            self._logger.exception("timer callback raised")
