"""`SlamLink`: the mapping node (``slam``, zenros_msgs.slam) and the ``explore`` action, as the
gateway's doors use them (docs/robot-api.md §5, docs/mapping.md "The robot API").

Calls: ``slam/start``, ``slam/stop``, ``slam/save`` (each refusal the port error of the node's
`ResultCode`, with its reason) and the ``explore`` goal. Topics: ``slam/state`` (latched; it
drives GalileoStatus ``mapStatus`` and ``busyStatus``, §7), ``slam/pose``, ``slam/track``
(latched), and the grid on ``map`` as it grows (read from the gateway's one subscription to
``map``, `NavServices`'s: the grid there when mapping started is nav's stored map, never taken for
the map being built; nav stops publishing ``map`` while the mapping node maps).
"""

from __future__ import annotations

import asyncio
import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

import msgspec
from zenros.action import ActionClient
from zenros.action.client_goal import ClientGoalHandle, GoalResult
from zenros.action.types import GoalStatus
from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosError, ZenrosTimeout
from zenros.message import Message
from zenros.msgs.geometry_msgs import Pose2D, PoseWithCovarianceStamped
from zenros.msgs.nav_msgs import OccupancyGrid, Path
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.slam import (
    Explore,
    ExploreFeedback,
    ExploreGoal,
    ExploreResult,
    MappingState,
    SaveSlamMap,
    SaveSlamMapRequest,
    SaveSlamMapResponse,
    StartMapping,
    StartMappingRequest,
    StartMappingResponse,
    StopMapping,
    StopMappingRequest,
    StopMappingResponse,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.rpc import Client
from zenros.tf.convert import yaw_from_msg

from ..errors import NoAnswer, Unavailable, port_error
from ..state.core import Core

__all__ = ["ExploreProgress", "MappingSummary", "SlamLink", "SlamPort", "TrackPoint"]

RAW_TRACK_STEP = 0.05   # m between two points of the recorded (raw) trajectory
RAW_TRACK_LENGTH = 20000
BUSY_STATES = frozenset({"starting", "stopping"})
OWN_START = 5.0   # s: a start seen on slam/state this soon after our own call is ours


class ExploreProgress(msgspec.Struct):
    """The ``explore`` goal as the gateway last saw it. ``state``: ``""`` (none sent),
    ``exploring``, ``returning``, ``done`` (no frontier left, back at the start),
    ``failed``, ``canceled``."""

    state: str = ""
    explored_area_m2: float = 0.0
    frontiers_left: int = 0
    goals_reached: int = 0
    goals_failed: int = 0
    message: str = ""


class MappingSummary(msgspec.Struct):
    """What ``/system/info`` says of mapping (the latest ``slam/state`` and the explore goal)."""

    state: str
    mode: str
    map_name: str
    scans: int
    nodes: int
    loop_closures: int
    width: int
    height: int
    resolution: float
    area_m2: float
    message: str
    update_map: bool
    explore: ExploreProgress


@dataclass(frozen=True)
class TrackPoint:
    x: float
    y: float


@dataclass
class _Latest:
    state: MappingState = field(default_factory=MappingState)
    state_seen: bool = False
    stale: OccupancyGrid | None = None   # the grid on `map` when mapping started: nav's
    pose: Pose2D | None = None
    keyframes: list[TrackPoint] = field(default_factory=list)
    raw: list[TrackPoint] = field(default_factory=list)


class SlamPort(Protocol):
    """What the mapping routes ask of the mapping node (a `SlamLink`, or a test's stand-in)."""

    update_map: bool

    def available(self) -> bool: ...
    def explore_available(self) -> bool: ...
    def state(self) -> MappingState: ...
    def mapping(self) -> bool: ...
    def grid(self) -> OccupancyGrid | None: ...
    def pose(self) -> Pose2D | None: ...
    def track(self, keyframes: bool) -> list[TrackPoint]: ...
    def explore(self) -> ExploreProgress: ...
    def summary(self) -> MappingSummary: ...
    async def start(self, mode: str, map_name: str = "",
                    initial_pose: Pose2D | None = None) -> None: ...
    async def stop(self) -> None: ...
    async def save(self, name: str, type: str, levels: list[int]) -> str: ...
    async def start_explore(self) -> None: ...
    async def cancel_explore(self) -> None: ...


class SlamLink:
    """The mapping node's calls and topics for the robot in ``node``'s namespace.

    Args:
        node: the gateway's node of that robot.
        core: its state; ``slam/state`` sets ``mapping`` and ``busy`` (§4, §7).
        grids: the latest grid on ``map`` (`NavServices.grid`: one subscription decodes it).
        timeout: s a call waits (slam/start asks nav first; slam/save writes the map).
    """

    def __init__(self, node: Node, core: Core, grids: Callable[[], OccupancyGrid | None],
                 timeout: float = 20.0) -> None:
        self.core = core
        self.presence = core.presence
        self.timeout = timeout
        self.update_map = False   # PUT /navigation/update_map started this mapping
        self._lock = threading.Lock()
        self._latest = _Latest()
        self._grids = grids
        self._since = 0.0          # time.monotonic() mapping (last) started
        self._explore = ExploreProgress()
        self._goal: ClientGoalHandle[ExploreGoal, ExploreResult] | None = None
        self._start = node.create_client(StartMapping, "slam/start")
        self._stop = node.create_client(StopMapping, "slam/stop")
        self._save = node.create_client(SaveSlamMap, "slam/save")
        self._explorer = ActionClient(node, Explore, "explore")
        node.create_subscription(MappingState, "slam/state", self.on_state, QOS_LATCHED)
        node.create_subscription(PoseWithCovarianceStamped, "slam/pose", self.on_pose, 10)
        node.create_subscription(Path, "slam/track", self.on_track, QOS_LATCHED)
        self.presence.watch("slam", self.available)
        self.presence.watch("explore", self.explore_available)

    # ------------------------------------------------------------------ presence

    def available(self) -> bool:
        """Whether a mapping node serves ``slam/start``."""
        return bool(self._start.service_is_ready())

    def explore_available(self) -> bool:
        return bool(self._explorer.server_is_ready())

    # ------------------------------------------------------------------ topics in

    def _begin(self) -> None:
        """Mapping (re)starts: forget the last map's grid, pose and tracks."""
        with self._lock:
            self._since = time.monotonic()
            latest = self._latest
            latest.stale, latest.pose = self._grids(), None
            latest.keyframes, latest.raw = [], []

    def on_state(self, msg: MappingState) -> None:
        with self._lock:
            before = self._latest.state.state if self._latest.state_seen else "idle"
            self._latest.state, self._latest.state_seen = msg, True
        if (before in ("idle", "stopping") and msg.state in ("starting", "mapping")
                and time.monotonic() - self._since > OWN_START):
            self._begin()  # started by someone else (the CLI, another gateway)
        s = self.core.state
        s.mapping = msg.state == "mapping"
        s.busy = msg.state in BUSY_STATES
        if msg.state == "idle":
            self.update_map = False

    def on_pose(self, msg: PoseWithCovarianceStamped) -> None:
        p = msg.pose.pose
        pose = Pose2D(x=p.position.x, y=p.position.y, theta=yaw_from_msg(p.orientation))
        with self._lock:
            latest = self._latest
            latest.pose = pose
            raw = latest.raw
            if not raw or math.hypot(pose.x - raw[-1].x, pose.y - raw[-1].y) >= RAW_TRACK_STEP:
                raw.append(TrackPoint(pose.x, pose.y))
                if len(raw) > RAW_TRACK_LENGTH:
                    del raw[: len(raw) - RAW_TRACK_LENGTH]

    def on_track(self, msg: Path) -> None:
        points = [TrackPoint(p.pose.position.x, p.pose.position.y) for p in msg.poses]
        with self._lock:
            self._latest.keyframes = points

    # ------------------------------------------------------------------ reads

    def state(self) -> MappingState:
        with self._lock:
            return self._latest.state

    def mapping(self) -> bool:
        """Whether the mapping node is mapping (or starting to)."""
        return self.state().state in ("starting", "mapping")

    def grid(self) -> OccupancyGrid | None:
        """The map being built, once its first grid came (None before, or when idle)."""
        grid = self._grids()
        with self._lock:
            if self._latest.state.state == "idle" or grid is self._latest.stale:
                return None
            return grid

    def pose(self) -> Pose2D | None:
        """The robot in the map being built: ``slam/pose``, else the state's pose."""
        with self._lock:
            latest = self._latest
            if latest.state.state == "idle":
                return None
            return latest.pose if latest.pose is not None else latest.state.pose

    def track(self, keyframes: bool) -> list[TrackPoint]:
        """The trajectory of this mapping: the pose graph's nodes as last optimised
        (``keyframes``, ``slam/track``), or the poses as they were published (one every
        `RAW_TRACK_STEP` m of travel, not corrected by later loop closures)."""
        with self._lock:
            return list(self._latest.keyframes if keyframes else self._latest.raw)

    def explore(self) -> ExploreProgress:
        with self._lock:
            return msgspec.structs.replace(self._explore)

    def summary(self) -> MappingSummary:
        st = self.state()
        return MappingSummary(
            state=st.state, mode=st.mode, map_name=st.map_name, scans=st.scans,
            nodes=st.nodes, loop_closures=st.loop_closures, width=st.width,
            height=st.height, resolution=st.resolution, area_m2=st.area_m2,
            message=st.message, update_map=self.update_map, explore=self.explore())

    # ------------------------------------------------------------------ calls

    async def _call(self, client_name: str, request: Message) -> Message:
        clients: dict[str, Client[Any, Any]] = {"start": self._start, "stop": self._stop,
                                                 "save": self._save}
        client = clients[client_name]
        try:
            res: Message = await client.call_async(request, self.timeout)
        except ServiceUnavailableError:
            raise self.presence.error("slam", f"no server for {client.name}") from None
        except ZenrosTimeout:
            raise NoAnswer(f"the mapping node did not answer {client.name} within "
                           f"{self.timeout:g} s") from None
        except ServiceError as exc:
            raise port_error(exc.code, exc.reason) from exc
        code = int(getattr(res, "code", ResultCode.OK))
        if code != ResultCode.OK:
            raise port_error(code, str(getattr(res, "message", "")) or
                             f"{client.name} failed (code {code})")
        return res

    async def start(self, mode: str, map_name: str = "",
                    initial_pose: Pose2D | None = None) -> None:
        """``slam/start``: a new map, or (``map_name``) extend that saved map with the robot
        at ``initial_pose`` (None: at the saved graph's last pose)."""
        req = StartMappingRequest(mode=mode, map_name=map_name,
                                  initial_pose=initial_pose or Pose2D(),
                                  use_initial_pose=initial_pose is not None)
        self._begin()   # grids from here on are the new map's
        with self._lock:
            self._explore = ExploreProgress()
        res = await self._call("start", req)
        assert isinstance(res, StartMappingResponse)

    async def stop(self) -> None:
        res = await self._call("stop", StopMappingRequest())
        assert isinstance(res, StopMappingResponse)
        self.update_map = False

    async def save(self, name: str, type: str, levels: list[int]) -> str:
        """``slam/save``: the map being built, stored as ``name``; returns the stored name."""
        res = await self._call("save", SaveSlamMapRequest(name=name, type=type,
                                                          levels=list(levels)))
        assert isinstance(res, SaveSlamMapResponse)
        return res.name or name

    async def start_explore(self) -> None:
        """Send the ``explore`` goal (return to the start when no frontier is left); wait
        until the explorer took it.

        Raises:
            Unavailable: no explore node; or it refused the goal (a port error of its kind).
        """
        if not self.explore_available():
            raise self.presence.error("explore", "no server for the explore action")
        handle = self._explorer.send_goal_async(ExploreGoal(return_to_start=True),
                                                feedback_callback=self._on_feedback)
        try:
            accepted = await asyncio.to_thread(handle.wait_accepted, self.timeout)
        except ZenrosTimeout:
            raise NoAnswer(f"the explore node did not answer the goal within "
                           f"{self.timeout:g} s") from None
        except ZenrosError as exc:
            raise Unavailable(f"the explore goal was not delivered: {exc}") from exc
        if not accepted:
            raise port_error(ResultCode.CONFLICT, f"the explore node refused the goal: "
                             f"{handle.reason or 'no reason given'}")
        with self._lock:
            self._goal = handle
            self._explore = ExploreProgress(state="exploring")
        handle.add_done_callback(self._on_done)

    def _on_feedback(self, msg: object) -> None:
        fb = getattr(msg, "feedback", None)
        if not isinstance(fb, ExploreFeedback):
            return
        with self._lock:
            if self._explore.state in ("exploring", "returning"):
                self._explore = msgspec.structs.replace(
                    self._explore, state=fb.stage, explored_area_m2=fb.explored_area_m2,
                    frontiers_left=fb.frontiers_left)

    def _on_done(self, handle: ClientGoalHandle[ExploreGoal, ExploreResult]) -> None:
        try:
            outcome: GoalResult[ExploreResult] = handle.result(0)
        except ZenrosError as exc:
            with self._lock:
                self._explore = msgspec.structs.replace(self._explore, state="failed",
                                                        message=str(exc))
            return
        r = outcome.result
        if outcome.status is GoalStatus.SUCCEEDED and r.error_code == 0:
            state = "done"
        elif outcome.status is GoalStatus.CANCELED:
            state = "canceled"
        else:
            state = "failed"
        with self._lock:
            self._explore = ExploreProgress(
                state=state, explored_area_m2=r.explored_area_m2, frontiers_left=0,
                goals_reached=r.goals_reached, goals_failed=r.goals_failed,
                message=r.error_msg or outcome.reason)

    async def cancel_explore(self) -> None:
        """Cancel exploring: every goal of the ``explore`` action, whoever sent it (this
        gateway, the dashboard through rosbridge, a ROS client); nothing without an explorer."""
        with self._lock:
            self._goal = None
        if not self.explore_available():
            return
        try:
            await asyncio.to_thread(self._explorer.cancel_all_goals, self.timeout)
        except ZenrosError as exc:
            raise Unavailable(f"exploring could not be canceled: {exc}") from exc
