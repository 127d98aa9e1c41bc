"""The obstacle layer: marking and clearing from a laser scan, Nav2's ObstacleLayer rules.

One update clears first, then marks (so a hit is never cleared by its own beam):
- **clearing** raytraces every valid beam from the sensor cell towards its end point and
  frees the cells passed through, not the end cell, for at most ``raytrace_max_range``
  (beams shorter than ``raytrace_min_range`` clear nothing);
- **marking** makes the end cell of each hit lethal when ``obstacle_min_range ≤ range <
  obstacle_max_range``.
A beam is valid when its range is finite and within ``[range_min, range_max)``; with
``inf_is_valid`` an infinite reading clears up to ``range_max`` and marks nothing. The layer
keeps its own grid (255 unknown, 0 free, 254 lethal) that the costmap combines by maximum.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .geometry import EMPTY, Bounds, GridGeometry
from .values import FREE_SPACE, LETHAL_OBSTACLE

__all__ = ["ObstacleParams", "Scan", "beam_endpoints", "raytrace_cells", "update_layer"]


@dataclass(frozen=True, slots=True)
class ObstacleParams:
    """Nav2's obstacle layer parameters (its defaults)."""

    obstacle_max_range: float = 2.5
    obstacle_min_range: float = 0.0
    raytrace_max_range: float = 3.0
    raytrace_min_range: float = 0.0
    inf_is_valid: bool = False


@dataclass(frozen=True, slots=True)
class Scan:
    """The parts of a sensor_msgs/LaserScan the layer reads (a LaserScan works too)."""

    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: np.ndarray


def beam_endpoints(
    scan: Scan, pose: tuple[float, float, float]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(ranges, cos, sin)`` of every beam in the map frame for a sensor at ``pose``
    (x, y, yaw): ranges as float64 (NaN kept), unit directions."""
    r = np.asarray(scan.ranges, dtype=np.float64).ravel()
    ang = pose[2] + scan.angle_min + scan.angle_increment * np.arange(r.size, dtype=np.float64)
    return r, np.cos(ang), np.sin(ang)


CHUNK = 1 << 20
"""Cells walked per batch of beams (bounds the temporary arrays)."""


def raytrace_cells(
    geo: GridGeometry, x0: float, y0: float, x1: np.ndarray, y1: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The cells (mx, my) traversed from (x0, y0), a point inside the grid, to each
    (x1, y1), excluding each end cell, clipped to the grid: a DDA stepping one cell along
    the major axis (Bresenham's cells), vectorised over beams (in batches)."""
    if x1.size == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    # no ray needs to go farther than the grid's farthest corner (plus a cell)
    corners_x = (geo.origin_x, geo.origin_x + geo.width * geo.resolution)
    corners_y = (geo.origin_y, geo.origin_y + geo.height * geo.resolution)
    reach = max(math.hypot(cx - x0, cy - y0) for cx in corners_x for cy in corners_y)
    reach += 2 * geo.resolution
    dx, dy = x1 - x0, y1 - y0
    length = np.hypot(dx, dy)
    scale = np.where(length > reach, reach / np.maximum(length, 1e-300), 1.0)
    x1, y1 = x0 + dx * scale, y0 + dy * scale
    steps = reach / geo.resolution + 2
    per = max(1, int(CHUNK // steps))
    if x1.size > per:
        parts = [_walk(geo, x0, y0, x1[i:i + per], y1[i:i + per]) for i in range(0, x1.size, per)]
        return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])
    return _walk(geo, x0, y0, x1, y1)


def _walk(
    geo: GridGeometry, x0: float, y0: float, x1: np.ndarray, y1: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    res = geo.resolution
    fx0, fy0 = (x0 - geo.origin_x) / res, (y0 - geo.origin_y) / res
    fx1, fy1 = (x1 - geo.origin_x) / res, (y1 - geo.origin_y) / res
    sx, sy = math.floor(fx0), math.floor(fy0)
    ex, ey = np.floor(fx1).astype(np.int64), np.floor(fy1).astype(np.int64)
    n = np.maximum(np.abs(ex - sx), np.abs(ey - sy))  # cells on the major axis
    nmax = int(n.max())
    if nmax == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    k = np.arange(nmax, dtype=np.float64)[None, :]  # steps 0 .. n-1 (the end cell excluded)
    nn = np.maximum(n, 1).astype(np.float64)[:, None]
    t = k / nn
    # centre of the start cell to the centre of the end cell, as Bresenham walks
    cx = (sx + 0.5) + t * ((ex - sx).astype(np.float64)[:, None])
    cy = (sy + 0.5) + t * ((ey - sy).astype(np.float64)[:, None])
    keep = k < n[:, None]
    mx = np.floor(cx[keep]).astype(np.int64)
    my = np.floor(cy[keep]).astype(np.int64)
    inside = (mx >= 0) & (mx < geo.width) & (my >= 0) & (my < geo.height)
    return mx[inside], my[inside]


def update_layer(
    layer: np.ndarray,
    geo: GridGeometry,
    params: ObstacleParams,
    scan: Scan,
    pose: tuple[float, float, float],
) -> Bounds:
    """Clear then mark ``layer`` in place from ``scan`` taken at ``pose`` (the sensor's
    x, y, yaw in the map frame); returns the window of the cells that changed."""
    if not all(math.isfinite(v) for v in pose):
        raise ValueError(f"sensor pose must be finite, got {pose!r}")
    if not (math.isfinite(scan.angle_min) and math.isfinite(scan.angle_increment)):
        raise ValueError("scan angles must be finite")
    r, c, s = beam_endpoints(scan, pose)
    x0, y0 = float(pose[0]), float(pose[1])
    finite = np.isfinite(r)
    valid = finite & (r >= scan.range_min) & (r < scan.range_max)
    # clearing
    clear_r = np.where(valid, r, np.nan)
    if params.inf_is_valid:
        clear_r = np.where(np.isposinf(r), scan.range_max, clear_r)
    ok = np.isfinite(clear_r) & (clear_r >= params.raytrace_min_range)
    clear_r = np.minimum(clear_r[ok], params.raytrace_max_range)
    if geo.world_to_map(x0, y0) is None:
        # Nav2: "sensor origin is out of map bounds ... the costmap cannot raytrace for it"
        cmx = cmy = np.empty(0, np.int64)
    else:
        cmx, cmy = raytrace_cells(geo, x0, y0, x0 + clear_r * c[ok], y0 + clear_r * s[ok])
    # marking
    hit = valid & (r >= params.obstacle_min_range) & (r < params.obstacle_max_range)
    cells = geo.world_to_cells(np.stack([x0 + r[hit] * c[hit], y0 + r[hit] * s[hit]], axis=1))
    mx, my = cells[:, 0], cells[:, 1]
    inside = (mx >= 0) & (mx < geo.width) & (my >= 0) & (my < geo.height)
    mx, my = mx[inside], my[inside]
    box = Bounds.around(cmx, cmy).union(Bounds.around(mx, my))
    if box.empty:
        return EMPTY
    before = layer[box.slices].copy()
    layer[cmy, cmx] = FREE_SPACE
    layer[my, mx] = LETHAL_OBSTACLE
    # only the cells whose value changed need the costmap rebuilt around them
    ys, xs = np.nonzero(layer[box.slices] != before)
    if ys.size == 0:
        return EMPTY
    return Bounds.around(xs + box.x0, ys + box.y0)
