"""Motion: the one behaviour that drives the robot now, and the control tick.

Starting a behaviour halts the one before it (preemption: the new one takes over the next
tick, without a stop in between). `tick` returns the command to send, or None when nothing
is active (after one final zero command, so the robot stops when a behaviour ends).
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from .behavior import Behavior, Sense

__all__ = ["Motion"]


class Motion:
    """Owns the active `Behavior`; thread-safe (actions start behaviours, a timer ticks)."""

    def __init__(self, on_change: Callable[[Behavior | None], None] | None = None) -> None:
        self._lock = threading.Lock()
        self._active: Behavior | None = None
        self._stop_pending = False
        self.on_change = on_change
        self.ticks = 0

    @property
    def active(self) -> Behavior | None:
        return self._active

    @property
    def idle(self) -> bool:
        """Nothing to tick: no behaviour, and no final stop command to send."""
        return self._active is None and not self._stop_pending

    def start(self, behavior: Behavior, reason: str = "preempted by a new goal") -> None:
        with self._lock:
            old, self._active = self._active, behavior
        if old is not None and old is not behavior:
            old.halt(reason)
        if self.on_change is not None:
            self.on_change(behavior)

    def halt(self, behavior: Behavior | None = None, reason: str = "canceled") -> bool:
        """Halt ``behavior`` (or whatever is active); False if it was not the active one."""
        with self._lock:
            cur = self._active
            if cur is None or (behavior is not None and cur is not behavior):
                return False
            self._active = None
            self._stop_pending = True
        cur.halt(reason)
        if self.on_change is not None:
            self.on_change(None)
        return True

    def tick(self, sense: Sense) -> tuple[float, float] | None:
        """One control step: the command for the active behaviour, or None when idle."""
        self.ticks += 1
        with self._lock:
            b = self._active
        if b is None:
            with self._lock:
                if self._stop_pending:
                    self._stop_pending = False
                    return 0.0, 0.0
            return None
        cmd = b.step(sense)
        if b.done.is_set():
            with self._lock:
                if self._active is b:
                    self._active = None
            if self.on_change is not None:
                self.on_change(None)
            return 0.0, 0.0
        return cmd
