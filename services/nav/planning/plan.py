"""plan(): the global planner's entry point, from cells or from map-frame points.

The cost model is Smac Planner 2D's: a step into a cell of cost ``c`` costs
``distance · (1 + cost_weight · c / 252)`` with distance 1 or √2 cells, so the path is the
cheapest 8-connected path, trading length against nearness to obstacles. Cells at or above
``lethal_cost`` (253, the inscribed cost, by default: the robot's centre there means a
collision) are refused; unknown cells (255) count as cost 252 when ``allow_unknown``.
"""

from __future__ import annotations

import math
import operator
import time
from dataclasses import dataclass, field

import numpy as np

from . import accel
from .astar import FIXED, FOUND, LIMIT, NO_PATH, TIMEOUT, SearchOutcome, search_python
from .errors import (
    GoalOccupied,
    GoalOutsideMap,
    NoValidPath,
    PlanningTimeout,
    StartOccupied,
    StartOutsideMap,
)

__all__ = ["PlanResult", "PlannerParams", "cost_multipliers", "path_length", "plan", "step_table"]

Cell = tuple[int, int]
MAX_COST_WEIGHT = 1000.0
"""Above this, fixed-point path costs could overflow 64 bits on the largest grids."""


@dataclass(frozen=True, slots=True)
class PlannerParams:
    """Planner parameters (defaults: Smac Planner 2D's where it has one)."""

    cost_weight: float = 2.0
    """Smac's ``cost_travel_multiplier`` (0 .. 1000): 0 plans the shortest path."""
    lethal_cost: int = 253
    """Cells with a cost at or above this (and below 255) are not entered."""
    allow_unknown: bool = True
    timeout: float = 2.0
    """Seconds (Smac's ``max_planning_time``); 0 for no limit."""
    max_iterations: int = 0
    """Cells expanded before giving up with NoValidPath (0: no limit)."""
    goal_tolerance: int = 0
    """Cells: an occupied goal is moved to the nearest free cell within this radius."""

    def __post_init__(self) -> None:
        if not (math.isfinite(self.cost_weight) and 0 <= self.cost_weight <= MAX_COST_WEIGHT):
            raise ValueError(
                f"cost_weight must be a number in 0 .. {MAX_COST_WEIGHT:g}, "
                f"got {self.cost_weight!r}"
            )
        if not 1 <= self.lethal_cost <= 255:
            raise ValueError(f"lethal_cost must be in 1..255, got {self.lethal_cost!r}")
        if not (math.isfinite(self.timeout) and self.timeout >= 0):
            raise ValueError(f"timeout must be a finite number >= 0, got {self.timeout!r}")
        if self.max_iterations < 0 or self.goal_tolerance < 0:
            raise ValueError("max_iterations and goal_tolerance must be >= 0")


