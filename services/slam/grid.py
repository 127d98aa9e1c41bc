"""LogOddsGrid: the occupancy grid the mapper builds, by log-odds ray casting (Probabilistic
Robotics ch. 9; OctoMap's hit/miss/clamp), vectorised with numpy.

Each scan adds ``l_hit`` to the cells its returns end in and ``l_miss`` to the cells its beams
cross before them (each cell at most once a scan); a beam with no return clears to the clear
range and marks nothing. Values are clamped so a cell can flip back. The grid grows in
chunks to hold whatever is cast into it; ``occupancy`` exports as map_server reads a map
(-1 unknown, 0 free below 0.196, 100 occupied above 0.65).
"""

from __future__ import annotations

import math

import numpy as np
from zenros.se2 import Pose2

from .scan import RangeScan, points_in

__all__ = ["LogOddsGrid", "logit"]

_GROW = 5.0  # metres added on a side that must grow
_OCCUPIED_P = 0.65
_FREE_P = 0.196


def logit(p: float) -> float:
    return math.log(p / (1.0 - p))


class LogOddsGrid:
    """A growable log-odds grid at ``resolution``; cell (row, col) covers
    [ox + col·res, ox + (col+1)·res) × [oy + row·res, …)."""

    def __init__(self, resolution: float, hit: float = 0.7, miss: float = 0.4,
                 clamp_min: float = 0.12, clamp_max: float = 0.97) -> None:
        self.res = resolution
        self.l_hit, self.l_miss = logit(hit), logit(miss)
        self.l_min, self.l_max = logit(clamp_min), logit(clamp_max)
        self.ox = self.oy = 0.0
        self.logodds = np.zeros((0, 0), dtype=np.float32)
        self.seen = np.zeros((0, 0), dtype=bool)

    @property
    def shape(self) -> tuple[int, int]:
        h, w = self.logodds.shape
        return h, w

    def clear(self) -> None:
        self.logodds = np.zeros((0, 0), dtype=np.float32)
        self.seen = np.zeros((0, 0), dtype=bool)

    def seed(self, cells: np.ndarray, origin: tuple[float, float]) -> None:
        """Start from a stored map (``cells`` at this resolution, map_server values, row 0 at
        ``origin``): its occupied and free cells at the clamps, as sure as the grid gets, so
        new scans can still overturn them."""
        h, w = cells.shape
        r = self.res
        self._ensure(origin[0], origin[1], origin[0] + (w - 0.5) * r, origin[1] + (h - 0.5) * r)
        c0 = round((origin[0] - self.ox) / r)
        r0 = round((origin[1] - self.oy) / r)
        view = self.logodds[r0:r0 + h, c0:c0 + w]
        seen = self.seen[r0:r0 + h, c0:c0 + w]
        occupied, free = cells >= 65, (cells >= 0) & (cells <= 25)
        view[occupied] = self.l_max
        view[free] = self.l_min
        seen |= occupied | free

    def _ensure(self, x0: float, y0: float, x1: float, y1: float) -> None:
        """Grow so [x0, x1] × [y0, y1] is inside."""
        h, w = self.shape
        if h and (x0 >= self.ox and y0 >= self.oy and x1 < self.ox + w * self.res
                  and y1 < self.oy + h * self.res):
            return
        r = self.res
        if h == 0:
            nx0, ny0 = math.floor((x0 - _GROW) / r), math.floor((y0 - _GROW) / r)
            nx1, ny1 = math.ceil((x1 + _GROW) / r), math.ceil((y1 + _GROW) / r)
        else:
            cx0, cy0 = round(self.ox / r), round(self.oy / r)
            cx1, cy1 = cx0 + w, cy0 + h
            nx0 = min(cx0, math.floor((x0 - _GROW) / r)) if x0 < self.ox else cx0
            ny0 = min(cy0, math.floor((y0 - _GROW) / r)) if y0 < self.oy else cy0
            nx1 = max(cx1, math.ceil((x1 + _GROW) / r)) if x1 >= cx1 * r else cx1
            ny1 = max(cy1, math.ceil((y1 + _GROW) / r)) if y1 >= cy1 * r else cy1
        lo = np.zeros((ny1 - ny0, nx1 - nx0), dtype=np.float32)
        seen = np.zeros(lo.shape, dtype=bool)
        if h:
            cx0, cy0 = round(self.ox / r), round(self.oy / r)
            lo[cy0 - ny0:cy0 - ny0 + h, cx0 - nx0:cx0 - nx0 + w] = self.logodds
            seen[cy0 - ny0:cy0 - ny0 + h, cx0 - nx0:cx0 - nx0 + w] = self.seen
        self.logodds, self.seen = lo, seen
        self.ox, self.oy = nx0 * r, ny0 * r

    def add_scan(self, pose: Pose2, scan: RangeScan) -> None:
        """Fold ``scan`` taken with the base at ``pose`` into the grid."""
        hits = points_in(pose, scan.points)
        clears = points_in(pose, scan.clear_points)
        origin = np.array(pose.apply(scan.mount.x, scan.mount.y))
        ends = np.vstack([hits, clears])
        if not len(ends):
            return
        self._ensure(min(ends[:, 0].min(), origin[0]), min(ends[:, 1].min(), origin[1]),
                     max(ends[:, 0].max(), origin[0]), max(ends[:, 1].max(), origin[1]))
        r = self.res
        h, w = self.shape
        # the scan's window of the grid, in cells
        c0 = max(0, math.floor((min(ends[:, 0].min(), origin[0]) - self.ox) / r))
        r0 = max(0, math.floor((min(ends[:, 1].min(), origin[1]) - self.oy) / r))
        c1 = min(w, math.floor((max(ends[:, 0].max(), origin[0]) - self.ox) / r) + 1)
        r1 = min(h, math.floor((max(ends[:, 1].max(), origin[1]) - self.oy) / r) + 1)
        lw = c1 - c0
        ox, oy = self.ox + c0 * r, self.oy + r0 * r
        # samples every cell along each beam, up to (not including) its end
        d = (ends - origin).astype(np.float32)
        length = np.hypot(d[:, 0], d[:, 1])
        n = np.ceil(length / r).astype(np.int32)
        steps = np.arange(int(n.max()), dtype=np.float32)
        t = steps[None, :] / np.maximum(n, 1).astype(np.float32)[:, None]  # (R, S) in [0, 1)
        inside = steps[None, :] < n[:, None]
        cols = ((origin[0] - ox) / r + t * (d[:, 0:1] / r)).astype(np.int32)
        rows = ((origin[1] - oy) / r + t * (d[:, 1:2] / r)).astype(np.int32)
        flat_pass = (rows * lw + cols)[inside]
        ecol = np.floor((ends[:, 0] - ox) / r).astype(np.int32)
        erow = np.floor((ends[:, 1] - oy) / r).astype(np.int32)
        ecol = np.minimum(ecol, lw - 1)
        erow = np.minimum(erow, r1 - r0 - 1)
        size = (r1 - r0) * lw
        passed = np.zeros(size, dtype=bool)
        passed[flat_pass] = True
        nh = len(hits)
        passed[erow[nh:] * lw + ecol[nh:]] = True  # clearing beams clear their last cell
        hit = np.zeros(size, dtype=bool)
        hit[erow[:nh] * lw + ecol[:nh]] = True
        passed &= ~hit
        passed = passed.reshape(r1 - r0, lw)
        hit = hit.reshape(r1 - r0, lw)
        view = self.logodds[r0:r1, c0:c1]
        view[passed] += self.l_miss
        view[hit] += self.l_hit
        np.clip(view, self.l_min, self.l_max, out=view)
        seen = self.seen[r0:r1, c0:c1]
        seen |= passed
        seen |= hit

    def occupancy(self) -> np.ndarray:
        """int8 (rows, cols): -1 unknown, 0 free, 100 occupied, as map_server exports."""
        out = np.full(self.shape, -1, dtype=np.int8)
        p_occ, p_free = logit(_OCCUPIED_P), logit(_FREE_P)
        out[self.seen & (self.logodds > p_occ)] = 100
        out[self.seen & (self.logodds < p_free)] = 0
        return out

    def known_area(self) -> float:
        """m² of cells that are free or occupied."""
        occ = self.occupancy()
        return float(np.count_nonzero(occ >= 0)) * self.res * self.res
