"""`StatusPublisher`: an action's `GoalStatusArray` on its latched ``status`` topic."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

import zenoh

from ..codec import codec_for
from ..executor import Executor
from .goal_handle import ServerGoalHandle
from .transport import status_publisher
from .types import GoalStatusArray, GoalStatusMsg

__all__ = ["STATUS_DELAY", "StatusPublisher"]

STATUS_DELAY = 0.002  # seconds: state changes within this window share one status array


class StatusPublisher:
    """Publishes the full status array after state changes, from the executor's thread.

    `mark` (called under the server's lock at each change) schedules one publication
    ``delay`` seconds later; changes made meanwhile coalesce into it. The array is built under
    the lock when published, so arrays always go out in order and show a consistent state,
    and publishing stays off the threads that answer requests and run goals.
    """

    def __init__(self, session: zenoh.Session, key: str, executor: Executor,
                 snapshot: Callable[[], list[ServerGoalHandle[Any]]], lock: threading.RLock,
                 delay: float = STATUS_DELAY) -> None:
        self._pub: Any = status_publisher(session, key, GoalStatusArray)
        self._codec = codec_for(GoalStatusArray)
        self._executor = executor
        self._snapshot = snapshot
        self._lock = lock
        self._delay = delay
        self._dirty = False
        self._pending = False
        self.closed = False

    def mark(self) -> None:
        """Note a state change (the caller holds the lock)."""
        self._dirty = True
        if not self._pending and not self.closed:
            self._pending = True
            ex = self._executor
            ex.call_soon(ex.loop.call_later, self._delay, self.flush)

    def flush(self, force: bool = False) -> None:
        """Publish now if anything changed since the last array (or ``force``)."""
        with self._lock:
            self._pending = False
            if not (self._dirty or force) or self.closed:
                return
            self._dirty = False
            arr = GoalStatusArray(status_list=[
                GoalStatusMsg(goal_info=h._info, status=int(h._status))
                for h in self._snapshot()])
            self._pub.put(self._codec.encode(arr))

    def close(self) -> None:
        with self._lock:
            self.closed = True
        self._pub.undeclare()
