"""`NavCalls`: what the navigation REST handlers share: the nav service's calls, the tasks
service's calls, nav points and the initial pose, each refusal a port error."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs.task_actions import Action
from zenros.msgs.zenros_msgs.task_docs import Task, as_document

from ..errors import Conflict, PortError, Refused
from ..state.core import Core, NavUnavailable
from .nav_link import NavLink
from .navigator import Navigator, pose_stamped
from .tasks_link import TasksLink

__all__ = ["OWN_TASKS", "Angle", "Coord", "Name", "NavCalls", "OptName"]

Name = Annotated[str, msgspec.Meta(pattern=r"^[A-Za-z0-9_][A-Za-z0-9_.\-]{0,63}$")]
"""A map or path name: no path separators, no leading dot (path traversal is a 400)."""
OptName = Annotated[str, msgspec.Meta(pattern=r"^([A-Za-z0-9_][A-Za-z0-9_.\-]{0,63})?$")]
Coord = Annotated[float, msgspec.Meta(ge=-1e5, le=1e5)]
Angle = Annotated[float, msgspec.Meta(ge=-100.0, le=100.0)]
OWN_TASKS = frozenset({"navigation task", "loop task", "charge task", "local move task"})


class NavCalls:
    """The nav and tasks services as the navigation handlers use them."""

    def __init__(self, core: Core, nav: Navigator, link: NavLink, tasks: TasksLink) -> None:
        self.core = core
        self.nav = nav
        self.link = link
        self.tasks = tasks

    async def run_task(self, name: str, sub_tasks: list[Action], loop: bool = False
                       ) -> dict[str, Any]:
        """Create and start a task; a running navigation task of ours gives way to it (a new
        goal replaces the old one), any other running task is a 409. Returns the started
        task's document."""
        task = await self.tasks.create(Task(name=name, sub_tasks=list(sub_tasks),
                                            loop_flag=loop))
        try:
            return as_document(await self.tasks.step("start", task.id))
        except Conflict:
            running = [t for t in await self.tasks.tasks() if t.state in ("WORKING", "PAUSED")]
            if not running or any(t.name not in OWN_TASKS for t in running):
                await self.tasks.command("delete", task.id)
                raise
            for t in running:
                await self.tasks.step("stop", t.id)
            return as_document(await self.tasks.step("start", task.id))

    async def point(self, index: int) -> tuple[float, float, float]:
        """Nav point ``index`` of the current path (404 when it does not exist)."""
        try:
            return await self.nav.nav_point(index)
        except NavUnavailable as exc:
            raise self.core.presence.error("nav", str(exc)) from exc
        except PortError:  # NotFound: no such nav point
            raise
        except ValueError as exc:
            raise Conflict(str(exc)) from exc

    async def current_map(self) -> str:
        res = await self.link.call("map_server/current_map", zm.GetCurrentMapRequest())
        return str(res.name)

    def same_map(self, map_name: str, path: str, current: str) -> None:
        """A goal on the current map: make ``path`` the current path (a goal on another
        map is the callers' cross-map case; one that reaches here is a bug, a 400)."""
        if map_name and map_name != current:
            raise Refused(f"map {map_name!r} is not the current map {current!r}")
        if path and path != self.nav.path_name:
            self.nav.path_name = path

    def publish_initialpose(self, x: float, y: float, theta: float) -> None:
        msg = PoseWithCovarianceStamped(header=Header(frame_id="map"))
        msg.pose.pose = pose_stamped(x, y, theta).pose
        self.link.initialpose.publish(msg)
