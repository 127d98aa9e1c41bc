"""Unicycle kinematics: exact integration of (v, w) over a step, and pose arithmetic."""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["Pose2", "integrate", "wrap"]


class Pose2(NamedTuple):
    """A planar pose: x, y (m), theta (rad)."""

    x: float
    y: float
    theta: float

    def compose(self, other: Pose2) -> Pose2:
        """``self * other``: ``other`` given in this pose's frame, expressed outside it."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2(self.x + c * other.x - s * other.y, self.y + s * other.x + c * other.y,
                     wrap(self.theta + other.theta))

    def inverse(self) -> Pose2:
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2(-c * self.x - s * self.y, s * self.x - c * self.y, -self.theta)


def wrap(angle: float) -> float:
    """The angle in [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def integrate(pose: Pose2, v: float, w: float, dt: float) -> Pose2:
    """The pose after moving at (v, w) for ``dt`` (an arc; a straight line when w is ~0)."""
    x, y, th = pose
    if abs(w) < 1e-9:
        return Pose2(x + v * dt * math.cos(th), y + v * dt * math.sin(th), th)
    th2 = th + w * dt
    r = v / w
    return Pose2(x + r * (math.sin(th2) - math.sin(th)), y - r * (math.cos(th2) - math.cos(th)),
                 wrap(th2))
