"""`NavNode`: wires `NavCore` (maps, localisation, costmaps, planner, controller) to Zenoh."""

from __future__ import annotations

import dataclasses
import math
import os
import threading
from collections.abc import Callable
from typing import Any

import numpy as np
from zenros.building import load_building
from zenros.errors import GoalRejectedError
from zenros.home import data_dir
from zenros.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from zenros.lifecycle.machine import ACTIVE
from zenros.maps import GridMap
from zenros.message import ActionType
from zenros.msgs.geometry_msgs import (
    Point,
    PoseStamped,
    PoseWithCovarianceStamped,
    Twist,
    Vector3,
)
from zenros.msgs.nav2_msgs import (
    BackUp,
    ClearEntireCostmap,
    ClearEntireCostmapRequest,
    ClearEntireCostmapResponse,
    ComputePathToPose,
    DockRobot,
    DriveOnHeading,
    FollowPath,
    FollowWaypoints,
    LoadMap,
    NavigateThroughPoses,
    NavigateToPose,
    SaveMap,
    SaveMapRequest,
    SaveMapResponse,
    Spin,
    UndockRobot,
)
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry, Path
from zenros.msgs.sensor_msgs import BatteryState, LaserScan
from zenros.msgs.std_msgs import Header
from zenros.msgs.tf2_msgs import TFMessage
from zenros.msgs.zenros_msgs import nav as navmsgs
from zenros.msgs.zenros_msgs import slam as slammsgs
from zenros.msgs.zenros_msgs.chassis import ChassisState
from zenros.msgs.zenros_msgs.people import (
    GetFollowStatus,
    PersonDetections,
    SetFollow,
    SetFollowRequest,
    SetFollowResponse,
    UwbTarget,
)
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.params import Parameter
from zenros.qos import QOS_LATCHED, QOS_SENSOR
from zenros.se2 import Pose2
from zenros.tf import TransformBroadcaster, yaw_from_msg
from zenros.tf.listener import DYNAMIC_LISTENER_QOS, STATIC_LISTENER_QOS

from .actions.base import Ledger
from .actions.behavior_server import BehaviorActions
from .actions.convert import (
    PoseReader,
    PoseStream,
    path_to_msg,
    pose2_from_msg,
)
from .actions.coverage import handle_compute_coverage_path
from .actions.goal_topics import GoalTopics
from .actions.landmarks import LandmarkServices
from .actions.navigation import NavActions
from .actions.routines import RoutineActions
from .actions.status import nav_status
from .core import MappingRefused, NavCore
from .diagnostics import nav_diagnostics
from .maps.building_maps import install_building
from .maps.connections import Connections
from .maps.saver import SaveRefused
from .motion.autocharge import AutoCharge
from .motion.docking import Dock
from .motion.loop import ControlLoop
from .motion.timed_loop import TimedLoop
from .params import DEMO_MAP, NavParameters, nav_config
from .people.control import FollowControl
from .people.follow import WALL_REACH, FollowParams, off_walls
from .people.legs import detect_people
from .refusals import coded
from .schedule_link import ScheduleLink

__all__ = ["NavNode"]


ACTIVATION_WAIT = 5.0  # seconds a goal waits for nav to be activated (a manager bringing it up)


