"""Costmap2D: construction, geometry, layers combined, published OccupancyGrid."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.codec import codec_for
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Point, Pose
from zenros.msgs.nav_msgs import MapMetaData, OccupancyGrid
from zenros.services.nav.costmap import Costmap2D, CostmapParams


def grid_msg(occ: np.ndarray, res: float, origin: tuple[float, float]) -> OccupancyGrid:
    h, w = occ.shape
    return OccupancyGrid(
        info=MapMetaData(resolution=res, width=w, height=h,
                         origin=Pose(position=Point(x=origin[0], y=origin[1]))),
        data=occ.ravel().astype(np.int8),
    )


def test_from_occupancy_grid_and_geometry() -> None:
    occ = np.zeros((20, 30), np.int8)
    occ[0, 0] = 100  # row 0 is the bottom row, at the origin
    cm = Costmap2D.from_occupancy_grid(grid_msg(occ, 0.1, (-1.0, 2.0)))
    assert (cm.width, cm.height, cm.resolution, cm.origin) == (30, 20, 0.1, (-1.0, 2.0))
    assert cm.world_to_map(-0.95, 2.05) == (0, 0)
    assert cm.cost_at(-0.95, 2.05) == 254
    assert cm.world_to_map(1.95, 3.95) == (29, 19)
    assert cm.world_to_map(2.0, 3.0) is None
    assert cm.world_to_map(-1.01, 2.5) is None
    assert cm.world_to_map(math.nan, 2.5) is None
    assert cm.cost_at(10.0, 10.0) == 255
    x, y = cm.map_to_world(3, 4)
    assert math.isclose(x, -0.65) and math.isclose(y, 2.45)
    assert cm.world_to_map(x, y) == (3, 4)


def test_to_occupancy_grid_uses_the_published_scale() -> None:
    occ = np.zeros((40, 40), np.int8)
    occ[20, 20] = 100
    occ[0:2, 0:2] = -1
    p = CostmapParams(inflation_radius=0.5, cost_scaling_factor=3.0, track_unknown_space=True)
    cm = Costmap2D(occ, 0.05, (1.0, -1.0), p)
    msg = cm.to_occupancy_grid("map", Time(sec=7, nanosec=5))
    assert msg.header.frame_id == "map" and msg.header.stamp.sec == 7
    assert (msg.info.width, msg.info.height, msg.info.resolution) == (40, 40, 0.05)
    assert (msg.info.origin.position.x, msg.info.origin.position.y) == (1.0, -1.0)
    g = msg.grid()
    assert g[20, 20] == 100 and g[20, 22] == 99 and g[0, 0] == -1 and g[39, 39] == 0
    c = int(cm.costs[20, 25])
    assert 0 < c < 253 and g[20, 25] == 1 + (97 * (c - 1)) // 251
    # the message survives its own codec
    codec = codec_for(OccupancyGrid)
    again = codec.decode(codec.encode(msg))
    assert np.array_equal(np.asarray(again.data), np.asarray(msg.data))


def test_costs_view_is_read_only() -> None:
    cm = Costmap2D(np.zeros((5, 5), np.int8), 0.1)
    with pytest.raises(ValueError):
        cm.costs[0, 0] = 1


def test_no_static_map() -> None:
    cm = Costmap2D(None, 0.05, (0.0, 0.0), CostmapParams(track_unknown_space=True), shape=(10, 20))
    assert cm.costs.shape == (10, 20) and np.all(cm.costs == 255)
    with pytest.raises(ValueError, match="shape"):
        Costmap2D(None, 0.05)


def test_bad_construction_is_a_clear_error() -> None:
    with pytest.raises(ValueError, match="resolution"):
        Costmap2D(np.zeros((3, 3), np.int8), 0.0)
    with pytest.raises(ValueError, match="resolution"):
        Costmap2D(np.zeros((3, 3), np.int8), math.nan)
    with pytest.raises(ValueError, match="2-D"):
        Costmap2D(np.zeros(9, np.int8), 0.05)
    with pytest.raises(ValueError, match="origin"):
        Costmap2D(np.zeros((3, 3), np.int8), 0.05, (math.inf, 0.0))
    with pytest.raises(ValueError, match="cells"):
        bad = grid_msg(np.zeros((3, 3), np.int8), 0.05, (0, 0))
        bad.info.width = 4
        Costmap2D.from_occupancy_grid(bad)
    with pytest.raises(ValueError, match="inflation_radius"):
        Costmap2D(np.zeros((3, 3), np.int8), 0.05, params=CostmapParams(inflation_radius=-1.0))


def test_set_static_mark_and_clear_obstacles() -> None:
    p = CostmapParams(inflation_radius=0.3, cost_scaling_factor=3.0)
    cm = Costmap2D(np.zeros((40, 40), np.int8), 0.05, (0.0, 0.0), p)
    cm.mark([(1.0, 1.0), (50.0, 50.0)])  # the second is outside: ignored
    assert cm.cost_at(1.0, 1.0) == 254 and cm.cost_at(1.1, 1.0) == 253
    cm.clear_obstacles()
    assert np.all(cm.costs == 0)
    occ = np.zeros((40, 40), np.int8)
    occ[10, 10] = 100
    cm.set_static(occ)
    assert cm.costs[10, 10] == 254 and cm.costs[10, 12] == 253
    with pytest.raises(ValueError, match="shape"):
        cm.set_static(np.zeros((3, 3), np.int8))
    with pytest.raises(IndexError):
        cm.cost(40, 0)
