"""SegmentMap: a map's free space cut into traffic segments, wide ones and narrow ones.

The map is covered by a coarse grid of ``cell_size`` squares (0.5 m). A map pixel's free
width is the shorter of its two free runs, along its row and along its column (the
cross-section of a corridor or a door it lies in); a cell is *narrow* when
``min_narrow_pixels`` of its free pixels or more are narrower than ``passing_width`` (what two
robots need to pass each other), else *wide*. Each wide cell is a segment of its own (robots
pass each other there: it is never reserved); 4-connected narrow cells form one narrow
segment (a corridor or a door, with the cells around it that are as tight), which the
reservation table (`traffic.TrafficTable`) gives to one robot at a time.

Axis runs measure a corridor at an angle to the map's axes wider than it is (a diagonal
one by up to 1.41 times): maps here are drawn square to their axes, as buildings are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from zenros.maps import GridMap

__all__ = ["Segment", "SegmentMap"]

FREE_BELOW = 50
"""Occupancy values 0..49 are free; unknown (-1) and 50..100 are not."""


@dataclass(frozen=True)
class Segment:
    """One segment: its cells ((row, col) of the coarse grid), narrow or wide, and the
    narrowest free width in it (m)."""

    id: int
    narrow: bool
    cells: tuple[tuple[int, int], ...]
    width: float


def _runs(free: np.ndarray) -> np.ndarray:
    """For each pixel, the length (in pixels) of the run of free pixels along its row that
    holds it (0 for a pixel that is not free)."""
    h, w = free.shape
    pad = np.zeros((h, w + 2), dtype=bool)
    pad[:, 1:-1] = free
    d = np.diff(pad.astype(np.int8), axis=1)
    out = np.zeros((h, w), dtype=np.int32)
    for r in range(h):
        starts = np.flatnonzero(d[r] == 1)
        ends = np.flatnonzero(d[r] == -1)
        for s, e in zip(starts, ends, strict=True):
            out[r, s:e] = e - s
    return out


class SegmentMap:
    """The segments of one map (``name``), built once; lookups are by map point."""

    def __init__(self, grid: GridMap, name: str = "", *, cell_size: float = 0.5,
                 passing_width: float = 1.3, min_narrow_pixels: int = 3) -> None:
        if not (math.isfinite(cell_size) and cell_size >= grid.resolution):
            raise ValueError(f"cell_size must be >= the map's resolution "
                             f"({grid.resolution} m), got {cell_size}")
        if not (math.isfinite(passing_width) and passing_width > 0):
            raise ValueError(f"passing_width must be > 0, got {passing_width}")
        self.grid, self.name = grid, name
        self.cell_size, self.passing_width = cell_size, passing_width
        self.k = max(1, round(cell_size / grid.resolution))  # pixels per cell side
        free = (grid.grid >= 0) & (grid.grid < FREE_BELOW)
        width_px = np.minimum(_runs(free), _runs(free.T).T)
        narrow_px = free & (width_px * grid.resolution < passing_width)
        h, w = free.shape
        self.rows, self.cols = -(-h // self.k), -(-w // self.k)
        pad = (self.rows * self.k - h, self.cols * self.k - w)

        def per_cell(a: np.ndarray) -> np.ndarray:
            out: np.ndarray = np.pad(a, ((0, pad[0]), (0, pad[1]))).reshape(
                self.rows, self.k, self.cols, self.k).sum(axis=(1, 3))
            return out

        big = np.where(free, width_px, np.iinfo(np.int32).max)
        big = np.pad(big, ((0, pad[0]), (0, pad[1])), constant_values=np.iinfo(np.int32).max)
        min_width = big.reshape(self.rows, self.k, self.cols, self.k).min(axis=(1, 3))
        n_free = per_cell(free.astype(np.int32))
        n_narrow = per_cell(narrow_px.astype(np.int32))
        self.free_cells = n_free > 0
        self.clear_cells = n_free == self.k * self.k  # no wall pixel: a body may stand there
        self.narrow_cells = self.free_cells & (n_narrow >= min_narrow_pixels)
        labels, count = ndimage.label(self.narrow_cells)
        self.segment_of = np.full((self.rows, self.cols), -1, dtype=np.int64)
        segments: list[Segment] = []
        for n in range(1, count + 1):
            cells = np.argwhere(labels == n)
            self.segment_of[labels == n] = len(segments)
            segments.append(Segment(len(segments), True,
                                    tuple((int(r), int(c)) for r, c in cells),
                                    float(min_width[labels == n].min()) * grid.resolution))
        for r, c in np.argwhere(self.free_cells & ~self.narrow_cells):
            self.segment_of[r, c] = len(segments)
            segments.append(Segment(len(segments), False, ((int(r), int(c)),),
                                    float(min_width[r, c]) * grid.resolution))
        self.segments: tuple[Segment, ...] = tuple(segments)

    def cell_at(self, x: float, y: float) -> tuple[int, int]:
        """The coarse cell (row, col) holding map point (x, y); may be off the grid."""
        row, col = self.grid.world_to_cell(x, y)
        return row // self.k, col // self.k

    def cell_centre(self, cell: tuple[int, int]) -> tuple[float, float]:
        """The map point at the centre of a coarse cell."""
        r, c = cell
        x0, y0 = self.grid.cell_to_world(r * self.k, c * self.k)
        half = (self.k - 1) * self.grid.resolution / 2
        return x0 + half, y0 + half

    def segments_at(self, xy: np.ndarray) -> np.ndarray:
        """The segment id of each map point of ``xy`` (N, 2); -1 off the free space."""
        pts = np.asarray(xy, dtype=float).reshape(-1, 2)
        ox, oy, yaw = self.grid.origin
        dx, dy = pts[:, 0] - ox, pts[:, 1] - oy
        if yaw:
            c, s = math.cos(yaw), math.sin(yaw)
            dx, dy = c * dx + s * dy, -s * dx + c * dy
        px = self.grid.resolution * self.k
        rows = np.floor(dy / px).astype(np.int64)
        cols = np.floor(dx / px).astype(np.int64)
        ok = (rows >= 0) & (rows < self.rows) & (cols >= 0) & (cols < self.cols)
        out = np.full(len(pts), -1, dtype=np.int64)
        out[ok] = self.segment_of[rows[ok], cols[ok]]
        return out

    def segment_at(self, x: float, y: float) -> Segment | None:
        """The segment holding map point (x, y) (None off the free space)."""
        sid = int(self.segments_at(np.array([[x, y]]))[0])
        return self.segments[sid] if sid >= 0 else None

    @property
    def narrow(self) -> tuple[Segment, ...]:
        return tuple(s for s in self.segments if s.narrow)