class NavNode(LifecycleNode):
    """Navigation: map server, localisation, costmaps, planner, controller, Nav2 actions.

    Topics, services, actions and parameters: docs/nav.md. Runs in the robot's namespace
    and needs the chassis (odom, scan, sim/ground_truth) and, in sim, ``use_sim_time``.

    A managed (lifecycle) node, as Nav2's servers are: goals are refused unless it is
    active (a goal that comes while its manager brings it up waits a moment), deactivating
    it cancels the running ones and stops auto-charging; the map, localisation and costmaps
    run in every state. By itself (``autostart`` true) it activates once set up; the
    launches bring it up through their lifecycle manager (docs/lifecycle.md).
    """

    node_name = "nav"
    autostart_default = True

    def setup(self) -> None:
        self.activation_wait = ACTIVATION_WAIT
        self._servers: list[Any] = []
        p = self.params = self.declare_parameters(NavParameters)
        cfg = nav_config(p, self.parameters)
        if self.context.deterministic:  # a replay (docs/replay.md): no threads of nav's own
            cfg = dataclasses.replace(cfg, deterministic=True)
        self.autocharge = AutoCharge(p.auto_charge, p.go_charge_percentage)
        self.on_parameter_change(lambda p: setattr(self.autocharge, "enabled", bool(p.value)),
                                 "auto_charge")
        self.on_parameter_change(lambda p: setattr(self.autocharge, "threshold", float(p.value)),
                                 "go_charge_percentage")
        self.on_parameter_change(self._on_localization_param, "localization")

        self.map_pub: Any = self.create_publisher(OccupancyGrid, "map", QOS_LATCHED)
        self._mapping_lock = threading.Lock()
        self._mapping_subs: list[Any] = []
        # before the core: open until the core has halted (`_halt` sends the last command)
        self.cmd_pub = self.create_publisher(Twist, "cmd_vel")
        self.core = self.own(NavCore(cfg, p.maps_dir or data_dir() / "maps",
                                     on_plan=self._publish_plan, on_map=self._publish_map))
        self.core.maps.start(p.map or DEMO_MAP)
        self.ledger = Ledger()
        self.actions = NavActions(self.core, self.now, self.logger, self.ledger)
        self.routines = RoutineActions(self.core, self.now, self.logger, self.ledger)
        self.behaviors = BehaviorActions(self.core, self.now, self.logger, self.ledger)

        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "robot_pose")
        self.plan_pub = self.create_publisher(Path, "plan", QOS_LATCHED)
        self.global_pub = self.create_publisher(OccupancyGrid, "global_costmap/costmap",
                                                QOS_LATCHED)
        self.local_pub = self.create_publisher(OccupancyGrid, "local_costmap/costmap")
        self.status_pub = self.create_publisher(navmsgs.NavStatus, "nav/status", QOS_LATCHED)
        self.tf = TransformBroadcaster(self)
        self._poses = PoseStream(0.0025, 0.003)  # robot_pose and map -> odom, 10 Hz
        self._serve_people(p)  # before the scan's subscription: on_scan publishes people
        self._serve_landmarks()  # before the scan's subscription too: on_scan feeds it

        self._odom_pose, self._truth_pose = PoseReader(), PoseReader()  # 50 Hz each
        self.create_subscription(Odometry, "odom", self.on_odom, QOS_SENSOR)
        self.create_subscription(Odometry, "sim/ground_truth", self.on_ground_truth, QOS_SENSOR)
        self.create_subscription(LaserScan, "scan", self.on_scan, QOS_SENSOR)
        self.create_subscription(BatteryState, "battery_state", self.on_battery)
        self.create_subscription(ChassisState, "chassis/state", self.on_chassis)
        self.create_subscription(PoseWithCovarianceStamped, "initialpose", self.on_initialpose)
        self.create_subscription(TFMessage, "/tf_static", self.on_tf_static, STATIC_LISTENER_QOS)
        goals = GoalTopics(self.core, self.logger, self._follow_refusal)
        self.create_subscription(PoseStamped, "goal_pose", goals.on_goal_pose)
        self.create_subscription(navmsgs.PatrolGoal, "patrol_goal", goals.on_patrol_goal)

        self._serve_maps()
        if p.building:
            added = install_building(self.core.maps.store, self.connections,
                                     load_building(os.path.expanduser(p.building)))
            self.logger.info("building %s: its floors are in the map store (%d new elevator "
                             "connections)", p.building, added)
        self._serve_actions()
        self.schedule = ScheduleLink(self, p)  # schedule mode: off unless schedule_mode
        # no ticks at rest: the loop sleeps while nothing drives, and a behaviour started or
        # halted wakes it (auto-charging is checked at the idle loop's 1 s steps)
        period = 1.0 / p.controller_frequency
        self.control: ControlLoop | TimedLoop = (
            TimedLoop(self, period, self.on_control, idle=lambda: self.core.motion.idle)
            if self.context.deterministic else
            ControlLoop(self.get_clock(), period, self.on_control, self.logger,
                        idle=lambda: self.core.motion.idle))
        self.core.motion.on_change = lambda _behavior: self.control.wake()
        self.control.start()
        # before the action servers close: running goals end as "navigation is shutting down"
        self.on_close(self._halt)
        self.create_timer(1.0 / p.pose_publish_rate, self.on_pose_timer)
        self.create_timer(1.0 / p.global_costmap_publish_rate, self.on_global_costmap_timer)
        self.create_timer(1.0 / p.local_costmap_publish_rate, self.on_local_costmap_timer)
        self.create_timer(0.5, self.on_status_timer)
        self.diagnostics = nav_diagnostics(self)  # localisation, goals on /diagnostics

    # ------------------------------------------------------------------ endpoints

    def _serve_maps(self) -> None:
        maps, rec = self.core.maps, self.core.records
        conn = self.connections = Connections(maps.store)
        for srv, name, handler in (
            (LoadMap, "map_server/load_map", maps.handle_load_map),
            (navmsgs.ListMaps, "map_server/list_maps", maps.handle_list_maps),
            (navmsgs.GetCurrentMap, "map_server/current_map", maps.handle_current_map),
            (navmsgs.ImportMap, "map_server/import_map", maps.handle_import_map),
            (navmsgs.SwitchMap, "switch_map", maps.handle_switch_map),
            (navmsgs.ListPaths, "list_paths", rec.handle_list_paths),
            (navmsgs.GetPath, "get_path", rec.handle_get_path),
            (navmsgs.SetPath, "set_path", rec.handle_set_path),
            (navmsgs.DeletePath, "delete_path", rec.handle_delete_path),
            (navmsgs.GetNavPoints, "get_nav_points", rec.handle_get_nav_points),
            (navmsgs.SetNavPoints, "set_nav_points", rec.handle_set_nav_points),
            (navmsgs.DeleteNavPoints, "delete_nav_points", rec.handle_delete_nav_points),
            (navmsgs.GetVirtualWalls, "get_virtual_walls", rec.handle_get_virtual_walls),
            (navmsgs.SetVirtualWalls, "set_virtual_walls", rec.handle_set_virtual_walls),
            (navmsgs.GetForbiddenAreas, "get_forbidden_areas", rec.handle_get_forbidden_areas),
            (navmsgs.SetForbiddenAreas, "set_forbidden_areas", rec.handle_set_forbidden_areas),
            (navmsgs.GetChargePose, "get_charge_pose", rec.handle_get_charge_pose),
            (navmsgs.ListPointConnections, "list_point_connections", conn.handle_list),
            (navmsgs.AddPointConnection, "add_point_connection", conn.handle_add),
            (navmsgs.DeletePointConnection, "delete_point_connection", conn.handle_delete),
            (navmsgs.SetChargePose, "set_charge_pose", rec.handle_set_charge_pose),
            (navmsgs.ComputeCoveragePath, "compute_coverage_path",
             handle_compute_coverage_path),
            (ClearEntireCostmap, "global_costmap/clear_entirely_global_costmap",
             self.handle_clear_costmap),
        ):
            self.create_service(srv, name, coded(handler))
        # these answer a ResultCode in the response, as the mapping contract has it
        self.create_service(slammsgs.SetMappingMode, "nav/set_mapping_mode",
                            self.handle_set_mapping_mode)
        self.create_service(slammsgs.SaveGrid, "map_server/save_grid",
                            self.core.saver.handle_save_grid)
        self.create_service(SaveMap, "map_saver/save_map", self.handle_save_map)

    def _serve_actions(self) -> None:
        a, r, b = self.actions, self.routines, self.behaviors
        actions: tuple[tuple[ActionType, str, Callable[[Any], Any], Any], ...] = (
            (NavigateToPose, "navigate_to_pose", a.execute_navigate_to_pose,
             a.goal_navigate_to_pose),
            (NavigateThroughPoses, "navigate_through_poses", a.execute_navigate_through_poses,
             a.goal_navigate_through_poses),
            (FollowPath, "follow_path", a.execute_follow_path, a.goal_follow_path),
            (ComputePathToPose, "compute_path_to_pose", a.execute_compute_path_to_pose, None),
            (DockRobot, "dock_robot", r.execute_dock_robot, None),
            (UndockRobot, "undock_robot", r.execute_undock_robot, None),
            (navmsgs.Patrol, "patrol", r.execute_patrol, r.goal_patrol),
            (FollowWaypoints, "follow_waypoints", r.execute_follow_waypoints,
             r.goal_follow_waypoints),
            (Spin, "spin", b.execute_spin, b.goal_spin),
            (BackUp, "backup", b.execute_backup, b.goal_backup),
            (DriveOnHeading, "drive_on_heading", b.execute_drive_on_heading,
             b.goal_drive_on_heading),
            (navmsgs.LocalMoveTarget, "local_move_target", b.execute_local_move_target,
             b.goal_local_move_target),
        )
        for act, name, execute, goal_cb in actions:
            policy = "parallel" if name == "compute_path_to_pose" else "simple"
            self._servers.append(self.create_action_server(
                act, name, execute, goal_callback=self._when_active(goal_cb), policy=policy))

    def _serve_people(self, p: NavParameters) -> None:
        """Person following (``follow/set``, ``follow/status``) on the leg detector or the
        UWB tag (``uwb/target``, subscribed once UWB following is first asked for: a fleet's
        navs declare nothing for a tag they never follow), and the leg detector's people on
        ``people/detections``."""
        self._uwb: tuple[float, float, float] | None = None
        self.follow = FollowControl(
            self.core.motion, FollowParams(max_linear=min(0.5, p.max_linear_vel),
                                           max_angular=min(1.2, p.max_angular_vel),
                                           body_radius=p.collision_radius),
            lambda: self._uwb, active=self._follow_refusal, walls=self._walls)
        self._uwb_sub: Any = None  # made when UWB following is first asked for
        self.create_service(SetFollow, "follow/set", self.handle_set_follow)
        self.create_service(GetFollowStatus, "follow/status", self.follow.handle_status)
        self.people_pub = self.create_publisher(PersonDetections, "people/detections")

    def _serve_landmarks(self) -> None:
        """``get_landmarks``, ``relocalize_landmarks`` and ``landmarks/detections`` (the
        reflectors each scan shows, detected for a listener only); docs/nav.md."""
        self.landmarks = LandmarkServices(self.core)
        self.create_service(navmsgs.GetLandmarks, "get_landmarks",
                            coded(self.landmarks.handle_get_landmarks))
        self.create_service(navmsgs.RelocalizeLandmarks, "relocalize_landmarks",
                            self.landmarks.handle_relocalize)
        self.landmarks_pub = self.create_publisher(navmsgs.LandmarkDetections,
                                                   "landmarks/detections")

    def handle_set_follow(self, req: SetFollowRequest) -> SetFollowResponse:
        if req.enable and req.mode == "uwb" and self._uwb_sub is None:
            self._uwb_sub = self.create_subscription(UwbTarget, "uwb/target", self.on_uwb,
                                                     QOS_SENSOR)
        return self.follow.handle_set(req)

    def _walls(self, points: np.ndarray) -> np.ndarray:
        return self.core.costmaps.near_static(points, WALL_REACH)

    def _follow_refusal(self) -> str:
        if self.current_state.state_id != ACTIVE:
            return f"nav is {self.current_state.label}, not active: it drives nowhere"
        return ""

    def on_uwb(self, msg: UwbTarget) -> None:
        if math.isfinite(msg.range) and math.isfinite(msg.bearing) and msg.range >= 0:
            self._uwb = (float(msg.range), float(msg.bearing), self._seconds())

    def _publish_people(self, stamp: Any) -> None:
        people = off_walls(detect_people(self.core.obstacles), self.core.localizer.pose(),
                           self._walls)
        self.people_pub.publish(PersonDetections(
            header=Header(stamp=stamp, frame_id="base_link"),
            people=[Point(x=round(float(x), 3), y=round(float(y), 3)) for x, y in people]))

    # ------------------------------------------------------------------ lifecycle

    def _when_active(self, check: Callable[[Any], Any] | None) -> Callable[[Any], Any]:
        """``check`` behind the lifecycle gate: a goal is refused unless nav is active."""

        def gate(goal: Any) -> Any:
            if not self.wait_for_active(self.activation_wait):
                raise GoalRejectedError(
                    f"nav is {self.current_state.label}, not active: its lifecycle manager "
                    f"has not brought it up within {self.activation_wait:g} s "
                    "(zenros lifecycle get)")
            return True if check is None else check(goal)

        return gate

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Leaving active: no new goals, the running ones canceled (the robot stops as on a
        client's cancel), no auto-charging."""
        canceled = sum(server.cancel_all_goals() for server in self._servers)
        if canceled:
            self.logger.warning("deactivated: %d goal(s) canceled", canceled)
        return super().on_deactivate(state)

    def handle_clear_costmap(self, req: ClearEntireCostmapRequest) -> ClearEntireCostmapResponse:
        self.core.clear_obstacles()
        return ClearEntireCostmapResponse()

    # ------------------------------------------------------------------ mapping mode

    def handle_set_mapping_mode(self, req: slammsgs.SetMappingModeRequest
                                ) -> slammsgs.SetMappingModeResponse:
        """Hand ``map`` and ``map -> odom`` to the SLAM node, or take them back."""
        resp = slammsgs.SetMappingModeResponse
        try:
            with self._mapping_lock:
                if req.enable:
                    self._enter_mapping()
                    return resp(code=int(ResultCode.OK), message="mapping mode: following "
                                "the SLAM node's map and map -> odom")
                start = None
                if req.use_map_to_odom:
                    m = req.map_to_odom
                    start = Pose2(float(m.x), float(m.y), float(m.theta))
                    if not all(math.isfinite(v) for v in (start.x, start.y, start.theta)):
                        return resp(code=int(ResultCode.INVALID),
                                    message="map_to_odom must be finite")
                name = self._leave_mapping(req.map_name, start)
                return resp(code=int(ResultCode.OK), message=f"navigating on map {name!r}")
        except MappingRefused as exc:
            return resp(code=int(exc.code), message=str(exc))

    def _enter_mapping(self) -> None:
        if self.core.mapping:
            return
        self.core.enter_mapping()
        self._follow_slam()
        self.logger.info("mapping mode: the SLAM node's map and map -> odom are followed")

    def _follow_slam(self) -> None:
        # a latched publisher's cache would give late joiners the old map: undeclare it
        if self.map_pub is not None:
            self.destroy(self.map_pub)
            self.map_pub = None
        self._mapping_subs = [
            self.create_subscription(OccupancyGrid, "map", self.on_slam_map, QOS_LATCHED),
            self.create_subscription(TFMessage, "/tf", self.on_slam_tf, DYNAMIC_LISTENER_QOS),
        ]

    def _leave_mapping(self, map_name: str, start: Pose2 | None) -> str:
        was = self.core.mapping
        self.core.map_after_mapping(map_name)  # refused before anything changes
        subs, self._mapping_subs = self._mapping_subs, []
        for sub in subs:
            self.destroy(sub)
        if self.map_pub is None:
            self.map_pub = self.create_publisher(OccupancyGrid, "map", QOS_LATCHED)
        try:
            name = self.core.leave_mapping(map_name, start)
        except MappingRefused:
            if self.core.mapping:  # the map would not load: follow the SLAM node again
                self._follow_slam()
            raise
        if was:
            self.logger.info("mapping mode left: navigating on map %r", name)
        return name

    def on_slam_map(self, msg: OccupancyGrid) -> None:
        try:
            grid = GridMap.from_msg(msg)
        except (ValueError, TypeError) as exc:
            self.logger.warning("map from the SLAM node ignored: %s", exc)
            return
        if grid.width and grid.height:
            self.core.on_slam_map(grid)

    def on_slam_tf(self, msg: TFMessage) -> None:
        for t in msg.transforms:
            if t.header.frame_id.lstrip("/") == "map" and t.child_frame_id.lstrip("/") == "odom":
                tr, q = t.transform.translation, t.transform.rotation
                try:
                    pose = Pose2(float(tr.x), float(tr.y), yaw_from_msg(q))
                except (ValueError, TypeError):
                    continue
                if math.isfinite(pose.x) and math.isfinite(pose.y) and math.isfinite(pose.theta):
                    self.core.on_slam_map_to_odom(pose)

    def handle_save_map(self, req: SaveMapRequest) -> SaveMapResponse:
        """Nav2's map_saver: take one grid from ``map_topic`` (default ``map``), write it to
        ``map_url`` (`GridSaver.save_map`); ``result`` false with the reason logged."""
        topic = req.map_topic or "map"
        got: list[OccupancyGrid] = []
        ready = threading.Event()

        def on_grid(msg: OccupancyGrid) -> None:
            got.append(msg)
            ready.set()

        try:
            sub = self.create_subscription(OccupancyGrid, topic, on_grid, QOS_LATCHED)
        except (ValueError, TypeError) as exc:
            self.logger.warning("map_saver: bad map_topic %r: %s", topic, exc)
            return SaveMapResponse(result=False)
        try:
            if not ready.wait(self.params.save_map_timeout):
                self.logger.warning("map_saver: no map on %r within %.1f s", topic,
                                    self.params.save_map_timeout)
                return SaveMapResponse(result=False)
        finally:
            self.destroy(sub)
        try:
            where = self.core.saver.save_map(got[0], req)
        except SaveRefused as exc:
            self.logger.warning("map_saver: %s", exc)
            return SaveMapResponse(result=False)
        self.logger.info("map_saver: map from %r saved as %s", topic, where)
        return SaveMapResponse(result=True)

    # ------------------------------------------------------------------ inputs

    def on_odom(self, msg: Odometry) -> None:
        try:
            pose = self._odom_pose(msg.pose.pose)
        except ValueError:
            self.logger.warning("odom with a bad pose ignored", exc_info=False)
            return
        t = msg.twist.twist
        self.core.on_odom(msg.header.stamp.nanoseconds, pose, t.linear.x, t.angular.z)

    def on_ground_truth(self, msg: Odometry) -> None:
        try:
            pose = self._truth_pose(msg.pose.pose)
        except ValueError:
            return
        self.core.on_ground_truth(msg.header.stamp.nanoseconds, pose)

    def on_scan(self, msg: LaserScan) -> None:
        self.core.on_scan(msg, self._seconds())
        self.landmarks.on_scan(msg)
        if self.landmarks_pub.subscription_count:
            self.landmarks_pub.publish(self.landmarks.detections(msg))
        if self.people_pub.subscription_count:  # the leg detector runs for a listener only
            self._publish_people(msg.header.stamp)

    def on_battery(self, msg: BatteryState) -> None:
        self.core.on_battery(msg.percentage, msg.power_supply_status in (
            BatteryState.POWER_SUPPLY_STATUS_CHARGING, BatteryState.POWER_SUPPLY_STATUS_FULL))

    def on_chassis(self, msg: ChassisState) -> None:
        self.core.on_chassis(msg.docked, msg.charging)

    def on_initialpose(self, msg: PoseWithCovarianceStamped) -> None:
        frame = msg.header.frame_id.lstrip("/")
        if frame not in ("", "map"):
            self.logger.warning("initialpose in frame %r ignored: it must be in map", frame)
            return
        try:
            pose = pose2_from_msg(msg.pose.pose)
        except ValueError as exc:
            self.logger.warning("initialpose ignored: %s", exc)
            return
        self.core.localizer.set_pose(pose)
        self.logger.info("initial pose set to (%.2f, %.2f, %.2f); localization: %s",
                         pose.x, pose.y, pose.theta, self.core.localizer.mode)

    def on_tf_static(self, msg: TFMessage) -> None:
        for t in msg.transforms:
            if t.header.frame_id.lstrip("/") == "base_link":
                tr, q = t.transform.translation, t.transform.rotation
                self.core.scan_mounts[t.child_frame_id.lstrip("/")] = Pose2(
                    tr.x, tr.y, yaw_from_msg(q))

    def _on_localization_param(self, p: Parameter) -> None:
        self.core.set_localization(str(p.value))

    # ------------------------------------------------------------------ timers

    def _seconds(self) -> float:
        return self.now().nanoseconds / 1e9

    def on_control(self) -> None:
        now = self._seconds()
        self._maybe_autocharge(now)
        cmd = self.core.tick(now)
        if cmd is not None:
            self.cmd_pub.publish(Twist(linear=Vector3(x=cmd[0]), angular=Vector3(z=cmd[1])))

    def _maybe_autocharge(self, now: float) -> None:
        core = self.core
        if self.current_state.state_id != ACTIVE:
            return  # an inactive nav drives nowhere on its own
        if core.mapping:
            return  # the dock is in the saved map's frame, not the one being built
        if not self.autocharge.due(core.battery, core.charging, core.docked,
                                   core.motion.active is not None, now):
            return
        try:
            dock = core.records.charge_pose()
        except Exception:  # noqa: BLE001 - no map: nothing to do
            dock = None
        if dock is None:
            self.logger.warning("battery at %.0f%% but map %r has no charge pose",
                                100 * (core.battery or 0), core.maps.current)
            return
        self.logger.info("battery at %.0f%%: going to charge", 100 * (core.battery or 0))
        core.start(Dock(dock, core.config.dock, core.make_nav))

    def on_pose_timer(self) -> None:
        loc = self.core.localizer
        pose = loc.pose()
        if pose is None:
            return
        stamp, poses = self.now(), self._poses
        self.pose_pub.publish(poses.pose_with_covariance(pose, stamp))
        if self.core.mapping:
            return  # map -> odom is the SLAM node's
        tol = 100_000_000  # 0.1 s ahead, as amcl's transform_tolerance
        odom_stamp = type(stamp).from_nanoseconds(loc.odom_stamp_ns + tol)
        self.tf.send_transform(poses.transform_stamped(loc.map_to_odom, odom_stamp, "map",
                                                       "odom"))

    def on_global_costmap_timer(self) -> None:
        msg = self.core.costmaps.global_msg(self.now())
        if msg is not None and self.global_pub.subscription_count > 0:
            self.global_pub.publish(msg)

    def on_local_costmap_timer(self) -> None:
        pose = self.core.localizer.pose()
        if pose is None or self.local_pub.subscription_count == 0:
            return
        msg = self.core.costmaps.local_msg(pose, self.now())
        if msg is not None:
            self.local_pub.publish(msg)

    def on_status_timer(self) -> None:
        self.status_pub.publish(nav_status(self.core, self.ledger, self.now()))

    # ------------------------------------------------------------------ outputs

    def _publish_plan(self, xy: np.ndarray) -> None:
        self.plan_pub.publish(path_to_msg(xy, self.now()))

    def _publish_map(self, name: str, grid: GridMap) -> None:
        pub = self.map_pub
        if pub is None:
            return
        pub.publish(grid.to_msg("map", self.now()))
        self.logger.info("map %r: %dx%d cells at %g m", name, grid.width, grid.height,
                         grid.resolution)

    def _halt(self) -> None:
        self.control.stop()
        moving = self.core.motion.active is not None
        self.core.close()
        if moving:  # leave the robot stopped, not coasting until its dead-man
            self.cmd_pub.publish(Twist())

