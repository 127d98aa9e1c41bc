"""`Robot`: what task actions need from the rest of the robot (nav, dock, maps, speech).

The tasks node implements it over zenros (actions and services of nav and chassis); unit
tests pass a double. Long calls take ``cancelled``, polled while they wait, and return an
`Outcome` with a reason.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Literal, NamedTuple, Protocol

__all__ = ["Feedback", "Outcome", "Robot"]

OutcomeName = Literal["complete", "fail", "error", "preempted"]


class Outcome(NamedTuple):
    name: OutcomeName
    reason: str = ""


class Feedback(NamedTuple):
    """Where a navigating robot is and how far it still has to go (m)."""

    x: float
    y: float
    theta: float
    distance: float


class Robot(Protocol):
    def now(self) -> float:
        """The node clock in seconds (simulated time when the robot runs on it)."""
        ...

    def nav_point(self, index: int, map_name: str, path_name: str) -> tuple[float, float, float]:
        """Nav point ``index`` of a path as (x, y, theta); LookupError if there is none.

        Empty ``map_name``: the current map; empty ``path_name``: the map's only path."""
        ...

    def navigate(self, x: float, y: float, theta: float, timeout: float,
                 feedback: Callable[[Feedback], None],
                 cancelled: Callable[[], bool]) -> Outcome:
        """Drive to (x, y, theta) in ``map``; ``timeout`` 0 means none."""
        ...

    def charge(self, pose: tuple[float, float, float] | None, level: float, timeout: float,
               cancelled: Callable[[], bool]) -> Outcome:
        """Dock at ``pose`` (None: the map's charge pose) until charging, or ``level``."""
        ...

    def switch_map(self, name: str, path: str, start_index: int) -> Outcome:
        ...

    def say(self, text: str) -> None:
        """Speak ``text`` (the simulated robot publishes it as text)."""
        ...
