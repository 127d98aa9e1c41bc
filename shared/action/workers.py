"""`WorkerPool`: daemon threads that run blocking goal bodies, grown on demand.

Not `concurrent.futures.ThreadPoolExecutor`: its threads are joined at interpreter exit, so one
execute callback that ignores cancellation would hang the process on shutdown. Idle workers
are reused (a hand-off costs far less than starting a thread), and an idle worker ends after
``idle_timeout`` seconds.
"""

from __future__ import annotations

import logging
import queue
import threading
from collections.abc import Callable

from ..errors import ActionError

__all__ = ["WorkerPool"]

_STOP = object()


class WorkerPool:
    """Runs ``fn()`` calls on daemon threads; never more than are busy at once plus idle ones."""

    def __init__(self, name: str, logger: logging.Logger, idle_timeout: float = 30.0) -> None:
        self._name = name
        self._logger = logger
        self._idle_timeout = idle_timeout
        self._jobs: queue.SimpleQueue[object] = queue.SimpleQueue()
        self._lock = threading.Lock()
        self._idle = 0
        self._count = 0
        self._closed = False

    def submit(self, fn: Callable[[], None]) -> None:
        """Run ``fn`` on a worker; an exception it raises is logged."""
        with self._lock:
            if self._closed:
                raise ActionError(f"worker pool {self._name} is closed")
            if self._idle > 0:
                self._idle -= 1
            else:
                self._count += 1
                threading.Thread(target=self._work, name=f"{self._name}-{self._count}",
                                 daemon=True).start()
            self._jobs.put(fn)

    def _work(self) -> None:
        while True:
            try:
                job = self._jobs.get(timeout=self._idle_timeout)
            except queue.Empty:
                with self._lock:
                    if self._idle > 0 and self._jobs.empty():
                        self._idle -= 1
                        return
                continue
            if job is _STOP:
                return
            try:
                job()  # type: ignore[operator]
            except Exception:
                self._logger.exception("%s: job raised", self._name)
            with self._lock:
                self._idle += 1

    def close(self) -> None:
        """Let idle workers end; busy ones end after their current job."""
        with self._lock:
            self._closed = True
            for _ in range(self._count):
                self._jobs.put(_STOP)
