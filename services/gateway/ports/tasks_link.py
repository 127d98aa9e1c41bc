"""`TasksLink`: the tasks service's ``tasks/<call>`` services, typed (zenros_msgs.tasks).

Each call returns the documents as Structs (`Task`, `Action`); a refusal of the service is
the port error of its `ResultCode`, the service missing, slow or failing `Unavailable`,
`NoAnswer` or `Failed`.
"""

from __future__ import annotations

from typing import Any

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.message import Message
from zenros.msgs.zenros_msgs import tasks as tm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.task_actions import Action
from zenros.msgs.zenros_msgs.task_docs import Task, TaskUpdate
from zenros.node import Node
from zenros.rpc import Client

from ..errors import Failed, NoAnswer, port_error
from ..state.presence import Presence

__all__ = ["TasksLink"]


class TasksLink:
    """The tasks service's calls; ``await link.start(id)`` → the started `Task`."""

    def __init__(self, node: Node, presence: Presence, timeout: float = 10.0) -> None:
        self.node = node
        self.presence = presence
        self.timeout = timeout
        self._clients: dict[str, Client] = {}

    def _client(self, name: str) -> Client:
        client = self._clients.get(name)
        if client is None:
            client = self._clients[name] = self.node.create_client(
                tm.TASK_SERVICES[name], f"tasks/{name}")
        return client

    def available(self) -> bool:
        """Whether the tasks service serves (its ``tasks/get``)."""
        return self._client("get").service_is_ready()

    async def call(self, name: str, request: Message) -> Any:
        """Call ``tasks/<name>``; its response when the code is OK, else a port error."""
        client = self._client(name)
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

    async def _task(self, name: str, request: Message) -> Task:
        task: Task | None = (await self.call(name, request)).task
        if task is None:
            raise Failed(f"tasks/{name} answered no task")
        return task

    async def tasks(self, ident: str = "") -> list[Task]:
        """Every task, or (``ident``) the one with that id."""
        out: list[Task] = (await self.call("get", tm.GetTasksRequest(id=ident))).tasks
        return out

    async def get(self, ident: str) -> Task:
        found = await self.tasks(ident)
        if not found:
            raise Failed(f"tasks/get answered no task {ident!r}")
        return found[0]

    async def create(self, task: Task) -> Task:
        return await self._task("create", tm.CreateTaskRequest(task=task))

    async def update(self, update: TaskUpdate) -> Task:
        return await self._task("update", tm.UpdateTaskRequest(update=update))

    async def step(self, name: str, ident: str = "") -> Task:
        """``start``, ``pause``, ``resume`` or ``stop`` (no ``ident``: the running task)."""
        return await self._task(name, tm.TaskCommandRequest(id=ident))

    async def command(self, name: str, ident: str = "") -> None:
        """``delete``, ``delete_action`` or ``update_wait_req``: they answer no document."""
        await self.call(name, tm.TaskCommandRequest(id=ident))

    async def loop(self, ident: str, flag: bool) -> Task:
        return await self._task("loop", tm.SetTaskLoopRequest(id=ident, loop_flag=flag))

    async def create_action(self, task_id: str | None, action: Action) -> Task:
        """Add ``action`` to task ``task_id``, or (None) to a new task "auto task"."""
        return await self._task("create_action",
                                tm.CreateActionRequest(task_id=task_id, action=action))

    async def actions(self, ident: str = "") -> list[Action]:
        """Every action of every task, or (``ident``) the one with that id."""
        out: list[Action] = (await self.call("get_action",
                                             tm.GetActionsRequest(id=ident))).actions
        return out

    async def update_action(self, ident: str, changes: dict[str, Any]) -> Action:
        action: Action | None = (await self.call("update_action", tm.UpdateActionRequest(
            id=ident, changes=changes))).action
        if action is None:
            raise Failed("tasks/update_action answered no action")
        return action
