"""`ExploreNode`: the ``explore`` action (zenros_msgs/Explore) over the ``map`` topic and nav.

It follows ``map`` (the SLAM node's growing grid, latched) and nav's ``robot_pose``, and
drives with nav's ``navigate_to_pose``; the decisions are `Explorer`'s. One exploration at a
time (a new goal replaces the running one). Cancel cancels the navigation goal, so nav stops
the robot. docs/mapping.md, "Exploration".
"""

from __future__ import annotations

import math
import threading
from typing import Annotated, Any

import msgspec
from msgspec import Meta
from zenros.action import ActionClient, GoalStatus, ServerGoalHandle
from zenros.errors import GoalRejectedError
from zenros.maps import GridMap
from zenros.msgs.geometry_msgs import Pose2D, PoseWithCovarianceStamped
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal, Spin, SpinGoal
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.msgs.zenros_msgs.slam import Explore, ExploreFeedback, ExploreGoal, ExploreResult
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.se2 import Pose2
from zenros.tf import yaw_from_msg, yaw_to_msg

from .explorer import NO_MAP, RETURN_FAILED, Decision, ExploreParams, Explorer
from .frontiers import FrontierParams

__all__ = ["ExploreNode", "ExploreParameters"]

Positive = Annotated[float, Meta(gt=0)]
HOME_TRIES = 2
"""Drives back to the start tried again after the first fails."""


class ExploreParameters(msgspec.Struct, kw_only=True):
    """The explore node's parameters (explore_lite's names where it has them)."""

    planner_frequency: Annotated[Positive, Meta(
        description="frontier searches per second of the node's clock")] = 1.0
    potential_scale: Annotated[float, Meta(ge=0, description="weight of the distance")] = 1e-3
    gain_scale: Annotated[float, Meta(ge=0, description="weight of the frontier's size")] = 1.0
    clearance: Annotated[float, Meta(ge=0, description=(
        "metres from walls the robot's path to a frontier keeps"))] = 0.25
    blacklist_radius: Annotated[float, Meta(ge=0, description=(
        "frontiers with a goal this close to a failed or reached goal are skipped"))] = 0.5
    wait_for_map: Annotated[Positive, Meta(
        description="seconds a goal waits for the first map and robot pose")] = 10.0
    sweep: Annotated[bool, Meta(description=(
        "turn round once at each goal reached (Yamauchi's sweep), so a mapper that adds "
        "scans by the turn sees all round"))] = True


def _pose_goal(p: Pose2, stamp: Any) -> NavigateToPoseGoal:
    g = NavigateToPoseGoal()
    g.pose.header.frame_id = "map"
    g.pose.header.stamp = stamp
    g.pose.pose.position.x, g.pose.pose.position.y = p.x, p.y
    g.pose.pose.orientation = yaw_to_msg(p.theta)
    return g


