"""The obstacle layer: marking and clearing from a laser scan (Nav2's ObstacleLayer rules)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from zenros.msgs.sensor_msgs import LaserScan
from zenros.services.nav.costmap import Costmap2D, CostmapParams, ObstacleParams, Scan
from zenros.services.nav.costmap.geometry import GridGeometry
from zenros.services.nav.costmap.obstacle import raytrace_cells

RES = 0.05
NO_INFLATION = CostmapParams(inflation_radius=0.0)


def ring_scan(r: float | list[float], n: int = 360, range_max: float = 10.0) -> LaserScan:
    ranges = np.full(n, r, dtype=np.float32) if np.isscalar(r) else np.asarray(r, np.float32)
    return LaserScan(angle_min=-math.pi, angle_max=math.pi, angle_increment=2 * math.pi / n,
                     range_min=0.05, range_max=range_max, ranges=ranges)


def empty(params: CostmapParams = NO_INFLATION, size: int = 100) -> Costmap2D:
    return Costmap2D(np.zeros((size, size), np.int8), RES, (0.0, 0.0), params)


def cell_of(cm: Costmap2D, x: float, y: float) -> tuple[int, int]:
    c = cm.world_to_map(x, y)
    assert c is not None
    return c


def test_marks_hits_and_clears_the_ray() -> None:
    cm = empty()
    cm.update_from_scan(ring_scan(1.0), (2.5, 2.5, 0.0))
    hit = cell_of(cm, 3.5, 2.5)
    assert cm.cost(*hit) == 254
    assert cm.cost(*cell_of(cm, 3.0, 2.5)) == 0
    lethal = np.argwhere(cm.costs == 254)
    d = np.hypot((lethal[:, 1] + 0.5) * RES - 2.5, (lethal[:, 0] + 0.5) * RES - 2.5)
    assert np.all(np.abs(d - 1.0) < 2 * RES)
    # the obstacle moves away: the old ring is cleared by rays passing through it
    cm.update_from_scan(ring_scan(2.0), (2.5, 2.5, 0.0))
    assert cm.cost(*hit) == 0
    assert cm.cost(*cell_of(cm, 4.5, 2.5)) == 254


def test_yaw_rotates_beams() -> None:
    cm = empty()
    ranges = np.full(4, np.inf, np.float32)
    ranges[2] = 1.0  # angle_min -pi + 2 * pi/2 = 0 in the sensor frame
    scan = LaserScan(angle_min=-math.pi, angle_increment=math.pi / 2, range_min=0.0, range_max=5.0,
                     ranges=ranges)
    cm.update_from_scan(scan, (2.5, 2.5, math.pi / 2))
    assert cm.cost(*cell_of(cm, 2.5, 3.5)) == 254
    assert int((cm.costs == 254).sum()) == 1


def test_ranges_limits() -> None:
    p = NO_INFLATION.with_(obstacle=ObstacleParams(obstacle_max_range=2.5, raytrace_max_range=3.0))
    cm = empty(p, size=200)
    cm.mark([(5.0 + 2.9, 5.0)])
    cm.mark([(5.0 + 3.5, 5.0)])
    # a hit at 4.0 m: beyond obstacle_max_range (no mark), clears up to 3.0 m only
    ranges = np.full(360, np.nan, np.float32)
    ranges[180] = 4.0  # angle 0
    cm.update_from_scan(ring_scan(ranges.tolist()), (5.0, 5.0, 0.0))
    assert cm.cost(*cell_of(cm, 9.0, 5.0)) == 0
    assert cm.cost(*cell_of(cm, 7.9, 5.0)) == 0  # within 3.0 m: cleared
    assert cm.cost(*cell_of(cm, 8.5, 5.0)) == 254  # beyond raytrace_max_range: kept


def test_invalid_readings_neither_mark_nor_clear() -> None:
    cm = empty()
    cm.mark([(3.0, 2.5)])
    ranges = [math.nan, math.inf, -1.0, 0.01, 11.0]  # range_min 0.05, range_max 10
    scan = LaserScan(angle_min=0.0, angle_increment=0.0, range_min=0.05, range_max=10.0,
                     ranges=np.array(ranges, np.float32))
    assert cm.update_from_scan(scan, (2.5, 2.5, 0.0)).empty
    assert cm.cost(*cell_of(cm, 3.0, 2.5)) == 254


def test_inf_is_valid_clears_to_range_max() -> None:
    p = NO_INFLATION.with_(obstacle=ObstacleParams(inf_is_valid=True, raytrace_max_range=3.0))
    cm = empty(p)
    cm.mark([(3.0, 2.5)])
    scan = LaserScan(angle_min=0.0, angle_increment=0.0, range_min=0.05, range_max=2.0,
                     ranges=np.array([math.inf], np.float32))
    cm.update_from_scan(scan, (2.5, 2.5, 0.0))
    assert cm.cost(*cell_of(cm, 3.0, 2.5)) == 0
    assert int((cm.costs == 254).sum()) == 0


def test_clearing_never_removes_the_static_map() -> None:
    occ = np.zeros((100, 100), np.int8)
    occ[50, 60] = 100  # (3.0 .. 3.05, 2.5)
    cm = Costmap2D(occ, RES, (0.0, 0.0), NO_INFLATION)
    cm.update_from_scan(ring_scan(2.0), (2.5, 2.5, 0.0))
    assert cm.costs[50, 60] == 254


def test_hit_cell_not_cleared_by_its_own_beam() -> None:
    cm = empty()
    scan = Scan(angle_min=0.3, angle_increment=0.0, range_min=0.0, range_max=10.0,
                ranges=np.array([1.37], np.float64))
    cm.update_from_scan(scan, (2.51, 2.47, 0.0))
    x, y = 2.51 + 1.37 * math.cos(0.3), 2.47 + 1.37 * math.sin(0.3)
    assert cm.cost(*cell_of(cm, x, y)) == 254


def test_unknown_becomes_known_where_seen() -> None:
    p = NO_INFLATION.with_(track_unknown_space=True)
    cm = Costmap2D(np.full((100, 100), -1, np.int8), RES, (0.0, 0.0), p)
    assert np.all(cm.costs == 255)
    cm.update_from_scan(ring_scan(1.0), (2.5, 2.5, 0.0))
    assert cm.cost(*cell_of(cm, 3.0, 2.5)) == 0
    assert cm.cost(*cell_of(cm, 3.5, 2.5)) == 254
    assert cm.cost(*cell_of(cm, 4.0, 2.5)) == 255


def test_update_window_matches_full_rebuild() -> None:
    rng = np.random.default_rng(5)
    occ = np.where(rng.random((120, 150)) < 0.01, 100, 0).astype(np.int8)
    p = CostmapParams(inflation_radius=0.5, cost_scaling_factor=3.0)
    cm = Costmap2D(occ, RES, (-1.0, -2.0), p)
    for _ in range(10):
        pose = (float(rng.uniform(0, 5)), float(rng.uniform(-1, 3)), float(rng.uniform(-3, 3)))
        r = rng.uniform(0.3, 4.0, 360)
        r[rng.random(360) < 0.1] = np.inf
        cm.update_from_scan(ring_scan(r.tolist()), pose)
        before = cm.costs.copy()
        cm.rebuild()
        assert np.array_equal(before, cm.costs)


def test_bad_pose_or_scan_is_a_clear_error() -> None:
    cm = empty()
    with pytest.raises(ValueError, match="pose"):
        cm.update_from_scan(ring_scan(1.0), (math.nan, 0.0, 0.0))
    bad = LaserScan(angle_min=math.nan, angle_increment=0.1, range_max=5.0,
                    ranges=np.ones(3, np.float32))
    with pytest.raises(ValueError, match="angles"):
        cm.update_from_scan(bad, (1.0, 1.0, 0.0))


def test_raytrace_cells_are_8_connected_and_exclude_end() -> None:
    geo = GridGeometry(50, 50, 1.0)
    mx, my = raytrace_cells(geo, 0.5, 0.5, np.array([10.5]), np.array([4.5]))
    cells = list(zip(mx.tolist(), my.tolist(), strict=True))
    assert cells[0] == (0, 0) and (10, 4) not in cells
    assert len(cells) == 10
    for (x0, y0), (x1, y1) in itertools.pairwise(cells):
        assert max(abs(x1 - x0), abs(y1 - y0)) == 1


def test_sensor_outside_the_map_marks_but_does_not_clear() -> None:
    cm = empty()
    cm.mark([(0.5, 2.5)])
    ranges = np.full(360, np.inf, np.float32)
    ranges[180] = 2.0  # angle 0: from (-1.0, 2.5) to (1.0, 2.5), through the marked cell
    cm.update_from_scan(ring_scan(ranges.tolist()), (-1.0, 2.5, 0.0))
    assert cm.cost(*cell_of(cm, 0.5, 2.5)) == 254  # Nav2 cannot raytrace from off the map
    assert cm.cost(*cell_of(cm, 1.0, 2.5)) == 254  # the hit is marked


def test_huge_ranges_and_many_beams_stay_bounded() -> None:
    p = NO_INFLATION.with_(obstacle=ObstacleParams(obstacle_max_range=math.inf,
                                                   raytrace_max_range=math.inf))
    cm = empty(p)
    cm.mark([(4.9, 2.5)])
    scan = LaserScan(angle_min=0.0, angle_increment=2 * math.pi / 20000, range_min=0.0,
                     range_max=1e12, ranges=np.full(20000, 1e9, np.float32))
    cm.update_from_scan(scan, (2.5, 2.5, 0.0))
    assert int((cm.costs == 254).sum()) == 0  # every beam cleared across the whole map


def test_live_costmaps_skip_the_scan_they_applied_last_from_the_same_pose() -> None:
    from zenros.maps import GridMap
    from zenros.se2 import Pose2
    from zenros.services.nav.costmap.live import Costmaps

    live = Costmaps(NO_INFLATION, update_rate=2.0)
    live.set_map(GridMap(np.zeros((100, 100), np.int8), RES, (0.0, 0.0, 0.0)))
    here = Pose2(2.5, 2.5, 0.0)
    assert live.update_from_scan(ring_scan(1.0), here, 0.0)
    assert live.lethal_at(3.5, 2.5)
    # at rest: the same ranges from the same pose, once per period, change nothing
    assert not live.update_from_scan(ring_scan(1.0), here, 0.6)
    assert not live.update_from_scan(ring_scan(1.0), here, 1.2)
    assert (live.updates, live.unchanged) == (1, 2)
    assert not live.update_from_scan(ring_scan(1.0), here, 1.3)  # not due: not counted
    assert live.unchanged == 2
    # the obstacles cleared: the same scan marks them again
    live.clear_obstacles()
    assert not live.lethal_at(3.5, 2.5)
    assert live.update_from_scan(ring_scan(1.0), here, 1.8)
    assert live.lethal_at(3.5, 2.5)
    # other ranges, or another pose: applied
    assert live.update_from_scan(ring_scan(1.5), here, 2.4)
    assert live.lethal_at(4.0, 2.5) and not live.lethal_at(3.5, 2.5)
    assert live.update_from_scan(ring_scan(1.5), Pose2(2.5, 2.0, 0.0), 3.0)
    assert live.lethal_at(4.0, 2.0)
    assert live.updates == 4
