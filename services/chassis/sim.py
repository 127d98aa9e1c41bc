"""Simulation: one robot in a `World`, stepped at a fixed rate; the chassis node's whole state.

Each `step` runs the drive (limits, dead-man, e-stop), moves the round body along its arc
unless that would overlap the map or an obstacle (then it stops at contact and the bumper
is pressed), integrates odometry, and updates the dock and the battery. Times are seconds
of sim time since the start.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from zenros.se2 import Pose2, wrap_angle

from .battery import Battery
from .dock import Dock
from .drive import Drive
from .kinematics import integrate
from .laser import Laser
from .obstacles import Obstacle
from .odometry import Odometry
from .world import World

__all__ = ["Simulation", "start_pose"]

_CONTACT_ITERATIONS = 10


@dataclass
class Simulation:
    """The robot (a disc of ``radius``) and its devices; ``truth`` is its pose in ``map``."""

    world: World
    drive: Drive
    laser: Laser
    odometry: Odometry
    battery: Battery
    dock: Dock | None
    truth: Pose2
    radius: float = 0.2
    laser_mount: Pose2 = Pose2(0.0, 0.0, 0.0)
    time: float = 0.0
    bumper: bool = False
    docked: bool = False

    def __post_init__(self) -> None:
        self.start = self.truth  # odom's origin in map
        self.docked = self.dock is not None and self.dock.docked(self.truth)

    # ---------------------------------------------------------------- stepping

    def step(self, dt: float) -> None:
        """Advance the world by ``dt`` seconds."""
        v, w = self.drive.step(self.time, dt)
        if self.battery.empty and (v or w):
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
        self.odometry.update(v * moved, w * moved, dt)
        self.docked = self.dock is not None and self.dock.docked(self.truth)
        self.battery.update(dt, v * moved, w * moved, self.docked)
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

    def scan(self) -> np.ndarray:
        """The laser's ranges from where it is now."""
        p = self.truth * self.laser_mount
        return self.laser.ranges(p.x, p.y, p.theta)

    @property
    def odom_in_map(self) -> Pose2:
        """The ``odom`` frame's pose in ``map`` as the simulator knows it (truth ∘ odom⁻¹)."""
        return self.truth * self.odometry.pose.inverse()

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
        self.docked = self.dock is not None and self.dock.docked(self.truth)
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
