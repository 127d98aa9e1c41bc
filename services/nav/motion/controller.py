"""Regulated Pure Pursuit: a path and the robot's pose in, a (v, ω) command out.

Nav2's RPP (specs/tf-nav.md D5): a carrot at the lookahead distance on the path, curvature
κ = 2y/(x²+y²) in the robot frame, ω = v·κ; the linear speed is regulated down in tight
turns (R < min_radius) and near obstacles (from the costmap cost at the robot), floored at
``regulated_linear_scaling_min_speed``, then slowed on the final approach. The robot turns
in place toward the path when it points more than ``rotate_to_heading_min_angle`` away, and
to the goal's heading once within ``xy_goal_tolerance`` (the position is latched there, as
Nav2's stateful goal checker does). Accelerations are limited against the last command.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from zenros.errors import ConfigError
from zenros.se2 import Pose2, angle_diff

from .pathtrack import PathTracker

__all__ = ["ControlOutput", "ControllerParams", "PurePursuit", "cost_to_distance", "curvature"]

State = Literal["following", "rotating_to_path", "rotating_to_goal", "goal_reached"]


@dataclass(frozen=True)
class ControllerParams:
    """RPP parameters and the goal checker's tolerances; the defaults are the nav service's
    (`zenros.services.nav.params.NavParameters`, a test holds them equal)."""

    max_linear_vel: float = 0.5
    max_angular_vel: float = 1.5
    lookahead_dist: float = 0.6
    min_lookahead_dist: float = 0.3
    max_lookahead_dist: float = 0.9
    lookahead_time: float = 1.5
    use_velocity_scaled_lookahead_dist: bool = False
    use_rotate_to_heading: bool = True
    rotate_to_heading_angular_vel: float = 1.0
    rotate_to_heading_min_angle: float = 0.785
    max_angular_accel: float = 3.0
    max_linear_accel: float = 1.0
    min_approach_linear_velocity: float = 0.05
    approach_velocity_scaling_dist: float = 0.6
    use_regulated_linear_velocity_scaling: bool = True
    regulated_linear_scaling_min_radius: float = 0.9
    regulated_linear_scaling_min_speed: float = 0.25
    use_cost_regulated_linear_velocity_scaling: bool = True
    cost_scaling_dist: float = 0.6
    cost_scaling_gain: float = 1.0
    inflation_cost_scaling_factor: float = 3.0
    inscribed_radius: float = 0.22
    xy_goal_tolerance: float = 0.15
    yaw_goal_tolerance: float = 0.15

    def check(self) -> None:
        """Raise `ConfigError` (a ValueError) for a non-positive speed, lookahead or tolerance."""
        for name in ("max_linear_vel", "max_angular_vel", "lookahead_dist",
                     "min_lookahead_dist", "max_lookahead_dist", "rotate_to_heading_angular_vel",
                     "max_angular_accel", "max_linear_accel", "xy_goal_tolerance",
                     "yaw_goal_tolerance", "regulated_linear_scaling_min_radius"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ConfigError(f"controller parameter {name} must be > 0, got {v}")


@dataclass(frozen=True)
class ControlOutput:
    """One command: speeds, what the controller is doing, and where it aims."""

    v: float
    w: float
    state: State
    carrot: tuple[float, float]
    distance_remaining: float


def curvature(x: float, y: float) -> float:
    """Pure pursuit's κ = 2y/(x²+y²) for a carrot at (x, y) in the robot frame."""
    d2 = x * x + y * y
    return 0.0 if d2 <= 0.001 else 2.0 * y / d2


def cost_to_distance(cost: float, inscribed_radius: float, csf: float) -> float:
    """RPP's distance-to-obstacle estimate from an inflation cost (Nav2's inverse formula)."""
    if cost <= 0:
        return math.inf
    return (csf * inscribed_radius - math.log(cost) + math.log(253.0)) / csf


