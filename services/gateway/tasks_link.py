"""`TasksLink`: calls the tasks service's ``tasks/<call>`` services (zenros_msgs/TaskCall)."""

from __future__ import annotations

from zenros.errors import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.msgs.zenros_msgs.tasks import TaskCall, TaskCallRequest
from zenros.node import Node
from zenros.rpc import Client

__all__ = ["TasksLink"]


class TasksLink:
    """``await link(name, id, body)`` → (HTTP code, message, JSON body text)."""

    def __init__(self, node: Node, timeout: float = 10.0) -> None:
        self.node = node
        self.timeout = timeout
        self._clients: dict[str, Client] = {}

    def _client(self, name: str) -> Client:
        client = self._clients.get(name)
        if client is None:
            client = self._clients[name] = self.node.create_client(TaskCall, f"tasks/{name}")
        return client

    async def __call__(self, name: str, ident: str, body: str) -> tuple[int, str, str]:
        client = self._client(name)
        try:
            res = await client.call_async(TaskCallRequest(id=ident, body=body), self.timeout)
        except ServiceUnavailableError:
            return 503, f"the tasks service is not running (no server for {client.name})", ""
        except ZenrosTimeout:
            return 504, f"the tasks service did not answer within {self.timeout:g} s", ""
        except ServiceError as exc:
            return 502, f"the tasks service failed: {exc}", ""
        return res.code, res.message, res.body
