"""`plan_coverage`: a boustrophedon coverage path over a polygon with holes (numpy only).

Structured like Nav2's opennav_coverage (Fields2Cover): validate the field, shrink it by
the headland, lay parallel swaths ``op_width`` apart at the swath angle, clip them to the
field minus its holes, then order the swaths into a back-and-forth route.

- Headland: a swath keeps only the parts at least ``headland_width`` from every edge of
  the border and of the holes (exact for any simple polygon, convex or not: the set of
  points of a line within a distance of a segment is one interval).
- Swaths: the region's extent across the swath direction is split into
  ``ceil(extent / op_width)`` evenly spaced swaths (spacing <= ``op_width``), the outer ones
  ``op_width / 2`` inside the headland, so every point of the region at least
  ``op_width / 2`` from its edges is within ``op_width / 2`` of a swath (the tips of corners
  that are not square to the swaths are left out, as in any swath planner). A swath crossed
  by a hole becomes several segments.
- Order: segments of neighbouring swaths that overlap one to one form a cell; each cell is
  driven back and forth, cells one after the other (the nearest next).
- Turns within a cell: ``turn_radius`` 0 joins a swath's end straight to the next one's
  start (the robot turns on the spot); ``turn_radius`` r > 0 inserts a sampled turn whose
  radius is never below r beyond the swath ends (`turn_points`: a U of two quarter circles
  when the swaths are >= 2r apart, else an omega turn), so it needs a headland at least
  that deep to stay inside the border. A move from one cell to the next is a straight
  connection that may cross a hole: driving it is the navigator's job.
- ``swath_angle`` < 0: the angle that needs the fewest swaths (the field's narrowest
  extent, trying every border edge direction and every 5 degrees; ties go to the longest
  edge).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["MAX_INPUT_POINTS", "MAX_PATH_POINTS", "CoverageError", "CoveragePlan",
           "Field", "plan_coverage", "validate_field"]

MAX_INPUT_POINTS = 10_000
"""Border and hole vertices together."""
MAX_PATH_POINTS = 100_000
MAX_WORK = 50_000_000
"""Swaths times edges: beyond this the request is refused (op_width too small)."""
_EPS = 1e-9
Point = tuple[float, float]


class CoverageError(ValueError):
    """A request the planner refuses; the message names the problem."""


@dataclass(frozen=True)
class Field:
    """A validated field: the border and holes as (n, 2) arrays, open (no repeated end)."""

    border: np.ndarray
    holes: tuple[np.ndarray, ...]


@dataclass(frozen=True)
class CoveragePlan:
    """The route (an (n, 2) array of segment ends, in driving order) and how it was made:
    the angle used (degrees), the swaths with something to drive, and the segments."""

    path: np.ndarray
    swath_angle: float
    swaths: int
    segments: int


# ---------------------------------------------------------------- validation

def _polygon(points: Sequence[Sequence[float]], what: str) -> np.ndarray:
    if len(points) > MAX_INPUT_POINTS:
        raise CoverageError(f"{what} has {len(points)} points (limit {MAX_INPUT_POINTS})")
    rows = []
    for i, p in enumerate(points):
        if len(p) not in (2, 3):
            raise CoverageError(f"{what} point {i} must be [x, y, z] (got {len(p)} numbers)")
        rows.append((p[0], p[1]))
    arr = np.asarray(rows, dtype=float).reshape(-1, 2)
    if not np.all(np.isfinite(arr)):
        raise CoverageError(f"{what} has a point that is not a finite number")
    if len(arr) > 1 and np.allclose(arr[0], arr[-1]):
        arr = arr[:-1]
    if len(arr) > 1:  # drop consecutive duplicates
        keep = np.any(np.abs(np.diff(arr, axis=0, append=arr[:1])) > _EPS, axis=1)
        arr = arr[keep]
    if len(arr) < 3:
        raise CoverageError(f"{what} needs at least 3 distinct points, got {len(arr)}")
    if _self_intersects(arr):
        raise CoverageError(f"{what} intersects itself")
    if abs(_area(arr)) <= _EPS:
        raise CoverageError(f"{what} has no area (its points are on one line)")
    return arr


def _area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    cross: np.ndarray = ((a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1])
                         - (a[..., 1] - o[..., 1]) * (b[..., 0] - o[..., 0]))
    return cross


def _edges_cross(a0: np.ndarray, a1: np.ndarray, b0: np.ndarray, b1: np.ndarray
                 ) -> np.ndarray:
    """Proper crossings (and touching) of segment pairs (broadcast)."""
    d1, d2 = _cross(b0, b1, a0), _cross(b0, b1, a1)
    d3, d4 = _cross(a0, a1, b0), _cross(a0, a1, b1)
    collinear = (d1 == 0) & (d2 == 0)
    boxes = ((np.minimum(a0[..., 0], a1[..., 0]) <= np.maximum(b0[..., 0], b1[..., 0]))
             & (np.minimum(b0[..., 0], b1[..., 0]) <= np.maximum(a0[..., 0], a1[..., 0]))
             & (np.minimum(a0[..., 1], a1[..., 1]) <= np.maximum(b0[..., 1], b1[..., 1]))
             & (np.minimum(b0[..., 1], b1[..., 1]) <= np.maximum(a0[..., 1], a1[..., 1])))
    crossing: np.ndarray = (d1 * d2 <= 0) & (d3 * d4 <= 0) & (~collinear | boxes)
    return crossing


def _self_intersects(poly: np.ndarray) -> bool:
    n = len(poly)
    p0, p1 = poly, np.roll(poly, -1, axis=0)
    lo, hi = np.minimum(p0, p1), np.maximum(p0, p1)
    idx = np.arange(n)
    for start in range(0, n, 64):  # a run of edges against the edges near its bounding box
        i = idx[start:start + 64]
        near = np.all((lo <= hi[i].max(axis=0)) & (hi >= lo[i].min(axis=0)), axis=1)
        j = idx[near][None, :]
        hit = _edges_cross(p0[i, None], p1[i, None], p0[j], p1[j])
        gap = np.abs(i[:, None] - j)
        if np.any(hit & (gap > 1) & (gap != n - 1)):
            return True
    return False


def _inside(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Even-odd point-in-polygon test for (m, 2) points."""
    x, y = points[:, 0:1], points[:, 1:2]
    a, b = poly[None, :, :], np.roll(poly, -1, axis=0)[None, :, :]
    straddle = (a[..., 1] > y) != (b[..., 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = a[..., 0] + (y - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    return np.asarray(np.count_nonzero(straddle & (x < xc), axis=1) % 2 == 1)


def validate_field(border: Sequence[Sequence[float]],
                   holes: Sequence[Sequence[Sequence[float]]] = ()) -> Field:
    """Check and normalise a border and its holes (`CoverageError` names the problem)."""
    total = len(border) + sum(len(h) for h in holes)
    if total > MAX_INPUT_POINTS:
        raise CoverageError(f"border and holes have {total} points together "
                            f"(limit {MAX_INPUT_POINTS})")
    outer = _polygon(border, "border")
    inner = []
    e0, e1 = outer, np.roll(outer, -1, axis=0)
    for k, h in enumerate(holes):
        hole = _polygon(h, f"hole {k}")
        if not np.all(_inside(hole, outer)):
            raise CoverageError(f"hole {k} is not inside the border")
        h0, h1 = hole[:, None, :], np.roll(hole, -1, axis=0)[:, None, :]
        if np.any(_edges_cross(h0, h1, e0[None], e1[None])):
            raise CoverageError(f"hole {k} crosses the border")
        inner.append(hole)
    return Field(outer, tuple(inner))


# ---------------------------------------------------------------- swaths

def _rotate(poly: np.ndarray, angle: float) -> np.ndarray:
    """Rotate by ``-angle`` so swaths at ``angle`` run along x."""
    c, s = math.cos(angle), math.sin(angle)
    rotated: np.ndarray = poly @ np.array([[c, -s], [s, c]])
    return rotated


def _crossings(poly: np.ndarray, y: float) -> list[tuple[float, float]]:
    """Intervals of the line at ``y`` inside ``poly``."""
    a, b = poly, np.roll(poly, -1, axis=0)
    straddle = (a[:, 1] > y) != (b[:, 1] > y)
    a, b = a[straddle], b[straddle]
    xs = np.sort(a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1]))
    return [(float(xs[i]), float(xs[i + 1])) for i in range(0, len(xs) - 1, 2)]


def _subtract(keep: list[tuple[float, float]], cut: list[tuple[float, float]]
              ) -> list[tuple[float, float]]:
    out = keep
    for c0, c1 in cut:
        nxt = []
        for k0, k1 in out:
            if c1 <= k0 or c0 >= k1:
                nxt.append((k0, k1))
                continue
            if c0 > k0:
                nxt.append((k0, c0))
            if c1 < k1:
                nxt.append((c1, k1))
        out = nxt
    return out


def _near_edges(e0: np.ndarray, e1: np.ndarray, y: float, h: float
                ) -> list[tuple[float, float]]:
    """Intervals of the line at ``y`` closer than ``h`` to any edge (capsule sections)."""
    lo_y = np.minimum(e0[:, 1], e1[:, 1]) - h
    hi_y = np.maximum(e0[:, 1], e1[:, 1]) + h
    sel = (lo_y < y) & (hi_y > y)
    a, b = e0[sel], e1[sel]
    if len(a) == 0:
        return []
    lo = np.full(len(a), np.inf)
    hi = np.full(len(a), -np.inf)
    for p in (a, b):  # the end discs
        dy = y - p[:, 1]
        ok = np.abs(dy) < h
        r = np.sqrt(np.where(ok, h * h - dy * dy, 0.0))
        lo = np.where(ok, np.minimum(lo, p[:, 0] - r), lo)
        hi = np.where(ok, np.maximum(hi, p[:, 0] + r), hi)
    d = b - a
    length = np.hypot(d[:, 0], d[:, 1])
    nrm = np.stack([-d[:, 1], d[:, 0]], axis=1) / length[:, None] * h
    quad = [a + nrm, b + nrm, b - nrm, a - nrm]  # the band's rectangle
    for i in range(4):
        p, q = quad[i], quad[(i + 1) % 4]
        ok = ((p[:, 1] - y) * (q[:, 1] - y) <= 0) & (p[:, 1] != q[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            x = p[:, 0] + (y - p[:, 1]) * (q[:, 0] - p[:, 0]) / (q[:, 1] - p[:, 1])
        lo = np.where(ok, np.minimum(lo, x), lo)
        hi = np.where(ok, np.maximum(hi, x), hi)
    good = lo < hi
    return sorted(zip(lo[good].tolist(), hi[good].tolist()))


def _extent(poly: np.ndarray, angle: float) -> float:
    n = np.array([-math.sin(angle), math.cos(angle)])
    proj = poly @ n
    return float(proj.max() - proj.min())


def best_angle(border: np.ndarray) -> float:
    """The swath angle (radians, in [0, pi)) with the narrowest extent across it."""
    d = np.roll(border, -1, axis=0) - border
    lengths = np.hypot(d[:, 0], d[:, 1])
    order = np.argsort(-lengths, kind="stable")[:64]
    edge_angles = np.mod(np.arctan2(d[order, 1], d[order, 0]), math.pi)
    candidates = np.concatenate([edge_angles, np.radians(np.arange(0.0, 180.0, 5.0))])
    normals = np.stack([-np.sin(candidates), np.cos(candidates)], axis=1)
    proj = border @ normals.T
    widths = proj.max(axis=0) - proj.min(axis=0)
    best = int(np.argmin(np.round(widths, 9)))  # first minimum: longest edge first
    return float(candidates[best])


def plan_coverage(field: Field, op_width: float, swath_angle: float = 0.0,
                  headland_width: float = 0.0, turn_radius: float = 0.0) -> CoveragePlan:
    """The coverage route of ``field`` (angles in degrees; negative: the fewest swaths)."""
    for name, v, low_ok in (("op_width", op_width, False),
                            ("headland_width", headland_width, True),
                            ("turn_radius", turn_radius, True),
                            ("swath_angle", swath_angle, True)):
        if not math.isfinite(v):
            raise CoverageError(f"{name} must be a finite number, got {v!r}")
        if name != "swath_angle" and (v < 0 or (v == 0 and not low_ok)):
            raise CoverageError(f"{name} must be {'>= 0' if low_ok else '> 0'}, got {v!r}")
    angle = best_angle(field.border) if swath_angle < 0 else math.radians(swath_angle)
    border = _rotate(field.border, angle)
    holes = [_rotate(h, angle) for h in field.holes]
    polys = [border, *holes]
    e0 = np.concatenate(polys)
    e1 = np.concatenate([np.roll(p, -1, axis=0) for p in polys])
    y0 = float(border[:, 1].min()) + headland_width
    y1 = float(border[:, 1].max()) - headland_width
    extent = y1 - y0
    if extent <= 0:
        raise CoverageError(f"headland_width {headland_width:g} m leaves nothing of the "
                            f"border to cover")
    count = max(1, math.ceil(extent / op_width - 1e-9))
    if 2 * count > MAX_PATH_POINTS or count * len(e0) > MAX_WORK:
        raise CoverageError(f"the path would need {count} swaths over {len(e0)} edges "
                            f"(limit {MAX_PATH_POINTS} path points): raise op_width")
    if count == 1:
        ys = [0.5 * (y0 + y1)]
    else:
        first, last = y0 + op_width / 2, y1 - op_width / 2
        ys = [first + k * (last - first) / (count - 1) for k in range(count)]
    rows: list[list[tuple[float, float]]] = []
    for y in ys:
        keep = _crossings(border, y)
        for hole in holes:
            keep = _subtract(keep, _crossings(hole, y))
        if headland_width > 0:
            keep = _subtract(keep, _near_edges(e0, e1, y, headland_width))
        rows.append([(a, b) for a, b in keep if b - a > _EPS])
    driven, turns = _order(rows, ys)
    route: list[Point] = []
    for k, (a, b) in enumerate(driven):
        if k and turns[k - 1] and turn_radius > 0:
            prev = driven[k - 1]
            route += turn_points(prev[1], a, turn_radius,
                                 1.0 if prev[1][0] >= prev[0][0] else -1.0)
        route += [a, b]
        if len(route) > MAX_PATH_POINTS:
            raise CoverageError(f"the path would have over {MAX_PATH_POINTS} points: "
                                f"raise op_width")
    xy = np.asarray(route, dtype=float).reshape(-1, 2)
    xy = _rotate(xy, -angle) if len(xy) else xy
    swaths = sum(1 for row in rows if row)  # lines the holes or headland left nothing of
    return CoveragePlan(xy, math.degrees(angle), swaths, len(driven))


# ---------------------------------------------------------------- ordering

def _cells(rows: list[list[tuple[float, float]]]) -> list[list[tuple[int, int]]]:
    """Chains of (row, segment) where neighbouring rows' segments overlap one to one."""
    def overlaps(a: tuple[float, float], b: tuple[float, float]) -> bool:
        return a[0] < b[1] and b[0] < a[1]

    owner: dict[tuple[int, int], int] = {}
    cells: list[list[tuple[int, int]]] = []
    for r, row in enumerate(rows):
        for s, seg in enumerate(row):
            if r > 0:
                up = [t for t, other in enumerate(rows[r - 1]) if overlaps(seg, other)]
                if len(up) == 1:
                    down = [t for t, other in enumerate(row) if overlaps(rows[r - 1][up[0]],
                                                                         other)]
                    if len(down) == 1 and (r - 1, up[0]) in owner:
                        cell = owner[(r - 1, up[0])]
                        cells[cell].append((r, s))
                        owner[(r, s)] = cell
                        continue
            owner[(r, s)] = len(cells)
            cells.append([(r, s)])
    return cells


def _order(rows: list[list[tuple[float, float]]], ys: list[float]
           ) -> tuple[list[tuple[Point, Point]], list[bool]]:
    """Driven segments in order, and for each but the last whether a turn within its cell
    (to the next swath, the other way) follows it."""
    driven: list[tuple[Point, Point]] = []
    turns: list[bool] = []
    todo = _cells(rows)
    pos: Point | None = None
    while todo:
        if pos is None:
            pick, reverse = 0, False
        else:
            here = pos

            def dist(c: list[tuple[int, int]], at: int, here: Point) -> float:
                r, s = c[at]
                a, b = rows[r][s]
                return min(math.hypot(a - here[0], ys[r] - here[1]),
                           math.hypot(b - here[0], ys[r] - here[1]))
            options = [(dist(c, 0, here), i, False) for i, c in enumerate(todo)]
            options += [(dist(c, -1, here), i, True) for i, c in enumerate(todo)]
            _, pick, reverse = min(options)
        cell = todo.pop(pick)
        seq = cell[::-1] if reverse else cell
        r, s = seq[0]
        a, b = rows[r][s]
        forward = pos is None or abs(a - pos[0]) <= abs(b - pos[0])
        for k, (r, s) in enumerate(seq):
            a, b = rows[r][s]
            if driven:
                turns.append(k > 0)  # within the cell: a turn; else a move to a new cell
            driven.append(((a, ys[r]), (b, ys[r])) if forward else ((b, ys[r]), (a, ys[r])))
            forward = not forward
        pos = driven[-1][1]
    return driven, turns


# ---------------------------------------------------------------- turns

def _arc(center: Point, radius: float, start: float, stop: float, step: float
         ) -> list[Point]:
    """Points of an arc from angle ``start`` to ``stop`` (the first left out)."""
    n = max(2, math.ceil(abs(stop - start) / step))
    return [(center[0] + radius * math.cos(t), center[1] + radius * math.sin(t))
            for t in np.linspace(start, stop, n + 1)[1:].tolist()]


def turn_points(end: Point, start: Point, radius: float, heading: float,
                step: float = math.radians(10)) -> list[Point]:
    """The points strictly between swath end ``end`` (driven towards ``heading``, +1 or -1
    along x) and the next swath's ``start`` (driven back) of a turn whose radius is never
    below ``radius``.

    Both swaths are first extended to the outer of the two ends. A spacing ``d`` >= 2r
    turns with two quarter circles and a straight between them (a U); a smaller one with an
    omega (bulb) turn: out, round a circle tangent to both, and in. The turn reaches r (U)
    or r + sqrt(4r^2 - (d/2 + r)^2) (omega) past the outer end.
    """
    sy = 1.0 if start[1] >= end[1] else -1.0
    outer = max(heading * end[0], heading * start[0]) * heading
    d = abs(start[1] - end[1])
    r = radius

    def world(x: float, y: float) -> Point:
        return (outer + heading * x, end[1] + sy * y)

    local: list[Point] = []
    if d >= 2 * r:
        local += _arc((0.0, r), r, -math.pi / 2, 0.0, step)
        if d > 2 * r + _EPS:
            local.append((r, d - r))
        local += _arc((0.0, d - r), r, 0.0, math.pi / 2, step)[:-1]
    else:
        x2 = math.sqrt(4 * r * r - (d / 2 + r) ** 2)
        phi = math.atan2(d / 2 + r, x2)
        local += _arc((0.0, -r), r, math.pi / 2, phi, step)
        local += _arc((x2, d / 2), r, math.pi + phi, 3 * math.pi - phi, step)
        local += _arc((0.0, d + r), r, -phi, -math.pi / 2, step)[:-1]
    pts = [world(x, y) for x, y in local]
    if abs(outer - end[0]) > _EPS:
        pts.insert(0, (outer, end[1]))
    if abs(outer - start[0]) > _EPS:
        pts.append((outer, start[1]))
    return pts
