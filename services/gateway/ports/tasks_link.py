"""`TasksLink`: the tasks service's ``tasks/<call>`` services, typed (zenros_msgs.tasks).

Each call returns the documents as Structs (`Task`, `Action`); a refusal of the service is
the port error of its `ResultCode`, the service missing, slow or failing `Unavailable`,
`NoAnswer` or `Failed`. `run_task` is how a REST goal becomes a task.
"""

from __future__ import annotations

from typing import Any, TypeVar

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.message import Q, ServiceType
from zenros.msgs.zenros_msgs import tasks as tm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.task_actions import Action
from zenros.msgs.zenros_msgs.task_docs import Task, TaskUpdate, as_document
from zenros.node import Node
from zenros.rpc import Client

from ..errors import Conflict, Failed, NoAnswer, port_error
from ..state.presence import Presence

__all__ = ["OWN_TASKS", "TasksLink"]

OWN_TASKS = frozenset({"navigation task", "loop task", "charge task", "local move task"})
"""The tasks the gateway's goals make: a new goal replaces a running one of these."""


C = TypeVar("C", tm.TaskResponse, tm.GetTasksResponse, tm.GetActionsResponse,
            tm.UpdateActionResponse)
"""A tasks service's response: each carries its `ResultCode` and a refusal's reason."""


class TasksLink:
    """The tasks service's calls; ``await link.start(id)`` → the started `Task`."""

    def __init__(self, node: Node, presence: Presence, timeout: float = 10.0) -> None:
        self.node = node
        self.presence = presence
        self.timeout = timeout
        self._clients: dict[str, Client[Any, Any]] = {}

    def _client(self, srv: ServiceType[Q, C], name: str) -> Client[Q, C]:
        client: Client[Q, C] | None = self._clients.get(name)
        if client is None:
            if tm.TASK_SERVICES[name] is not srv:
                raise TypeError(f"tasks/{name} is a {tm.TASK_SERVICES[name].name}, "
                                f"not a {srv.name}")
            client = self._clients[name] = self.node.create_client(srv, f"tasks/{name}")
        return client

    def available(self) -> bool:
        """Whether the tasks service serves (its ``tasks/get``)."""
        return self._client(tm.GetTasks, "get").service_is_ready()

    async def call(self, srv: ServiceType[Q, C], name: str, request: Q) -> C:
        """Call ``tasks/<name>`` (of type ``srv``: several names share `TaskCommand`); its
        response when the code is OK, else a port error."""
        client = self._client(srv, name)
        try:
            res = await client.call_async(request, self.timeout)
        except ServiceUnavailableError:
            raise self.presence.error("tasks", f"no server for {client.name}") from None
        except ZenrosTimeout:
            raise NoAnswer(f"the tasks service did not answer within "
                           f"{self.timeout:g} s") from None
        except ServiceError as exc:
            raise Failed(f"the tasks service failed: {exc}") from exc
        if res.code != ResultCode.OK:
            raise port_error(res.code, res.message or f"tasks/{name} failed ({res.code})")
        return res

    async def _task(self, srv: ServiceType[Q, tm.TaskResponse], name: str, request: Q) -> Task:
        task = (await self.call(srv, name, request)).task
        if task is None:
            raise Failed(f"tasks/{name} answered no task")
        return task

    async def tasks(self, ident: str = "") -> list[Task]:
        """Every task, or (``ident``) the one with that id."""
        return (await self.call(tm.GetTasks, "get", tm.GetTasksRequest(id=ident))).tasks

    async def get(self, ident: str) -> Task:
        found = await self.tasks(ident)
        if not found:
            raise Failed(f"tasks/get answered no task {ident!r}")
        return found[0]

    async def create(self, task: Task) -> Task:
        return await self._task(tm.CreateTask, "create", tm.CreateTaskRequest(task=task))

    async def update(self, update: TaskUpdate) -> Task:
        return await self._task(tm.UpdateTask, "update", tm.UpdateTaskRequest(update=update))

    async def step(self, name: str, ident: str = "") -> Task:
        """``start``, ``pause``, ``resume`` or ``stop`` (no ``ident``: the running task)."""
        return await self._task(tm.TaskCommand, name, tm.TaskCommandRequest(id=ident))

    async def command(self, name: str, ident: str = "") -> None:
        """``delete``, ``delete_action`` or ``update_wait_req``: they answer no document."""
        await self.call(tm.TaskCommand, name, tm.TaskCommandRequest(id=ident))

    async def loop(self, ident: str, flag: bool) -> Task:
        return await self._task(tm.SetTaskLoop, "loop",
                                tm.SetTaskLoopRequest(id=ident, loop_flag=flag))

    async def create_action(self, task_id: str | None, action: Action) -> Task:
        """Add ``action`` to task ``task_id``, or (None) to a new task "auto task"."""
        return await self._task(tm.CreateAction, "create_action",
                                tm.CreateActionRequest(task_id=task_id, action=action))

    async def actions(self, ident: str = "") -> list[Action]:
        """Every action of every task, or (``ident``) the one with that id."""
        return (await self.call(tm.GetActions, "get_action",
                                tm.GetActionsRequest(id=ident))).actions

    async def update_action(self, ident: str, changes: dict[str, Any]) -> Action:
        action = (await self.call(tm.UpdateAction, "update_action", tm.UpdateActionRequest(
            id=ident, changes=changes))).action
        if action is None:
            raise Failed("tasks/update_action answered no action")
        return action

    async def run_task(self, name: str, sub_tasks: list[Action], loop: bool = False,
                       replaces: frozenset[str] = OWN_TASKS) -> dict[str, Any]:
        """Create and start a task; a running task named in ``replaces`` (by default the
        gateway's goals: a new goal replaces the old one) gives way to it, any other running
        task is a 409. Returns the started task's document."""
        task = await self.create(Task(name=name, sub_tasks=list(sub_tasks), loop_flag=loop))
        try:
            return as_document(await self.step("start", task.id))
        except Conflict:
            running = [t for t in await self.tasks() if t.state in ("WORKING", "PAUSED")]
            if not running or any(t.name not in replaces for t in running):
                await self.command("delete", task.id)
                raise
            for t in running:
                await self.step("stop", t.id)
            return as_document(await self.step("start", task.id))
