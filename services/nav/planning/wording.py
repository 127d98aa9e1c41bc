"""`in_map_terms`: a planning error said in the map frame, as a user gave the goal.

The search works on costmap cells and says so ("goal cell (90, 79) has cost 254"); a user
gave metres in ``map``. Every error that leaves nav (action results, ``nav/status``, the
gateway and the tasks service after them) is worded here; the ComputePathToPose code stays
the exception's.
"""

from __future__ import annotations

from zenros.se2 import Pose2

from .errors import (
    GoalOccupied,
    GoalOutsideMap,
    NoValidPath,
    PlanningError,
    PlanningTimeout,
    StartOccupied,
    StartOutsideMap,
)

__all__ = ["at", "in_map_terms"]


def at(p: Pose2) -> str:
    """A map point as the errors write it: ``(1.50, -5.80)``."""
    return f"({p.x:.2f}, {p.y:.2f})"


def in_map_terms(exc: PlanningError, start: Pose2, goal: Pose2, timeout: float) -> str:
    """What went wrong planning from ``start`` to ``goal`` (``timeout``: the planner's, s)."""
    if isinstance(exc, GoalOccupied):
        return f"goal {at(goal)} is inside an obstacle"
    if isinstance(exc, StartOccupied):
        return f"start {at(start)} is inside an obstacle"
    if isinstance(exc, GoalOutsideMap):
        return f"goal {at(goal)} is outside the map"
    if isinstance(exc, StartOutsideMap):
        return f"start {at(start)} is outside the map"
    if isinstance(exc, NoValidPath):
        return f"no path from {at(start)} to {at(goal)}: every way there is blocked"
    if isinstance(exc, PlanningTimeout):
        return f"no path from {at(start)} to {at(goal)} found within {timeout:g} s"
    return str(exc)