@dataclass(frozen=True, slots=True)
class PlanResult:
    """A plan: the cells from start to goal, and what it cost to find."""

    cells: np.ndarray
    """(N, 2) int32 ``(mx, my)`` from the start cell to the goal cell."""
    cost: float
    """The path's traversal cost (cells, weighted by the cost model)."""
    length: float
    """The path's length in cells (steps of 1 and √2)."""
    expansions: int
    planning_time: float
    """Seconds."""
    goal: Cell = (0, 0)
    """The goal cell actually reached (differs from the request with a goal tolerance)."""
    compiled: bool = field(default=False)

    def points(self, resolution: float, origin: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
        """The cells' centres in the map frame, (N, 2) float64."""
        c = self.cells.astype(np.float64)
        return np.column_stack(
            [origin[0] + (c[:, 0] + 0.5) * resolution, origin[1] + (c[:, 1] + 0.5) * resolution]
        )

    def poses(self, resolution: float, origin: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
        """(N, 3) ``x, y, yaw``: the centres, each heading towards the next point (the
        last one keeps the previous heading; a one-cell plan has yaw 0)."""
        p = self.points(resolution, origin)
        yaw = np.zeros(len(p))
        if len(p) > 1:
            d = np.diff(p, axis=0)
            yaw[:-1] = np.arctan2(d[:, 1], d[:, 0])
            yaw[-1] = yaw[-2]
        return np.column_stack([p, yaw])


def cost_multipliers(params: PlannerParams) -> np.ndarray:
    """The step multiplier of each cost byte: ``1 + w·c/252``; inf where not passable."""
    c = np.arange(256, dtype=np.float64)
    m = 1.0 + params.cost_weight * np.minimum(c, 252.0) / 252.0
    m[params.lethal_cost:255] = math.inf
    if not params.allow_unknown:
        m[255] = math.inf
    return m


def step_table(mult: np.ndarray) -> tuple[np.ndarray, int, int]:
    """The fixed-point step costs (512 int64: straight then diagonal per cost byte, −1
    where not passable) and the heuristic's two coefficients for a multiplier table."""
    finite = np.isfinite(mult)
    steps = np.full(512, -1, dtype=np.int64)
    steps[:256][finite] = np.floor(mult[finite] * FIXED + 0.5).astype(np.int64)
    steps[256:][finite] = np.floor(mult[finite] * math.sqrt(2.0) * FIXED + 0.5).astype(np.int64)
    passable = steps[:256][finite]
    hs = int(passable.min()) if passable.size else 0
    # the diagonal part: the cheapest diagonal step minus a straight one, rounded down, so
    # hs + hd never exceeds any diagonal step (the heuristic stays consistent)
    hd = int(steps[256:][finite].min()) - hs if passable.size else 0
    return steps, hs, max(0, min(hd, hs))


def path_length(cells: np.ndarray) -> float:
    """The length of a cell path in cells (1 per straight step, √2 per diagonal)."""
    c = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    if len(c) < 2:
        return 0.0
    d = np.abs(np.diff(c, axis=0))
    diag = (d[:, 0] != 0) & (d[:, 1] != 0)
    return float(np.count_nonzero(~diag) + math.sqrt(2) * np.count_nonzero(diag))


def _check_cell(costs: np.ndarray, cell: Cell, what: str) -> tuple[int, int]:
    try:
        if len(cell) != 2:
            raise ValueError
        mx, my = operator.index(cell[0]), operator.index(cell[1])
    except (TypeError, ValueError, IndexError):
        raise ValueError(f"{what} must be an (mx, my) cell, got {cell!r}") from None
    h, w = costs.shape
    if not (0 <= mx < w and 0 <= my < h):
        err = StartOutsideMap if what == "start" else GoalOutsideMap
        raise err(f"{what} cell ({mx}, {my}) is outside the {w} x {h} map")
    return mx, my


def _nearest_free(costs: np.ndarray, mult: np.ndarray, cell: Cell, radius: int) -> Cell | None:
    h, w = costs.shape
    x0, x1 = max(0, cell[0] - radius), min(w, cell[0] + radius + 1)
    y0, y1 = max(0, cell[1] - radius), min(h, cell[1] + radius + 1)
    ys, xs = np.mgrid[y0:y1, x0:x1]
    ok = np.isfinite(mult[costs[y0:y1, x0:x1]])
    d2 = (xs - cell[0]) ** 2 + (ys - cell[1]) ** 2
    ok &= d2 <= radius * radius
    if not ok.any():
        return None
    d2 = np.where(ok, d2, np.iinfo(np.int64).max)
    i = int(np.argmin(d2))  # row-major: ties go to the lowest row, then column
    return int(xs.ravel()[i]), int(ys.ravel()[i])


def plan(
    costs: np.ndarray,
    start: Cell,
    goal: Cell,
    params: PlannerParams = PlannerParams(),
    *,
    use_compiled: bool | None = None,
) -> PlanResult:
    """The cheapest 8-connected path from ``start`` to ``goal`` (``(mx, my)`` cells) over a
    uint8 cost grid ``costs[my, mx]`` (Nav2's cost values).

    Args:
        use_compiled: None uses the C search when it is built; False forces Python;
            True insists on C (RuntimeError where it is not built).

    Raises:
        StartOutsideMap, GoalOutsideMap, StartOccupied, GoalOccupied, NoValidPath,
        PlanningTimeout: all PlanningError, each with its ComputePathToPose ``code``.
        ValueError: costs that are not a 2-D grid, or a start/goal that is not a cell.
    """
    t0 = time.perf_counter()
    raw = np.asarray(costs)
    if raw.dtype != np.uint8 and (
        raw.dtype.kind not in "iu" or (raw.size and (raw.min() < 0 or raw.max() > 255))
    ):
        raise ValueError(f"costs must be cost bytes (uint8 0..255), got {raw.dtype}")
    grid = np.ascontiguousarray(raw, dtype=np.uint8)
    if grid.ndim != 2 or grid.size == 0:
        raise ValueError(f"costs must be a non-empty 2-D grid, got shape {grid.shape}")
    h, w = grid.shape
    s = _check_cell(grid, start, "start")
    g = _check_cell(grid, goal, "goal")
    mult = cost_multipliers(params)
    if not math.isfinite(mult[grid[s[1], s[0]]]):
        raise StartOccupied(f"start cell {s} has cost {grid[s[1], s[0]]}")
    if not math.isfinite(mult[grid[g[1], g[0]]]):
        moved = None
        if params.goal_tolerance:
            moved = _nearest_free(grid, mult, g, params.goal_tolerance)
        if moved is None:
            raise GoalOccupied(f"goal cell {g} has cost {grid[g[1], g[0]]}")
        g = moved
    steps, hs, hd = step_table(mult)
    module = accel.compiled if use_compiled is not False else None
    if use_compiled and module is None:
        raise RuntimeError("the compiled planner is not built here (or ZENROS_NAV_PURE is set)")
    budget = params.timeout - (time.perf_counter() - t0) if params.timeout > 0 else 0.0
    if params.timeout > 0 and budget <= 0:
        raise PlanningTimeout(f"no time left to plan within {params.timeout} s")
    si, gi = s[1] * w + s[0], g[1] * w + g[0]
    if module is not None:
        st, raw, g_goal, n_exp = module.search(
            grid, w, h, steps, si, gi, hs, hd, budget, params.max_iterations
        )
        out = SearchOutcome(st, np.frombuffer(raw, dtype=np.int32), g_goal, n_exp)
    else:
        out = search_python(grid, steps, si, gi, hs, hd, budget, params.max_iterations)
    elapsed = time.perf_counter() - t0
    if out.status == TIMEOUT:
        raise PlanningTimeout(
            f"no path found within {params.timeout} s ({out.expansions} cells expanded)"
        )
    if out.status == LIMIT:
        raise NoValidPath(f"exceeded maximum iterations ({params.max_iterations})")
    if out.status == NO_PATH:
        raise NoValidPath(f"no valid path from {s} to {g} ({out.expansions} cells expanded)")
    assert out.status == FOUND
    flat = out.path[::-1]
    cells = np.column_stack([flat % w, flat // w]).astype(np.int32)
    return PlanResult(
        cells=cells, cost=out.g_goal / FIXED, length=path_length(cells), expansions=out.expansions,
        planning_time=elapsed, goal=g, compiled=module is not None,
    )
