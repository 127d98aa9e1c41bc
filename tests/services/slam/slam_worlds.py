"""Synthetic worlds for the SLAM unit tests: walls as segments, scans ray-cast against them."""

from __future__ import annotations

import math

import numpy as np
from zenros.se2 import Pose2
from zenros.services.slam.scan import RangeScan

Segment = tuple[float, float, float, float]

# a 10 x 6 m room with a pillar and an alcove: no symmetry a match could fold onto
ROOM: list[Segment] = [
    (0, 0, 10, 0), (10, 0, 10, 6), (10, 6, 0, 6), (0, 6, 0, 0),
    (3, 2, 4, 2), (4, 2, 4, 3), (4, 3, 3, 3), (3, 3, 3, 2),
    (7, 6, 7, 4.5), (7, 4.5, 8.5, 4.5),
]


def corridor(length: float = 40.0, width: float = 2.0) -> list[Segment]:
    """Two long parallel walls: every place along it looks the same."""
    return [(-length / 2, -width / 2, length / 2, -width / 2),
            (-length / 2, width / 2, length / 2, width / 2)]


def cast(walls: list[Segment], pose: Pose2, beams: int = 360, max_range: float = 12.0,
         noise: float = 0.0, seed: int = 0) -> RangeScan:
    """A scan from the base at ``pose`` (laser on the base's centre)."""
    angles = -math.pi + np.arange(beams) * (2 * math.pi / beams)
    a = pose.theta + angles
    dx, dy = np.cos(a), np.sin(a)
    best = np.full(beams, np.inf)
    for x0, y0, x1, y1 in walls:
        ex, ey = x1 - x0, y1 - y0
        den = dx * ey - dy * ex
        with np.errstate(divide="ignore", invalid="ignore"):
            t = ((x0 - pose.x) * ey - (y0 - pose.y) * ex) / den
            u = ((x0 - pose.x) * dy - (y0 - pose.y) * dx) / den
        ok = (np.abs(den) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1)
        best = np.where(ok & (t < best), t, best)
    if noise:
        rng = np.random.default_rng(seed)
        best = best + rng.normal(0, noise, beams) * np.isfinite(best)
    best[best > max_range] = np.inf
    return RangeScan.from_laser(best.astype(np.float32), -math.pi, 2 * math.pi / beams,
                                Pose2(), 0.05, max_range, 20.0, 6.0)
