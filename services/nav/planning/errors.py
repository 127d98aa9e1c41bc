"""Planning errors, each with its nav2_msgs/ComputePathToPose result code."""

from __future__ import annotations

__all__ = [
    "GoalOccupied",
    "GoalOutsideMap",
    "NoValidPath",
    "PlanningError",
    "PlanningTimeout",
    "StartOccupied",
    "StartOutsideMap",
]


class PlanningError(Exception):
    """A plan could not be made; ``code`` is ComputePathToPose's error code."""

    code: int = 200  # UNKNOWN


class StartOutsideMap(PlanningError):
    code = 203


class GoalOutsideMap(PlanningError):
    code = 204


class StartOccupied(PlanningError):
    code = 205


class GoalOccupied(PlanningError):
    code = 206


class PlanningTimeout(PlanningError):
    code = 207


class NoValidPath(PlanningError):
    code = 208
