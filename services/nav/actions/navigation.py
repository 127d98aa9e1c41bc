"""NavActions: navigate_to_pose, navigate_through_poses, follow_path and
compute_path_to_pose, with Nav2's fields, feedback and error codes (see `base`)."""

from __future__ import annotations

import math

import numpy as np
from zenros.action import ServerGoalHandle
from zenros.errors import GoalRejectedError
from zenros.msgs.builtin_interfaces import Duration
from zenros.msgs.nav2_msgs import (
    ComputePathToPoseFeedback,
    ComputePathToPoseGoal,
    ComputePathToPoseResult,
    FollowPathFeedback,
    FollowPathGoal,
    FollowPathResult,
    NavigateThroughPosesFeedback,
    NavigateThroughPosesGoal,
    NavigateThroughPosesResult,
    NavigateToPoseFeedback,
    NavigateToPoseGoal,
    NavigateToPoseResult,
    WaypointStatus,
)
from zenros.se2 import Pose2

from ..motion.behavior import Behavior
from ..motion.navigate import Codes, Navigate
from .base import ActionBase
from .convert import path_from_msg, path_to_msg

__all__ = ["NavActions"]

NAV_CODES = Codes(timeout=NavigateToPoseResult.TIMEOUT, tf_error=NavigateToPoseResult.TF_ERROR,
                  unknown=NavigateToPoseResult.UNKNOWN)
THROUGH_CODES = Codes(timeout=NavigateThroughPosesResult.TIMEOUT,
                      tf_error=NavigateThroughPosesResult.TF_ERROR,
                      unknown=NavigateThroughPosesResult.UNKNOWN)
FOLLOW_CODES = Codes(timeout=FollowPathResult.CONTROLLER_TIMED_OUT,
                     tf_error=FollowPathResult.TF_ERROR, unknown=FollowPathResult.UNKNOWN)


class NavActions(ActionBase):
    """Execute (and goal) callbacks of the navigation actions."""

    # ------------------------------------------------------------------ navigate_to_pose

    def goal_navigate_to_pose(self, goal: NavigateToPoseGoal) -> bool:
        self._map_pose(goal.pose)
        self.arrived("navigate_to_pose")
        return True

    def execute_navigate_to_pose(
        self, gh: ServerGoalHandle[NavigateToPoseGoal, NavigateToPoseFeedback]
    ) -> NavigateToPoseResult:
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

    def execute_navigate_through_poses(
        self, gh: ServerGoalHandle[NavigateThroughPosesGoal, NavigateThroughPosesFeedback]
    ) -> NavigateThroughPosesResult:
        goal: NavigateThroughPosesGoal = gh.request
        result = NavigateThroughPosesResult()
        goals = [self._map_pose(ps) for ps in goal.poses]
        b = Navigate(goals, self.core, self.core.config.nav, self.core.config.controller,
                     THROUGH_CODES, gate=self.core.traffic)

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

    def execute_follow_path(
        self, gh: ServerGoalHandle[FollowPathGoal, FollowPathFeedback]
    ) -> FollowPathResult:
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
                     FOLLOW_CODES, fixed_path=xy, final_yaw=yaw is not None,
                     gate=self.core.traffic)

        def feedback(_: Behavior) -> FollowPathFeedback:
            d = b.distance_remaining if math.isfinite(b.distance_remaining) else 0.0
            return FollowPathFeedback(distance_to_goal=d, speed=self.core.speed[0])

        return self._settle(gh, self._run("follow_path", gh, b, end, feedback), b, result)

    # ------------------------------------------------------------------ compute_path_to_pose

    def execute_compute_path_to_pose(
        self, gh: ServerGoalHandle[ComputePathToPoseGoal, ComputePathToPoseFeedback]
    ) -> ComputePathToPoseResult:
        goal: ComputePathToPoseGoal = gh.request
        result = ComputePathToPoseResult()

        def fail(code: int, msg: str) -> ComputePathToPoseResult:
            result.error_code, result.error_msg = code, msg
            gh.abort()
            return result

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
        out = self.core.planner.plan(snap, start, [*vias, target], goal.planner_id)
        result.planning_time = Duration.from_seconds(out.planning_time)
        if not out.ok:
            return fail(out.error_code, out.error_msg)
        assert out.xy is not None
        result.path = path_to_msg(out.xy, self.now(), final_yaw=target.theta)
        self.core.on_plan(out.xy)
        gh.succeed()
        return result


def _tracking_error(path: np.ndarray, pose: Pose2) -> float:
    d = np.hypot(path[:, 0] - pose.x, path[:, 1] - pose.y)
    return float(d.min()) if len(d) else 0.0
