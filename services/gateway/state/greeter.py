"""`Greeter`: when to greet a person who comes near: once per approach, not again while they
stay, again after they have gone (hysteresis in distance and time)."""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = ["DEFAULT_GREETING", "Greeter"]

DEFAULT_GREETING = "Hello! Nice to meet you."


class Greeter:
    """Greets when a person comes within ``near`` m; the approach ends once nobody has been
    within ``far`` m for ``forget`` s (a person standing by, seen now and then, is greeted
    once)."""

    def __init__(self, near: float = 1.5, far: float = 2.0, forget: float = 2.0) -> None:
        if not 0 < near <= far:
            raise ValueError(f"greeting distances: expected 0 < near <= far, got {near}, {far}")
        self.near, self.far, self.forget = near, far, forget
        self.approached = False
        self._last_near = -math.inf

    def update(self, people: Sequence[tuple[float, float]], now: float) -> bool:
        """Take one look (people in the robot's frame, m) at ``now`` (s); True: greet now."""
        nearest = min((math.hypot(x, y) for x, y in people), default=math.inf)
        if nearest <= self.far:
            self._last_near = now
        elif self.approached and now - self._last_near > self.forget:
            self.approached = False
        if nearest <= self.near and not self.approached:
            self.approached = True
            return True
        return False
