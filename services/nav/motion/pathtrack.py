"""PathTracker: where the robot is along a path (closest segment), what is left, the carrot.

The closest point is searched on the segments from the last index onward, within a window
of ``search_dist`` metres of path, so a path that passes near itself is not short-cut
(Nav2's RPP prunes the same way). Distances are along the path.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["PathTracker"]


class PathTracker:
    """Progress along an (N, 2) polyline."""

    def __init__(self, xy: np.ndarray, search_dist: float = 2.0) -> None:
        self.xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        seg = np.diff(self.xy, axis=0)
        self.seg_len = np.hypot(seg[:, 0], seg[:, 1]) if len(seg) else np.zeros(0)
        self.cum = np.concatenate(([0.0], np.cumsum(self.seg_len)))
        self.length = float(self.cum[-1]) if len(self.cum) else 0.0
        self.search_dist = search_dist
        self.index = 0          # segment index of the closest point
        self.t = 0.0            # fraction along that segment

    def _project(self, px: float, py: float, lo: int, hi: int) -> tuple[int, float, float]:
        """Closest point on segments lo..hi-1: (segment, fraction, distance)."""
        a = self.xy[lo:hi]
        b = self.xy[lo + 1:hi + 1]
        d = b - a
        l2 = np.einsum("ij,ij->i", d, d)
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.where(l2 > 0, ((px - a[:, 0]) * d[:, 0] + (py - a[:, 1]) * d[:, 1]) / l2, 0.0)
        t = np.clip(t, 0.0, 1.0)
        qx = a[:, 0] + t * d[:, 0]
        qy = a[:, 1] + t * d[:, 1]
        dist = np.hypot(qx - px, qy - py)
        k = int(np.argmin(dist))
        return lo + k, float(t[k]), float(dist[k])

    def update(self, px: float, py: float) -> float:
        """Advance to the closest point to (px, py); returns the distance to the path."""
        n = len(self.xy)
        if n < 2:
            return math.hypot(px - self.xy[0, 0], py - self.xy[0, 1]) if n else math.inf
        start = self.index
        limit = self.cum[start] + self.search_dist
        hi = int(np.searchsorted(self.cum, limit, side="right"))
        hi = min(max(hi, start + 1), n - 1)
        k, t, dist = self._project(px, py, start, hi)
        if (k, t) >= (self.index, self.t):
            self.index, self.t = k, t
        return dist

    def position(self) -> float:
        """Arc length of the closest point from the start."""
        if len(self.seg_len) == 0:
            return 0.0
        return float(self.cum[self.index] + self.t * self.seg_len[self.index])

    def distance_remaining(self, px: float, py: float) -> float:
        """Path length from the closest point to the end, plus the gap to the path."""
        if len(self.xy) == 0:
            return 0.0
        if len(self.xy) == 1:
            return math.hypot(px - self.xy[0, 0], py - self.xy[0, 1])
        i, t = self.index, self.t
        q = self.xy[i] + t * (self.xy[i + 1] - self.xy[i])
        return self.length - self.position() + math.hypot(px - q[0], py - q[1])

    def point_at(self, s: float) -> tuple[float, float]:
        """The path point at arc length ``s`` (clamped to the ends)."""
        if len(self.xy) == 1 or s >= self.length:
            return float(self.xy[-1, 0]), float(self.xy[-1, 1])
        s = max(s, 0.0)
        i = int(np.searchsorted(self.cum, s, side="right")) - 1
        i = min(max(i, 0), len(self.seg_len) - 1)
        seg = self.seg_len[i]
        t = 0.0 if seg <= 0 else (s - self.cum[i]) / seg
        p = self.xy[i] + t * (self.xy[i + 1] - self.xy[i])
        return float(p[0]), float(p[1])

    def carrot(self, px: float, py: float, lookahead: float,
               max_s: float | None = None) -> tuple[float, float]:
        """The first path point at least ``lookahead`` from (px, py), beyond the closest point
        (interpolated on its segment); the path's end when none is that far. With ``max_s``
        the carrot goes no further along the path than that arc length."""
        n = len(self.xy)
        if n < 2:
            return float(self.xy[-1, 0]), float(self.xy[-1, 1])
        if max_s is not None:
            cap = self.point_at(max_s)
            if math.hypot(cap[0] - px, cap[1] - py) < lookahead:
                return cap
        start = self.index + 1
        d = np.hypot(self.xy[start:, 0] - px, self.xy[start:, 1] - py)
        far = np.nonzero(d >= lookahead)[0]
        if len(far) == 0:
            return float(self.xy[-1, 0]), float(self.xy[-1, 1])
        j = start + int(far[0])
        # interpolate between j-1 (inside the circle, or the closest point) and j (outside)
        a = self.xy[j - 1] if j - 1 > self.index else self.xy[self.index] + self.t * (
            self.xy[self.index + 1] - self.xy[self.index])
        b = self.xy[j]
        return _circle_hit((px, py), (float(a[0]), float(a[1])), (float(b[0]), float(b[1])),
                           lookahead)


def _circle_hit(c: tuple[float, float], a: tuple[float, float], b: tuple[float, float],
                r: float) -> tuple[float, float]:
    """Where segment a→b leaves the circle of radius r around c (b when it does not)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    fx, fy = a[0] - c[0], a[1] - c[1]
    qa = dx * dx + dy * dy
    if qa <= 1e-12:
        return b
    qb = 2 * (fx * dx + fy * dy)
    qc = fx * fx + fy * fy - r * r
    disc = qb * qb - 4 * qa * qc
    if disc < 0:
        return b
    t = (-qb + math.sqrt(disc)) / (2 * qa)
    t = min(max(t, 0.0), 1.0)
    return a[0] + t * dx, a[1] + t * dy
