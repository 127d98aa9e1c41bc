"""Clocks (system, steady, simulated/manual), `Rate`, and the `Time`/`Duration` value types."""

from __future__ import annotations

import asyncio
import heapq
import itertools
import threading
import time as _time
from typing import Protocol

from .msgs.builtin_interfaces import Duration, Time

__all__ = ["Clock", "Duration", "ManualClock", "Rate", "SteadyClock", "SystemClock", "Time"]


class Clock(Protocol):
    """What timers, `Rate` and stamps need from a clock."""

    kind: str

    def now(self) -> Time: ...

    def sleep_until(self, t: Time, timeout: float | None = None) -> bool:
        """Block the calling thread until ``t``; False if ``timeout`` (wall seconds) ran out."""
        ...

    async def async_sleep_until(self, t: Time) -> None: ...


class _RealClock:
    kind = "system"

    def ns(self) -> int:
        """Now, in nanoseconds: a real clock's, whose waits can be the event loop's own
        timers (`Timer` waits so, and keeps its deadlines in nanoseconds)."""
        return _time.time_ns()

    def now(self) -> Time:
        return Time.from_nanoseconds(self.ns())

    def sleep_until(self, t: Time, timeout: float | None = None) -> bool:
        delay = (t.nanoseconds - self.ns()) / 1e9
        if timeout is not None and delay > timeout:
            _time.sleep(max(0.0, timeout))
            return False
        if delay > 0:
            _time.sleep(delay)
        return True

    async def async_sleep_until(self, t: Time) -> None:
        delay = (t.nanoseconds - self.ns()) / 1e9
        await asyncio.sleep(max(0.0, delay))


class SystemClock(_RealClock):
    """Wall-clock time (Unix epoch); what stamps use when sim time is off."""

    kind = "system"


class SteadyClock(_RealClock):
    """Monotonic time; never jumps; for measuring intervals."""

    kind = "steady"

    def ns(self) -> int:
        return _time.monotonic_ns()


class ManualClock:
    """A clock that moves only when told: simulated time (fed by /clock) and tests' fake clock.

    Thread waiters block on a condition; asyncio waiters are woken on their own loop.
    """

    kind = "ros"

    def __init__(self, start: Time | None = None) -> None:
        self._now = start or Time()
        self._cond = threading.Condition()
        self._waiters: list[tuple[int, int, asyncio.AbstractEventLoop, asyncio.Future[None]]] = []
        self._seq = itertools.count()
        self.active = False  # True once a time has been received

    def now(self) -> Time:
        return self._now

    def set(self, t: Time) -> None:
        """Move the clock to ``t`` (ROS sim time may jump back, e.g. when a bag restarts)."""
        with self._cond:
            self._now = t
            self.active = True
            self._cond.notify_all()
            due = []
            while self._waiters and self._waiters[0][0] <= t.nanoseconds:
                due.append(heapq.heappop(self._waiters))
        for _, _, loop, fut in due:
            if fut.done() or loop.is_closed():
                continue  # a cancelled sleeper, or its loop (an executor) is gone
            try:
                loop.call_soon_threadsafe(_resolve, fut)
            except RuntimeError:  # the loop closed just now
                pass

    def advance(self, seconds: float) -> None:
        self.set(self._now + Duration.from_seconds(seconds))

    def sleep_until(self, t: Time, timeout: float | None = None) -> bool:
        deadline = None if timeout is None else _time.monotonic() + timeout
        with self._cond:
            while self._now.nanoseconds < t.nanoseconds:
                left = None if deadline is None else deadline - _time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._cond.wait(left)
        return True

    async def async_sleep_until(self, t: Time) -> None:
        loop = asyncio.get_running_loop()
        fut: asyncio.Future[None] = loop.create_future()
        entry = (t.nanoseconds, next(self._seq), loop, fut)
        with self._cond:
            if self._now.nanoseconds >= t.nanoseconds:
                return
            heapq.heappush(self._waiters, entry)
        try:
            await fut
        finally:
            if not fut.done() or fut.cancelled():
                with self._cond:
                    if entry in self._waiters:
                        self._waiters.remove(entry)
                        heapq.heapify(self._waiters)


def _resolve(fut: asyncio.Future[None]) -> None:
    if not fut.done():
        fut.set_result(None)


class Rate:
    """Sleep so that a loop runs at ``hz``, without drift: deadlines are start + k * period.

    If the loop falls more than one period behind, the schedule restarts from now instead of
    bursting to catch up.
    """

    def __init__(self, hz: float, clock: Clock | None = None) -> None:
        if hz <= 0:
            raise ValueError(f"rate must be positive, got {hz}")
        self.clock: Clock = clock or SteadyClock()
        self.period = Duration.from_seconds(1.0 / hz)
        self._next = self.clock.now() + self.period

    def sleep(self) -> None:
        self.clock.sleep_until(self._next)
        self._tick()

    async def async_sleep(self) -> None:
        await self.clock.async_sleep_until(self._next)
        self._tick()

    def _tick(self) -> None:
        now = self.clock.now()
        self._next = self._next + self.period
        if (now - self._next).nanoseconds > self.period.nanoseconds:
            self._next = now + self.period

    def reset(self) -> None:
        self._next = self.clock.now() + self.period
