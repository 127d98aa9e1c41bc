"""`TasksLink`: calls the tasks service's ``tasks/<call>`` services (zenros_msgs/TaskCall)."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from typing import NamedTuple

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.msgs.zenros_msgs.tasks import TaskCall, TaskCallRequest
from zenros.node import Node
from zenros.rpc import Client

from ..errors import TaskError
from ..state.presence import Presence

__all__ = ["TaskCaller", "TaskReply", "TasksLink"]


class TaskReply(NamedTuple):
    """What a tasks call answered: HTTP code, message, JSON body text, and (a 503 while the
    tasks service is starting) the seconds after which to retry."""

    code: int
    message: str
    body: str
    retry_after: int | None = None

    def error(self, name: str) -> TaskError:
        return TaskError(self.code, self.message or f"tasks/{name} failed ({self.code})",
                         self.retry_after)


# name, id, JSON body text -> TaskReply
TaskCaller = Callable[[str, str, str], Awaitable[TaskReply]]


class TasksLink:
    """``await link(name, id, body)`` → `TaskReply` (HTTP code, message, JSON body text)."""

    def __init__(self, node: Node, presence: Presence, timeout: float = 10.0) -> None:
        self.node = node
        self.presence = presence
        self.timeout = timeout
        self._clients: dict[str, Client] = {}

    def _client(self, name: str) -> Client:
        client = self._clients.get(name)
        if client is None:
            client = self._clients[name] = self.node.create_client(TaskCall, f"tasks/{name}")
        return client

    def available(self) -> bool:
        """Whether the tasks service serves (its ``tasks/get``)."""
        return self._client("get").service_is_ready()

    async def __call__(self, name: str, ident: str, body: str) -> TaskReply:
        client = self._client(name)
        try:
            res = await client.call_async(TaskCallRequest(id=ident, body=body), self.timeout)
        except ServiceUnavailableError:
            err = self.presence.error("tasks", f"no server for {client.name}")
            return TaskReply(503, err.detail, "", err.retry_after)
        except ZenrosTimeout:
            return TaskReply(504, f"the tasks service did not answer within "
                                  f"{self.timeout:g} s", "")
        except ServiceError as exc:
            return TaskReply(502, f"the tasks service failed: {exc}", "")
        return TaskReply(res.code, res.message, res.body)
