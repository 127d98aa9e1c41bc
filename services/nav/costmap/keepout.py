"""Keep-out areas and virtual walls: polygons and polylines in map coordinates, rasterised.

A polygon (forbidden area) covers every cell whose centre is inside it (even-odd rule) plus
every cell its outline passes through; a polyline (virtual wall) covers every cell its
segments pass through (a 4-connected "supercover" line, so no 8-connected path can slip
diagonally between two of its cells). Shapes are lists of ``(x, y)`` points in the map
frame; cells outside the grid are dropped.

The costmap writes these cells as a Nav2 KeepoutFilter does with mask value 100: cost 254
after inflation, so a wall is lethal but not inflated into the free space around it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence

import numpy as np

from .geometry import GridGeometry

__all__ = ["Point", "check_shape", "rasterise"]

Point = tuple[float, float]


def check_shape(points: Sequence[Sequence[float]], kind: str, minimum: int) -> np.ndarray:
    """``points`` as an (N, 2) float array, or ValueError naming what is wrong."""
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"a {kind} is a list of (x, y) points: {e}") from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"a {kind} is a list of (x, y) points, got shape {arr.shape}")
    if len(arr) < minimum:
        raise ValueError(f"a {kind} needs at least {minimum} points, got {len(arr)}")
    if not np.isfinite(arr).all():
        raise ValueError(f"a {kind} has a non-finite coordinate")
    return arr


def _segment_cells(
    geo: GridGeometry, a: np.ndarray, b: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Every cell the segment a→b touches (supercover), possibly outside the grid (the
    segment is first clipped to the grid and a one-cell margin)."""
    clipped = geo.clip_segment((float(a[0]), float(a[1])), (float(b[0]), float(b[1])))
    if clipped is None:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    a, b = np.asarray(clipped[0]), np.asarray(clipped[1])
    res = geo.resolution
    fx0, fy0 = (a[0] - geo.origin_x) / res, (a[1] - geo.origin_y) / res
    fx1, fy1 = (b[0] - geo.origin_x) / res, (b[1] - geo.origin_y) / res
    length = math.hypot(fx1 - fx0, fy1 - fy0)
    n = max(1, math.ceil(length * 4))  # quarter-cell samples ...
    t = np.linspace(0.0, 1.0, n + 1)
    xs = fx0 + t * (fx1 - fx0)
    ys = fy0 + t * (fy1 - fy0)
    cx, cy = np.floor(xs).astype(np.int64), np.floor(ys).astype(np.int64)
    # ... plus, wherever two consecutive samples are diagonal neighbours, the cell between
    # them on the line's side, so the cells form a 4-connected chain
    diag = (cx[1:] != cx[:-1]) & (cy[1:] != cy[:-1])
    if diag.any():
        i = np.nonzero(diag)[0]
        # the crossing point of the x grid line between samples i and i+1
        gx = np.maximum(cx[i], cx[i + 1]).astype(np.float64)
        dx = xs[i + 1] - xs[i]
        tt = np.where(dx != 0, (gx - xs[i]) / np.where(dx != 0, dx, 1.0), 0.0)
        yc = ys[i] + tt * (ys[i + 1] - ys[i])
        # crossing x first: the extra cell is (next column, this row) unless the row has
        # already changed at the crossing
        row = np.where(np.floor(yc).astype(np.int64) == cy[i], cy[i], cy[i + 1])
        col = np.where(row == cy[i], cx[i + 1], cx[i])
        cx = np.concatenate([cx, col])
        cy = np.concatenate([cy, row])
    return cx, cy


def _polygon_interior(geo: GridGeometry, poly: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cells whose centre is inside the polygon (even-odd rule), within its bounding box."""
    cells = geo.world_to_cells(np.array([poly.min(axis=0), poly.max(axis=0)]))
    x0, y0 = max(0, int(cells[0, 0])), max(0, int(cells[0, 1]))
    x1, y1 = min(geo.width - 1, int(cells[1, 0])), min(geo.height - 1, int(cells[1, 1]))
    if x1 < x0 or y1 < y0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    mx, my = np.meshgrid(np.arange(x0, x1 + 1), np.arange(y0, y1 + 1))
    px = geo.origin_x + (mx + 0.5) * geo.resolution
    py = geo.origin_y + (my + 0.5) * geo.resolution
    inside = np.zeros(mx.shape, dtype=bool)
    ax, ay = poly[:, 0], poly[:, 1]
    bx, by = np.roll(ax, -1), np.roll(ay, -1)
    for xa, ya, xb, yb in zip(ax, ay, bx, by, strict=True):
        if ya == yb:
            continue
        crosses = (ya > py) != (yb > py)
        xcross = xa + (py - ya) * (xb - xa) / (yb - ya)
        inside ^= crosses & (px < xcross)
    return mx[inside], my[inside]


def rasterise(
    geo: GridGeometry,
    polygons: Iterable[Sequence[Sequence[float]]] = (),
    walls: Iterable[Sequence[Sequence[float]]] = (),
) -> np.ndarray:
    """A (height, width) bool mask of the cells covered by the polygons and polylines."""
    mask = np.zeros((geo.height, geo.width), dtype=bool)
    xs: list[np.ndarray] = []
    ys: list[np.ndarray] = []
    for p in polygons:
        poly = check_shape(p, "polygon", 3)
        mx, my = _polygon_interior(geo, poly)
        xs.append(mx)
        ys.append(my)
        closed = np.vstack([poly, poly[:1]])
        for a, b in itertools.pairwise(closed):
            mx, my = _segment_cells(geo, a, b)
            xs.append(mx)
            ys.append(my)
    for w in walls:
        line = check_shape(w, "wall", 2)
        for a, b in itertools.pairwise(line):
            mx, my = _segment_cells(geo, a, b)
            xs.append(mx)
            ys.append(my)
    if xs:
        mx, my = np.concatenate(xs), np.concatenate(ys)
        inside = (mx >= 0) & (mx < geo.width) & (my >= 0) & (my < geo.height)
        mask[my[inside], mx[inside]] = True
    return mask
