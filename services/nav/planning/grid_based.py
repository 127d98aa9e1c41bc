"""`AStarPlanner`: the grid planner plugin (``zenros_nav/AStarPlanner``): this package's
optimal, cost-aware 8-connected A* (Smac Planner 2D's cost model), one leg at a time."""

from __future__ import annotations

import dataclasses

import numpy as np
from zenros.se2 import Pose2

from ..costmap.snapshot import CostSnapshot
from .errors import GoalOutsideMap, PlanningError, StartOutsideMap
from .interface import NoParameters, PlannerPlugin
from .plan import plan
from .wording import at, in_map_terms

__all__ = ["AStarPlanner"]


class AStarPlanner(PlannerPlugin[NoParameters]):
    """Plans with nav's planner parameters (`PlannerContext`); an occupied goal moves to
    the nearest free cell within ``planner_tolerance``. The path starts exactly at
    ``start`` and, unless the goal moved, ends exactly at ``goal``."""

    def create_plan(self, costmap: CostSnapshot, start: Pose2, goal: Pose2) -> np.ndarray:
        s = costmap.world_to_map(start.x, start.y)
        if s is None:
            raise StartOutsideMap(f"start {at(start)} is outside the map")
        g = costmap.world_to_map(goal.x, goal.y)
        if g is None:
            raise GoalOutsideMap(f"goal {at(goal)} is outside the map")
        params = dataclasses.replace(
            self.context.search,
            goal_tolerance=round(self.context.goal_tolerance / costmap.resolution))
        try:
            res = plan(costmap.costs, s, g, params)
        except PlanningError as exc:  # cells and costs, said in the map frame
            raise type(exc)(in_map_terms(exc, start, goal, params.timeout)) from exc
        pts = res.points(costmap.resolution, costmap.origin)
        if res.goal == g:  # end exactly on the requested point, not the cell centre
            pts[-1] = (goal.x, goal.y)
        pts[0] = (start.x, start.y)
        return pts
