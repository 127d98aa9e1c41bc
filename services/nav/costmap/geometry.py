"""GridGeometry: a costmap's size, resolution and origin, and world ↔ map cell conversion.

Cells are indexed ``(mx, my)`` = (column, row), row 0 at the origin (the bottom of the map,
as in an OccupancyGrid), so a cell's value is ``grid[my, mx]``. A world point ``(x, y)`` in
the map frame lies in cell ``(floor((x − ox)/res), floor((y − oy)/res))``; a cell's world
point is its centre. The origin's yaw is not supported (as most of Nav2 ignores it).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["EMPTY", "Bounds", "GridGeometry"]


@dataclass(frozen=True, slots=True)
class Bounds:
    """A half-open window of cells: columns ``x0 ≤ mx < x1``, rows ``y0 ≤ my < y1``."""

    x0: int
    y0: int
    x1: int
    y1: int

    @staticmethod
    def around(mx: np.ndarray, my: np.ndarray) -> Bounds:
        """The smallest window holding the cells (mx[i], my[i]); EMPTY for none."""
        if mx.size == 0:
            return Bounds(0, 0, 0, 0)
        return Bounds(int(mx.min()), int(my.min()), int(mx.max()) + 1, int(my.max()) + 1)

    @property
    def empty(self) -> bool:
        return self.x1 <= self.x0 or self.y1 <= self.y0

    def grow(self, cells: int, width: int, height: int) -> Bounds:
        """This window widened by ``cells`` on each side, clipped to a width × height grid."""
        return Bounds(
            max(0, self.x0 - cells), max(0, self.y0 - cells),
            min(width, self.x1 + cells), min(height, self.y1 + cells),
        )

    def union(self, other: Bounds) -> Bounds:
        if self.empty:
            return other
        if other.empty:
            return self
        return Bounds(
            min(self.x0, other.x0), min(self.y0, other.y0),
            max(self.x1, other.x1), max(self.y1, other.y1),
        )

    @property
    def slices(self) -> tuple[slice, slice]:
        """``grid[bounds.slices]``: the window of a (rows, columns) array."""
        return slice(self.y0, self.y1), slice(self.x0, self.x1)


EMPTY = Bounds(0, 0, 0, 0)
_FAR = float(1 << 40)  # cells: farther than any grid, small enough for int64


@dataclass(frozen=True, slots=True)
class GridGeometry:
    """The placement of a width × height grid of square cells in the map frame."""

    width: int
    height: int
    resolution: float
    origin_x: float = 0.0
    origin_y: float = 0.0

    def __post_init__(self) -> None:
        if self.width <= 0 or self.height <= 0:
            raise ValueError(f"a costmap needs a positive size, got {self.width} x {self.height}")
        if not (math.isfinite(self.resolution) and self.resolution > 0):
            raise ValueError(f"resolution must be a positive number, got {self.resolution!r}")
        if not (math.isfinite(self.origin_x) and math.isfinite(self.origin_y)):
            raise ValueError(f"origin must be finite, got ({self.origin_x!r}, {self.origin_y!r})")

    @property
    def full(self) -> Bounds:
        return Bounds(0, 0, self.width, self.height)

    def contains(self, mx: int, my: int) -> bool:
        return 0 <= mx < self.width and 0 <= my < self.height

    def world_to_map(self, x: float, y: float) -> tuple[int, int] | None:
        """The cell ``(mx, my)`` holding the world point, or None outside the grid (or NaN)."""
        if not (math.isfinite(x) and math.isfinite(y)):
            return None
        mx = math.floor((x - self.origin_x) / self.resolution)
        my = math.floor((y - self.origin_y) / self.resolution)
        return (mx, my) if self.contains(mx, my) else None

    def world_to_map_unbounded(self, x: float, y: float) -> tuple[int, int]:
        """The cell of a world point, possibly outside the grid."""
        return (
            math.floor((x - self.origin_x) / self.resolution),
            math.floor((y - self.origin_y) / self.resolution),
        )

    def map_to_world(self, mx: float, my: float) -> tuple[float, float]:
        """The world point at the centre of cell ``(mx, my)``."""
        return (
            self.origin_x + (mx + 0.5) * self.resolution,
            self.origin_y + (my + 0.5) * self.resolution,
        )

    def cells_to_world(self, cells: np.ndarray) -> np.ndarray:
        """An (N, 2) array of ``(mx, my)`` cells as an (N, 2) float array of centres."""
        c = np.asarray(cells, dtype=np.float64).reshape(-1, 2)
        out = np.empty_like(c)
        out[:, 0] = self.origin_x + (c[:, 0] + 0.5) * self.resolution
        out[:, 1] = self.origin_y + (c[:, 1] + 0.5) * self.resolution
        return out

    def world_to_cells(self, points: np.ndarray) -> np.ndarray:
        """An (N, 2) array of world points as (N, 2) int64 cells (unclipped)."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        out = np.empty(p.shape, dtype=np.int64)
        # far-away points are clipped first so that the cast cannot overflow
        out[:, 0] = np.clip(np.floor((p[:, 0] - self.origin_x) / self.resolution), -_FAR, _FAR)
        out[:, 1] = np.clip(np.floor((p[:, 1] - self.origin_y) / self.resolution), -_FAR, _FAR)
        return out

    def clip_segment(
        self, a: Sequence[float], b: Sequence[float], margin: float = 1.0
    ) -> tuple[tuple[float, float], tuple[float, float]] | None:
        """The part of the segment a→b within the grid grown by ``margin`` cells, or None
        (Liang–Barsky)."""
        m = margin * self.resolution
        lo = (self.origin_x - m, self.origin_y - m)
        hi = (self.origin_x + self.width * self.resolution + m,
              self.origin_y + self.height * self.resolution + m)
        t0, t1 = 0.0, 1.0
        for axis in (0, 1):
            d = b[axis] - a[axis]
            for p, q in ((-d, a[axis] - lo[axis]), (d, hi[axis] - a[axis])):
                if p == 0:
                    if q < 0:
                        return None
                    continue
                t = q / p
                if p < 0:
                    t0 = max(t0, t)
                else:
                    t1 = min(t1, t)
        if t0 > t1:
            return None
        return (
            (a[0] + t0 * (b[0] - a[0]), a[1] + t0 * (b[1] - a[1])),
            (a[0] + t1 * (b[0] - a[0]), a[1] + t1 * (b[1] - a[1])),
        )

    def cell_distance(self, metres: float) -> int:
        """Nav2's ``cellDistance``: ``ceil(metres / resolution)``, at least 0."""
        return int(max(0.0, math.ceil(metres / self.resolution)))
