"""`SlamNode`: wires the mapping session (`MappingSession`, the `Mapper`) to Zenoh.

Idle until ``slam/start``. While mapping it publishes ``map`` (latched), ``map -> odom`` on
``/tf``, ``slam/pose``, ``slam/track`` (latched) and ``slam/state`` (latched), and serves
``slam/stop``, ``slam/save`` and slam_toolbox's services (docs/mapping.md).

A managed (lifecycle) node, as Nav2's servers are: ``slam/start`` is refused unless it is
active; deactivating it stops a mapping run. By itself (``autostart`` true, the default) it
activates once set up; the launches bring it up through their lifecycle manager
(docs/lifecycle.md, "The robot's services").
"""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

import numpy as np

from zenros.errors import (MapError, NodeClosedError, ServiceError, ServiceUnavailableError,
                           ZenrosTimeout)
from zenros.home import data_dir
from zenros.maps import load_map
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry, Path as PathMsg
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import Header
from zenros.msgs.tf2_msgs import TFMessage
from zenros.msgs import slam_toolbox as st
from zenros.msgs.zenros_msgs import slam as sm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from zenros.lifecycle.machine import ACTIVE
from zenros.pubsub import Publisher
from zenros.qos import QOS_LATCHED, QOS_SENSOR
from zenros.se2 import Pose2
from zenros.tf import TransformBroadcaster, yaw_from_msg
from zenros.tf.listener import STATIC_LISTENER_QOS

from .diagnostics import slam_diagnostics
from .mapper import Prior, ScanOutcome
from .messages import grid_msg, pose2d, pose_with_covariance, track_msg, transform_msg
from .params import SlamParameters
from .session import MappingSession
from .store import check_name, load_graph, save_graph

__all__ = ["SlamNode"]

_NAV_TIMEOUT = 3.0
_ACTIVATION_WAIT = 5.0  # seconds slam/start waits for the node to be activated
_POSE_COV = np.diag([0.0025, 0.0025, 0.003])  # as nav's robot_pose
_MODES = ("laser", "explore")


def _time(seconds: float) -> Time:
    return Time.from_nanoseconds(int(round(seconds * 1e9)))


