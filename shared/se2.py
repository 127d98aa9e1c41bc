"""Pose2: a pose in the plane (x, y, theta), the SE(2) algebra the services share, and the
angle wrap they use (into [-pi, pi); `zenros.tf.normalize_angle` is ROS's, into (-pi, pi])."""

from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["Pose2", "angle_diff", "wrap_angle"]


def wrap_angle(a: float) -> float:
    """``a`` wrapped into [-pi, pi)."""
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def angle_diff(to: float, frm: float) -> float:
    """The shortest signed turn from ``frm`` to ``to``, in [-pi, pi)."""
    return wrap_angle(to - frm)


class Pose2(NamedTuple):
    """A rigid transform of the plane: rotate by ``theta``, then translate by (x, y).

    As a pose it is a frame in its parent: ``parent_T_child``. ``a * b`` composes
    (``a`` applied after ``b``: ``b`` given in ``a``'s frame, expressed outside it), as tf
    does with 4x4 matrices. Headings stay wrapped into [-pi, pi).
    """

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0

    def __mul__(self, other: object) -> Pose2:
        if not isinstance(other, Pose2):
            return NotImplemented
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2(self.x + c * other.x - s * other.y,
                     self.y + s * other.x + c * other.y,
                     wrap_angle(self.theta + other.theta))

    def inverse(self) -> Pose2:
        c, s = math.cos(self.theta), math.sin(self.theta)
        return Pose2(-c * self.x - s * self.y, s * self.x - c * self.y, wrap_angle(-self.theta))

    def apply(self, x: float, y: float) -> tuple[float, float]:
        """The point (x, y) of this frame, expressed in the parent frame."""
        c, s = math.cos(self.theta), math.sin(self.theta)
        return self.x + c * x - s * y, self.y + s * x + c * y

    def distance(self, other: Pose2) -> float:
        return math.hypot(other.x - self.x, other.y - self.y)

    def is_finite(self) -> bool:
        return all(math.isfinite(v) for v in self)
