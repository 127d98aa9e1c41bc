"""The executor: one asyncio loop per context, in its own thread, for timers and async callbacks.

Plain (sync) subscription and service callbacks run on the Zenoh thread that delivered the
sample: every hop between Zenoh and the user costs latency. Timers, `async def` callbacks and
anything awaiting run here.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import logging
import threading
from collections.abc import Callable, Coroutine
from typing import Any, TypeVar

__all__ = ["CallbackGroup", "Executor", "MutuallyExclusiveCallbackGroup", "ReentrantCallbackGroup"]

T = TypeVar("T")
_log = logging.getLogger("zenros.executor")


class CallbackGroup:
    """Base: decides whether callbacks may run concurrently."""

    def run(self, fn: Callable[..., T], *args: Any) -> T:
        return fn(*args)


class ReentrantCallbackGroup(CallbackGroup):
    """Callbacks may run at the same time on different threads (the default)."""


class MutuallyExclusiveCallbackGroup(CallbackGroup):
    """At most one callback of the group runs at a time (one lock), across all threads."""

    def __init__(self) -> None:
        self._lock = threading.RLock()

    def run(self, fn: Callable[..., T], *args: Any) -> T:
        with self._lock:
            return fn(*args)


class Executor:
    """An asyncio event loop running in a daemon thread, started on creation."""

    def __init__(self, name: str = "zenros-executor") -> None:
        self.loop = asyncio.new_event_loop()
        self._done = threading.Event()
        self._work = threading.Condition()
        self._work_count = 0
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        asyncio.set_event_loop(self.loop)
        try:
            self.loop.run_forever()
        finally:
            self._done.set()

    @property
    def in_loop_thread(self) -> bool:
        return threading.current_thread() is self._thread

    def call_soon(self, fn: Callable[..., Any], *args: Any) -> None:
        """Run ``fn(*args)`` on the loop thread, from any thread."""
        if not self.loop.is_closed():
            self.loop.call_soon_threadsafe(fn, *args)

    def submit(self, coro: Coroutine[Any, Any, T]) -> concurrent.futures.Future[T]:
        """Schedule a coroutine on the loop from any thread."""
        return asyncio.run_coroutine_threadsafe(coro, self.loop)

    def mark_work(self) -> None:
        """Count one executed callback (what `wait_for_work` waits for)."""
        with self._work:
            self._work_count += 1
            self._work.notify_all()

    def wait_for_work(self, timeout: float | None) -> bool:
        """Block until the next callback runs on the executor; False on timeout."""
        with self._work:
            start = self._work_count
            return self._work.wait_for(lambda: self._work_count != start, timeout)

    def stop(self, timeout: float = 2.0) -> None:
        """Cancel pending tasks, stop the loop and join its thread."""
        if self.loop.is_closed():
            return

        async def _cancel_all() -> None:
            tasks = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
            for t in tasks:
                t.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

        if self._thread.is_alive() and not self.in_loop_thread:
            try:
                asyncio.run_coroutine_threadsafe(_cancel_all(), self.loop).result(timeout)
            except (concurrent.futures.TimeoutError, RuntimeError):
                _log.warning("executor tasks did not finish within %.1f s", timeout)
            self.loop.call_soon_threadsafe(self.loop.stop)
            self._thread.join(timeout)
        if not self._thread.is_alive():
            self.loop.close()
