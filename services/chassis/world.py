"""World: the map's solid cells with their distance field, plus the movable obstacles.

A cell is solid when its occupancy is >= ``OCCUPIED_AT`` (unknown cells are not solid);
outside the grid counts as solid for the robot's body (it cannot leave the map) and as
"no return" for the laser. Coordinates are metres in ``map``; the map's yaw must be 0.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
from scipy.ndimage import distance_transform_edt
from zenros.errors import ConfigError
from zenros.maps import GridMap

from .obstacles import Obstacle

__all__ = ["OCCUPIED_AT", "World"]

OCCUPIED_AT = 50


class World:
    """The static map and the movable obstacles, with overlap tests for a round body."""

    def __init__(self, grid_map: GridMap) -> None:
        if abs(grid_map.origin[2]) > 1e-9:
            raise ConfigError("the simulator needs a map whose origin yaw is 0")
        self.map = grid_map
        self.res = float(grid_map.resolution)
        self.ox, self.oy = float(grid_map.origin[0]), float(grid_map.origin[1])
        self.height: int = grid_map.grid.shape[0]
        self.width: int = grid_map.grid.shape[1]
        self.solid = np.ascontiguousarray(grid_map.grid >= OCCUPIED_AT)
        # metres from each cell centre to the nearest solid cell centre (0 on solid cells)
        if self.solid.any():
            edt = distance_transform_edt(~self.solid) * self.res
        else:
            edt = np.full(self.solid.shape, 1e9)
        self.edt = np.ascontiguousarray(edt, dtype=np.float32)
        self.obstacles: dict[str, Obstacle] = {}
        self.generation = 0  # counts `take_map` calls: what caches the map checks

    def take_map(self, other: World) -> None:
        """Become ``other``'s map in place (the robot changed floors): every device holding
        this world sees the new one; caches of the map compare ``generation``. The
        obstacles are the caller's to swap."""
        self.map, self.res, self.ox, self.oy = other.map, other.res, other.ox, other.oy
        self.height, self.width = other.height, other.width
        self.solid, self.edt = other.solid, other.edt
        self.generation += 1

    # ---------------------------------------------------------------- cells

    def cell(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the cell holding (x, y); may be outside the grid."""
        return math.floor((y - self.oy) / self.res), math.floor((x - self.ox) / self.res)

    def inside(self, x: float, y: float) -> bool:
        r, c = self.cell(x, y)
        return 0 <= r < self.height and 0 <= c < self.width

    def cell_centre(self, row: int, col: int) -> tuple[float, float]:
        return self.ox + (col + 0.5) * self.res, self.oy + (row + 0.5) * self.res

    # ---------------------------------------------------------------- overlap

    def map_clearance(self, x: float, y: float, limit: float) -> float:
        """Distance from (x, y) to the nearest solid cell or the map's edge, exact up to
        ``limit`` (anything farther returns a value >= limit)."""
        r, c = self.cell(x, y)
        if not (0 <= r < self.height and 0 <= c < self.width):
            return 0.0
        edge = min(x - self.ox, y - self.oy, self.ox + self.width * self.res - x,
                   self.oy + self.height * self.res - y)
        coarse = float(self.edt[r, c]) - self.res * math.sqrt(2)
        if coarse >= limit:
            return min(coarse, edge)
        n = math.ceil(limit / self.res) + 1
        r0, r1 = max(r - n, 0), min(r + n + 1, self.height)
        c0, c1 = max(c - n, 0), min(c + n + 1, self.width)
        rows, cols = np.nonzero(self.solid[r0:r1, c0:c1])
        if rows.size == 0:
            return min(max(coarse, limit), edge)
        # distance from the point to each solid square
        x0 = self.ox + (cols + c0) * self.res
        y0 = self.oy + (rows + r0) * self.res
        ex = np.maximum(np.maximum(x0 - x, x - (x0 + self.res)), 0.0)
        ey = np.maximum(np.maximum(y0 - y, y - (y0 + self.res)), 0.0)
        return min(float(np.min(np.hypot(ex, ey))), edge)

    def clearance(self, x: float, y: float, limit: float) -> float:
        """Distance from (x, y) to the nearest solid thing: map, edge or obstacle."""
        d = self.map_clearance(x, y, limit)
        for ob in self.obstacles.values():
            d = min(d, ob.distance(x, y))
        return d

    def body_free(self, x: float, y: float, radius: float) -> bool:
        """True when a disc of ``radius`` at (x, y) overlaps nothing solid."""
        return self.clearance(x, y, radius + self.res) > radius

    def nearest_free(self, x: float, y: float, radius: float) -> tuple[float, float] | None:
        """The centre of the free cell nearest to (x, y) where the body fits, if any."""
        if self.body_free(x, y, radius):
            return x, y
        rows, cols = np.nonzero(self.edt > radius)  # necessary: clearance <= edt
        if rows.size == 0:
            return None
        cx = self.ox + (cols + 0.5) * self.res
        cy = self.oy + (rows + 0.5) * self.res
        for i in np.argsort(np.hypot(cx - x, cy - y))[:2000]:
            if self.body_free(float(cx[i]), float(cy[i]), radius):
                return float(cx[i]), float(cy[i])
        return None

    # ---------------------------------------------------------------- obstacles

    def set_obstacles(self, obstacles: Iterable[Obstacle]) -> None:
        """Add each obstacle, or replace the one with the same id."""
        for ob in obstacles:
            self.obstacles[ob.id] = ob

    def remove_obstacles(self, ids: Iterable[str]) -> list[str]:
        """Remove the obstacles named; return the names that were not there."""
        missing = []
        for i in ids:
            if self.obstacles.pop(i, None) is None:
                missing.append(i)
        return missing
