"""Collision checks on the command about to be sent: the robot's arc against scan points.

A circular robot of ``radius`` moving at (v, ω) sweeps an arc; `first_collision` samples it
every ``step`` metres (and radians) for ``horizon`` seconds and returns the time of the
first pose that comes within ``radius`` of an obstacle point (robot frame), or None. A
turn in place never collides (the disc does not move), so only the current pose matters
then, and it is not checked: the robot may always turn away.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["arc_poses", "first_collision", "points_in_frame"]


def arc_poses(v: float, w: float, horizon: float, step: float = 0.05) -> np.ndarray:
    """(K, 4) samples ``t, x, y, yaw`` of the arc from the origin, K >= 1, t > 0."""
    travel = max(abs(v) * horizon, 1e-9)
    n = max(1, math.ceil(travel / step), math.ceil(abs(w) * horizon / 0.2))
    t = np.linspace(horizon / n, horizon, n)
    yaw = w * t
    if abs(w) < 1e-6:
        x, y = v * t, np.zeros_like(t)
    else:
        r = v / w
        x, y = r * np.sin(yaw), r * (1.0 - np.cos(yaw))
    return np.column_stack([t, x, y, yaw])


def first_collision(v: float, w: float, obstacles: np.ndarray, radius: float,
                    horizon: float, step: float = 0.05) -> float | None:
    """Seconds until the robot's disc would touch an obstacle point, None if it won't
    within ``horizon``. ``obstacles`` is (M, 2) in the robot frame."""
    if abs(v) < 1e-6 or len(obstacles) == 0:
        return None
    reach = abs(v) * horizon + radius
    pts = obstacles[np.einsum("ij,ij->i", obstacles, obstacles) <= reach * reach]
    if len(pts) == 0:
        return None
    arc = arc_poses(v, w, horizon, step)
    d2 = ((arc[:, None, 1] - pts[None, :, 0]) ** 2 + (arc[:, None, 2] - pts[None, :, 1]) ** 2)
    hit = np.nonzero((d2 <= radius * radius).any(axis=1))[0]
    return float(arc[hit[0], 0]) if len(hit) else None


def points_in_frame(points: np.ndarray, x: float, y: float, theta: float) -> np.ndarray:
    """(M, 2) points of the parent frame expressed in the frame at (x, y, theta)."""
    if len(points) == 0:
        return points.reshape(0, 2)
    c, s = math.cos(theta), math.sin(theta)
    dx, dy = points[:, 0] - x, points[:, 1] - y
    return np.column_stack([c * dx + s * dy, -s * dx + c * dy])
