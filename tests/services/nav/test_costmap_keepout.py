"""Keep-out areas and virtual walls: rasterised lethal cells, not inflated, never crossed."""

from __future__ import annotations

import numpy as np
import pytest
from zenros.services.nav.costmap import Costmap2D, CostmapParams
from zenros.services.nav.costmap.geometry import GridGeometry
from zenros.services.nav.costmap.keepout import rasterise
from zenros.services.nav.planning import NoValidPath, plan

RES = 0.05
PARAMS = CostmapParams(inflation_radius=0.5, cost_scaling_factor=3.0)


def open_map(size: int = 100) -> Costmap2D:
    return Costmap2D(np.zeros((size, size), np.int8), RES, (0.0, 0.0), PARAMS)


def test_wall_is_lethal_and_not_inflated() -> None:
    cm = open_map()
    cm.set_keepout(walls=[[(1.0, 0.5), (1.0, 4.5)]])
    col = 20
    assert np.all(cm.costs[10:90, col] == 254)
    assert np.all(cm.costs[10:90, col + 1] == 0)  # free space beside it stays free
    assert np.all(cm.costs[10:90, col - 1] == 0)
    assert cm.keepout_mask.sum() == 80 or cm.keepout_mask.sum() == 81


def test_wall_over_unknown_and_over_inflation() -> None:
    occ = np.zeros((100, 100), np.int8)
    occ[50, 25] = 100
    occ[:, 80:] = -1
    cm = Costmap2D(occ, RES, (0.0, 0.0), PARAMS.with_(track_unknown_space=True))
    cm.set_keepout(walls=[[(1.0, 0.0), (1.0, 5.0)], [(4.5, 0.0), (4.5, 5.0)]])
    assert cm.costs[50, 20] == 254  # on top of the obstacle's inflation
    assert np.all(cm.costs[:, 90] == 254)  # on unknown cells


@pytest.mark.parametrize(
    "direction", [(1.0, 0.87), (0.87, 1.0), (1.0, -0.33), (0.2, 1.0), (1.0, 0.5)]
)
def test_diagonal_wall_blocks_8_connected_paths(direction: tuple[float, float]) -> None:
    # a wall through the middle of the map, across it in any direction
    cm = open_map()
    d = np.array(direction) / np.hypot(*direction)
    mid = np.array([2.5, 2.5])
    cm.set_keepout(walls=[[tuple(mid - 10 * d), tuple(mid + 10 * d)]])
    mask = cm.keepout_mask
    ys, xs = np.nonzero(~mask)
    px, py = (xs + 0.5) * RES - mid[0], (ys + 0.5) * RES - mid[1]
    side = np.sign(d[0] * py - d[1] * px)
    near = np.hypot(px, py)
    left = np.argmin(np.where(side > 0, near, np.inf))
    right = np.argmin(np.where(side < 0, near, np.inf))
    a, b = (int(xs[left]), int(ys[left])), (int(xs[right]), int(ys[right]))
    assert max(abs(a[0] - b[0]), abs(a[1] - b[1])) <= 3  # the two cells are close ...
    with pytest.raises(NoValidPath):
        plan(cm.costs, a, b)  # ... yet no 8-connected path crosses the wall
    far = np.argmax(np.where(side > 0, near, -np.inf))
    res = plan(cm.costs, a, (int(xs[far]), int(ys[far])))
    assert not mask[res.cells[:, 1], res.cells[:, 0]].any()


def test_supercover_line_is_4_connected() -> None:
    geo = GridGeometry(200, 200, 0.05)
    rng = np.random.default_rng(2)
    for _ in range(50):
        a, b = rng.uniform(0, 10, 2), rng.uniform(0, 10, 2)
        mask = rasterise(geo, walls=[[tuple(a), tuple(b)]])
        cells = np.argwhere(mask)
        # 4-connected: flood fill from one cell with 4-neighbours reaches them all
        todo = [tuple(cells[0])]
        seen = {todo[0]}
        cellset = {tuple(c) for c in cells}
        while todo:
            y, x = todo.pop()
            for n in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
                if n in cellset and n not in seen:
                    seen.add(n)
                    todo.append(n)
        assert len(seen) == len(cellset)


def test_polygon_covers_interior_and_outline() -> None:
    cm = open_map()
    cm.set_keepout(polygons=[[(1.0, 1.0), (3.0, 1.0), (3.0, 2.0), (1.0, 2.0)]])
    assert np.all(cm.costs[21:39, 21:59] == 254)
    assert cm.costs[19, 30] == 0 and cm.costs[41, 30] == 0
    # a triangle: a point inside and one outside
    cm.set_keepout(polygons=[[(0.5, 0.5), (4.5, 0.5), (2.5, 4.5)]])
    assert cm.cost_at(2.5, 2.0) == 254
    assert cm.cost_at(0.7, 4.0) == 0
    assert cm.cost_at(2.0, 1.5) == 254  # the old rectangle is gone where the triangle is not
    assert cm.cost_at(1.05, 1.95) == 0


def test_replacing_and_clearing_shapes_restores_costs() -> None:
    occ = np.zeros((100, 100), np.int8)
    occ[50, 50] = 100
    cm = Costmap2D(occ, RES, (0.0, 0.0), PARAMS)
    before = cm.costs.copy()
    cm.set_keepout(walls=[[(2.0, 0.0), (2.0, 5.0)]])
    assert not np.array_equal(before, cm.costs)
    cm.set_keepout()
    assert np.array_equal(before, cm.costs)


def test_bad_shapes_are_clear_errors_and_keep_previous() -> None:
    cm = open_map()
    cm.set_keepout(walls=[[(1.0, 1.0), (1.0, 4.0)]])
    kept = cm.costs.copy()
    with pytest.raises(ValueError, match="polygon needs at least 3"):
        cm.set_keepout(polygons=[[(0.0, 0.0), (1.0, 1.0)]])
    with pytest.raises(ValueError, match="non-finite"):
        cm.set_keepout(walls=[[(0.0, 0.0), (float("nan"), 1.0)]])
    with pytest.raises(ValueError, match="points"):
        cm.set_keepout(walls=[[1.0, 2.0, 3.0]])
    assert np.array_equal(kept, cm.costs)


def test_shapes_partly_outside_the_map() -> None:
    cm = open_map()
    cm.set_keepout(
        walls=[[(-3.0, 2.5), (9.0, 2.5)]],
        polygons=[[(-1, -1), (0.5, -1), (0.5, 0.5), (-1, 0.5)]],
    )
    assert np.all(cm.costs[50, :] == 254)
    assert np.all(cm.costs[:10, :10] == 254)


def test_planner_goes_around_a_wall_with_a_gap() -> None:
    cm = open_map()
    cm.set_keepout(walls=[[(2.5, 0.0), (2.5, 4.0)]])  # a gap from y = 4.0 to 5.0
    res = plan(cm.costs, (10, 10), (90, 10))
    mask = cm.keepout_mask
    assert not mask[res.cells[:, 1], res.cells[:, 0]].any()
    assert res.cells[:, 1].max() >= 80


def test_far_away_coordinates_are_clipped_not_walked() -> None:
    cm = open_map()
    cm.set_keepout(walls=[[(-1e12, 2.5), (1e12, 2.5)], [(1e9, 1e9), (2e9, 2e9)]])
    assert np.all(cm.costs[50, :] == 254) and int(cm.keepout_mask.sum()) == 100
