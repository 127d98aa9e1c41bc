"""Dock: whether the robot sits on the charging dock (within a few cm and degrees of its pose)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from zenros.se2 import Pose2, wrap_angle

__all__ = ["Dock"]


@dataclass(frozen=True)
class Dock:
    """The docked pose in ``map``; docked within ``tolerance`` m and ``yaw_tolerance`` rad.

    Driving onto the dock counts: the map's dock block is where the bumper touches, and the
    docked pose sits within the tolerance of that contact.
    """

    pose: Pose2
    tolerance: float = 0.05
    yaw_tolerance: float = 0.1

    def docked(self, pose: Pose2) -> bool:
        return (math.hypot(pose.x - self.pose.x, pose.y - self.pose.y) <= self.tolerance
                and abs(wrap_angle(pose.theta - self.pose.theta)) <= self.yaw_tolerance)
