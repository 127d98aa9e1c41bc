"""`Presence`: whether a backend the gateway calls (nav, tasks, chassis) is starting, up, or
went away, so a 503 says which (and a client retries a starting one)."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from ..errors import Unavailable

__all__ = ["RETRY_AFTER", "Presence"]

RETRY_AFTER = 2  # s a client waits before retrying a backend that is starting


class Presence:
    """Backends by name, each with a ``probe()`` that says whether it is up now.

    A backend is *starting* while it has not been seen since the gateway started and the
    startup grace (``grace`` s) runs; *went away* once seen and gone; else *not running*.
    `refresh` (on every graph change, and before each answer) records when each was seen.
    """

    def __init__(self, grace: float = 30.0,
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.grace = grace
        self._clock = clock
        self._start = clock()
        self._probes: dict[str, Callable[[], bool]] = {}
        self._seen: dict[str, float] = {}
        self._lock = threading.Lock()

    def watch(self, backend: str, probe: Callable[[], bool]) -> None:
        """Track ``backend`` (``nav``, ``tasks``, ...) with ``probe``."""
        with self._lock:
            self._probes[backend] = probe
        self.refresh()

    def refresh(self) -> None:
        """Note every backend that is up now."""
        with self._lock:
            names = list(self._probes)
        for name in names:
            self._up(name)

    def _up(self, backend: str) -> bool:
        probe = self._probes.get(backend)
        try:
            up = probe is not None and probe()
        except Exception:  # a probe reads the graph; it never breaks an answer
            up = False
        if up:
            self._seen[backend] = self._clock()
        return up

    def seen(self, backend: str) -> bool:
        return backend in self._seen

    def error(self, backend: str, detail: str) -> Unavailable:
        """The `Unavailable` (a 503) for ``backend``; ``detail`` says what was asked.

        Starting (not seen yet, within the grace): ``Retry-After`` and "is starting";
        seen before: "went away"; else: "is not running". A backend that is up (the call
        failed for another reason, e.g. one of its services missing) gets ``detail`` alone.
        """
        if self._up(backend):
            return Unavailable(detail)
        now = self._clock()
        last = self._seen.get(backend)
        if last is not None:
            return Unavailable(f"{detail}: the {backend} service went away (last seen "
                               f"{now - last:.0f} s ago)")
        age = now - self._start
        if age < self.grace:
            return Unavailable(f"{detail}: the {backend} service is starting (not up yet, "
                               f"{age:.0f} s after the gateway started); retry in "
                               f"{RETRY_AFTER} s", retry_after=RETRY_AFTER)
        return Unavailable(f"{detail}: the {backend} service is not running (not seen "
                           f"since the gateway started {age:.0f} s ago)")
