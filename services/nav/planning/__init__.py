"""Planning: the global planner (optimal, cost-aware 8-connected A* on a Nav2 costmap), the
navigation planner built on it, and coverage paths.

API (cells ``(mx, my)`` = (column, row) of ``costs[my, mx]``, as in the costmap)::

    from zenros.services.nav.planning import plan, PlannerParams, PlanningError

    try:
        result = plan(costmap.costs, start_cell, goal_cell, PlannerParams(timeout=2.0))
    except PlanningError as e:      # StartOutsideMap 203, GoalOutsideMap 204,
        code = e.code               # StartOccupied 205, GoalOccupied 206,
                                    # PlanningTimeout 207, NoValidPath 208
    result.cells                    # (N, 2) int32, start → goal
    result.poses(res, origin)       # (N, 3) x, y, yaw in the map frame
    result.cost, result.length, result.expansions, result.planning_time

    plan_between(costmap, (x0, y0), (x1, y1))   # the same from map-frame points

The search is compiled (``_astar.c``) when built, with ``astar.search_python`` as the
reference; ``ZENROS_NAV_PURE=1`` selects Python. See docs/nav-planner.md.

Modules: ``astar`` (the Python search), ``accel`` (the compiled one, if built), ``plan`` (the
cost model and `plan`), ``errors``, ``world`` (`plan_between`), ``global_planner``
(`GlobalPlanner` through several poses with Nav2's error codes, and `PlanWorker`, its thread),
``coverage`` (`plan_coverage`, boustrophedon). Imports costmap (the snapshot it plans on).
"""

from .errors import (
    GoalOccupied,
    GoalOutsideMap,
    NoValidPath,
    PlanningError,
    PlanningTimeout,
    StartOccupied,
    StartOutsideMap,
)
from .plan import PlannerParams, PlanResult, cost_multipliers, path_length, plan
from .world import plan_between

__all__ = [
    "GoalOccupied",
    "GoalOutsideMap",
    "NoValidPath",
    "PlanResult",
    "PlannerParams",
    "PlanningError",
    "PlanningTimeout",
    "StartOccupied",
    "StartOutsideMap",
    "cost_multipliers",
    "path_length",
    "plan",
    "plan_between",
]
