"""`Inbox`: one thread that runs a client's feedback callbacks and goal endings in arrival order.

Feedback samples and result replies reach the client on Zenoh's own threads, in the order the
server sent them. User callbacks must not run there (a Zenoh call from inside one can
deadlock), yet a goal's last feedback must not be overtaken by its end. Both therefore go
through this queue; a goal without a feedback callback ends directly, with no hop.
"""

from __future__ import annotations

import logging
import queue
import threading
from collections.abc import Callable

__all__ = ["Inbox"]

_STOP = object()


class Inbox:
    """A daemon thread draining a FIFO of calls; started on first use."""

    def __init__(self, name: str, logger: logging.Logger) -> None:
        self._name = name
        self._logger = logger
        self._jobs: queue.SimpleQueue[object] = queue.SimpleQueue()
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._closed = False

    def put(self, fn: Callable[[], None]) -> None:
        """Run ``fn()`` after everything put before it."""
        with self._lock:
            if self._closed:
                return
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name=self._name, daemon=True)
                self._thread.start()
        self._jobs.put(fn)

    def _run(self) -> None:
        while True:
            job = self._jobs.get()
            if job is _STOP:
                return
            try:
                job()  # type: ignore[operator]
            except Exception:
                self._logger.exception("%s: callback raised", self._name)

    def close(self) -> None:
        """Stop after the calls already queued."""
        with self._lock:
            self._closed = True
            if self._thread is not None:
                self._jobs.put(_STOP)
