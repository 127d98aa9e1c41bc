"""The global planner: optimal against brute-force Dijkstra, C against its Python reference,
the cost model, errors with ComputePathToPose codes."""

from __future__ import annotations

import heapq
import itertools
import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from zenros.services.nav.costmap import Costmap2D
from zenros.services.nav.planning import (
    GoalOccupied,
    GoalOutsideMap,
    NoValidPath,
    PlannerParams,
    PlanningError,
    PlanningTimeout,
    StartOccupied,
    StartOutsideMap,
    path_length,
    plan,
    plan_between,
)
from zenros.services.nav.planning.accel import compiled
from zenros.services.nav.planning.astar import FOUND, LIMIT, TIMEOUT, SearchOutcome, search_python
from zenros.services.nav.planning.plan import cost_multipliers, step_table


@pytest.fixture(params=["c", "python"])
def impl(request: pytest.FixtureRequest) -> bool:
    """``True``: the compiled search; ``False``: the Python reference."""
    if request.param == "c" and compiled is None:
        pytest.skip("the planner's C search is not built here (or ZENROS_NAV_PURE is set)")
    return bool(request.param == "c")


def dijkstra(costs: np.ndarray, start: tuple[int, int], goal: tuple[int, int],
             weight: float = 2.0, allow_unknown: bool = True) -> float:
    """Brute force: every cell settled, real-valued Smac 2D step costs; inf if unreachable."""
    h, w = costs.shape
    dist = np.full((h, w), np.inf)
    dist[start[1], start[0]] = 0.0
    heap = [(0.0, start)]
    while heap:
        d, (x, y) = heapq.heappop(heap)
        if d > dist[y, x]:
            continue
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                nx, ny = x + dx, y + dy
                if (dx, dy) == (0, 0) or not (0 <= nx < w and 0 <= ny < h):
                    continue
                c = int(costs[ny, nx])
                if c in (253, 254) or (c == 255 and not allow_unknown):
                    continue
                step = (math.sqrt(2) if dx and dy else 1.0) * (1 + weight * min(c, 252) / 252)
                if d + step < dist[ny, nx]:
                    dist[ny, nx] = d + step
                    heapq.heappush(heap, (d + step, (nx, ny)))
    return float(dist[goal[1], goal[0]])


def real_cost(costs: np.ndarray, cells: np.ndarray, weight: float = 2.0) -> float:
    total = 0.0
    for (x0, y0), (x1, y1) in itertools.pairwise(cells.tolist()):
        assert max(abs(x1 - x0), abs(y1 - y0)) == 1  # 8-connected steps
        c = int(costs[y1, x1])
        assert c not in (253, 254)
        total += (math.sqrt(2) if x1 != x0 and y1 != y0 else 1.0) * (1 + weight * min(c, 252) / 252)
    return total


def random_costs(seed: int, shape: tuple[int, int] = (18, 23)) -> np.ndarray:
    rng = np.random.default_rng(seed)
    values = np.array([0, 0, 0, 0, 10, 60, 128, 200, 252, 253, 254, 254, 255], np.uint8)
    return rng.choice(values, size=shape)


@pytest.mark.parametrize("seed", range(25))
def test_optimal_against_brute_force(seed: int, impl: bool) -> None:
    costs = random_costs(seed)
    rng = np.random.default_rng(1000 + seed)
    free = np.argwhere(costs < 253)
    s = tuple(int(v) for v in free[rng.integers(len(free))][::-1])
    g = tuple(int(v) for v in free[rng.integers(len(free))][::-1])
    best = dijkstra(costs, s, g)
    if math.isinf(best):
        with pytest.raises(NoValidPath):
            plan(costs, s, g, use_compiled=impl)
        return
    res = plan(costs, s, g, use_compiled=impl)
    assert tuple(res.cells[0]) == s and tuple(res.cells[-1]) == g
    # the path it returns costs the optimum (fixed point: within 1e-6 per step)
    assert real_cost(costs, res.cells) == pytest.approx(best, abs=1e-6 * len(res.cells) + 1e-9)
    assert res.cost == pytest.approx(best, abs=1e-6 * len(res.cells) + 1e-9)
    assert res.length == pytest.approx(path_length(res.cells))


