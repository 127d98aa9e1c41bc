"""ScanWorker: folds scans in on a thread of its own, so the scan callback never blocks, and
says whether it keeps up (slam_toolbox's sync mode queues every scan; here a bounded queue
that drops the oldest scan only when it is full, counting it)."""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Generic, TypeVar

__all__ = ["ScanWorker"]

T = TypeVar("T")


class ScanWorker(Generic[T]):
    """Runs ``fold(item)`` for each submitted item, in order, on one thread.

    ``capacity`` items may wait; one more drops the oldest waiting (``skipped`` counts them).
    ``lag`` is the wall time the last item waited before its fold began; ``max_lag`` the
    largest. With ``threaded=False`` there is no thread: `submit` folds at once, in the
    caller, and nothing is ever skipped (a deterministic replay, docs/replay.md).
    """

    def __init__(self, fold: Callable[[T], None], capacity: int = 50,
                 on_error: Callable[[BaseException], None] | None = None, *,
                 threaded: bool = True) -> None:
        self._fold = fold
        self._queue: deque[tuple[float, T]] = deque()
        self._capacity = capacity
        self._cond = threading.Condition()
        self._stop = False
        self._busy = False
        self._on_error = on_error
        self.skipped = 0
        self.done = 0
        self.lag = 0.0
        self.max_lag = 0.0
        self._thread: threading.Thread | None = None
        self.threaded = threaded

    def start(self) -> None:
        if self.threaded and self._thread is None:
            self._thread = threading.Thread(target=self._run, name="slam-worker", daemon=True)
            self._thread.start()

    def submit(self, item: T) -> None:
        if not self.threaded:
            self._fold_one(item)
            return
        with self._cond:
            if len(self._queue) >= self._capacity:
                self._queue.popleft()
                self.skipped += 1
            self._queue.append((time.perf_counter(), item))
            self._cond.notify()

    def clear(self) -> None:
        """Drop what waits (not counted as skipped: the caller asked)."""
        with self._cond:
            self._queue.clear()

    def idle(self) -> bool:
        with self._cond:
            return not self._queue and not self._busy

    def wait_idle(self, timeout: float) -> bool:
        end = time.monotonic() + timeout
        with self._cond:
            while self._queue or self._busy:
                left = end - time.monotonic()
                if left <= 0:
                    return False
                self._cond.wait(min(left, 0.05))
            return True

    def close(self, timeout: float = 5.0) -> None:
        with self._cond:
            self._stop = True
            self._queue.clear()
            self._cond.notify_all()
        if self._thread is not None:
            self._thread.join(timeout)
            self._thread = None

    def _run(self) -> None:
        while True:
            with self._cond:
                while not self._queue and not self._stop:
                    self._cond.wait()
                if self._stop:
                    return
                queued, item = self._queue.popleft()
                self._busy = True
            self.lag = time.perf_counter() - queued
            self.max_lag = max(self.max_lag, self.lag)
            try:
                self._fold_one(item)
            finally:
                with self._cond:
                    self._busy = False
                    self._cond.notify_all()

    def _fold_one(self, item: T) -> None:
        try:
            self._fold(item)
        except Exception as exc:  # noqa: BLE001 - a bad scan must not end the worker
            if self._on_error is not None:
                self._on_error(exc)
        finally:
            self.done += 1
