"""NavActions: the execute and goal callbacks of nav's actions (Nav2's semantics).

Each execute callback turns its goal into a `Behavior`, hands it to the core's `Motion`
(which halts whatever ran before: a goal of another nav action is aborted, "preempted"),
then waits for it while sending feedback, and settles the goal: SUCCEEDED with error_code
0, ABORTED with the behaviour's error code, or CANCELED. A new goal on the same action
preempts the running one (the action server's ``simple`` policy); like Nav2, the old goal
ends ABORTED with "preempted by a new goal". Goals that are malformed (NaN, a frame other
than ``map``/``odom``/empty, no poses) are rejected at once.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from typing import Any

import numpy as np

from zenros.errors import GoalRejectedError, MapError
from zenros.msgs.builtin_interfaces import Duration, Time
from zenros.msgs.geometry_msgs import PoseStamped
from zenros.msgs.nav2_msgs import (
    ComputePathToPoseGoal,
    ComputePathToPoseResult,
    DockRobotFeedback,
    DockRobotGoal,
    DockRobotResult,
    FollowPathFeedback,
    FollowPathGoal,
    FollowPathResult,
    NavigateThroughPosesFeedback,
    NavigateThroughPosesGoal,
    NavigateThroughPosesResult,
    NavigateToPoseFeedback,
    NavigateToPoseGoal,
    NavigateToPoseResult,
    UndockRobotGoal,
    UndockRobotResult,
    WaypointStatus,
)
from zenros.msgs.zenros_msgs.nav import PatrolFeedback, PatrolGoal, PatrolResult

from .behavior import Behavior
from .convert import path_from_msg, path_to_msg, pose2_from_msg, pose_stamped
from .core import NavCore
from .docking import Dock, Undock
from .navigate import Codes, Navigate
from .patrol import Patrol
from .se2 import Pose2

__all__ = ["NavActions"]

NAV_CODES = Codes(timeout=NavigateToPoseResult.TIMEOUT, tf_error=NavigateToPoseResult.TF_ERROR,
                  unknown=NavigateToPoseResult.UNKNOWN)
THROUGH_CODES = Codes(timeout=NavigateThroughPosesResult.TIMEOUT,
                      tf_error=NavigateThroughPosesResult.TF_ERROR,
                      unknown=NavigateThroughPosesResult.UNKNOWN)
FOLLOW_CODES = Codes(timeout=FollowPathResult.CONTROLLER_TIMED_OUT,
                     tf_error=FollowPathResult.TF_ERROR, unknown=FollowPathResult.UNKNOWN)
FEEDBACK_PERIOD = 0.1  # wall seconds between feedback messages
DOCK_IDS = ("", "charger", "dock", "home")


class NavActions:
    """Execute callbacks for navigate_to_pose, navigate_through_poses, follow_path,
    compute_path_to_pose, dock_robot, undock_robot and patrol."""

    def __init__(self, core: NavCore, now: Callable[[], Time], logger: logging.Logger) -> None:
        self.core = core
        self.now = now
        self.logger = logger
        self._lock = threading.Lock()
        self._arrivals: dict[str, int] = {}
        self.current: tuple[str, Behavior, Pose2 | None] | None = None
        self.last_outcome: tuple[int, int, str] = (0, 0, "")  # goal_status, code, message

    # ------------------------------------------------------------------ helpers

    def _seconds(self) -> float:
        return self.now().nanoseconds / 1e9

    def _map_pose(self, ps: PoseStamped) -> Pose2:
        """A goal pose in ``map``; raises GoalRejectedError for bad values or frames."""
        try:
            p = pose2_from_msg(ps.pose)
        except ValueError as exc:
            raise GoalRejectedError(f"bad goal pose: {exc}") from None
        frame = ps.header.frame_id.lstrip("/")
        if frame in ("", "map"):
            return p
        if frame == "odom":
            return self.core.localizer.map_to_odom * p
        raise GoalRejectedError(f"goal frame {ps.header.frame_id!r} cannot be transformed "
                                "to map; use 'map' or 'odom'")

    def arrived(self, action: str) -> None:
        """A goal for ``action`` was accepted (called from the goal callbacks)."""
        with self._lock:
            self._arrivals[action] = self._arrivals.get(action, 0) + 1

    def _run(self, action: str, gh: Any, b: Behavior, goal: Pose2 | None,
             feedback: Callable[[Behavior], Any] | None) -> str:
        """Run ``b`` until it ends or the goal is canceled; ``done``, ``canceled`` or
        ``preempted``."""
        with self._lock:
            arrivals = self._arrivals.get(action, 0)
        self.current = (action, b, goal)
        self.core.start(b)
        try:
            while not b.done.wait(FEEDBACK_PERIOD):
                if gh.is_cancel_requested:
                    with self._lock:
                        newer = self._arrivals.get(action, 0) > arrivals
                    self.core.motion.halt(b, "preempted by a new goal" if newer else "canceled")
                    return "preempted" if newer else "canceled"
                if feedback is not None:
                    try:
                        gh.publish_feedback(feedback(b))
                    except Exception:  # noqa: BLE001 - feedback is best effort
                        self.logger.debug("feedback for %s failed", action, exc_info=True)
            return "done"
        finally:
            if self.current is not None and self.current[1] is b:
                self.current = None

    def _settle(self, gh: Any, outcome: str, b: Behavior, result: Any) -> Any:
        if outcome == "canceled":
            gh.canceled()
            self.last_outcome = (4, 0, "canceled")
            return result
        if outcome == "preempted":
            result.error_msg = "preempted by a new goal"
            gh.abort()
            self.last_outcome = (4, 0, result.error_msg)
            return result
        if b.succeeded:
            gh.succeed()
            self.last_outcome = (2, 0, "")
            return result
        result.error_code, result.error_msg = b.error_code, b.error_msg
        gh.abort()
        self.last_outcome = (3, b.error_code, b.error_msg)
        return result

    def _nav_times(self, b: Behavior, distance: float) -> tuple[Duration, Duration]:
        now = self._seconds()
        elapsed = 0.0 if b.started_at is None else max(0.0, now - b.started_at)
        v = abs(self.core.speed[0])
        eta = distance / v if v > 0.01 and distance > 0.1 and math.isfinite(distance) else 0.0
        return Duration.from_seconds(elapsed), Duration.from_seconds(eta)

    def _current_pose(self) -> PoseStamped:
        p = self.core.localizer.pose()
        return pose_stamped(p or Pose2(), self.now())

    # ------------------------------------------------------------------ navigate_to_pose

    def goal_navigate_to_pose(self, goal: NavigateToPoseGoal) -> bool:
        self._map_pose(goal.pose)
        self.arrived("navigate_to_pose")
        return True

    def execute_navigate_to_pose(self, gh: Any) -> NavigateToPoseResult:
        goal: NavigateToPoseGoal = gh.request
        result = NavigateToPoseResult()
        try:
            target = self._map_pose(goal.pose)
        except GoalRejectedError as exc:
            gh.abort()
            result.error_code, result.error_msg = NavigateToPoseResult.TF_ERROR, str(exc)
            return result
        b = self.core.make_nav(target, NAV_CODES)

        def feedback(_: Behavior) -> NavigateToPoseFeedback:
            d = b.distance_remaining if math.isfinite(b.distance_remaining) else 0.0
            t, eta = self._nav_times(b, d)
            pose = self.core.localizer.pose()
            err = 0.0 if pose is None or b.path is None else _tracking_error(b.path, pose)
            return NavigateToPoseFeedback(
                current_pose=self._current_pose(), navigation_time=t,
                estimated_time_remaining=eta, number_of_recoveries=min(b.recoveries, 32767),
                distance_remaining=d, position_tracking_error=err)

        return self._settle(gh, self._run("navigate_to_pose", gh, b, target, feedback), b,
                            result)

    # ------------------------------------------------------------------ navigate_through_poses

    def goal_navigate_through_poses(self, goal: NavigateThroughPosesGoal) -> bool:
        if not goal.poses:
            raise GoalRejectedError("navigate_through_poses needs at least one pose")
        for ps in goal.poses:
            self._map_pose(ps)
        self.arrived("navigate_through_poses")
        return True

    def execute_navigate_through_poses(self, gh: Any) -> NavigateThroughPosesResult:
        goal: NavigateThroughPosesGoal = gh.request
        result = NavigateThroughPosesResult()
        goals = [self._map_pose(ps) for ps in goal.poses]
        b = Navigate(goals, self.core, self.core.config.nav, self.core.config.controller,
                     THROUGH_CODES)

        def statuses() -> list[WaypointStatus]:
            return [WaypointStatus(waypoint_status=w.status, waypoint_index=i,
                                   waypoint_pose=goal.poses[i], error_code=w.error_code,
                                   error_msg=w.error_msg)
                    for i, w in enumerate(b.waypoints)]

        def feedback(_: Behavior) -> NavigateThroughPosesFeedback:
            d = b.distance_remaining if math.isfinite(b.distance_remaining) else 0.0
            t, eta = self._nav_times(b, d)
            left = sum(1 for w in b.waypoints if w.status == 0)
            return NavigateThroughPosesFeedback(
                current_pose=self._current_pose(), navigation_time=t,
                estimated_time_remaining=eta, number_of_recoveries=min(b.recoveries, 32767),
                distance_remaining=d, number_of_poses_remaining=left,
                waypoint_statuses=statuses())

        out = self._run("navigate_through_poses", gh, b, goals[-1], feedback)
        result = self._settle(gh, out, b, result)
        result.waypoint_statuses = statuses()
        return result

    # ------------------------------------------------------------------ follow_path

    def goal_follow_path(self, goal: FollowPathGoal) -> bool:
        if goal.controller_id not in ("", "FollowPath"):
            raise GoalRejectedError(f"unknown controller_id {goal.controller_id!r}; "
                                    "this server has FollowPath")
        self.arrived("follow_path")
        return True

    def execute_follow_path(self, gh: Any) -> FollowPathResult:
        goal: FollowPathGoal = gh.request
        result = FollowPathResult()
        try:
            xy, yaw = path_from_msg(goal.path)
        except ValueError as exc:
            gh.abort()
            result.error_code, result.error_msg = FollowPathResult.INVALID_PATH, str(exc)
            return result
        frame = goal.path.header.frame_id.lstrip("/")
        if len(xy) == 0 or frame not in ("", "map"):
            gh.abort()
            result.error_code = FollowPathResult.INVALID_PATH
            result.error_msg = ("the path is empty" if len(xy) == 0 else
                                f"path frame {goal.path.header.frame_id!r} is not map")
            return result
        end = Pose2(float(xy[-1, 0]), float(xy[-1, 1]), yaw or 0.0)
        b = Navigate([end], self.core, self.core.config.nav, self.core.config.controller,
                     FOLLOW_CODES, fixed_path=xy, final_yaw=yaw is not None)

        def feedback(_: Behavior) -> FollowPathFeedback:
            d = b.distance_remaining if math.isfinite(b.distance_remaining) else 0.0
            return FollowPathFeedback(distance_to_goal=d, speed=self.core.speed[0])

        return self._settle(gh, self._run("follow_path", gh, b, end, feedback), b, result)

    # ------------------------------------------------------------------ compute_path_to_pose

    def execute_compute_path_to_pose(self, gh: Any) -> ComputePathToPoseResult:
        goal: ComputePathToPoseGoal = gh.request
        result = ComputePathToPoseResult()

        def fail(code: int, msg: str) -> ComputePathToPoseResult:
            result.error_code, result.error_msg = code, msg
            gh.abort()
            return result

        if goal.planner_id not in ("", "GridBased"):
            return fail(ComputePathToPoseResult.INVALID_PLANNER,
                        f"unknown planner_id {goal.planner_id!r}; this server has GridBased")
        try:
            target = self._map_pose(goal.goal)
            vias = [self._map_pose(v) for v in goal.viapoints]
            if goal.use_start:
                start = self._map_pose(goal.start)
            else:
                pose = self.core.localizer.pose()
                if pose is None:
                    return fail(ComputePathToPoseResult.TF_ERROR,
                                "the robot's pose in map is unknown")
                start = pose
        except GoalRejectedError as exc:
            return fail(ComputePathToPoseResult.TF_ERROR, str(exc))
        try:
            snap = self.core.costmaps.snapshot()
        except RuntimeError as exc:
            return fail(ComputePathToPoseResult.UNKNOWN, str(exc))
        out = self.core.planner.plan(snap, start, [*vias, target])
        result.planning_time = Duration.from_seconds(out.planning_time)
        if not out.ok:
            return fail(out.error_code, out.error_msg)
        assert out.xy is not None
        result.path = path_to_msg(out.xy, self.now(), final_yaw=target.theta)
        self.core.on_plan(out.xy)
        gh.succeed()
        return result

    # ------------------------------------------------------------------ docking

    def _dock_pose(self, goal: DockRobotGoal) -> Pose2:
        if goal.use_dock_id:
            if goal.dock_id not in DOCK_IDS:
                raise LookupError(f"unknown dock_id {goal.dock_id!r}; this map's dock is "
                                  "'charger' (or empty)")
            try:
                pose = self.core.records.charge_pose()
            except MapError as exc:
                raise LookupError(str(exc)) from exc
            if pose is None:
                raise LookupError(f"map {self.core.maps.current!r} has no charge pose; set "
                                  "one with set_charge_pose")
            return pose
        return self._map_pose(goal.dock_pose)

    def execute_dock_robot(self, gh: Any) -> DockRobotResult:
        goal: DockRobotGoal = gh.request
        result = DockRobotResult(success=False)
        try:
            dock = self._dock_pose(goal)
        except (LookupError, GoalRejectedError) as exc:
            result.error_code = DockRobotResult.DOCK_NOT_IN_DB if isinstance(exc, LookupError) \
                else DockRobotResult.DOCK_NOT_VALID
            result.error_msg = str(exc)
            gh.abort()
            return result
        if not (math.isfinite(goal.max_staging_time) and goal.max_staging_time > 0):
            result.error_code, result.error_msg = DockRobotResult.UNKNOWN, "bad max_staging_time"
            gh.abort()
            return result
        b = Dock(dock, self.core.config.dock, self.core.make_nav,
                 goal.navigate_to_staging_pose, goal.max_staging_time)

        def feedback(_: Behavior) -> DockRobotFeedback:
            elapsed = 0.0 if b.started_at is None else max(0.0, self._seconds() - b.started_at)
            return DockRobotFeedback(state=b.state, docking_time=Duration.from_seconds(elapsed),
                                     num_retries=b.retries)

        out = self._run("dock_robot", gh, b, dock, feedback)
        result = self._settle(gh, out, b, result)
        result.success = out == "done" and b.succeeded
        result.num_retries = b.retries
        return result

    def execute_undock_robot(self, gh: Any) -> UndockRobotResult:
        goal: UndockRobotGoal = gh.request
        result = UndockRobotResult(success=False)
        if not (math.isfinite(goal.max_undocking_time) and goal.max_undocking_time > 0):
            result.error_code = UndockRobotResult.UNKNOWN
            result.error_msg = "max_undocking_time must be a positive number"
            gh.abort()
            return result
        try:
            dock = self.core.records.charge_pose()
        except MapError:
            dock = None
        b = Undock(dock, self.core.config.dock, goal.max_undocking_time)
        out = self._run("undock_robot", gh, b, None, None)
        result = self._settle(gh, out, b, result)
        result.success = out == "done" and b.succeeded
        return result

    # ------------------------------------------------------------------ patrol

    def goal_patrol(self, goal: PatrolGoal) -> bool:
        try:
            _, points = self.core.records.nav_points(goal.map_name, goal.path_name)
        except MapError as exc:
            raise GoalRejectedError(str(exc)) from None
        if goal.map_name and goal.map_name != self.core.maps.current:
            raise GoalRejectedError(f"map {goal.map_name!r} is not the current map "
                                    f"({self.core.maps.current!r}); switch_map first")
        if not points:
            raise GoalRejectedError(f"path {goal.path_name!r} has no nav points")
        if goal.loops < 0 or not (math.isfinite(goal.wait_time) and goal.wait_time >= 0):
            raise GoalRejectedError("loops and wait_time must be >= 0")
        if not 0 <= goal.start_index < len(points):
            raise GoalRejectedError(f"start_index {goal.start_index} is outside "
                                    f"0..{len(points) - 1}")
        self.arrived("patrol")
        return True

    def execute_patrol(self, gh: Any) -> PatrolResult:
        goal: PatrolGoal = gh.request
        result = PatrolResult()
        _, points = self.core.records.nav_points(goal.map_name, goal.path_name)
        poses = [Pose2(p.x, p.y, p.theta) for p in points]
        b = Patrol(poses, self.core.make_nav, loops=goal.loops, wait_time=goal.wait_time,
                   start_index=goal.start_index)

        def feedback(_: Behavior) -> PatrolFeedback:
            nav = b.nav
            d = nav.distance_remaining if nav is not None else 0.0
            elapsed = 0.0 if b.started_at is None else max(0.0, self._seconds() - b.started_at)
            return PatrolFeedback(current_index=b.index, loop=b.loop,
                                  current_pose=self._current_pose(),
                                  distance_remaining=d if math.isfinite(d) else 0.0,
                                  waiting=b.waiting,
                                  navigation_time=Duration.from_seconds(elapsed))

        out = self._run("patrol", gh, b, None, feedback)
        result = self._settle(gh, out, b, result)
        result.loops_completed, result.points_visited = b.loop, b.visited
        return result


def _tracking_error(path: np.ndarray, pose: Pose2) -> float:
    d = np.hypot(path[:, 0] - pose.x, path[:, 1] - pose.y)
    return float(d.min()) if len(d) else 0.0
