"""RoutineActions: dock_robot, undock_robot, patrol and follow_waypoints (Nav2's docking
server and waypoint follower, and the robot API's patrol), see `base`."""

from __future__ import annotations

import math

from zenros.action import ServerGoalHandle
from zenros.errors import GoalRejectedError, MapError
from zenros.msgs.builtin_interfaces import Duration
from zenros.msgs.nav2_msgs import (
    DockRobotFeedback,
    DockRobotGoal,
    DockRobotResult,
    FollowWaypointsFeedback,
    FollowWaypointsGoal,
    FollowWaypointsResult,
    UndockRobotFeedback,
    UndockRobotGoal,
    UndockRobotResult,
    WaypointStatus,
)
from zenros.msgs.zenros_msgs.nav import PatrolFeedback, PatrolGoal, PatrolResult
from zenros.se2 import Pose2

from ..motion.behavior import Behavior
from ..motion.docking import Dock, Undock
from ..motion.patrol import Patrol
from .base import ActionBase

__all__ = ["RoutineActions"]

DOCK_IDS = ("", "charger", "dock", "home")


class RoutineActions(ActionBase):
    """Execute (and goal) callbacks of the docking, patrol and waypoint actions."""

    waypoint_pause = 0.2  # seconds at each waypoint (nav2_params' wait_at_waypoint)

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

    def execute_dock_robot(
        self, gh: ServerGoalHandle[DockRobotGoal, DockRobotFeedback]
    ) -> DockRobotResult:
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

    def execute_undock_robot(
        self, gh: ServerGoalHandle[UndockRobotGoal, UndockRobotFeedback]
    ) -> UndockRobotResult:
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

    def execute_patrol(self, gh: ServerGoalHandle[PatrolGoal, PatrolFeedback]) -> PatrolResult:
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

    # ------------------------------------------------------------------ follow_waypoints

    def goal_follow_waypoints(self, goal: FollowWaypointsGoal) -> bool:
        if not goal.poses:
            raise GoalRejectedError("follow_waypoints needs at least one pose")
        if goal.goal_index >= len(goal.poses):
            raise GoalRejectedError(f"goal_index {goal.goal_index} is outside "
                                    f"0..{len(goal.poses) - 1}")
        for ps in goal.poses:
            self._map_pose(ps)
        self.arrived("follow_waypoints")
        return True

    def execute_follow_waypoints(
        self, gh: ServerGoalHandle[FollowWaypointsGoal, FollowWaypointsFeedback]
    ) -> FollowWaypointsResult:
        goal: FollowWaypointsGoal = gh.request
        result = FollowWaypointsResult()
        poses = [self._map_pose(ps) for ps in goal.poses]
        b = Patrol(poses, self.core.make_nav, loops=goal.number_of_loops + 1,
                   wait_time=self.waypoint_pause, start_index=goal.goal_index)

        def feedback(_: Behavior) -> FollowWaypointsFeedback:
            return FollowWaypointsFeedback(current_waypoint=b.index)

        out = self._run("follow_waypoints", gh, b, None, feedback)
        code = b.error_code
        result = self._settle(gh, out, b, result)
        if code:
            result.error_code = FollowWaypointsResult.UNKNOWN
        result.missed_waypoints = [
            WaypointStatus(waypoint_status=WaypointStatus.FAILED, waypoint_index=i,
                           waypoint_pose=goal.poses[i], error_code=c, error_msg=m)
            for i, c, m in b.missed]
        return result
