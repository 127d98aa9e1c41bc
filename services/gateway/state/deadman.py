"""`DeadMan`: a velocity command that holds only for a short time, about 0.5 s
(docs/robot-api.md §3.2)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

__all__ = ["DeadMan"]


class DeadMan:
    """Holds the last (linear, lateral, angular) command; `tick` says what to publish.

    While a command is fresh `tick` returns it; the first tick after ``timeout`` seconds
    of silence returns zeros once (the stop), then None (publish nothing, so other
    drivers such as the navigation controller are not overridden). The ticker may stop
    once `tick` returned None: the next `command` calls ``on_arm`` (outside the lock) to
    start it again.
    """

    def __init__(self, timeout: float = 0.5,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.timeout = timeout
        self._clock = clock
        self._cmd: tuple[float, float, float] | None = None
        self._at = 0.0
        self._lock = threading.Lock()
        self._idle = False  # tick() returned None: the ticker may have stopped
        self.on_arm: Callable[[], None] | None = None

    def command(self, x: float, y: float, theta: float) -> None:
        with self._lock:
            self._cmd = (x, y, theta)
            self._at = self._clock()
            wake, self._idle = self._idle, False
        if wake and self.on_arm is not None:
            self.on_arm()

    def current(self) -> tuple[float, float, float]:
        """The command in force now (zeros when none or expired)."""
        with self._lock:
            if self._cmd is None or self._clock() - self._at > self.timeout:
                return (0.0, 0.0, 0.0)
            return self._cmd

    @property
    def active(self) -> bool:
        with self._lock:
            return self._cmd is not None

    def tick(self) -> tuple[float, float, float] | None:
        with self._lock:
            if self._cmd is None:
                self._idle = True
                return None
            if self._clock() - self._at > self.timeout:
                self._cmd = None
                return (0.0, 0.0, 0.0)
            return self._cmd