class SlamNode(LifecycleNode):
    """The mapping node (``slam``): occupancy-grid SLAM from ``scan`` and ``odom``."""

    node_name = "slam"
    autostart_default = True

    def setup(self) -> None:
        p = self.params = self.declare_parameters(SlamParameters, read_only=True)
        self.graph_dir = Path(p.graph_dir) if p.graph_dir else data_dir() / "slam"
        self.session = self.own(MappingSession(p, self._on_folded, self._on_fold_error,
                                               threaded=not self.context.deterministic))
        self.state = sm.MappingState(state="idle")
        self.saved_name = ""
        self._map_due = 0.0
        self._closures_published = 0
        self._nodes_published = -1
        self.activation_wait = _ACTIVATION_WAIT

        # declared while mapping only: once nav takes the map back, no latched cache of ours
        # may serve a late joiner the SLAM map beside nav's
        self.map_pub: Publisher[OccupancyGrid] | None = None
        self.track_pub = self.create_publisher(PathMsg, "slam/track", QOS_LATCHED)
        self.state_pub = self.create_publisher(sm.MappingState, "slam/state", QOS_LATCHED)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "slam/pose")
        self.tf = TransformBroadcaster(self)
        self.nav_mode = self.create_client(sm.SetMappingMode, "nav/set_mapping_mode")
        self.nav_save = self.create_client(sm.SaveGrid, "map_server/save_grid")

        # scan and odom are subscribed while mapping only: an idle node costs nothing
        self._inputs: list[Any] = []
        self.create_subscription(TFMessage, "/tf_static", self.on_tf_static, STATIC_LISTENER_QOS)

        for srv, name, handler in (
            (sm.StartMapping, "slam/start", self.handle_start),
            (sm.StopMapping, "slam/stop", self.handle_stop),
            (sm.SaveSlamMap, "slam/save", self.handle_save),
            (st.SaveMap, "slam_toolbox/save_map", self.handle_save_map),
            (st.SerializePoseGraph, "slam_toolbox/serialize_map", self.handle_serialize),
            (st.DeserializePoseGraph, "slam_toolbox/deserialize_map", self.handle_deserialize),
            (st.Pause, "slam_toolbox/pause_new_measurements", self.handle_pause),
            (st.Reset, "slam_toolbox/reset", self.handle_reset),
        ):
            self.create_service(srv, name, handler)

        # they tick while mapping only (`_begin_run` to `_end_mapping`): an idle node
        # publishes no map -> odom, as slam_toolbox publishes it only while it runs
        self._mapping_timers = [
            self.create_timer(period, callback, autostart=False) for period, callback in (
                (p.transform_publish_period, self.on_tf_timer), (0.2, self.on_map_timer),
                (1.0, self.on_state_timer)) if period > 0]
        self._publish_state()
        self.diagnostics = slam_diagnostics(self)  # slam: mapping, on /diagnostics

    # ------------------------------------------------------------------ inputs

    def on_odom(self, msg: Odometry) -> None:
        q, pos = msg.pose.pose.orientation, msg.pose.pose.position
        try:
            pose = Pose2(pos.x, pos.y, yaw_from_msg(q))
        except (ValueError, ZeroDivisionError):
            return
        if pose.is_finite():
            self.session.on_odom(msg.header.stamp.nanoseconds / 1e9, pose)

    def on_scan(self, msg: LaserScan) -> None:
        try:
            self.session.on_scan(msg.header.stamp.nanoseconds / 1e9, msg.ranges, msg.angle_min,
                                 msg.angle_increment, msg.range_min, msg.range_max)
        except ValueError as exc:
            self.logger.warning("scan ignored: %s", exc)

    def on_tf_static(self, msg: TFMessage) -> None:
        for t in msg.transforms:
            if (t.header.frame_id.lstrip("/") == self.params.base_frame
                    and t.child_frame_id.lstrip("/") == self.params.laser_frame):
                tr = t.transform.translation
                self.session.mount = Pose2(tr.x, tr.y, yaw_from_msg(t.transform.rotation))

    def _on_folded(self, out: ScanOutcome, stamp: float) -> None:
        """On the worker, after each scan: the pose, and the track when a node was added."""
        s = _time(stamp)
        self.pose_pub.publish(pose_with_covariance(out.pose, _POSE_COV, s,
                                                   self.params.map_frame))
        if out.node is not None:
            poses, stamps = self.session.track()
            self.track_pub.publish(track_msg(poses, [_time(t) for t in stamps],
                                             self.params.map_frame, s))

    def _on_fold_error(self, exc: BaseException) -> None:
        if isinstance(exc, NodeClosedError) and self.closed:  # a scan in flight at close
            return
        self.logger.error("a scan could not be folded in: %s: %s", type(exc).__name__, exc)

    # ------------------------------------------------------------------ timers

    def on_tf_timer(self) -> None:
        if not self.session.active:
            return
        _, m2o, stamp = self.session.pose()
        if stamp <= 0:
            return
        # slam_toolbox stamps map -> odom at the scan's time plus transform_timeout
        t = _time(stamp + self.params.transform_timeout)
        self.tf.send_transform(transform_msg(m2o, t, self.params.map_frame,
                                             self.params.odom_frame))

    def on_map_timer(self) -> None:
        if not self.session.active:
            return
        now = self.now().nanoseconds / 1e9
        _, nodes, closures = self.session.counts()
        closed = closures > self._closures_published
        if not closed and (now < self._map_due or nodes == self._nodes_published):
            return
        self._publish_map()
        self._closures_published = closures
        self._nodes_published = nodes
        self._map_due = now + self.params.map_update_interval

    def _publish_map(self) -> None:
        snap = self.session.snapshot()
        pub = self.map_pub
        if snap is None or pub is None:
            return
        pub.publish(grid_msg(snap.cells, snap.resolution, snap.origin, self.now(),
                                      self.params.map_frame))
        self.state.width, self.state.height = snap.cells.shape[1], snap.cells.shape[0]
        self.state.resolution = snap.resolution
        self.state.origin = pose2d(Pose2(snap.origin[0], snap.origin[1], 0.0))
        self.state.area_m2 = snap.area_m2

    def on_state_timer(self) -> None:
        if self.session.active:
            self._publish_state()

    def _publish_state(self, **changes: object) -> None:
        for k, v in changes.items():
            setattr(self.state, k, v)
        scans, nodes, closures = self.session.counts()
        pose, _, _ = self.session.pose()
        st_ = self.state
        st_.scans, st_.nodes, st_.loop_closures = scans, nodes, closures
        st_.pose = pose2d(pose)
        st_.header = Header(stamp=self.now(), frame_id=self.params.map_frame)
        skipped = self.session.skipped
        if self.session.active and skipped and "skipped" not in st_.message:
            st_.message = f"{skipped} scans skipped: the mapper did not keep up"
        self.state_pub.publish(st_)

    # ------------------------------------------------------------------ nav

    async def _set_nav_mode(self, req: sm.SetMappingModeRequest) -> tuple[int, str]:
        """nav's answer, or OK with a note when no nav is there (slam may run alone)."""
        try:
            res = await self.nav_mode.call_async(req, timeout=_NAV_TIMEOUT)
        except (ServiceUnavailableError, ZenrosTimeout) as exc:
            self.logger.warning("nav/set_mapping_mode: %s; mapping without nav", exc)
            return ResultCode.OK, "no nav answered"
        except ServiceError as exc:
            return ResultCode.FAILED, f"nav/set_mapping_mode failed: {exc}"
        return int(res.code), res.message

    # ------------------------------------------------------------------ lifecycle

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """With ``start_mapping``, a new mapping run begins at once (nav is not asked)."""
        ret = super().on_activate(state)
        if self.params.start_mapping and self.state.state == "idle":
            self._begin_run("mapping", "", None, None, None)
            self.logger.info("mapping started (start_mapping)")
        return ret

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        """Leaving active stops a mapping run (its map is not saved), as a Nav2 server stops
        its work; nav is told to leave mapping mode in the background."""
        if self.state.state == "mapping":
            self.logger.warning("deactivated while mapping: mapping stopped, the map not saved")
            nav_req = self._end_mapping()
            self.context.executor.submit(self._leave_nav_mapping(nav_req))
        return super().on_deactivate(state)

    async def _leave_nav_mapping(self, nav_req: sm.SetMappingModeRequest) -> None:
        code, why = await self._set_nav_mode(nav_req)
        self._publish_state(state="idle", message="" if code == ResultCode.OK else why)

    def _end_mapping(self) -> sm.SetMappingModeRequest:
        """Stop taking scans and drop the map topic; what nav must be told."""
        self._publish_state(state="stopping")
        _, m2o, _ = self.session.pose()
        self.session.end()
        for timer in self._mapping_timers:
            timer.cancel()
        for sub in self._inputs:
            self.destroy(sub)
        self._inputs = []
        if self.map_pub is not None:
            self.destroy(self.map_pub)
            self.map_pub = None
        return sm.SetMappingModeRequest(enable=False, map_name=self.saved_name,
                                        map_to_odom=pose2d(m2o),
                                        use_map_to_odom=bool(self.saved_name))

    # ------------------------------------------------------------------ services

    async def handle_start(self, req: sm.StartMappingRequest) -> sm.StartMappingResponse:
        if not self.wait_for_active(0):  # a launch's manager may be bringing it up right now
            await asyncio.to_thread(self.wait_for_active, self.activation_wait)
        if self.current_state.state_id != ACTIVE:
            return sm.StartMappingResponse(
                code=ResultCode.CONFLICT,
                message=f"slam is {self.current_state.label}, not active: its lifecycle "
                        f"manager has not brought it up within {self.activation_wait:g} s "
                        "(zenros lifecycle get)")
        if self.state.state != "idle":
            return sm.StartMappingResponse(code=ResultCode.CONFLICT,
                                           message=f"already {self.state.state}")
        if req.mode not in _MODES:
            return sm.StartMappingResponse(
                code=ResultCode.INVALID,
                message=f"unknown mode {req.mode!r}: use one of {', '.join(_MODES)}")
        graph, at, prior = None, None, None
        if req.map_name:
            if req.use_initial_pose:
                ip = req.initial_pose
                at = Pose2(ip.x, ip.y, ip.theta)
                if not at.is_finite():
                    return sm.StartMappingResponse(code=ResultCode.INVALID,
                                                   message="initial_pose must be finite")
            try:
                graph, _, _ = load_graph(self._graph_path(req.map_name))
            except FileNotFoundError:
                code, why, prior = self._stored_grid(req.map_name, at)
                if code != ResultCode.OK:
                    return sm.StartMappingResponse(code=code, message=why)
            except ValueError as exc:
                return sm.StartMappingResponse(code=ResultCode.INVALID, message=str(exc))
        self._publish_state(state="starting", mode=req.mode, map_name=req.map_name,
                            message="")
        code, why = await self._set_nav_mode(sm.SetMappingModeRequest(enable=True))
        if code != ResultCode.OK:
            self._publish_state(state="idle", message=why)
            return sm.StartMappingResponse(code=code, message=why)
        self._begin_run(req.mode, req.map_name, graph, at, prior,
                        why if why == "no nav answered" else "")
        self.logger.info("mapping started (%s%s)", req.mode,
                         f", extending {req.map_name!r}" if req.map_name else "")
        return sm.StartMappingResponse(code=ResultCode.OK, message=why)

    def _begin_run(self, mode: str, map_name: str, graph: Any, at: Pose2 | None, prior: Any,
                   message: str = "") -> None:
        """Take scans into the session (from ``graph``, ``prior`` or empty)."""
        if self.map_pub is None:
            self.map_pub = self.create_publisher(OccupancyGrid, "map", QOS_LATCHED)
        self.session.begin(graph, at, prior)
        for timer in self._mapping_timers:
            if timer.is_canceled():
                timer.reset()
        if not self._inputs:
            self._inputs = [
                self.create_subscription(Odometry, "odom", self.on_odom, QOS_SENSOR),
                self.create_subscription(LaserScan, "scan", self.on_scan, QOS_SENSOR)]
        self.saved_name = map_name
        self._closures_published = self.session.counts()[2]
        self._nodes_published = -1
        self._map_due = 0.0
        self._publish_state(state="mapping", mode=mode, map_name=map_name, message=message)

    async def handle_stop(self, req: sm.StopMappingRequest) -> sm.StopMappingResponse:
        if self.state.state != "mapping":
            return sm.StopMappingResponse(code=ResultCode.CONFLICT,
                                          message=f"not mapping (state {self.state.state})")
        nav_req = self._end_mapping()
        code, why = await self._set_nav_mode(nav_req)
        self._publish_state(state="idle", message="" if code == ResultCode.OK else why)
        self.logger.info("mapping stopped")
        return sm.StopMappingResponse(code=code, message=why)

    async def handle_save(self, req: sm.SaveSlamMapRequest) -> sm.SaveSlamMapResponse:
        code, message = await self._save(req.name, req.type, list(req.levels))
        return sm.SaveSlamMapResponse(code=code, message=message,
                                      name=req.name if code == ResultCode.OK else "")

    async def _save(self, name: str, kind: str, levels: list[int]) -> tuple[int, str]:
        try:
            path = self._graph_path(name)
        except ValueError as exc:
            return ResultCode.INVALID, str(exc)
        if self.state.state != "mapping" or not self.session.has_map():
            return ResultCode.CONFLICT, "nothing mapped yet: start mapping and drive first"
        snap = self.session.snapshot()
        with self.session.lock:
            m = self.session.mapper
            save_graph(path, m.graph, m.map_to_odom, m.p.resolution)
            m2o = m.map_to_odom
        assert snap is not None
        grid = grid_msg(snap.cells, snap.resolution, snap.origin, self.now(),
                        self.params.map_frame)
        try:
            res = await self.nav_save.call_async(
                sm.SaveGridRequest(name=name, grid=grid, type=kind, levels=levels,
                                   map_to_odom=pose2d(m2o), use_map_to_odom=True),
                timeout=10.0)
        except (ServiceUnavailableError, ZenrosTimeout) as exc:
            return ResultCode.UNAVAILABLE, f"pose graph saved to {path}, but the map was not: {exc}"
        except ServiceError as exc:
            return ResultCode.FAILED, f"map_server/save_grid failed: {exc}"
        if res.code == ResultCode.OK:
            self.saved_name = name
            self.logger.info("map %r saved (%s)", name, path)
        return int(res.code), res.message

    def _stored_grid(self, name: str, at: Pose2 | None) -> tuple[int, str, Prior | None]:
        """The map ``name`` of nav's store as a prior, for a map with no pose graph."""
        root = Path(self.params.maps_dir) if self.params.maps_dir else data_dir() / "maps"
        path = root / name / f"{name}.yaml"
        if not path.is_file():
            return (ResultCode.NOT_FOUND,
                    f"no pose graph saved and no stored map named {name!r}", None)
        if at is None:
            return (ResultCode.INVALID,
                    f"map {name!r} has no pose graph: give initial_pose (use_initial_pose) to "
                    "extend its stored grid", None)
        try:
            grid = load_map(path)
        except (MapError, OSError) as exc:
            return ResultCode.FAILED, f"map {name!r} could not be read: {exc}", None
        if abs(grid.origin[2]) > 1e-9:
            return ResultCode.INVALID, f"map {name!r}: its origin must have yaw 0", None
        self.logger.info("map %r has no pose graph: extending its stored grid", name)
        return (ResultCode.OK, "",
                Prior(grid.grid, grid.resolution, (grid.origin[0], grid.origin[1])))

    def _graph_path(self, name: str) -> Path:
        return self.graph_dir / f"{check_name(name)}.posegraph"

    # ------------------------------------------------------------------ slam_toolbox

    async def handle_save_map(self, req: st.SaveMapRequest) -> st.SaveMapResponse:
        code, message = await self._save(req.name.data, "floor", [])
        if code == ResultCode.OK:
            return st.SaveMapResponse(result=st.SaveMapResponse.RESULT_SUCCESS)
        self.logger.warning("slam_toolbox/save_map %r: %s", req.name.data, message)
        if code == ResultCode.CONFLICT:
            return st.SaveMapResponse(result=st.SaveMapResponse.RESULT_NO_MAP_RECEIEVD)
        return st.SaveMapResponse(result=st.SaveMapResponse.RESULT_UNDEFINED_FAILURE)

    def handle_serialize(self, req: st.SerializePoseGraphRequest
                         ) -> st.SerializePoseGraphResponse:
        try:
            path = self._graph_path(Path(req.filename).name if req.filename else "")
            if not self.session.has_map():
                raise ValueError("nothing mapped yet")
            with self.session.lock:
                m = self.session.mapper
                save_graph(path, m.graph, m.map_to_odom, m.p.resolution)
        except (ValueError, OSError) as exc:
            self.logger.warning("slam_toolbox/serialize_map %r: %s", req.filename, exc)
            return st.SerializePoseGraphResponse(
                result=st.SerializePoseGraphResponse.RESULT_FAILED_TO_WRITE_FILE)
        return st.SerializePoseGraphResponse(result=st.SerializePoseGraphResponse.RESULT_SUCCESS)

    async def handle_deserialize(self, req: st.DeserializePoseGraphRequest
                                 ) -> st.DeserializePoseGraphResponse:
        if req.match_type not in (1, 2, 3):
            raise ValueError(f"match_type must be 1, 2 or 3, got {req.match_type}")
        name = Path(req.filename).name if req.filename else ""
        if name.endswith(".posegraph"):
            name = name[: -len(".posegraph")]
        start = sm.StartMappingRequest(map_name=name, initial_pose=req.initial_pose,
                                       use_initial_pose=req.match_type != 1)
        if req.match_type == 1:
            try:
                graph, _, _ = load_graph(self._graph_path(name))
            except (FileNotFoundError, ValueError) as exc:
                raise ValueError(str(exc)) from exc
            if graph.nodes:
                first = graph.nodes[0].pose
                start.initial_pose = pose2d(first)
                start.use_initial_pose = True
        res = await self.handle_start(start)
        if res.code != ResultCode.OK:
            raise ValueError(res.message)
        return st.DeserializePoseGraphResponse()

    def handle_pause(self, req: st.PauseRequest) -> st.PauseResponse:
        self.session.paused = not self.session.paused
        self.logger.info("new measurements %s", "paused" if self.session.paused else "resumed")
        return st.PauseResponse(status=self.session.paused)

    def handle_reset(self, req: st.ResetRequest) -> st.ResetResponse:
        self.session.reset()
        self.session.paused = req.pause_new_measurements
        self._nodes_published = -1
        self.logger.info("reset: the graph and the map are dropped")
        return st.ResetResponse(result=st.ResetResponse.RESULT_SUCCESS)
