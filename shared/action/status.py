"""`StatusPublisher`: an action's `GoalStatusArray` on its latched ``status`` topic."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

import zenoh

from ..codec import codec_for
from ..executor import Executor
from ..keytag import key_tag
from .goal_handle import ServerGoalHandle
from .transport import status_publisher
from .types import GoalStatusArray, GoalStatusMsg

__all__ = ["STATUS_DELAY", "STATUS_INTERVAL", "StatusPublisher"]

STATUS_DELAY = 0.002  # seconds: state changes within this window share one status array
STATUS_INTERVAL = 0.005  # seconds: at most one array per interval while goals come quickly


class StatusPublisher:
    """Publishes the full status array after state changes, from the executor's thread.

    `mark` (called under the server's lock at each change) schedules one publication
    ``delay`` seconds later, or ``interval`` seconds after the previous one if that is later;
    changes made meanwhile coalesce into it. So an idle server reports a change within
    ``delay``, and a busy one publishes at most 1/``interval`` arrays a second (each array
    costs every client; results and acceptance never wait for it: they come by query). The
    array is built under the lock when published, so arrays always go out in order and show
    a consistent state, and publishing stays off the threads that answer requests and run
    goals.
    """

    def __init__(self, session: zenoh.Session, key: str, executor: Executor,
                 snapshot: Callable[[], list[ServerGoalHandle[Any]]], lock: threading.RLock,
                 delay: float = STATUS_DELAY, interval: float = STATUS_INTERVAL) -> None:
        self._pub: Any = status_publisher(session, key, GoalStatusArray)
        self._tag = key_tag(key)
        self._codec = codec_for(GoalStatusArray)
        self._executor = executor
        self._snapshot = snapshot
        self._lock = lock
        self._delay = delay
        self._interval = interval
        self._last = -interval  # monotonic time of the last array
        self._dirty = False
        self._pending = False
        self.closed = False

    def mark(self) -> None:
        """Note a state change (the caller holds the lock)."""
        self._dirty = True
        if not self._pending and not self.closed:
            self._pending = True
            wait = max(self._delay, self._last + self._interval - time.monotonic())
            ex = self._executor
            ex.call_soon(ex.loop.call_later, wait, self.flush)

    def flush(self, force: bool = False) -> None:
        """Publish now if anything changed since the last array (or ``force``)."""
        with self._lock:
            self._pending = False
            if not (self._dirty or force) or self.closed:
                return
            self._dirty = False
            self._last = time.monotonic()
            arr = GoalStatusArray(status_list=[
                GoalStatusMsg(goal_info=h.info, status=int(h.status))
                for h in self._snapshot()])
            self._pub.put(self._codec.encode(arr), attachment=self._tag)

    def close(self) -> None:
        with self._lock:
            self.closed = True
        self._pub.undeclare()
