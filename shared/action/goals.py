"""`GoalTable`: an action server's goals, from arrival to the expiry of their results.

Pure bookkeeping (no Zenoh, no threads): the server calls it under its own lock.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator
from itertools import islice
from typing import Any

from .goal_handle import ServerGoalHandle
from .types import GoalStatus

__all__ = ["GoalTable"]

Handle = ServerGoalHandle[Any]


class GoalTable:
    """Goals by id: pending (goal callback deciding), active (until their result is set) and
    finished (results kept ``result_timeout`` seconds, oldest first).

    Args:
        result_timeout: seconds a result stays available after the goal ended.
        status_history: how many finished goals the status array still lists.
    """

    def __init__(self, result_timeout: float, status_history: int) -> None:
        if result_timeout < 0:
            raise ValueError(f"result_timeout must be >= 0 s, got {result_timeout}")
        if status_history < 0:
            raise ValueError(f"status_history must be >= 0, got {status_history}")
        self.result_timeout = result_timeout
        self.status_history = status_history
        self._all: dict[bytes, Handle] = {}
        self.active: dict[bytes, Handle] = {}
        self._finished: deque[tuple[float, Handle]] = deque()  # (when it ended, goal)

    def __len__(self) -> int:
        return len(self._all)

    def lookup(self, key: bytes) -> Handle | None:
        return self._all.get(key)

    def add_pending(self, handle: Handle) -> bool:
        """Register a goal the goal callback is deciding on; False if the id is taken."""
        if handle.key in self._all:
            return False
        self._all[handle.key] = handle
        return True

    def remove(self, handle: Handle) -> None:
        """Forget a rejected goal."""
        self._all.pop(handle.key, None)
        self.active.pop(handle.key, None)

    def activate(self, handle: Handle) -> None:
        self.active[handle.key] = handle

    def retire(self, handle: Handle, now: float) -> None:
        """The goal's result is set: keep it until ``now + result_timeout``."""
        self.active.pop(handle.key, None)
        self._finished.append((now, handle))

    def next_expiry(self) -> float | None:
        """When the oldest kept result expires (monotonic seconds), if any."""
        return self._finished[0][0] + self.result_timeout if self._finished else None

    def expire(self, now: float) -> list[Handle]:
        """Drop the results older than ``result_timeout``; return the dropped goals."""
        dropped = []
        while self._finished and self._finished[0][0] + self.result_timeout <= now:
            h = self._finished.popleft()[1]
            self._all.pop(h.key, None)
            dropped.append(h)
        return dropped

    def status_list(self) -> list[Handle]:
        """What the status array shows: every active goal (in acceptance order), then the
        ``status_history`` most recently finished ones."""
        recent = [h for _, h in islice(reversed(self._finished), self.status_history)]
        recent.reverse()
        return list(self.active.values()) + recent

    def cancel_targets(self, key: bytes | None, stamp_ns: int) -> Iterator[Handle]:
        """Active goals a cancel request names: the goal ``key``, and (``stamp_ns`` > 0) every
        goal accepted at or before the stamp; no key and no stamp: every active goal."""
        for h in list(self.active.values()):
            if not h.status.active:
                continue
            if key is not None and h.key == key or key is None and stamp_ns == 0 or stamp_ns > 0 and _ns(h) <= stamp_ns:
                yield h

    def terminal_or_unknown(self, key: bytes) -> GoalStatus:
        """For a cancel naming a goal that is not cancelable: its state (UNKNOWN if not here)."""
        h = self._all.get(key)
        return GoalStatus.UNKNOWN if h is None else h.status


def _ns(h: Handle) -> int:
    return h.stamp.sec * 1_000_000_000 + h.stamp.nanosec
