"""The inflation layer against Nav2's computeCost and a brute-force distance transform."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.services.nav.costmap import Costmap2D, CostmapParams, Inflation, inflation_cost
from zenros.services.nav.costmap.inflation import squared_distance


def nav2_cost(d: float, r_i: float, csf: float) -> int:
    if d == 0:
        return 254
    if d <= r_i:
        return 253
    return int(252 * math.exp(-1.0 * csf * (d - r_i)))


@pytest.mark.parametrize(
    ("csf", "expected"),
    [
        (3.0, {0.25: 230, 0.30: 198, 0.40: 146, 0.55: 93, 0.70: 59}),
        (10.0, {0.25: 186, 0.30: 113, 0.40: 41, 0.55: 9}),
    ],
)
def test_worked_values(csf: float, expected: dict[float, int]) -> None:
    for d, cost in expected.items():
        assert inflation_cost(d, 0.22, csf) == cost
    assert inflation_cost(0.0, 0.22, csf) == 254
    assert inflation_cost(0.22, 0.22, csf) == 253
    assert inflation_cost(0.05, 0.22, csf) == 253


def test_costmap_cells_follow_the_formula() -> None:
    res, r_i, csf, radius = 0.05, 0.22, 3.0, 0.7
    occ = np.zeros((61, 61), dtype=np.int8)
    occ[30, 30] = 100
    cm = Costmap2D(occ, res, (0.0, 0.0), CostmapParams(robot_radius=r_i, inflation_radius=radius,
                                                       cost_scaling_factor=csf))
    cells = math.ceil(radius / res)
    for my in range(61):
        for mx in range(61):
            d_cells = math.hypot(mx - 30, my - 30)
            want = nav2_cost(d_cells * res, r_i, csf) if d_cells <= cells else 0
            assert cm.costs[my, mx] == want, (mx, my)
    # the worked example along a row: 5 cells = 0.25 m
    assert cm.costs[30, 35] == 230 and cm.costs[30, 44] == 59


def test_inflation_radius_in_cells_is_nav2_cell_distance() -> None:
    # ceil(0.55 / 0.05) is 12 in floating point, as Nav2's cellDistance computes it
    assert Inflation(0.05, inflation_radius=0.55).cells == math.ceil(0.55 / 0.05)
    assert Inflation(0.05, inflation_radius=0.5).cells == 10


def test_cost_is_max_over_obstacles_and_never_lowers_static() -> None:
    occ = np.zeros((40, 40), dtype=np.int8)
    occ[10, 10] = 100
    occ[10, 16] = 100
    cm = Costmap2D(occ, 0.05, params=CostmapParams(inflation_radius=0.5, cost_scaling_factor=3.0))
    mid = cm.costs[10, 13]  # 3 cells from both
    assert mid == nav2_cost(0.15, 0.22, 3.0) == 253
    assert cm.costs[10, 10] == 254 and cm.costs[10, 16] == 254


def test_unknown_cells_take_only_inscribed_or_lethal() -> None:
    occ = np.full((30, 30), -1, dtype=np.int8)
    occ[:, :15] = 0
    occ[15, 10] = 100
    p = CostmapParams(track_unknown_space=True, inflation_radius=0.5, cost_scaling_factor=3.0)
    cm = Costmap2D(occ, 0.05, params=p)
    # 5 cells to the right of the obstacle is unknown: 0.25 m > r_i, so it stays 255
    assert cm.costs[15, 15] == 255
    assert cm.costs[15, 14] == 253  # known, 4 cells = 0.2 m: inscribed
    occ[15, 13] = 100
    cm2 = Costmap2D(occ, 0.05, params=p)
    # 2 cells from the obstacle at column 13: an unknown cell within r_i becomes 253
    assert cm2.costs[15, 15] == 253
    assert cm2.costs[15, 20] == 255
    cm3 = Costmap2D(occ, 0.05, params=p.with_(inflate_unknown=True))
    assert cm3.costs[15, 20] == nav2_cost(7 * 0.05, 0.22, 3.0)


def test_inflate_around_unknown() -> None:
    occ = np.zeros((20, 20), dtype=np.int8)
    occ[10, 10] = -1
    p = CostmapParams(track_unknown_space=True, inflation_radius=0.3, cost_scaling_factor=3.0)
    assert Costmap2D(occ, 0.05, params=p).costs[10, 12] == 0
    cm = Costmap2D(occ, 0.05, params=p.with_(inflate_around_unknown=True))
    # as in Nav2 the unknown source itself is at distance 0: it becomes lethal
    assert cm.costs[10, 12] == 253 and cm.costs[10, 10] == 254


def test_squared_distance_matches_brute_force() -> None:
    rng = np.random.default_rng(3)
    src = rng.random((37, 53)) < 0.02
    radius = 6
    got = squared_distance(src, radius)
    ys, xs = np.nonzero(src)
    for y in range(src.shape[0]):
        for x in range(src.shape[1]):
            d2 = int(((xs - x) ** 2 + (ys - y) ** 2).min()) if xs.size else 10**9
            if d2 <= radius * radius:
                assert got[y, x] == d2, (x, y)
            else:
                assert got[y, x] > radius * radius, (x, y)


def test_compiled_transform_matches_numpy_reference() -> None:
    from zenros.services.nav.costmap import inflation
    from zenros.services.nav.costmap.accel import edt

    if edt is None:
        pytest.skip("the costmap's C distance transform is not built here")
    for seed in range(60):
        rng = np.random.default_rng(seed)
        shape = (int(rng.integers(1, 50)), int(rng.integers(1, 50)))
        src = rng.random(shape) < rng.uniform(0.0, 0.2)
        r = int(rng.integers(0, 12))
        ref = squared_distance(src, r)
        got = inflation.distance_transform(src, r)
        near = ref <= r * r
        assert np.array_equal(ref[near], got[near]), seed
        assert np.all(got[~near] > r * r), seed


def test_costmaps_agree_with_and_without_compiled_transform(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from zenros.services.nav.costmap import inflation

    rng = np.random.default_rng(9)
    occ = np.where(rng.random((80, 90)) < 0.02, 100, 0).astype(np.int8)
    p = CostmapParams(inflation_radius=0.45, cost_scaling_factor=4.0)
    compiled_costs = Costmap2D(occ, 0.05, params=p).costs.copy()
    monkeypatch.setattr(inflation, "_edt", None)
    assert np.array_equal(Costmap2D(occ, 0.05, params=p).costs, compiled_costs)
