"""A stand-in mapping node (``slam``) and explorer (``explore``) that follow the mapping
contract of ``zenros_msgs.slam`` (docs/mapping.md), for testing the gateway's doors before the
real nodes are there. Not SLAM: the map it "builds" is the disc the robot's odometry has swept
(free cells within `SWEEP` m of each pose), in a frame that is the robot's pose when mapping
started, as the contract says.

- ``slam/start``: CONFLICT while mapping; asks nav's ``nav/set_mapping_mode`` when nav serves
  it (its refusal is answered as is); then ``starting`` → ``mapping`` on ``slam/state``,
  ``map`` (latched) and ``slam/pose`` at 5 Hz, ``slam/track`` (latched).
- ``slam/save``: INVALID for a bad name; else the grid goes to nav's ``map_server/save_grid``
  when nav serves it, else (nav of main, before mapping mode) through a map_server file pair
  and ``map_server/import_map``.
- ``slam/stop``: back to ``idle``, nav's mapping mode off.
- ``explore``: feedback ``exploring`` with frontiers counting down, then success.

Run it as a process: ``python slam_stand_in.py -e tcp/127.0.0.1:PORT --prefix P
[--namespace /robot1]``; it prints ``started`` when it serves.
"""

from __future__ import annotations

import argparse
import math
import signal
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
from zenros.action import ActionServer
from zenros.context import Context
from zenros.maps import GridMap, save_map
from zenros.msgs.geometry_msgs import Pose, Pose2D, PoseStamped, PoseWithCovarianceStamped
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.nav_msgs import Path as PathMsg
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import ImportMap, ImportMapRequest
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.slam import (
    Explore,
    ExploreFeedback,
    ExploreResult,
    MappingState,
    SaveGrid,
    SaveGridRequest,
    SaveSlamMap,
    SaveSlamMapRequest,
    SaveSlamMapResponse,
    SetMappingMode,
    SetMappingModeRequest,
    StartMapping,
    StartMappingRequest,
    StartMappingResponse,
    StopMapping,
    StopMappingRequest,
    StopMappingResponse,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.session import SessionOptions
from zenros.tf.convert import yaw_from_msg, yaw_to_msg

SIZE = 200          # cells a side
RES = 0.05          # m a cell
SWEEP = 1.0         # m round each pose that become known (free)
PERIOD = 0.2        # s between two map/pose publications
NAME_OK = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-"


def _valid_name(name: str) -> bool:
    return (0 < len(name) <= 64 and all(c in NAME_OK for c in name)
            and name[0] not in ".-")


class SlamStandIn(Node):
    """The stand-in mapping node and explorer (see the module)."""

    node_name = "slam"

    def setup(self) -> None:
        self.lock = threading.Lock()
        self.state = MappingState()
        self.cells = np.full((SIZE, SIZE), -1, dtype=np.int8)
        self.odom: Pose2D | None = None
        self.start_odom = Pose2D()
        self.poses: list[Pose2D] = []
        self.started_at = 0.0
        self.map_pub = self.create_publisher(OccupancyGrid, "map", QOS_LATCHED)
        self.state_pub = self.create_publisher(MappingState, "slam/state", QOS_LATCHED)
        self.track_pub = self.create_publisher(PathMsg, "slam/track", QOS_LATCHED)
        self.pose_pub = self.create_publisher(PoseWithCovarianceStamped, "slam/pose", 10)
        self.mode_client = self.create_client(SetMappingMode, "nav/set_mapping_mode")
        self.save_grid = self.create_client(SaveGrid, "map_server/save_grid")
        self.import_map = self.create_client(ImportMap, "map_server/import_map")
        self.create_subscription(Odometry, "odom", self.on_odom, 50)
        self.create_service(StartMapping, "slam/start", self.on_start)
        self.create_service(StopMapping, "slam/stop", self.on_stop)
        self.create_service(SaveSlamMap, "slam/save", self.on_save)
        self.create_timer(PERIOD, self.on_tick)
        self.explore_server = ActionServer(self, Explore, "explore", self.explore)
        self.state_pub.publish(self.state)

    # ------------------------------------------------------------------ mapping

    def on_odom(self, msg: Odometry) -> None:
        p = msg.pose.pose
        self.odom = Pose2D(x=p.position.x, y=p.position.y, theta=yaw_from_msg(p.orientation))

    def _map_pose(self) -> Pose2D:
        o, s = self.odom or Pose2D(), self.start_odom
        dx, dy = o.x - s.x, o.y - s.y
        c, sn = math.cos(-s.theta), math.sin(-s.theta)
        return Pose2D(x=c * dx - sn * dy, y=sn * dx + c * dy,
                      theta=math.atan2(math.sin(o.theta - s.theta),
                                       math.cos(o.theta - s.theta)))

    def _publish_state(self, **changes: Any) -> None:
        for k, v in changes.items():
            setattr(self.state, k, v)
        self.state_pub.publish(self.state)

    def _set_mode(self, req: SetMappingModeRequest) -> tuple[int, str]:
        if not self.mode_client.service_is_ready():
            return ResultCode.OK, ""
        res = self.mode_client.call(req, 10.0)
        return res.code, res.message

    def on_start(self, req: StartMappingRequest) -> StartMappingResponse:
        with self.lock:
            if self.state.state != "idle":
                return StartMappingResponse(code=ResultCode.CONFLICT,
                                            message=f"mapping already ({self.state.state})")
            self._publish_state(state="starting", mode=req.mode, map_name=req.map_name,
                                message="")
        code, message = self._set_mode(SetMappingModeRequest(enable=True))
        with self.lock:
            if code != ResultCode.OK:
                self._publish_state(state="idle", message=message)
                return StartMappingResponse(code=code, message=message)
            self.start_odom = self.odom or Pose2D()
            if req.use_initial_pose:  # the robot stands at initial_pose in the saved map
                ip, o = req.initial_pose, self.start_odom
                th = o.theta - ip.theta
                c, s = math.cos(th), math.sin(th)
                self.start_odom = Pose2D(x=o.x - (c * ip.x - s * ip.y),
                                         y=o.y - (s * ip.x + c * ip.y), theta=th)
            self.cells[:] = -1
            self.poses = []
            self.started_at = time.monotonic()
            self._publish_state(state="mapping")
        return StartMappingResponse()

    def on_stop(self, req: StopMappingRequest) -> StopMappingResponse:
        with self.lock:
            self._publish_state(state="stopping")
        self._set_mode(SetMappingModeRequest(enable=False))
        with self.lock:
            self._publish_state(state="idle", scans=0, nodes=0, area_m2=0.0)
        return StopMappingResponse()

    def _grid(self) -> OccupancyGrid:
        return GridMap(self.cells.copy(), RES, (-SIZE * RES / 2, -SIZE * RES / 2, 0.0)).to_msg()

    def on_tick(self) -> None:
        with self.lock:
            if self.state.state != "mapping":
                return
            pose = self._map_pose()
            half = SIZE * RES / 2
            ys, xs = np.mgrid[0:SIZE, 0:SIZE]
            cx, cy = (xs + 0.5) * RES - half, (ys + 0.5) * RES - half
            self.cells[(cx - pose.x) ** 2 + (cy - pose.y) ** 2 <= SWEEP ** 2] = 0
            if not self.poses or math.hypot(pose.x - self.poses[-1].x,
                                            pose.y - self.poses[-1].y) >= 0.2:
                self.poses.append(pose)
            known = int((self.cells >= 0).sum())
            self._publish_state(scans=self.state.scans + 1, nodes=len(self.poses),
                                width=SIZE, height=SIZE, resolution=RES,
                                origin=Pose2D(x=-half, y=-half), area_m2=known * RES * RES,
                                pose=pose)
            grid = self._grid()
            track = PathMsg(header=Header(frame_id="map"), poses=[
                PoseStamped(header=Header(frame_id="map"), pose=_pose(p)) for p in self.poses])
        self.map_pub.publish(grid)
        self.track_pub.publish(track)
        msg = PoseWithCovarianceStamped(header=Header(frame_id="map"))
        msg.pose.pose = _pose(pose)
        self.pose_pub.publish(msg)

    def on_save(self, req: SaveSlamMapRequest) -> SaveSlamMapResponse:
        if not _valid_name(req.name):
            return SaveSlamMapResponse(code=ResultCode.INVALID,
                                       message=f"invalid map name {req.name!r}")
        with self.lock:
            if self.state.state != "mapping":
                return SaveSlamMapResponse(code=ResultCode.CONFLICT, message="not mapping")
            grid = self._grid()
        if self.save_grid.service_is_ready():
            res = self.save_grid.call(SaveGridRequest(name=req.name, grid=grid, type=req.type,
                                                      levels=req.levels), 20.0)
            return SaveSlamMapResponse(code=res.code, message=res.message, name=req.name)
        with tempfile.TemporaryDirectory() as tmp:
            yaml_path = Path(tmp) / f"{req.name}.yaml"
            save_map(GridMap.from_msg(grid), yaml_path)
            self.import_map.call(ImportMapRequest(name=req.name, yaml_path=str(yaml_path),
                                                  overwrite=True), 20.0)
        return SaveSlamMapResponse(name=req.name)

    # ------------------------------------------------------------------ exploring

    def explore(self, handle: Any) -> ExploreResult:
        for left in (3, 2, 1, 0):
            if handle.is_cancel_requested:
                handle.canceled()
                return ExploreResult(error_code=1, error_msg="canceled")
            handle.publish_feedback(ExploreFeedback(stage="exploring" if left else "returning",
                                                    explored_area_m2=self.state.area_m2,
                                                    frontiers_left=left))
            time.sleep(0.3)
        handle.succeed()
        return ExploreResult(explored_area_m2=self.state.area_m2, goals_reached=3)


def _pose(p: Pose2D) -> Pose:
    pose = Pose()
    pose.position.x, pose.position.y = p.x, p.y
    pose.orientation = yaw_to_msg(p.theta)
    return pose


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-e", "--endpoint", required=True)
    ap.add_argument("--prefix", required=True)
    ap.add_argument("--namespace", default="")
    args = ap.parse_args()
    done = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: done.set())
    signal.signal(signal.SIGINT, lambda *_: done.set())
    with Context(SessionOptions(connect=[args.endpoint]), prefix=args.prefix) as ctx:
        node = SlamStandIn(context=ctx, namespace=args.namespace or None)
        print("slam stand-in started", flush=True)
        done.wait()
        node.close()


if __name__ == "__main__":
    main()
