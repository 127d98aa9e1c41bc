"""Patrol: visit poses in order, waiting at each, for a number of loops (0: until halted).

Each leg is a `Navigate` built by ``make_nav``; a leg that fails is recorded as missed and
the patrol goes on (Nav2's waypoint follower with ``stop_on_failure: false``). A whole loop
of misses ends the patrol with NAVIGATION_FAILED.
"""

from __future__ import annotations

from collections.abc import Callable

from zenros.msgs.zenros_msgs.nav import PatrolResult
from zenros.se2 import Pose2

from .behavior import Behavior, Sense
from .navigate import Navigate

__all__ = ["Patrol"]


class Patrol(Behavior):
    name = "patrol"

    def __init__(self, points: list[Pose2], make_nav: Callable[[Pose2], Navigate], *,
                 loops: int = 0, wait_time: float = 0.0, start_index: int = 0) -> None:
        super().__init__()
        if not points:
            raise ValueError("a patrol needs at least one point")
        if not 0 <= start_index < len(points):
            raise ValueError(f"start_index {start_index} is outside 0..{len(points) - 1}")
        self.points, self.make_nav = points, make_nav
        self.loops, self.wait_time = loops, wait_time
        self.index, self.loop = start_index, 0
        self.visited = 0
        self.missed: list[tuple[int, int, str]] = []  # (index, code, message)
        self._misses_this_loop = 0
        self.nav: Navigate | None = None
        self._wait_until: float | None = None

    @property
    def waiting(self) -> bool:
        return self._wait_until is not None

    def tick(self, s: Sense) -> tuple[float, float]:
        if self._wait_until is not None:
            if s.now < self._wait_until:
                return 0.0, 0.0
            self._wait_until = None
            return self._advance()
        if self.nav is None:
            self.nav = self.make_nav(self.points[self.index])
        v, w = self.nav.step(s)
        if not self.nav.done.is_set():
            return v, w
        nav, self.nav = self.nav, None
        if nav.succeeded:
            self.visited += 1
            if self.wait_time > 0:
                self._wait_until = s.now + self.wait_time
                return 0.0, 0.0
        else:
            self.missed.append((self.index, nav.error_code, nav.error_msg))
            self._misses_this_loop += 1
        return self._advance()

    def _advance(self) -> tuple[float, float]:
        self.index += 1
        if self.index < len(self.points):
            return 0.0, 0.0
        if self._misses_this_loop >= len(self.points):
            _, code, msg = self.missed[-1]
            return self.finish(False, PatrolResult.NAVIGATION_FAILED,
                               f"every point of loop {self.loop + 1} failed; last: {msg} ({code})")
        self._misses_this_loop = 0
        self.index = 0
        self.loop += 1
        if self.loops and self.loop >= self.loops:
            return self.finish(True)
        return 0.0, 0.0

    def halt(self, reason: str) -> None:
        if self.nav is not None:
            self.nav.halt(reason)
        super().halt(reason)
