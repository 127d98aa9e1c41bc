"""`Waiters`: threads blocked on a condition and asyncio futures waiting for transforms.

The buffer calls `wake` (holding its lock) after every accepted insert while anyone waits.
Blocked threads are notified and re-check their own condition; each asyncio waiter is
checked there and then, and resolved on its own loop with ``call_soon_threadsafe``, so
inserts may come from any thread. Nothing polls.
"""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Callable
from typing import NamedTuple

__all__ = ["Waiters"]

Check = Callable[[str, str, int], bool]


class _Waiter(NamedTuple):
    target: str
    source: str
    t: int
    loop: asyncio.AbstractEventLoop
    future: asyncio.Future[bool]


def _resolve(fut: asyncio.Future[bool]) -> None:
    if not fut.done():
        fut.set_result(True)


class Waiters:
    """The waiting side of a buffer; shares the buffer's lock.

    Args:
        lock: the buffer's lock (held by the caller of `block` and `wake`).
        on_count: told how many are waiting after each change, so the buffer can skip
            `wake` cheaply when nobody waits.
    """

    def __init__(self, lock: threading.Lock, on_count: Callable[[int], None]) -> None:
        self._cond = threading.Condition(lock)
        self._lock = lock
        self._on_count = on_count
        self.blocked = 0
        self.pending: list[_Waiter] = []

    def _count(self) -> None:
        self._on_count(self.blocked + len(self.pending))

    def block(self, ready: Callable[[], bool], timeout: float) -> bool:
        """Wait until ``ready()`` (called with the lock held) or ``timeout`` seconds pass."""
        deadline = time.monotonic() + timeout
        with self._cond:
            if ready():
                return True
            self.blocked += 1
            self._count()
            try:
                while True:
                    remaining = deadline - time.monotonic()
                    if remaining <= 0.0:
                        return False
                    self._cond.wait(remaining)
                    if ready():
                        return True
            finally:
                self.blocked -= 1
                self._count()

    def add(self, target: str, source: str, t: int, fut: asyncio.Future[bool]) -> None:
        """Register a future (lock held) to be resolved once ``can(target, source, t)``."""
        self.pending.append(_Waiter(target, source, t, fut.get_loop(), fut))
        self._count()
        fut.add_done_callback(self._forget)

    def wake(self, can: Check) -> None:
        """After an insert (lock held): notify blocked threads, resolve ready futures."""
        if self.blocked:
            self._cond.notify_all()
        if not self.pending:
            return
        keep = []
        for w in self.pending:
            if w.future.done():
                continue
            if not can(w.target, w.source, w.t):
                keep.append(w)
                continue
            try:
                w.loop.call_soon_threadsafe(_resolve, w.future)
            except RuntimeError:  # its loop is closed: nobody is waiting any more
                pass
        self.pending = keep
        self._count()

    def _forget(self, fut: asyncio.Future[bool]) -> None:
        """Done callback (on the future's loop): drop a cancelled or resolved waiter."""
        with self._lock:
            self.pending = [w for w in self.pending if w.future is not fut]
            self._count()
