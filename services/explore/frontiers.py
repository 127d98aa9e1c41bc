"""Frontier search on an occupancy grid, with explore_lite's rules (specs/mapping.md, section 6).

From the free cell nearest the robot, a breadth-first walk over the free cells the robot's
body fits in (at least ``clearance`` from every occupied cell) finds what is reachable. An
unknown cell with a free 4-neighbour seeds a frontier when it lies beside a reached cell, or
beside a free cell within ``clearance`` of one (a doorway a mapper still draws narrower than
the robot is looked through); it is grown over 8-neighbours through every such cell;
frontiers of fewer than ``min_frontier_size`` metres of cells are dropped. Each one's cost
is explore_lite's, ``potential_scale * distance * resolution - gain_scale * size *
resolution`` (``size`` in metres, ``distance`` the walk's length in metres to the frontier:
nearest *reachable*, where explore_lite takes the straight line), cheapest first. Its goal
is the reached cell within the robot's reach of it nearest its centroid (so a goal is never
in a wall or in unknown space, and the laser sees into the unknown from there), away from
the goals tried before; when every such spot was tried, a reached cell further away (up to
``far_look``), until ``far_tries`` goals were tried round it: then it is left out.

Plain numpy/scipy, no Zenoh: the ``explore`` node calls `find_frontiers` on each map.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

__all__ = ["Frontier", "FrontierParams", "find_frontiers", "is_free", "known_area"]

FREE_MAX = 25  # map_saver's free: values 0..25 (trinary 254 on save)
OCCUPIED_MIN = 65


@dataclass(frozen=True)
class FrontierParams:
    min_frontier_size: float = 0.5
    """Metres of frontier cells (cells x resolution) a frontier needs (explore_lite 0.5)."""
    potential_scale: float = 1e-3
    gain_scale: float = 1.0
    clearance: float = 0.25
    """Metres from the nearest occupied cell the walk keeps (the robot's radius and a bit)."""
    start_radius: float = 1.0
    """Metres from the robot within which the walk must find a free cell to start from; with
    none (a map that does not show the robot's surroundings yet) there is no answer."""
    far_look: float = 1.5
    """Metres from a frontier a goal may be when every spot beside it was tried: it is then
    looked at from further away (a mapper may leave unknown the cells round where the robot
    stood, which no spot beside them shows)."""
    far_tries: int = 3
    """Goals tried within ``far_look`` of a frontier's centroid after which it is left out."""


@dataclass
class Frontier:
    """A frontier: ``size`` cells; ``distance`` (m) the walk to it; ``centroid`` and ``goal``
    (x, y in the map's frame); ``cells`` (row, col) of its cells."""

    size: int
    distance: float
    cost: float
    centroid: tuple[float, float]
    goal: tuple[float, float]
    cells: np.ndarray = field(repr=False)


def is_free(grid: np.ndarray) -> np.ndarray:
    return (grid >= 0) & (grid <= FREE_MAX)


def known_area(grid: np.ndarray, resolution: float) -> float:
    """Square metres of known (free or occupied) cells."""
    return float(np.count_nonzero(grid >= 0)) * resolution * resolution


_N4 = ((1, 0), (-1, 0), (0, 1), (0, -1))


def _walk(walkable: np.ndarray, start: tuple[int, int]) -> np.ndarray:
    """Steps (4-connected) from ``start`` to every walkable cell; -1 where not reached.
    (A breadth-first walk, as explore_lite's, run as scipy's Dijkstra on unit steps: the
    walk in Python took a second on the office.)"""
    h, w = walkable.shape
    idx = np.full(walkable.shape, -1, dtype=np.int64)
    n = int(np.count_nonzero(walkable))
    idx[walkable] = np.arange(n)
    pairs = []
    for a, b in ((idx[:, :-1], idx[:, 1:]), (idx[:-1, :], idx[1:, :])):
        both = (a >= 0) & (b >= 0)
        pairs.append((a[both], b[both]))
    src = np.concatenate([p[0] for p in pairs])
    dst = np.concatenate([p[1] for p in pairs])
    graph = csr_matrix((np.ones(len(src)), (src, dst)), shape=(n, n))
    d = dijkstra(graph, directed=False, indices=int(idx[start]), unweighted=True)
    out = np.full(walkable.shape, -1, dtype=np.int32)
    ok = np.isfinite(d)
    vals = np.full(n, -1, dtype=np.int32)
    vals[ok] = d[ok].astype(np.int32)
    out[walkable] = vals
    return out


def _nearest(mask: np.ndarray, row: float, col: float) -> tuple[int, int] | None:
    rows, cols = np.nonzero(mask)
    if len(rows) == 0:
        return None
    k = int(np.argmin((rows - row) ** 2 + (cols - col) ** 2))
    return int(rows[k]), int(cols[k])


def find_frontiers(grid: np.ndarray, resolution: float, origin: tuple[float, float],
                   robot: tuple[float, float], params: FrontierParams = FrontierParams(),
                   avoid: Sequence[tuple[float, float]] = (), avoid_radius: float = 0.5
                   ) -> list[Frontier] | None:
    """The reachable frontiers of ``grid`` (int8, row 0 at the bottom, -1 unknown, 0..100),
    cheapest first (empty: all explored). ``origin``: the map point of cell (0, 0)'s
    lower-left corner; ``robot``: (x, y) in the map's frame. None when the map shows no free
    cell the robot fits in within ``start_radius`` of it: not explored, not known yet (a
    mapper's first grid may hold only the walls its first scan hit). A goal is never within
    ``avoid_radius`` of an ``avoid`` point (goals tried before): a frontier takes its next
    best spot, and is left out when it has none."""
    g = np.asarray(grid)
    if g.ndim != 2 or g.size == 0 or not resolution > 0:
        return None
    free = is_free(g)
    unknown = g < 0
    occupied = g >= OCCUPIED_MIN
    clear = ndimage.distance_transform_edt(~occupied) * resolution if occupied.any() \
        else np.full(g.shape, np.inf)
    ox, oy = origin
    rc = ((robot[1] - oy) / resolution - 0.5, (robot[0] - ox) / resolution - 0.5)
    walkable = free & (clear >= params.clearance)
    start = _nearest(walkable, *rc)
    if start is None or math.hypot(start[0] - rc[0], start[1] - rc[1]) * resolution \
            > params.start_radius:
        return None
    steps = _walk(walkable, start)
    reached = steps >= 0
    # how far each cell is from the reached ones, and the walk's length to the nearest
    gap, (ir, ic) = ndimage.distance_transform_edt(~reached, return_indices=True)
    gap *= resolution
    via = steps[ir, ic] * resolution + gap
    # the free cells the robot's body reaches over from a reached one (a doorway the map
    # draws narrower than the robot is still looked through)
    touch = reached | (free & (gap <= params.clearance + resolution))
    # frontier cells: unknown, with a free 4-neighbour; seeded beside a touched cell
    free4 = np.zeros_like(free)
    touch4 = np.zeros_like(free)
    for dr, dc in _N4:
        free4 |= _shift_mask(free, dr, dc)
        touch4 |= _shift_mask(touch, dr, dc)
    candidate = unknown & free4
    labels, n = ndimage.label(candidate, structure=np.ones((3, 3), dtype=bool))
    if n == 0:
        return []
    seeded = np.unique(labels[candidate & touch4])
    seeded = seeded[seeded > 0]
    min_cells = params.min_frontier_size / resolution
    out: list[Frontier] = []
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    boxes = ndimage.find_objects(labels)
    h, w = g.shape
    pad_m = params.clearance + 2 * resolution
    pad = int(math.ceil(pad_m / resolution)) + 1
    for lab in seeded:
        if sizes[lab] < min_cells:
            continue
        box = boxes[lab - 1]
        r0, c0 = max(box[0].start - pad, 0), max(box[1].start - pad, 0)
        win = (slice(r0, min(box[0].stop + pad, h)), slice(c0, min(box[1].stop + pad, w)))
        mine = labels[win] == lab
        rows, cols = np.nonzero(mine)
        distance = float(via[win][rows, cols].min())
        rows, cols = rows + r0, cols + c0
        cr, cc = float(rows.mean()), float(cols.mean())
        # the goal: the reached cell next to this frontier (within the robot's reach of it)
        # nearest its centroid, from where the laser sees into the unknown; the centroid
        # itself may be unknown or in a wall
        spots = reached[win] & (ndimage.distance_transform_edt(~mine) * resolution <= pad_m)
        if avoid:
            spots &= ~_near_any(spots.shape, r0, c0, origin, resolution, avoid, avoid_radius)
        spot = _nearest(spots, cr - r0, cc - c0)
        if spot is not None:
            gr, gc = spot[0] + r0, spot[1] + c0
        else:  # every spot next to it was tried: from further away, a few times
            cx, cy = ox + (cc + 0.5) * resolution, oy + (cr + 0.5) * resolution
            tried = sum(math.hypot(x - cx, y - cy) <= params.far_look for x, y in avoid)
            far = None if tried >= params.far_tries else _far_spot(
                labels, lab, box, reached, (cr, cc), origin, resolution, avoid, avoid_radius,
                params.far_look)
            if far is None:
                continue
            gr, gc = far
        size_m = len(rows) * resolution
        cost = params.potential_scale * distance * resolution \
            - params.gain_scale * size_m * resolution
        out.append(Frontier(
            size=len(rows), distance=distance, cost=cost,
            centroid=(ox + (cc + 0.5) * resolution, oy + (cr + 0.5) * resolution),
            goal=(ox + (gc + 0.5) * resolution, oy + (gr + 0.5) * resolution),
            cells=np.column_stack([rows, cols])))
    out.sort(key=lambda f: f.cost)
    return out


def _far_spot(labels: np.ndarray, lab: int, box: tuple[slice, ...], reached: np.ndarray,
              centroid: tuple[float, float], origin: tuple[float, float], resolution: float,
              avoid: Sequence[tuple[float, float]], avoid_radius: float, far: float
              ) -> tuple[int, int] | None:
    """The reached cell within ``far`` metres of frontier ``lab``, away from ``avoid``,
    nearest its centroid (row, col of the grid); None if there is none."""
    h, w = labels.shape
    pad = int(math.ceil(far / resolution)) + 1
    r0, c0 = max(box[0].start - pad, 0), max(box[1].start - pad, 0)
    win = (slice(r0, min(box[0].stop + pad, h)), slice(c0, min(box[1].stop + pad, w)))
    near = ndimage.distance_transform_edt(labels[win] != lab) * resolution <= far
    spots = reached[win] & near
    spots &= ~_near_any(spots.shape, r0, c0, origin, resolution, avoid, avoid_radius)
    spot = _nearest(spots, centroid[0] - r0, centroid[1] - c0)
    return None if spot is None else (spot[0] + r0, spot[1] + c0)


def _near_any(shape: tuple[int, ...], r0: int, c0: int, origin: tuple[float, float],
              resolution: float, points: Sequence[tuple[float, float]], radius: float
              ) -> np.ndarray:
    """Cells of a window (its corner at row ``r0``, col ``c0``) within ``radius`` of any of
    ``points`` (map coordinates)."""
    rows = (r0 + np.arange(shape[0]) + 0.5) * resolution + origin[1]
    cols = (c0 + np.arange(shape[1]) + 0.5) * resolution + origin[0]
    out = np.zeros(shape, dtype=bool)
    r2 = radius * radius
    for x, y in points:
        dy = (rows - y) ** 2
        dx = (cols - x) ** 2
        if dy.min() > r2 or dx.min() > r2:
            continue
        out |= (dy[:, None] + dx[None, :]) <= r2
    return out


def _shift_values(a: np.ndarray, dr: int, dc: int) -> np.ndarray:
    """``out[r, c] = a[r + dr, c + dc]`` (-1 off the grid)."""
    out = np.full_like(a, -1)
    h, w = a.shape
    rs = slice(max(-dr, 0), h - max(dr, 0))
    cs = slice(max(-dc, 0), w - max(dc, 0))
    out[rs, cs] = a[max(dr, 0):h + min(dr, 0), max(dc, 0):w + min(dc, 0)]
    return out


def _shift_mask(mask: np.ndarray, dr: int, dc: int) -> np.ndarray:
    out = np.zeros_like(mask)
    h, w = mask.shape
    out[max(-dr, 0):h - max(dr, 0), max(-dc, 0):w - max(dc, 0)] = \
        mask[max(dr, 0):h + min(dr, 0), max(dc, 0):w + min(dc, 0)]
    return out