class PurePursuit:
    """Follows one path; call `set_path`, then `compute` every control period."""

    def __init__(self, params: ControllerParams | None = None) -> None:
        self.params = params or ControllerParams()
        self.params.check()
        self.track = PathTracker(np.zeros((0, 2)))
        self.goal_yaw: float | None = None
        self.last_v = 0.0
        self.last_w = 0.0
        self._xy_reached = False

    def set_path(self, xy: np.ndarray, goal_yaw: float | None, *, keep_goal_latch: bool = False
                 ) -> None:
        """Follow ``xy`` (N, 2) in ``map``; turn to ``goal_yaw`` at the end (None: don't)."""
        if len(xy) == 0:
            raise ValueError("cannot follow an empty path")
        if not np.all(np.isfinite(xy)):
            raise ValueError("path has non-finite points")
        self.track = PathTracker(np.asarray(xy, dtype=float))
        self.goal_yaw = goal_yaw
        if not keep_goal_latch:
            self._xy_reached = False

    def reset_speed(self, v: float = 0.0, w: float = 0.0) -> None:
        self.last_v, self.last_w = v, w

    @property
    def goal(self) -> tuple[float, float]:
        x, y = self.track.xy[-1]
        return float(x), float(y)

    def lookahead(self, speed: float) -> float:
        p = self.params
        if p.use_velocity_scaled_lookahead_dist:
            return min(max(abs(speed) * p.lookahead_time, p.min_lookahead_dist),
                       p.max_lookahead_dist)
        return p.lookahead_dist

    def compute(self, pose: Pose2, dt: float, cost_at_robot: float = 0.0,
                carrot_limit: float | None = None, lookahead: float | None = None,
                commit: bool = True) -> ControlOutput:
        """The command for the robot at ``pose`` (``dt``: seconds since the last command).

        ``carrot_limit`` (arc length along the path) keeps the carrot from passing a via
        point, so the robot goes through it instead of cutting the corner. ``lookahead``
        overrides the lookahead distance; with ``commit`` false the command is not taken as
        sent (a trial: the acceleration limits still start from the last sent one)."""
        saved = (self.last_v, self.last_w, self._xy_reached)
        out = self._compute(pose, dt, cost_at_robot, carrot_limit, lookahead)
        if not commit:
            self.last_v, self.last_w, self._xy_reached = saved
        return out

    def _compute(self, pose: Pose2, dt: float, cost_at_robot: float,
                 carrot_limit: float | None, lookahead: float | None) -> ControlOutput:
        p = self.params
        self.track.update(pose.x, pose.y)
        remaining = self.track.distance_remaining(pose.x, pose.y)
        gx, gy = self.goal
        to_goal = math.hypot(gx - pose.x, gy - pose.y)
        if not self._xy_reached and to_goal <= p.xy_goal_tolerance \
                and remaining <= p.xy_goal_tolerance + self.lookahead(self.last_v):
            self._xy_reached = True
        if self._xy_reached:
            return self._rotate_to_goal(pose, dt, (gx, gy), to_goal)

        ahead = lookahead if lookahead is not None else self.lookahead(self.last_v)
        carrot = self.track.carrot(pose.x, pose.y, ahead, carrot_limit)
        cx, cy = pose.inverse().apply(*carrot)
        angle = math.atan2(cy, cx)
        if p.use_rotate_to_heading and abs(angle) > p.rotate_to_heading_min_angle:
            w = math.copysign(p.rotate_to_heading_angular_vel, angle)
            v, w = self._limit(0.0, w, dt)
            return ControlOutput(v, w, "rotating_to_path", carrot, remaining)

        k = curvature(cx, cy)
        v = self._regulate(k, cost_at_robot, remaining)
        w = v * k
        if abs(w) > p.max_angular_vel:  # keep the arc: slow down rather than cut the turn
            v *= p.max_angular_vel / abs(w)
            w = math.copysign(p.max_angular_vel, w)
        v, w = self._limit(v, w, dt)
        return ControlOutput(v, w, "following", carrot, remaining)

    def _regulate(self, k: float, cost: float, remaining: float) -> float:
        p = self.params
        v = p.max_linear_vel
        regulated = v
        if p.use_regulated_linear_velocity_scaling and abs(k) > 1e-9:
            radius = abs(1.0 / k)
            if radius < p.regulated_linear_scaling_min_radius:
                regulated = v * radius / p.regulated_linear_scaling_min_radius
        if p.use_cost_regulated_linear_velocity_scaling and cost > 0:
            d = cost_to_distance(cost, p.inscribed_radius, p.inflation_cost_scaling_factor)
            if d < p.cost_scaling_dist:
                regulated = min(regulated, v * p.cost_scaling_gain * d / p.cost_scaling_dist)
        v = max(regulated, p.regulated_linear_scaling_min_speed)
        if p.approach_velocity_scaling_dist > 0 and remaining < p.approach_velocity_scaling_dist:
            approach = v * remaining / p.approach_velocity_scaling_dist
            v = min(v, max(approach, p.min_approach_linear_velocity))
        return min(max(v, 0.0), p.max_linear_vel)

    def _rotate_to_goal(self, pose: Pose2, dt: float, goal: tuple[float, float],
                        to_goal: float) -> ControlOutput:
        p = self.params
        if self.goal_yaw is None:
            v, w = self._limit(0.0, 0.0, dt, hard_stop=True)
            return ControlOutput(0.0, 0.0, "goal_reached", goal, to_goal)
        err = angle_diff(self.goal_yaw, pose.theta)
        if abs(err) <= p.yaw_goal_tolerance:
            self.reset_speed()
            return ControlOutput(0.0, 0.0, "goal_reached", goal, to_goal)
        # as fast as allowed, but slow enough to stop on the heading: ω ≤ sqrt(2·α·|err|)
        speed = min(p.rotate_to_heading_angular_vel,
                    math.sqrt(2.0 * p.max_angular_accel * abs(err)))
        v, w = self._limit(0.0, math.copysign(speed, err), dt)
        return ControlOutput(v, w, "rotating_to_goal", goal, to_goal)

    def _limit(self, v: float, w: float, dt: float, hard_stop: bool = False) -> tuple[float, float]:
        p = self.params
        if not hard_stop and dt > 0:
            dv, dw = p.max_linear_accel * dt, p.max_angular_accel * dt
            v = min(max(v, self.last_v - dv), self.last_v + dv)
            w = min(max(w, self.last_w - dw), self.last_w + dw)
        self.last_v, self.last_w = v, w
        return v, w