@pytest.mark.parametrize("weight", [0.0, 0.5, 5.0, 1000.0])
def test_cost_weight_and_unknown(weight: float, impl: bool) -> None:
    for seed in range(6):
        costs = random_costs(100 + seed, (15, 15))
        costs[0, 0] = costs[14, 14] = 0
        for allow in (True, False):
            best = dijkstra(costs, (0, 0), (14, 14), weight, allow)
            params = PlannerParams(cost_weight=weight, allow_unknown=allow)
            if math.isinf(best):
                with pytest.raises(NoValidPath):
                    plan(costs, (0, 0), (14, 14), params, use_compiled=impl)
                continue
            res = plan(costs, (0, 0), (14, 14), params, use_compiled=impl)
            assert real_cost(costs, res.cells, weight) == pytest.approx(best, abs=1e-4)
            if not allow:
                assert not (costs[res.cells[:, 1], res.cells[:, 0]] == 255).any()


def test_compiled_matches_python_reference() -> None:
    if compiled is None:
        pytest.skip("the planner's C search is not built here")
    for seed in range(30):
        costs = random_costs(200 + seed, (40, 50))
        costs[0, 0] = costs[-1, -1] = 0
        outs = []
        for use in (True, False):
            try:
                outs.append(plan(costs, (0, 0), (49, 39), use_compiled=use))
            except NoValidPath as e:
                outs.append(e)
        a, b = outs
        if isinstance(a, Exception) or isinstance(b, Exception):
            assert type(a) is type(b)
            continue
        assert np.array_equal(a.cells, b.cells)
        assert a.cost == b.cost and a.expansions == b.expansions
        assert a.compiled and not b.compiled


def test_lethal_and_inscribed_cells_refused(impl: bool) -> None:
    costs = np.zeros((5, 9), np.uint8)
    costs[:, 4] = 253
    with pytest.raises(NoValidPath):
        plan(costs, (0, 2), (8, 2), use_compiled=impl)
    costs[2, 4] = 252  # a costly gap is fine
    res = plan(costs, (0, 2), (8, 2), use_compiled=impl)
    assert (4, 2) in {tuple(c) for c in res.cells}
    # lethal_cost 254 lets the robot's centre through inscribed cells
    costs[2, 4] = 253
    res = plan(costs, (0, 2), (8, 2), PlannerParams(lethal_cost=254), use_compiled=impl)
    assert len(res.cells) == 9


def test_costs_steer_away_from_obstacles(impl: bool) -> None:
    costs = np.zeros((11, 30), np.uint8)
    costs[5, 3:27] = 200  # an expensive band along the straight line
    straight = plan(costs, (0, 5), (29, 5), PlannerParams(cost_weight=0.0), use_compiled=impl)
    assert straight.length == 29
    aware = plan(costs, (0, 5), (29, 5), use_compiled=impl)
    assert not (costs[aware.cells[:, 1], aware.cells[:, 0]] == 200).any()


def test_errors_carry_compute_path_to_pose_codes(impl: bool) -> None:
    costs = np.zeros((10, 10), np.uint8)
    costs[5, 5] = 254
    costs[0, 9] = 253
    cases: list[tuple[tuple[int, int], tuple[int, int], type[PlanningError], int]] = [
        ((-1, 0), (3, 3), StartOutsideMap, 203),
        ((0, 0), (3, 10), GoalOutsideMap, 204),
        ((5, 5), (3, 3), StartOccupied, 205),
        ((0, 0), (9, 0), GoalOccupied, 206),
    ]
    for s, g, err, code in cases:
        with pytest.raises(err) as info:
            plan(costs, s, g, use_compiled=impl)
        assert info.value.code == code
    costs[:, 7] = 254
    with pytest.raises(NoValidPath) as nv:
        plan(costs, (0, 0), (9, 9), use_compiled=impl)
    assert nv.value.code == 208
    with pytest.raises(ValueError, match="cell"):
        plan(costs, ("a", 0), (3, 3), use_compiled=impl)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="cell"):
        plan(costs, (1.5, 0), (3, 3), use_compiled=impl)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="cell"):
        plan(costs, (1, 0, 2), (3, 3), use_compiled=impl)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="2-D"):
        plan(np.zeros(5, np.uint8), (0, 0), (1, 0), use_compiled=impl)
    with pytest.raises(ValueError, match="cost bytes"):
        plan(np.zeros((3, 3)), (0, 0), (1, 0), use_compiled=impl)
    with pytest.raises(ValueError, match="cost bytes"):
        plan(np.full((3, 3), 300), (0, 0), (1, 0), use_compiled=impl)
    res = plan(np.zeros((3, 3), np.int64), (np.int64(0), 0), (2, 2), use_compiled=impl)
    assert res.length == pytest.approx(2 * math.sqrt(2))


