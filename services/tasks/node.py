"""`TasksNode`: wires the task manager to the ``tasks/*`` services and ``tasks/status``."""

from __future__ import annotations

import asyncio
import os
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import msgspec
from msgspec import Meta
from zenros.building import load_building
from zenros.home import data_dir
from zenros.launch.files import launch_dir
from zenros.message import Message
from zenros.msgs.zenros_msgs.task_docs import Task
from zenros.msgs.zenros_msgs.tasks import TaskStatus
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.smach import Container, IntrospectionServer

from .api import CALLS, call
from .documents import is_task, kind_of, snapshot
from .elevator_link import ElevatorLink
from .launcher import Launcher
from .local_link import LocalLink
from .manager import TaskManager
from .program_api import PROGRAM_CALLS, program_call
from .programs import ProgramStore
from .store import TaskStore

__all__ = ["DB_NAME", "TasksNode", "TasksParameters"]

DB_NAME = "tasks.db"


def _nothing() -> None:
    pass


class TasksParameters(msgspec.Struct, kw_only=True):
    """The tasks node's parameters."""

    data_dir: Annotated[str, Meta(description="where tasks.db lives (default $ZENROS_HOME "
                                              "or ~/.zenros)")] = ""
    resume_on_start: Annotated[bool, Meta(
        description="a task that was WORKING when the service stopped runs again at start "
                    "(false: it waits PAUSED for a resume)")] = False
    introspection: Annotated[bool, Meta(
        description="publish the running task's state machine for zenros smach")] = True
    reconnect_timeout: Annotated[float, Meta(
        ge=0, description="seconds a nav or dock goal waits for its server to come back (a "
                          "link flap, a respawn) before the action ends in ERROR; the goal "
                          "is then sent again")] = 30.0
    building: Annotated[str, Meta(
        description="a building file (docs/building.md): goals on another floor ride its "
                    "elevators ('' = none)")] = ""
    launch_dir: Annotated[str, Meta(
        description="the launch files roslaunch_action may start, by name ('' = those "
                    "zenros ships, deploy/launch)")] = ""


class TasksNode(Node):
    """The robot API's tasks and actions (docs/robot-api.md §8-§9) as a service.

    Parameters: `TasksParameters`.
    """

    node_name = "tasks"

    def setup(self) -> None:
        p = self.declare_parameters(TasksParameters)
        directory, resume = data_dir(p.data_dir), p.resume_on_start
        self.introspection = p.introspection
        self.smach_server: IntrospectionServer | None = None
        self.status_pub = self.create_publisher(TaskStatus, "tasks/status", QOS_LATCHED)
        self.store = self.own(TaskStore(directory / DB_NAME))
        self.link = LocalLink(self, p.reconnect_timeout)
        if p.building:
            self.link.elevators = ElevatorLink(self, load_building(
                os.path.expanduser(p.building)))
        self.link.launcher = self.own(Launcher(
            Path(p.launch_dir).expanduser() if p.launch_dir else launch_dir(),
            {**os.environ, "ZENROS_PREFIX": self.context.keys.prefix},
            directory / "logs" / "launches",
            lambda fqn: fqn in self.context.graph.node_names()))
        self.manager = self.own(TaskManager(self.store, self.link, self.publish_status,
                                            self.introspect if self.introspection else None,
                                            resume_on_start=resume))
        for task_id in self.manager.recovered:
            self.logger.warning("task %s was running when the service stopped: %s", task_id,
                                "resumed" if resume else "PAUSED until resumed")
        if self.store.bad_rows:
            self.logger.error("unreadable task rows skipped: %s", ", ".join(self.store.bad_rows))
        for name, entry in CALLS.items():
            self.create_service(entry.srv, f"tasks/{name}", self._handler(name))
        self.programs = self.own(ProgramStore(directory / DB_NAME))
        self.link.programs = self.programs
        for name, (srv, _) in PROGRAM_CALLS.items():
            self.create_service(srv, f"tasks/blockly/{name}", self._program_handler(name))
        self.logger.info("tasks in %s (%d stored)", self.store.path, len(self.manager.tasks()))

    def _handler(self, name: str) -> Callable[[Message], Any]:
        async def handle(req: Message) -> Message:
            return await asyncio.to_thread(call, self.manager, name, req)
        return handle

    def _program_handler(self, name: str) -> Callable[[Message], Any]:
        async def handle(req: Message) -> Message:
            return await asyncio.to_thread(program_call, self.programs, name, req)
        return handle

    def publish_status(self, doc: Task, event: str) -> None:
        current = doc.current_task
        self.status_pub.publish(TaskStatus(
            stamp=self.now(), id=doc.id, name=doc.name, state=doc.state,
            progress=float(doc.progress), loop_count=doc.loop_count,
            current_id="" if current is None else current.id,
            current_type="" if current is None or is_task(current) else kind_of(current),
            event=event, task=snapshot(doc)))

    def introspect(self, task_id: str, machine: Container) -> Callable[[], None]:
        """Show the running task's machine on ``~/smach`` (one server for every run; the
        last run stays visible with its final status)."""
        if self.smach_server is None:
            self.smach_server = IntrospectionServer(self, machine, "~/smach")
        else:
            self.smach_server.set_machine(machine)
        return _nothing