class ExploreNode(Node):
    node_name = "explore"

    def setup(self) -> None:
        self.params = self.declare_parameters(ExploreParameters)
        self._lock = threading.Lock()
        self._grid: GridMap | None = None
        self._pose: Pose2 | None = None
        self._map_sub = self.create_subscription(OccupancyGrid, "map", self.on_map,
                                                 QOS_LATCHED)
        self.create_subscription(PoseWithCovarianceStamped, "robot_pose", self.on_pose)
        self.nav = ActionClient(self, NavigateToPose, "navigate_to_pose")
        self.spin = ActionClient(self, Spin, "spin")
        self.create_action_server(Explore, "explore", self.execute,
                                  goal_callback=self.on_goal)

    # ------------------------------------------------------------------ inputs

    def on_map(self, msg: OccupancyGrid) -> None:
        try:
            grid = GridMap.from_msg(msg)
        except (ValueError, TypeError) as exc:
            self.logger.warning("map ignored: %s", exc)
            return
        with self._lock:
            self._grid = grid

    def on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p = msg.pose.pose
        pose = Pose2(p.position.x, p.position.y, yaw_from_msg(p.orientation))
        if math.isfinite(pose.x) and math.isfinite(pose.y) and math.isfinite(pose.theta):
            with self._lock:
                self._pose = pose

    def _fresh_inputs(self) -> None:
        """Forget the map and the pose, and subscribe to ``map`` anew: the latched sample it
        brings is the current publisher's (the SLAM node's once nav has handed the map
        over), and the next ``robot_pose`` is in its frame; never a map or a pose kept from
        before mapping started (the frame of the map nav had)."""
        with self._lock:
            self._grid = None
            self._pose = None
        old = self._map_sub
        self._map_sub = self.create_subscription(OccupancyGrid, "map", self.on_map,
                                                 QOS_LATCHED)
        self.destroy(old)

    def _inputs(self) -> tuple[GridMap | None, Pose2 | None]:
        with self._lock:
            return self._grid, self._pose

    def _seconds(self) -> float:
        return self.now().nanoseconds / 1e9

    # ------------------------------------------------------------------ the action

    def on_goal(self, goal: ExploreGoal) -> bool:
        for name in ("min_frontier_size", "progress_timeout"):
            v = getattr(goal, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise GoalRejectedError(f"{name} must be a finite number >= 0, got {v!r}")
        return True

    def _explorer(self, goal: ExploreGoal, start: Pose2) -> Explorer:
        p = self.params
        return Explorer(ExploreParams(
            frontiers=FrontierParams(min_frontier_size=goal.min_frontier_size,
                                     potential_scale=p.potential_scale,
                                     gain_scale=p.gain_scale, clearance=p.clearance),
            progress_timeout=goal.progress_timeout or 30.0,
            blacklist_radius=p.blacklist_radius, return_to_start=goal.return_to_start), start)

    def execute(self, gh: ServerGoalHandle[ExploreGoal]) -> ExploreResult:
        goal: ExploreGoal = gh.request
        self._fresh_inputs()
        waited = 0.0
        grid, pose = self._inputs()
        while (grid is None or pose is None) and waited < self.params.wait_for_map:
            if gh.wait_for_cancel(0.1):
                gh.canceled()
                return ExploreResult()
            waited += 0.1
            grid, pose = self._inputs()
        if grid is None or pose is None:
            gh.abort()
            return ExploreResult(error_code=NO_MAP, error_msg=(
                "no map" if grid is None else "no robot pose") + " within "
                f"{self.params.wait_for_map:g} s (is mapping started? is nav running?)")
        ex = self._explorer(goal, pose)
        self.logger.info("exploring from (%.2f, %.2f)", pose.x, pose.y)
        run = _Run(self, ex)
        try:
            return run.loop(gh)
        finally:
            run.stop_driving()


class _Run:
    """One exploration: the loop of planning steps and the navigation goal it drives."""

    def __init__(self, node: ExploreNode, ex: Explorer) -> None:
        self.node = node
        self.ex = ex
        self.handle: Any = None
        self.target: Pose2 | None = None
        self.home_tries = 0
        self.spun = False
        self.sweep: Any = None  # the turn round at a goal reached
        self.spin: Any = None  # the turn on the spot that shows the mapper the surroundings
        self.waiting_since: float | None = None

    def result(self, code: int = 0, msg: str = "") -> ExploreResult:
        ex = self.ex
        return ExploreResult(error_code=code, error_msg=msg,
                             explored_area_m2=ex.explored_area,
                             goals_reached=ex.goals_reached, goals_failed=ex.goals_failed)

    def stop_driving(self) -> None:
        for h in (self.handle, self.spin, self.sweep):
            if h is not None and not h.done:
                try:
                    h.cancel()
                except Exception as exc:  # noqa: BLE001 - nav gone: nothing drives then
                    self.node.logger.warning("could not cancel the navigation goal: %s", exc)
        self.handle = None

    def _send(self, target: Pose2) -> None:
        self.target = target
        try:
            self.handle = self.node.nav.send_goal_async(_pose_goal(target, self.node.now()))
        except Exception as exc:  # noqa: BLE001 - reported as a failed goal
            self.node.logger.warning("navigate_to_pose not sent: %s", exc)
            self.handle = None
            self.ex.fail(target)

    def _outcome(self) -> bool | None:
        """True/False when the current navigation goal ended reached/not; None meanwhile."""
        h = self.handle
        if h is None or not h.done:
            return None
        self.handle = None
        try:
            res = h.result(timeout=0)
        except Exception as exc:  # noqa: BLE001 - lost or never sent
            self.node.logger.info("navigation goal lost: %s", exc)
            return False
        if res.status is not GoalStatus.SUCCEEDED:
            r = res.result
            self.node.logger.info("navigation goal ended %s: %s %s", res.status.name,
                                  getattr(r, "error_code", ""), getattr(r, "error_msg", ""))
        return res.status is GoalStatus.SUCCEEDED

    def loop(self, gh: ServerGoalHandle[ExploreGoal]) -> ExploreResult:
        node, ex = self.node, self.ex
        period = 1.0 / node.params.planner_frequency
        next_plan = -math.inf
        while True:
            if gh.is_cancel_requested:
                self.stop_driving()
                gh.canceled()
                return self.result(msg="canceled")
            outcome = self._outcome()
            if outcome is not None and self.target is not None:
                node.logger.info("goal (%.2f, %.2f) %s", self.target.x, self.target.y,
                                 "reached" if outcome else "failed")
                if ex.stage == "returning":
                    if not outcome and self.home_tries < HOME_TRIES:
                        # nav gave up (a path blocked for a while, the map corrected under
                        # it): drive back again
                        self.home_tries += 1
                        self._send(ex.start)
                        continue
                    ex.returned(outcome)
                elif outcome:
                    ex.reached(self.target)
                    if node.params.sweep:
                        self.sweep = self._turn_round()
                else:
                    ex.fail(self.target)
                next_plan = -math.inf  # plan the next goal now
            if ex.stage == "done":
                break
            if self.sweep is not None:
                if not self.sweep.done:
                    gh.wait_for_cancel(0.05)
                    continue
                self.sweep = None
                next_plan = -math.inf
            now = node._seconds()
            if now >= next_plan or now < next_plan - 2 * period:
                next_plan = now + period
                grid, pose = node._inputs()
                if grid is not None and pose is not None:
                    self._act(ex.step(grid, pose, now), now)
                    if self._waited_too_long(now):
                        if ex.goals_reached + ex.goals_failed == 0:
                            self.stop_driving()
                            gh.abort()
                            return self.result(NO_MAP, "the map shows no free space round "
                                               "the robot, even after a turn on the spot (is "
                                               "the mapping node running?)")
                        # late in an exploration: this spot of the map is drawn too badly to
                        # plan from; what was explored stands, and the robot goes back
                        node.logger.warning("the map shows no free space round the robot "
                                            "(%.2f, %.2f): exploring ends here", pose.x,
                                            pose.y)
                        self.waiting_since = None
                        self._act(ex.end_here(), now)
                    gh.publish_feedback(ExploreFeedback(
                        stage="returning" if ex.stage == "returning" else "exploring",
                        explored_area_m2=ex.explored_area, frontiers_left=ex.frontiers_left,
                        target=Pose2D(x=self.target.x, y=self.target.y,
                                      theta=self.target.theta) if self.target else Pose2D()))
            gh.wait_for_cancel(0.05)
        if ex.p.return_to_start and not ex.return_ok:
            gh.abort()
            return self.result(RETURN_FAILED, "explored, but the robot could not drive back "
                                              "to where it started")
        gh.succeed()
        return self.result(msg="no frontier left")

    def _turn_round(self) -> Any:
        """A full turn on the spot (nav's ``spin``); None if it could not be sent."""
        try:
            return self.node.spin.send_goal_async(SpinGoal(target_yaw=2 * math.pi))
        except Exception as exc:  # noqa: BLE001 - then no turn
            self.node.logger.warning("spin not sent: %s", exc)
            return None

    def _waited_too_long(self, now: float) -> bool:
        """Waited ``wait_for_map`` since the turn ended with still no free space in sight."""
        if self.waiting_since is None:
            return False
        if self.spin is not None:
            if not self.spin.done:
                return False
            self.spin = None
            self.waiting_since = now  # the mapper's next grid shows what the turn saw
        return now - self.waiting_since > self.node.params.wait_for_map

    def _act(self, d: Decision, now: float) -> None:
        if d.action == "wait":
            if self.waiting_since is None:
                self.waiting_since = now
            if not self.spun and (self.handle is None or self.handle.done):
                self.spun = True
                # what a mapper that adds a scan only after a move sees of a robot at rest
                # is its first scan alone; a full turn shows it the surroundings
                self.node.logger.info("the map shows no free space round the robot yet: "
                                      "turning round once")
                self.spin = self._turn_round()
            return
        self.waiting_since = None
        self.spun = False  # a later wait may turn round again
        if d.action in ("goto", "home") and d.target is not None:
            self.node.logger.info("%s (%.2f, %.2f), %d frontiers left",
                                  "to" if d.action == "goto" else "back to the start at",
                                  d.target.x, d.target.y, d.frontiers_left)
            self._send(d.target)
        elif d.action == "keep" and self.handle is None and d.target is not None \
                and self.ex.stage == "exploring":
            self._send(d.target)  # the goal ended without an outcome (never sent): again
