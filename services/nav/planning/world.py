"""plan_between(): plan on a Costmap2D between two map-frame points."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from .errors import GoalOutsideMap, StartOutsideMap
from .plan import PlannerParams, PlanResult, plan

__all__ = ["plan_between"]


class _Grid(Protocol):
    @property
    def costs(self) -> np.ndarray: ...
    @property
    def resolution(self) -> float: ...
    @property
    def origin(self) -> tuple[float, float]: ...
    def world_to_map(self, x: float, y: float) -> tuple[int, int] | None: ...


def plan_between(
    costmap: _Grid,
    start: tuple[float, float],
    goal: tuple[float, float],
    params: PlannerParams | None = None,
) -> PlanResult:
    """``plan`` between the cells holding two map-frame points of a costmap.

    Raises:
        StartOutsideMap, GoalOutsideMap: a point outside the map (or not finite); and
        everything ``plan`` raises.
    """
    s = costmap.world_to_map(float(start[0]), float(start[1]))
    if s is None:
        raise StartOutsideMap(f"start ({start[0]}, {start[1]}) is outside the map")
    g = costmap.world_to_map(float(goal[0]), float(goal[1]))
    if g is None:
        raise GoalOutsideMap(f"goal ({goal[0]}, {goal[1]}) is outside the map")
    return plan(costmap.costs, s, g, params if params is not None else PlannerParams())
