"""`NavActions`: the gateway's `NavPort` on the nav service's actions (Nav2's
``navigate_to_pose``, ``dock_robot``, ``undock_robot``) and the nav points they go to.

Goals go to ``navigate_to_pose``; nav point indexes are looked up with ``get_nav_points``
on the current path; charging uses ``dock_robot`` / ``undock_robot``. ``nav/status``
(latched) keeps the docs/robot-api.md §4 goal fields (targetStatus, targetDistance) truthful.
"""

from __future__ import annotations

import asyncio
import math
import time
from collections import deque
from dataclasses import replace
from typing import Any

from zenros.action import ActionClient
from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosError, ZenrosTimeout
from zenros.msgs.nav2_msgs import (
    DockRobot,
    DockRobotGoal,
    NavigateToPose,
    NavigateToPoseGoal,
    UndockRobot,
    UndockRobotGoal,
)
from zenros.msgs.zenros_msgs import (
    GetCurrentMap,
    GetCurrentMapRequest,
    GetNavPoints,
    GetNavPointsRequest,
    ListPaths,
    ListPathsRequest,
    NavStatus,
    TaskStatus,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED

from ..errors import Conflict, NotFound, PortError, Refused
from ..state.core import Core, NavUnavailable
from ..state.status import GoalState
from ..state.target import NO_ID, task_target
from .nav_services import pose_stamped
from .tasks_link import TasksLink

__all__ = ["NavActions"]

CALL_TIMEOUT = 10.0    # s for a nav service call (a loaded machine answers slowly)
TRACK_PERIOD = 1.0     # s between recorded track points
TRACK_LENGTH = 3600    # points kept per map

# nav/status goal_status → §4 (targetStatus, angleGoalStatus)
_GOAL = {0: (0, -1), 1: (1, 0), 2: (0, 1), 3: (3, 2), 4: (0, -1)}


class NavActions:
    """Starts, pauses, resumes and cancels goals; `path_name` is the current path."""

    def __init__(self, node: Node, core: Core) -> None:
        self.node = node
        self.core = core
        self.path_name = ""
        self.stopped = False          # /navigation/stop was called: navStatus 0
        self._paused: tuple[float, float, float, int] | None = None
        self._last: tuple[float, float, float, int] | None = None
        self._handles: list[Any] = []
        self._target = NO_ID          # §4 targetNumID of the goal being driven
        self.tasks: TasksLink | None = None  # the tasks service, for pause/resume/cancel
        self.navigate = ActionClient(node, NavigateToPose, "navigate_to_pose")
        self.dock = ActionClient(node, DockRobot, "dock_robot")
        self.undock = ActionClient(node, UndockRobot, "undock_robot")
        self.points = node.create_client(GetNavPoints, "get_nav_points")
        self.paths = node.create_client(ListPaths, "list_paths")
        self.current = node.create_client(GetCurrentMap, "map_server/current_map")
        self.loop_task_id = ""        # the patrol task started by /navigation/loop_task
        self.tracks: dict[str, deque[tuple[float, float]]] = {}  # map -> 1 Hz poses
        self._track_at = 0.0
        node.create_subscription(NavStatus, "nav/status", self.on_status, QOS_LATCHED)
        node.create_subscription(TaskStatus, "tasks/status", self.on_task, QOS_LATCHED)

    # ------------------------------------------------------------------ state

    def available(self) -> bool:
        return bool(self.navigate.server_is_ready())

    def on_status(self, msg: NavStatus) -> None:
        s = self.core.state
        now = time.monotonic()
        if msg.localized and msg.map_name and now - self._track_at >= TRACK_PERIOD:
            self._track_at = now
            track = self.tracks.setdefault(msg.map_name, deque(maxlen=TRACK_LENGTH))
            track.append((msg.pose.x, msg.pose.y))
        s.nav_open = not self.stopped
        s.looping = msg.state == "patrolling" or bool(self.loop_task_id)
        s.docking_phase = {"docking": 4}.get(msg.state, 0)
        status, angle = _GOAL.get(msg.goal_status, (-1, -1))
        if self._paused is not None:
            status = 2
        s.goal = GoalState(num_id=self._target if msg.goal_status or self._paused else -1,
                           status=status, distance=msg.target_distance, angle_status=angle)

    def on_task(self, msg: TaskStatus) -> None:
        target = task_target(msg.task) if msg.state == "WORKING" else None
        if target is not None:  # the task drives a goal: §4 names it from now on
            self._target = target
            self.core.state.goal = replace(self.core.state.goal, num_id=target)
        if msg.id == self.loop_task_id and msg.state not in ("WAITTING", "WORKING", "PAUSED"):
            self.loop_task_id = ""
            self.core.state.looping = False

    def _require(self) -> None:
        if not self.available():
            raise NavUnavailable("navigation is not available: no navigate_to_pose server")

    # ------------------------------------------------------------------ NavPort

    async def goto_pose(self, x: float, y: float, theta: float, num_id: int = -2) -> None:
        if not all(math.isfinite(v) for v in (x, y, theta)):
            raise ValueError(f"goal ({x}, {y}, {theta}) is not finite")
        self._require()
        running = await self._task("WORKING", "PAUSED")
        if running:  # a direct goal replaces the running task
            await self._task_step("stop", running)
        self._paused = None
        self._last = (x, y, theta, num_id)
        self._target = num_id
        self.stopped = False
        self.core.state.nav_open = True
        self.core.state.goal = GoalState(num_id=num_id, status=1, distance=-1.0, angle_status=0)
        handle = self.navigate.send_goal_async(
            NavigateToPoseGoal(pose=pose_stamped(x, y, theta)))
        self._handles = [h for h in self._handles if not h.done] + [handle]

    async def current_path(self) -> str:
        """The current path: the one chosen (``/navigation/start?path=``), else the current
        map's first.

        Raises:
            NavUnavailable: nav does not answer.
            ValueError: the map has no path.
        """
        if self.path_name:
            return str(self.path_name)
        try:
            current = await self.current.call_async(GetCurrentMapRequest(), CALL_TIMEOUT)
            res = await self.paths.call_async(ListPathsRequest(map_name=current.name),
                                              CALL_TIMEOUT)
        except (ServiceUnavailableError, ZenrosTimeout) as exc:
            raise NavUnavailable(f"nav paths are not available: {exc}") from exc
        except ServiceError as exc:
            raise ValueError(exc.reason) from exc
        names = sorted(p.path_name for p in res.paths if p.map_name == current.name)
        if not names:
            raise ValueError(f"map {current.name!r} has no path with nav points yet "
                             "(POST /navigation/nav_points)")
        return str(names[0])

    async def nav_point(self, index: int) -> tuple[float, float, float]:
        """The pose of nav point ``index`` of the current path.

        Raises:
            NavUnavailable: nav does not answer.
            NotFound: the path has no nav point ``index`` (a ValueError).
            ValueError: the map has no path, or nav refused the path.
        """
        try:
            path = await self.current_path()
            res = await self.points.call_async(
                GetNavPointsRequest(map_name="", path_name=path), CALL_TIMEOUT)
        except (ServiceUnavailableError, ZenrosTimeout) as exc:
            raise NavUnavailable(f"nav points are not available: {exc}") from exc
        except ServiceError as exc:
            raise ValueError(f"nav points of path {self.path_name!r}: {exc.reason}") from exc
        n = len(res.points)
        if not 0 <= index < n:
            has = f"has {n} (0..{n - 1})" if n else "has no nav points"
            raise NotFound(f"nav point {index} does not exist: path {res.path_name!r} {has}")
        p = res.points[index]
        return p.x, p.y, p.theta

    async def point(self, index: int) -> tuple[float, float, float]:
        """Nav point ``index`` of the current path, for the REST handlers: `NotFound` when it
        does not exist, `Conflict` when the map has no path, nav's absence `Unavailable`."""
        try:
            return await self.nav_point(index)
        except NavUnavailable as exc:
            raise self.core.presence.error("nav", str(exc)) from exc
        except PortError:  # NotFound: no such nav point
            raise
        except ValueError as exc:
            raise Conflict(str(exc)) from exc

    def same_map(self, map_name: str, path: str, current: str) -> None:
        """A goal on the current map: make ``path`` the current path (a goal on another
        map is the callers' cross-map case; one that reaches here is a bug, a 400)."""
        if map_name and map_name != current:
            raise Refused(f"map {map_name!r} is not the current map {current!r}")
        if path and path != self.path_name:
            self.path_name = path

    async def goto_index(self, index: int) -> None:
        self._require()
        x, y, theta = await self.nav_point(index)
        await self.goto_pose(x, y, theta, num_id=index)

    async def _cancel_all(self, client: ActionClient) -> None:
        try:
            await asyncio.to_thread(client.cancel_all_goals)
        except ZenrosError as exc:  # no server, or it did not answer
            raise NavUnavailable(f"cannot cancel {client.name}: {exc}") from exc

    async def _task(self, *states: str) -> str:
        """The id of a task of the tasks service in one of ``states``, or ""."""
        if self.tasks is None:
            return ""
        try:
            tasks = await self.tasks.tasks()
        except PortError:
            return ""
        return next((t.id for t in tasks if t.state in states), "")

    async def _task_step(self, name: str, ident: str) -> None:
        """Raises a ValueError when the tasks service refuses or fails (the refusal's port
        error when it refused)."""
        assert self.tasks is not None
        try:
            await self.tasks.step(name, ident)
        except PortError as exc:
            text = f"task {ident}: {name} refused: {exc.detail}"
            if isinstance(exc, Refused):
                raise type(exc)(text, exc.retry_after) from exc
            raise ValueError(text) from exc

    def open(self) -> None:
        """Navigation on (navStatus 1): ``/navigation/start``, native ``m 00``."""
        self.stopped = False
        self.core.state.nav_open = True

    async def stop(self) -> None:
        """Navigation off (navStatus 0, kept through nav's status updates until `open` or a
        new goal): cancel the goal and the running task (``/navigation/stop``, ``m 04``).

        Raises:
            NavUnavailable: the goal could not be canceled (navigation is off all the same).
        """
        try:
            if self.available():
                await self.cancel()
        finally:
            self.stopped = True
            self.core.state.nav_open = False

    async def cancel(self) -> None:
        """Cancel the goal: the running task when there is one, else the direct goal."""
        self._paused = None
        running = await self._task("WORKING", "PAUSED")
        if running:
            await self._task_step("stop", running)
        await self._cancel_all(self.navigate)

    async def pause(self) -> None:
        running = await self._task("WORKING")
        if running:
            await self._task_step("pause", running)
            return
        if self._last is None or self._paused is not None:
            return
        self._paused = self._last
        await self._cancel_all(self.navigate)
        self.core.state.goal = GoalState(num_id=self._last[3], status=2,
                                         distance=self.core.state.goal.distance, angle_status=0)

    async def resume(self) -> None:
        paused_task = await self._task("PAUSED")
        if paused_task:
            await self._task_step("resume", paused_task)
            return
        paused = self._paused
        if paused is None:
            return
        x, y, theta, num_id = paused
        await self.goto_pose(x, y, theta, num_id)

    async def go_charge(self) -> None:
        if not self.dock.server_is_ready():
            raise NavUnavailable("charging is not available: no dock_robot server")
        self.core.state.docking_phase = 3
        self.dock.send_goal_async(DockRobotGoal(use_dock_id=True, dock_id=""))

    async def stop_charge(self) -> None:
        await self._cancel_all(self.dock)
        if self.undock.server_is_ready():
            self.undock.send_goal_async(UndockRobotGoal())
        self.core.state.docking_phase = 0
