"""Local moves: drive on a heading, spin in place, and a short move to a pose, all without
the global planner (Nav2's behavior server plugins, and the robot API's local moves).

Each is a `Behavior` ticked by `Motion`. Error codes come from the action's result type
(`MoveCodes`), so DriveOnHeading, BackUp and Spin each report their own Nav2 numbers.
Straight moves look ``ahead`` seconds along the remaining distance in the scan and stop
with COLLISION_AHEAD before the body would touch anything (unless collision checks are
off); a turn in place cannot hit anything with a round body. ``time_allowance`` <= 0 means
no limit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from zenros.se2 import Pose2, angle_diff

from .behavior import Behavior, Sense
from .collision import first_collision

__all__ = ["DriveOnHeading", "LocalMoveTarget", "MoveCodes", "SpinInPlace"]

NO_POSE_WAIT = 2.0  # seconds without a localised pose before TF_ERROR


@dataclass(frozen=True)
class MoveCodes:
    """The error codes one action reports."""

    timeout: int
    tf_error: int
    collision: int


class _Timed(Behavior):
    """Common start, timeout and no-pose handling."""

    def __init__(self, time_allowance: float, codes: MoveCodes) -> None:
        super().__init__()
        self.time_allowance = time_allowance
        self.codes = codes
        self.start: Pose2 | None = None
        self.t0: float | None = None

    def _check(self, s: Sense) -> bool:
        """False (after finishing) on a timeout or no pose; sets ``start`` on the first
        pose."""
        if self.t0 is None:
            self.t0 = s.now
        if s.pose is None:
            if s.now - self.t0 > NO_POSE_WAIT:
                self.finish(False, self.codes.tf_error, "no robot pose (not localised)")
            return False
        if self.start is None:
            self.start = s.pose
        if self.time_allowance > 0 and s.now - self.t0 > self.time_allowance:
            self.finish(False, self.codes.timeout,
                        f"not done within the time allowance ({self.time_allowance:g} s)")
            return False
        return True

    def elapsed(self, now: float) -> float:
        return 0.0 if self.t0 is None else max(0.0, now - self.t0)

    def measure(self, pose: Pose2) -> None:
        """Update how far the robot got from ``pose`` (after a cancel, once it stopped)."""


class DriveOnHeading(_Timed):
    """Drive straight ``distance`` metres (negative: backwards) at ``speed`` m/s (> 0),
    slowing down over the last centimetres so the base stops on the mark."""

    name = "drive_on_heading"

    def __init__(self, distance: float, speed: float, time_allowance: float, codes: MoveCodes,
                 radius: float, check_collisions: bool = True, ahead: float = 2.0,
                 tolerance: float = 0.005) -> None:
        super().__init__(time_allowance, codes)
        self.distance, self.speed = distance, abs(speed)
        self.radius, self.check_collisions, self.ahead = radius, check_collisions, ahead
        self.tolerance = tolerance
        self.traveled = 0.0

    def measure(self, pose: Pose2) -> None:
        if self.start is not None:
            self.traveled = abs((self.start.inverse() * pose).x)

    def tick(self, s: Sense) -> tuple[float, float]:
        if not self._check(s):
            return 0.0, 0.0
        assert s.pose is not None and self.start is not None
        self.measure(s.pose)
        left = abs(self.distance) - self.traveled
        if left <= self.tolerance:
            return self.finish(True)
        v = math.copysign(min(self.speed, max(0.02, 1.5 * left)), self.distance)
        if self.check_collisions:
            horizon = min(self.ahead, left / abs(v))
            if first_collision(v, 0.0, s.obstacles, self.radius, max(horizon, 0.05)) is not None:
                return self.finish(False, self.codes.collision,
                                   f"collision ahead after {self.traveled:.2f} of "
                                   f"{abs(self.distance):.2f} m")
        # hold the start heading (the base may drift a little while accelerating)
        w = max(-0.5, min(0.5, 2.0 * angle_diff(self.start.theta, s.pose.theta)))
        return v, w


class SpinInPlace(_Timed):
    """Turn in place by ``angle`` radians (+ counter-clockwise), fast while far and slowing
    over the last radian (recovery's spin law), done within ``tolerance`` of the angle.

    The rotation is tracked signed, so a turn that went past the mark (a control tick late
    on a loaded machine, the robot turning on meanwhile: 0.11 rad at a sim speed of 10)
    turns back to it rather than ending off by the overshoot."""

    name = "spin"

    def __init__(self, angle: float, speed: float, time_allowance: float,
                 codes: MoveCodes, tolerance: float = 0.02) -> None:
        super().__init__(time_allowance, codes)
        self.angle, self.speed, self.tolerance = angle, abs(speed), tolerance
        self.rotated = 0.0  # signed, + counter-clockwise
        self._last: float | None = None

    @property
    def turned(self) -> float:
        """How far the robot has turned from its start (Nav2's angular_distance_traveled)."""
        return abs(self.rotated)

    def measure(self, pose: Pose2) -> None:
        if self._last is not None:
            self.rotated += angle_diff(pose.theta, self._last)
        self._last = pose.theta

    def tick(self, s: Sense) -> tuple[float, float]:
        if not self._check(s):
            return 0.0, 0.0
        assert s.pose is not None
        self.measure(s.pose)
        left = self.angle - self.rotated
        if abs(left) <= self.tolerance:
            return self.finish(True)
        return 0.0, math.copysign(min(self.speed, max(0.2, 2.0 * abs(left))), left)


class LocalMoveTarget(_Timed):
    """A precise short move to ``target`` without the planner: turn toward it (when
    ``start_rotate``), drive to it (forwards, or backwards when it is behind and the robot
    may not turn first), then turn to its heading (when ``target_rotate``).

    ``target`` is in ``map``; ``relative`` makes it relative to the robot's pose at the
    start (``base_link``). Done within ``xy_tolerance`` (and ``yaw_tolerance`` when turning
    at the end)."""

    name = "local_move_target"

    def __init__(self, target: Pose2, relative: bool, xy_tolerance: float,
                 yaw_tolerance: float, time_allowance: float, start_rotate: bool,
                 target_rotate: bool, speed: float, turn_speed: float, codes: MoveCodes,
                 radius: float) -> None:
        super().__init__(time_allowance, codes)
        self.local_target, self.relative = target, relative
        self.goal: Pose2 | None = None if relative else target
        self.xy_tol, self.yaw_tol = xy_tolerance, yaw_tolerance
        self.start_rotate, self.target_rotate = start_rotate, target_rotate
        self.speed, self.turn_speed, self.radius = speed, turn_speed, radius
        self.phase = "start_rotate" if start_rotate else "drive"

    def distance_remaining(self, pose: Pose2 | None) -> float:
        if pose is None or self.goal is None:
            return 0.0
        return pose.distance(self.goal)

    def _turn(self, error: float) -> float:
        return math.copysign(min(self.turn_speed, max(0.15, 2.0 * abs(error))), error)

    def tick(self, s: Sense) -> tuple[float, float]:
        if not self._check(s):
            return 0.0, 0.0
        assert s.pose is not None and self.start is not None
        if self.goal is None:
            self.goal = self.start * self.local_target
        goal = self.goal
        local = s.pose.inverse().apply(goal.x, goal.y)
        d = math.hypot(*local)
        if self.phase == "start_rotate":
            if d <= self.xy_tol:
                self.phase = "drive"
            else:
                err = math.atan2(local[1], local[0])
                if abs(err) <= min(self.yaw_tol, 0.05):
                    self.phase = "drive"
                else:
                    return 0.0, self._turn(err)
        if self.phase == "drive":
            if d <= self.xy_tol:
                self.phase = "target_rotate"
            else:
                return self._drive(s, local, d)
        err = angle_diff(goal.theta, s.pose.theta)
        if not self.target_rotate or abs(err) <= self.yaw_tol:
            return self.finish(True)
        return 0.0, self._turn(err)

    def _drive(self, s: Sense, local: tuple[float, float], d: float) -> tuple[float, float]:
        backwards = local[0] < 0
        ahead_x = -local[0] if backwards else local[0]
        ahead_y = -local[1] if backwards else local[1]
        bearing = math.atan2(ahead_y, max(ahead_x, 1e-6))
        if abs(bearing) > 0.6 and d > 2 * self.xy_tol:
            return 0.0, self._turn(bearing)  # same sign backwards: the rear swings to it
        v = min(self.speed, max(0.03, 1.2 * d)) * math.cos(bearing)
        v = -v if backwards else v
        horizon = max(min(2.0, d / max(abs(v), 1e-3)), 0.05)
        if first_collision(v, 0.0, s.obstacles, self.radius, horizon) is not None:
            return self.finish(False, self.codes.collision,
                               f"collision ahead {d:.2f} m short of the target")
        return v, max(-self.turn_speed, min(self.turn_speed, 2.0 * bearing))