def test_timeout_and_iteration_limit(impl: bool) -> None:
    n = 600 if impl else 120
    costs = np.zeros((n, n), np.uint8)
    for i, y in enumerate(range(3, n - 3, 6)):  # a long serpentine
        costs[y, :] = 254
        costs[y, (n - 2, n - 1) if i % 2 == 0 else (0, 1)] = 0
    with pytest.raises(PlanningTimeout) as t:
        plan(costs, (0, 0), (n - 1, n - 1), PlannerParams(timeout=1e-6), use_compiled=impl)
    assert t.value.code == 207
    with pytest.raises(NoValidPath, match="maximum iterations"):
        plan(costs, (0, 0), (n - 1, n - 1), PlannerParams(max_iterations=100), use_compiled=impl)


def test_search_statuses_on_both_paths() -> None:
    """The search itself stops on its budget (status 2) and expansion limit (status 3)
    after the same number of expansions in C and in Python."""
    costs = np.zeros((120, 120), np.uint8)
    costs[60, :119] = 254  # the goal is behind a wall with a gap at the far end
    steps, hs, hd = step_table(cost_multipliers(PlannerParams()))
    goal = 119 * 120 + 0
    impls: list[Callable[..., SearchOutcome]] = [search_python]
    if compiled is not None:
        module = compiled

        def c_search(grid: np.ndarray, *args: Any) -> SearchOutcome:
            st, raw, g, n = module.search(grid, grid.shape[1], grid.shape[0], *args)
            return SearchOutcome(st, np.frombuffer(raw, np.int32), g, n)

        impls.append(c_search)
    for search in impls:
        out = search(costs, steps, 0, goal, hs, hd, 1e-9, 0)
        assert out.status == TIMEOUT and out.expansions == 1024 and out.path.size == 0
        out = search(costs, steps, 0, goal, hs, hd, 0.0, 500)
        assert out.status == LIMIT and out.expansions == 501
        out = search(costs, steps, 0, goal, hs, hd, 0.0, 0)
        assert out.status == FOUND and out.path[0] == goal and out.path[-1] == 0


def test_goal_tolerance_moves_an_occupied_goal(impl: bool) -> None:
    costs = np.zeros((20, 20), np.uint8)
    costs[8:13, 8:13] = 254
    with pytest.raises(GoalOccupied):
        plan(costs, (0, 0), (10, 10), use_compiled=impl)
    with pytest.raises(GoalOccupied):
        plan(costs, (0, 0), (10, 10), PlannerParams(goal_tolerance=2), use_compiled=impl)
    res = plan(costs, (0, 0), (10, 10), PlannerParams(goal_tolerance=3), use_compiled=impl)
    assert res.goal == (10, 7) and tuple(res.cells[-1]) == (10, 7)


def test_start_is_goal(impl: bool) -> None:
    res = plan(np.zeros((4, 4), np.uint8), (2, 1), (2, 1), use_compiled=impl)
    assert res.cells.tolist() == [[2, 1]] and res.cost == 0 and res.length == 0
    assert res.poses(0.1).tolist() == [[0.25, 0.15000000000000002, 0.0]]


def test_poses_and_plan_between() -> None:
    occ = np.zeros((50, 80), np.int8)
    cm = Costmap2D(occ, 0.1, (-2.0, 1.0))
    res = plan_between(cm, (-1.95, 1.05), (5.95, 1.05))
    poses = res.poses(cm.resolution, cm.origin)
    assert poses.shape == (80, 3)
    assert poses[0, :2] == pytest.approx((-1.95, 1.05))
    assert poses[-1, :2] == pytest.approx((5.95, 1.05))
    assert np.allclose(poses[:, 2], 0.0)
    with pytest.raises(StartOutsideMap):
        plan_between(cm, (-3.0, 1.5), (0.0, 2.0))
    with pytest.raises(GoalOutsideMap):
        plan_between(cm, (0.0, 2.0), (0.0, math.nan))


def test_bad_params() -> None:
    for kw in ({"cost_weight": -1.0}, {"cost_weight": math.nan}, {"cost_weight": 1e4},
               {"lethal_cost": 0},
               {"timeout": -1.0}, {"max_iterations": -1}, {"goal_tolerance": -2}):
        with pytest.raises(ValueError):
            PlannerParams(**kw)  # type: ignore[arg-type]
