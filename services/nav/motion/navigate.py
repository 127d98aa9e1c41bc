"""Navigate: plan through goal poses and follow the plan, replanning and recovering.

The Nav2 navigator's default tree as a state machine: plan (on the planner thread) →
follow with Regulated Pure Pursuit, replanning every ``replan_period``; a command whose arc
would touch a scan point within ``collision_horizon`` (or enter a keep-out cell) is not
sent and the robot stops (``blocked``), a replan is asked for at once, and after
``blocked_wait`` (or ``progress_timeout`` without progress) a recovery runs: clear the
obstacle layer, then wait / back up / spin in turn. After ``max_recoveries`` the goal fails
with the last planner error (ComputePathToPose's 2xx code) or FAILED_TO_MAKE_PROGRESS (105).

With ``fixed_path`` (the ``follow_path`` action) there is no planner: a blocked path is
waited on, then fails with FAILED_TO_MAKE_PROGRESS.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from zenros.msgs.nav2_msgs import FollowPathResult as FollowCodes
from zenros.se2 import Pose2

from ..planning.global_planner import PlanOutcome
from .behavior import Behavior, NavParams, NavTools, Sense
from .collision import arc_poses, first_collision
from .controller import ControllerParams, PurePursuit
from .recovery import Recovery, recovery_cycle
from .traffic import TrafficGate

__all__ = ["Codes", "Navigate", "WaypointState"]

PENDING, COMPLETED, FAILED = 0, 1, 3


@dataclass(frozen=True)
class Codes:
    """The result codes of the action that runs the behaviour (they differ per action)."""

    timeout: int = 9003
    tf_error: int = 9002
    unknown: int = 9000


@dataclass
class WaypointState:
    pose: Pose2
    status: int = PENDING
    error_code: int = 0
    error_msg: str = ""


class Navigate(Behavior):
    """Drive to ``goals`` in order (one path through them all), ending at the last pose."""

    name = "navigate"

    def __init__(self, goals: list[Pose2], tools: NavTools, params: NavParams,
                 controller: ControllerParams, codes: Codes = Codes(), *,
                 fixed_path: np.ndarray | None = None, final_yaw: bool = True,
                 gate: TrafficGate | None = None) -> None:
        super().__init__()
        self.gate = gate  # schedule mode's traffic gate (motion/traffic.py); None: none
        self.goals = list(goals)
        self.waypoints = [WaypointState(g) for g in goals]
        self.tools, self.p, self.codes = tools, params, codes
        self.pp = PurePursuit(controller)
        self.final_yaw = final_yaw
        self.fixed = fixed_path is not None
        self.state = "planning"
        self.recoveries = 0
        self.distance_remaining = math.nan
        self.speed = 0.0
        self.path: np.ndarray | None = None
        self._leg_ends: list[float] = []
        self._first_wp = 0  # index of the first waypoint the current plan leads to
        self._pending_first = 0  # the same for the plan being made
        self._ticket: int | None = None
        self._last_request = -math.inf
        self._plan_failures = 0
        self._last_plan_error: tuple[int, str] | None = None
        self._blocked_since: float | None = None
        self._recovery: Recovery | None = None
        self._progress_at = (0.0, math.inf)  # (time, distance remaining) of the last progress
        self._no_pose_since: float | None = None
        # schedule mode's wait off the path (`TrafficGate.aside`): the place, the plan to it
        # (None: being made; empty: none, wait where it stands), and the path it left
        self._aside: tuple[float, float] | None = None
        self._aside_ticket: int | None = None
        self._aside_path: np.ndarray | None = None
        self._left: tuple[np.ndarray, float] | None = None
        if fixed_path is not None:
            yaw = goals[-1].theta if goals and final_yaw else None
            self._adopt(fixed_path, yaw, [])

    # ------------------------------------------------------------------ planning

    def _remaining_goals(self) -> list[Pose2]:
        return [w.pose for w in self.waypoints if w.status == PENDING]

    def _request_plan(self, sense: Sense) -> None:
        if self.fixed or sense.pose is None or self._ticket is not None:
            return
        goals = self._remaining_goals()
        if not goals:
            return
        self._pending_first = len(self.waypoints) - len(goals)
        self._ticket = self.tools.worker.submit(sense.pose, goals)
        self._last_request = sense.now

    def _adopt(self, xy: np.ndarray, yaw: float | None, leg_ends: list[float]) -> None:
        self.pp.set_path(xy, yaw, keep_goal_latch=self.path is not None)
        self.path = xy
        self._leg_ends = leg_ends
        self.tools.on_plan(xy)

    def _on_plan(self, out: PlanOutcome, sense: Sense) -> None:
        if self._aside is not None:
            self._last_request = -math.inf  # waiting off the path: plan again once back
            return
        if out.ok:
            assert out.xy is not None
            done = sum(1 for w in self.waypoints if w.status != PENDING)
            if self.path is not None and done != self._pending_first:
                self._last_request = -math.inf  # a waypoint was passed meanwhile: plan again
                return
            self._first_wp = self._pending_first
            self._plan_failures = 0
            self._last_plan_error = None
            yaw = self.goals[-1].theta if self.final_yaw else None
            self._adopt(out.xy, yaw, out.leg_ends)
            if self.state == "planning":
                self.state = "following"
                self._progress_at = (sense.now, math.inf)
            return
        self._last_plan_error = (out.error_code, out.error_msg)
        if self.path is not None and self.state == "following":
            return  # a periodic replan failed: keep the plan we have
        self._plan_failures += 1
        if self.state == "planning" and self._plan_failures > self.p.plan_retries:
            self._fail_waypoints(out.error_code, out.error_msg)
            self.finish(False, out.error_code, out.error_msg)
        elif self.state == "planning":
            self.tools.clear_obstacles()  # Nav2's first recovery: clear the costmaps
            self.recoveries += 1

    def _fail_waypoints(self, code: int, msg: str) -> None:
        for w in self.waypoints:
            if w.status == PENDING:
                w.status, w.error_code, w.error_msg = FAILED, code, msg

    def _via_limit(self) -> float | None:
        """The arc length of the next via point still to pass (None: only the goal left)."""
        for k, end in enumerate(self._leg_ends[:-1]):
            i = self._first_wp + k
            if i < len(self.waypoints) and self.waypoints[i].status == PENDING:
                return end
        return None

    def _update_waypoints(self) -> None:
        if not self._leg_ends or self.path is None:
            return
        s = self.pp.track.position()
        tol = self.pp.params.xy_goal_tolerance
        for k, end in enumerate(self._leg_ends[:-1]):  # the last one completes on success
            i = self._first_wp + k
            if i < len(self.waypoints) and self.waypoints[i].status == PENDING and s >= end - tol:
                self.waypoints[i].status = COMPLETED

    # ------------------------------------------------------------------ the tick

    def tick(self, sense: Sense) -> tuple[float, float]:
        if sense.pose is None:
            if self._no_pose_since is None:
                self._no_pose_since = sense.now
            if sense.now - self._no_pose_since > self.p.localization_timeout:
                return self.finish(False, self.codes.tf_error, "the robot's pose in map is unknown")
            return 0.0, 0.0
        self._no_pose_since = None
        assert self.started_at is not None
        limit = self.p.navigation_timeout
        if limit > 0 and sense.now - self.started_at > limit:
            self._fail_waypoints(self.codes.timeout, "timed out")
            return self.finish(False, self.codes.timeout,
                               f"navigation took longer than {self.p.navigation_timeout} s")
        if self._ticket is not None:
            out = self.tools.worker.poll(self._ticket)
            if out is not None:
                self._ticket = None
                self._on_plan(out, sense)
                if self.done.is_set():
                    return 0.0, 0.0
        if self.state == "planning":
            if self._ticket is None:
                self._request_plan(sense)
            return self._stop(sense)
        if (self.p.replan_period > 0 and sense.now - self._last_request >= self.p.replan_period
                and self._aside is None):
            self._request_plan(sense)
        if self.state == "recovering":
            return self._recover(sense)
        return self._follow(sense)

    def _stop(self, sense: Sense) -> tuple[float, float]:
        self.pp.reset_speed()
        self.speed = 0.0
        return 0.0, 0.0

    def finish(self, ok: bool, code: int = 0, msg: str = "") -> tuple[float, float]:
        if self.gate is not None:
            self.gate.end()
        return super().finish(ok, code, msg)

    def _gate_limit(self, sense: Sense) -> float | None:
        """How far along the path the traffic gate lets the robot go (None: the gate's
        off or has no limit). Off the path (waiting aside), it asks with the path and the
        point where the robot left it."""
        if self.gate is None or self.path is None or sense.pose is None:
            return None
        path, s = self._left or (self.path, self.pp.track.position())
        return self.gate.limit(sense.now, sense.pose, path, s)

    def _step_aside(self, sense: Sense, place: tuple[float, float] | None
                    ) -> tuple[float, float]:
        """Drive to the gate's place off the path and wait there; once the gate no longer
        names one, plan from there to the goals again."""
        assert sense.pose is not None
        pose = sense.pose
        if place is None:  # back to the goals, on a new plan (no goal latched from the aside)
            self._aside, self._aside_ticket, self._aside_path, self._left = None, None, None, None
            self.state, self._ticket, self.path = "planning", None, None
            self._request_plan(sense)
            return self._stop(sense)
        if place != self._aside:
            if self._left is None:
                assert self.path is not None
                self._left = (self.path, self.pp.track.position())
            self._aside, self._aside_path, self._ticket = place, None, None
            self._aside_ticket = self.tools.worker.submit(
                pose, [Pose2(place[0], place[1], pose.theta)])
        if self._aside_ticket is not None:
            plan = self.tools.worker.poll(self._aside_ticket)
            if plan is None:
                return self._wait_for_traffic(sense)
            self._aside_ticket = None
            self._aside_path = plan.xy if plan.ok and plan.xy is not None else np.zeros((0, 2))
            if len(self._aside_path):
                self.pp.set_path(self._aside_path, None, keep_goal_latch=False)
        if self._aside_path is None or len(self._aside_path) < 2:
            return self._wait_for_traffic(sense)  # no way there: wait where it stands
        cost = self.tools.cost_at(pose.x, pose.y)
        out = self.pp.compute(pose, sense.dt, 0 if cost >= 253 else cost, None)
        if out.state == "goal_reached" or self._collides(pose, out.v, out.w, sense):
            return self._wait_for_traffic(sense)
        self.state = "waiting"
        self._blocked_since = None
        self._progress_at = (sense.now, math.inf)
        self.speed = out.v
        return out.v, out.w

    def _wait_for_traffic(self, sense: Sense) -> tuple[float, float]:
        """Stopped at the end of the grant: not blocked, no recovery, no progress timeout."""
        self.state = "waiting"
        self._blocked_since = None
        self._progress_at = (sense.now, math.inf)
        return self._stop(sense)

    def _follow(self, sense: Sense) -> tuple[float, float]:
        assert sense.pose is not None
        pose = sense.pose
        cost = self.tools.cost_at(pose.x, pose.y)
        sent = (self.pp.last_v, self.pp.last_w)
        cap = self._gate_limit(sense)
        if self.gate is not None:
            place = self.gate.aside(sense.now)
            if place is not None or self._aside is not None:
                return self._step_aside(sense, place)
        carrot_limit = self._via_limit()
        if cap is not None:
            if cap - self.pp.track.position() <= 0.05:
                return self._wait_for_traffic(sense)
            carrot_limit = cap if carrot_limit is None else min(carrot_limit, cap)
        out = self.pp.compute(pose, sense.dt, 0 if cost >= 253 else cost, carrot_limit)
        self.distance_remaining = out.distance_remaining
        self._update_waypoints()
        if out.state == "goal_reached":
            for wp in self.waypoints:
                if wp.status == PENDING:
                    wp.status = COMPLETED
            self.distance_remaining = 0.0
            return self.finish(True)
        v, w = out.v, out.w
        if cap is not None and v > 0:  # slow enough to stop at the end of the grant
            room = max(0.0, cap - self.pp.track.position() - 0.03)
            top = math.sqrt(2.0 * self.pp.params.max_linear_accel * room)
            if v > top:
                v, w = top, w * top / v
                self.pp.reset_speed(v, w)
        if self._collides(pose, v, w, sense):
            # the arc to a nearer carrot hugs the plan more closely: try that before stopping
            self.pp.reset_speed(*sent)
            alt = self.pp.compute(pose, sense.dt, 0 if cost >= 253 else cost, carrot_limit,
                                  lookahead=self.pp.params.min_lookahead_dist, commit=False)
            if alt.state != out.state or self._collides(pose, alt.v, alt.w, sense):
                return self._blocked(sense)
            v, w = alt.v, alt.w
            self.pp.reset_speed(v, w)
        self._blocked_since = None
        self.state = "following"
        self.speed = v
        # progress: the remaining distance must shrink by progress_distance now and then
        t0, d0 = self._progress_at
        if out.distance_remaining < d0 - self.p.progress_distance or out.state != "following":
            self._progress_at = (sense.now, out.distance_remaining)
        elif sense.now - t0 > self.p.progress_timeout:
            self._progress_at = (sense.now, out.distance_remaining)
            return self._start_recovery(sense)
        return v, w

    def _collides(self, pose: Pose2, v: float, w: float, sense: Sense) -> bool:
        radius = self.p.collision_radius
        if first_collision(v, w, sense.obstacles, radius, self.p.collision_horizon) is not None:
            return True
        if abs(v) < 1e-6:
            return False
        arc = arc_poses(v, w, min(self.p.collision_horizon, 0.5), 0.02)
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        pts = np.column_stack([pose.x + c * arc[:, 1] - s * arc[:, 2],
                               pose.y + s * arc[:, 1] + c * arc[:, 2]])
        return self.tools.keepout_hit(pts)

    def _blocked(self, sense: Sense) -> tuple[float, float]:
        if self._blocked_since is None:
            self._blocked_since = sense.now
            self.state = "blocked"
            if self._ticket is None and not self.fixed:
                self._request_plan(sense)
        elif sense.now - self._blocked_since > self.p.blocked_wait:
            return self._start_recovery(sense)
        return self._stop(sense)

    def _start_recovery(self, sense: Sense) -> tuple[float, float]:
        self._blocked_since = None
        if self.fixed:
            return self.finish(False, FollowCodes.FAILED_TO_MAKE_PROGRESS,
                               "the path is blocked")
        if self.recoveries >= self.p.max_recoveries:
            code, msg = self._last_plan_error or (
                FollowCodes.FAILED_TO_MAKE_PROGRESS,
                f"blocked: no progress after {self.recoveries} recoveries")
            self._fail_waypoints(code, msg)
            return self.finish(False, code, msg)
        self.tools.clear_obstacles()
        self._recovery = recovery_cycle(
            self.recoveries, wait=self.p.wait_duration, backup=self.p.backup_distance,
            backup_speed=self.p.backup_speed, spin=self.p.spin_angle,
            spin_speed=self.p.spin_speed, radius=self.p.collision_radius)
        self.recoveries += 1
        self.state = "recovering"
        return self._recover(sense)

    def _recover(self, sense: Sense) -> tuple[float, float]:
        assert self._recovery is not None
        v, w = self._recovery.tick(sense)
        if self._recovery.done:
            self._recovery = None
            self.state = "following"
            self._progress_at = (sense.now, math.inf)
            self.pp.reset_speed()
            if self._ticket is None:
                self._request_plan(sense)
            return 0.0, 0.0
        self.pp.reset_speed(v, w)
        return v, w

    @property
    def plan_error(self) -> tuple[int, str] | None:
        return self._last_plan_error

