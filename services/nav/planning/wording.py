"""`in_map_terms`: a planning error said in the map frame, as a user gave the goal.

The search works on costmap cells and says so ("goal cell (90, 79) has cost 254"); a user
gave metres in ``map``. Every error that leaves nav (action results, ``nav/status``, the
gateway and the tasks service after them) is worded here; the ComputePathToPose code stays
the exception's.
"""

from __future__ import annotations

from zenros.se2 import Pose2

from . import errors

__all__ = ["at", "in_map_terms"]

_WORDS: dict[type[errors.PlanningError], str] = {
    errors.GoalOccupied: "goal {goal} is inside an obstacle",
    errors.StartOccupied: "start {start} is inside an obstacle",
    errors.GoalOutsideMap: "goal {goal} is outside the map",
    errors.StartOutsideMap: "start {start} is outside the map",
    errors.NoValidPath: "no path from {start} to {goal}: every way there is blocked",
    errors.PlanningTimeout: "no path from {start} to {goal} found within {timeout:g} s",
}


def at(p: Pose2) -> str:
    """A map point as the errors write it: ``(1.50, -5.80)``."""
    return f"({p.x:.2f}, {p.y:.2f})"


def in_map_terms(exc: errors.PlanningError, start: Pose2, goal: Pose2, timeout: float) -> str:
    """What went wrong planning from ``start`` to ``goal`` (``timeout``: the planner's, s)."""
    words = next((w for kind, w in _WORDS.items() if isinstance(exc, kind)), None)
    if words is None:
        return str(exc)
    return words.format(start=at(start), goal=at(goal), timeout=timeout)
