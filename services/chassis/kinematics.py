"""Unicycle kinematics: exact integration of (v, w) over a step."""

from __future__ import annotations

import math

from zenros.se2 import Pose2, wrap_angle

__all__ = ["integrate"]


def integrate(pose: Pose2, v: float, w: float, dt: float) -> Pose2:
    """The pose after moving at (v, w) for ``dt`` (an arc; a straight line when w is ~0)."""
    x, y, th = pose
    if abs(w) < 1e-9:
        return Pose2(x + v * dt * math.cos(th), y + v * dt * math.sin(th), th)
    th2 = th + w * dt
    r = v / w
    return Pose2(x + r * (math.sin(th2) - math.sin(th)), y - r * (math.cos(th2) - math.cos(th)),
                 wrap_angle(th2))
