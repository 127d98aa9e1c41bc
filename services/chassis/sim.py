"""Simulation: the robot's round body in a `World`, stepped at a fixed rate.

Each `step` runs the drive (limits, dead-man, e-stop), moves the round body along its arc
unless that would overlap the map or an obstacle (then it stops at contact and the bumper
is pressed). The devices (odometry, battery, laser, ...: `device.Device`) are not here: the
`device.Chassis` steps them after the body. Times are seconds of sim time since the start.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

from zenros.se2 import Pose2, wrap_angle

from .drive import Drive
from .kinematics import integrate
from .obstacles import Obstacle
from .world import World

__all__ = ["Simulation", "start_pose"]

_CONTACT_ITERATIONS = 10


@dataclass
class Simulation:
    """The robot (a disc of ``radius``) in its world; ``truth`` is its pose in ``map``.

    ``linear`` and ``angular`` are what the base did over the last step (the drive's speeds,
    less what a contact cut short): what the odometry and the battery see. ``bumper`` is
    the body's contact: pressed by a step that stopped at contact, released by one that
    moved freely. ``powered`` false (an empty battery) holds the base still.
    """

    world: World
    drive: Drive
    truth: Pose2
    radius: float = 0.2
    time: float = 0.0
    bumper: bool = False
    powered: bool = True
    linear: float = 0.0
    angular: float = 0.0

    # ---------------------------------------------------------------- stepping

    def step(self, dt: float) -> None:
        """Advance the world by ``dt`` seconds."""
        v, w = self.drive.step(self.time, dt)
        if not self.powered and (v or w):
            self.drive.stop_now()
            v = w = 0.0
        moved = 1.0
        if v or w:
            target = integrate(self.truth, v, w, dt)
            if self.world.body_free(target.x, target.y, self.radius):
                self.truth = target
                self.bumper = False
            else:
                moved = self._contact(v, w, dt)
                self.drive.stop_now()
                self.bumper = True
        self.linear, self.angular = v * moved, w * moved
        self.time += dt

    def _contact(self, v: float, w: float, dt: float) -> float:
        """Move as far along the arc as the body fits; return the fraction moved."""
        lo, hi = 0.0, 1.0
        for _ in range(_CONTACT_ITERATIONS):
            mid = (lo + hi) / 2
            p = integrate(self.truth, v, w, dt * mid)
            if self.world.body_free(p.x, p.y, self.radius):
                lo = mid
            else:
                hi = mid
        if lo > 0:
            self.truth = integrate(self.truth, v, w, dt * lo)
        return lo

    # ---------------------------------------------------------------- requests

    def teleport(self, pose: Pose2) -> str:
        """Put the robot at ``pose``; return "" or why not (the robot is left where it was)."""
        if not all(math.isfinite(v) for v in pose):
            return f"pose must be finite, got ({pose.x}, {pose.y}, {pose.theta})"
        if not self.world.inside(pose.x, pose.y):
            return f"({pose.x:g}, {pose.y:g}) is outside the map"
        if not self.world.body_free(pose.x, pose.y, self.radius):
            return (f"the robot (radius {self.radius:g} m) does not fit at "
                    f"({pose.x:g}, {pose.y:g}): it would overlap a wall or an obstacle")
        self.truth = Pose2(pose.x, pose.y, wrap_angle(pose.theta))
        self.drive.stop_now()
        self.bumper = False
        return ""

    def check_obstacles(self, obstacles: Iterable[Obstacle]) -> str:
        """"" if none of ``obstacles`` overlaps the robot, else why."""
        for ob in obstacles:
            if ob.distance(self.truth.x, self.truth.y) <= self.radius:
                return (f"obstacle {ob.id!r} would overlap the robot at "
                        f"({self.truth.x:.2f}, {self.truth.y:.2f})")
        return ""


def start_pose(world: World, radius: float, wanted: Pose2 | None) -> Pose2:
    """Where the robot starts: ``wanted`` (the map folder's start pose) if given, else the
    map origin (0, 0) if free, else the free place nearest to it.

    Raises:
        ValueError: ``wanted`` is blocked or outside the map, or no place fits the robot.
    """
    if wanted is not None:
        if not (world.inside(wanted.x, wanted.y)
                and world.body_free(wanted.x, wanted.y, radius)):
            raise ValueError(f"start pose ({wanted.x:g}, {wanted.y:g}) is outside the map or "
                             f"the robot (radius {radius:g} m) does not fit there")
        return wanted
    spot = world.nearest_free(0.0, 0.0, radius)
    if spot is None:
        raise ValueError(f"the map has no free place for a robot of radius {radius:g} m")
    return Pose2(spot[0], spot[1], 0.0)
