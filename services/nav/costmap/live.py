"""Costmaps: nav's global costmap (static, obstacle from scan, inflation, keep-out) and the
local rolling window, shared by the planner thread, the control loop and the publishers.

The global grid is the costmap package's `Costmap2D` over the whole map; scans update its
obstacle layer (at most ``update_rate`` times per second of the node's clock, since one
update costs a few milliseconds). The local costmap is the ``local_size`` square of the
same layered grid centred on the robot, as Nav2's rolling window would show it.
"""

from __future__ import annotations

import math
import threading
from typing import Any

import numpy as np
from zenros.maps import GridMap
from zenros.message import Int8Array
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Point, Pose
from zenros.msgs.nav_msgs import MapMetaData, OccupancyGrid
from zenros.msgs.std_msgs import Header
from zenros.se2 import Pose2

from ..maps.navdata import MapNavData
from .costmap import Costmap2D, CostmapParams
from .snapshot import CostSnapshot
from .values import LETHAL_OBSTACLE, NO_INFORMATION, cost_to_occupancy

__all__ = ["Costmaps"]


def _xy(points: list[Any]) -> list[tuple[float, float]]:
    return [(float(p.x), float(p.y)) for p in points]


class Costmaps:
    """The global costmap of the current map; thread-safe."""

    def __init__(self, params: CostmapParams, local_size: float = 3.0,
                 update_rate: float = 2.0) -> None:
        self.params = params
        self.local_size = local_size
        self.update_period = 1.0 / update_rate if update_rate > 0 else 0.0
        self._lock = threading.Lock()
        self._cm: Costmap2D | None = None
        self._last_update = -math.inf
        self.updates = 0
        self.unchanged = 0
        """Scans not applied since they were the last applied one, from the same pose."""
        self._applied: tuple[tuple[Any, ...], np.ndarray] | None = None

    def set_map(self, grid: GridMap, keepout: MapNavData | None = None) -> None:
        """Build the global costmap for a newly loaded map (and its keep-out shapes)."""
        cm = Costmap2D(grid.grid, grid.resolution, (grid.origin[0], grid.origin[1]), self.params)
        if keepout is not None:
            self._apply_keepout(cm, keepout)
        with self._lock:
            self._cm = cm
            self._last_update = -math.inf
            self._applied = None

    def drop(self) -> None:
        """Forget the map (until the next `set_map`): the costmaps are empty, plans fail."""
        with self._lock:
            self._cm = None
            self._applied = None

    def _apply_keepout(self, cm: Costmap2D, data: MapNavData) -> None:
        cm.set_keepout(polygons=[_xy(a.points) for a in data.forbidden_areas],
                       walls=[_xy(w.points) for w in data.virtual_walls])

    def set_keepout(self, data: MapNavData) -> None:
        with self._lock:
            if self._cm is not None:
                self._apply_keepout(self._cm, data)

    @property
    def ready(self) -> bool:
        return self._cm is not None

    def update_from_scan(self, scan: Any, sensor: Pose2, now: float) -> bool:
        """Mark and clear the obstacle layer from a scan taken at ``sensor`` (map frame);
        skipped (False) when the last update is younger than the update period, or when
        the scan and the pose are those of the last update (a robot at rest: clearing then
        marking the same cells again changes nothing)."""
        if now - self._last_update < self.update_period and now >= self._last_update:
            return False
        pose = (sensor.x, sensor.y, sensor.theta)
        key = (pose, float(scan.angle_min), float(scan.angle_increment),
               float(scan.range_min), float(scan.range_max))
        ranges = np.asarray(scan.ranges)
        with self._lock:
            if self._cm is None:
                return False
            if self._applied is not None and self._applied[0] == key \
                    and np.array_equal(self._applied[1], ranges):
                self._last_update = now
                self.unchanged += 1
                return False
            self._applied = None  # the layer is half-updated if the update raises
            self._cm.update_from_scan(scan, pose)
            self._applied = (key, ranges.copy())
            self._last_update = now
            self.updates += 1
        return True

    def clear_obstacles(self) -> None:
        with self._lock:
            self._applied = None  # the next scan marks what is still there
            if self._cm is not None:
                self._cm.clear_obstacles()

    def snapshot(self) -> CostSnapshot:
        with self._lock:
            if self._cm is None:
                raise RuntimeError("no map loaded: the global costmap is empty")
            return CostSnapshot(np.array(self._cm.costs), self._cm.resolution, self._cm.origin)

    def cost_at(self, x: float, y: float) -> int:
        cm = self._cm
        return NO_INFORMATION if cm is None else cm.cost_at(x, y)

    def near_static(self, points: np.ndarray, reach: float) -> np.ndarray:
        """Whether each (N, 2) map point is within ``reach`` m of the static map's walls
        (all false without a map)."""
        cm = self._cm
        if cm is None or len(points) == 0:
            return np.zeros(len(points), dtype=bool)
        return cm.near_static(points, reach)

    def keepout_hit(self, points: np.ndarray) -> bool:
        """True when any of the (N, 2) map points lies in a keep-out cell."""
        cm = self._cm
        if cm is None or len(points) == 0:
            return False
        mask = cm.keepout_mask
        cells = cm.geometry.world_to_cells(np.asarray(points, dtype=np.float64))
        mx, my = cells[:, 0], cells[:, 1]
        inside = (mx >= 0) & (mx < cm.width) & (my >= 0) & (my < cm.height)
        return bool(mask[my[inside], mx[inside]].any())

    def in_keepout(self, x: float, y: float) -> bool:
        return self.keepout_hit(np.array([[x, y]]))

    def lethal_at(self, x: float, y: float) -> bool:
        return self.cost_at(x, y) == LETHAL_OBSTACLE

    def global_msg(self, stamp: Time, frame_id: str = "map") -> OccupancyGrid | None:
        with self._lock:
            return None if self._cm is None else self._cm.to_occupancy_grid(frame_id, stamp)

    def local_msg(self, center: Pose2, stamp: Time, frame_id: str = "map") -> OccupancyGrid | None:
        """The ``local_size`` window around ``center``, cells aligned with the global grid
        (outside the map: unknown)."""
        with self._lock:
            cm = self._cm
            if cm is None:
                return None
            res = cm.resolution
            n = max(1, round(self.local_size / res))
            cx = math.floor((center.x - cm.origin[0]) / res) - n // 2
            cy = math.floor((center.y - cm.origin[1]) / res) - n // 2
            win = np.full((n, n), NO_INFORMATION, dtype=np.uint8)
            x0, y0 = max(cx, 0), max(cy, 0)
            x1, y1 = min(cx + n, cm.width), min(cy + n, cm.height)
            if x1 > x0 and y1 > y0:
                win[y0 - cy:y1 - cy, x0 - cx:x1 - cx] = cm.costs[y0:y1, x0:x1]
        origin = Pose(position=Point(x=cm.origin[0] + cx * res, y=cm.origin[1] + cy * res))
        return OccupancyGrid(
            header=Header(stamp=stamp, frame_id=frame_id),
            info=MapMetaData(map_load_time=stamp, resolution=res, width=n, height=n,
                             origin=origin),
            data=cost_to_occupancy(win).ravel().view(Int8Array))
