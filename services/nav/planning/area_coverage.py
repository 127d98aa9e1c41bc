"""`CoveragePlanner`: the coverage planner plugin (``zenros_nav/CoveragePlanner``).

``create_plan(start, goal)`` covers the rectangle with ``start`` and ``goal`` at opposite
corners (sides along the map's axes): `plan_coverage`'s boustrophedon route over it,
``op_width`` apart, then from ``start`` through each swath end to ``goal``, every stretch
planned by the grid planner on the costmap, so the path goes round what stands in the area
(a swath end inside an obstacle is left out). As nobleo's full_coverage_path_planner is
a global planner plugin that covers from the start pose, this one is one that covers an
area; `compute_coverage_path` plans over any polygon with holes without the costmap.
"""

from __future__ import annotations

import math
from typing import Annotated

import msgspec
import numpy as np
from msgspec import Meta
from zenros.se2 import Pose2

from ..costmap.snapshot import CostSnapshot
from .coverage import CoverageError, plan_coverage, validate_field
from .errors import NoValidPath, PlanningError
from .grid_based import AStarPlanner
from .interface import NoParameters, PlannerContext, PlannerPlugin

__all__ = ["CoverageParameters", "CoveragePlanner"]

_LETHAL = 253  # inscribed and lethal: a swath end there is left out


class CoverageParameters(msgspec.Struct, kw_only=True, frozen=True):
    op_width: Annotated[float, Meta(gt=0, description="m between swaths")] = 0.4
    swath_angle: Annotated[float, Meta(
        description="degrees from the map's x axis; negative: the fewest swaths")] = 0.0
    headland_width: Annotated[float, Meta(
        ge=0, description="m left uncovered along the area's edge")] = 0.0


class CoveragePlanner(PlannerPlugin[CoverageParameters]):
    """Swaths over the area between start and goal, joined by grid-planned stretches."""

    Parameters = CoverageParameters

    def __init__(self, params: CoverageParameters, context: PlannerContext) -> None:
        super().__init__(params, context)
        self._grid = AStarPlanner(NoParameters(), context)

    def create_plan(self, costmap: CostSnapshot, start: Pose2, goal: Pose2) -> np.ndarray:
        xs, ys = sorted((start.x, goal.x)), sorted((start.y, goal.y))
        border = [(xs[0], ys[0]), (xs[1], ys[0]), (xs[1], ys[1]), (xs[0], ys[1])]
        p = self.params
        try:
            route = plan_coverage(validate_field(border), p.op_width, p.swath_angle,
                                  p.headland_width).path
        except CoverageError as exc:
            raise NoValidPath(f"no coverage of ({xs[0]:.2f}, {ys[0]:.2f})-({xs[1]:.2f}, "
                              f"{ys[1]:.2f}): {exc}") from exc
        pieces = [np.array([[start.x, start.y]])]
        here = start
        for x, y in route.tolist():
            cell = costmap.world_to_map(x, y)
            if cell is None or costmap.costs[cell[1], cell[0]] >= _LETHAL:
                continue
            end = Pose2(x, y, math.atan2(y - here.y, x - here.x))
            try:
                leg = self._grid.create_plan(costmap, here, end)
            except PlanningError:
                continue  # unreachable from here: the next swath end may not be
            pieces.append(leg[1:])
            here = Pose2(float(leg[-1][0]), float(leg[-1][1]), end.theta)
        pieces.append(self._grid.create_plan(costmap, here, goal)[1:])
        return np.vstack(pieces)
