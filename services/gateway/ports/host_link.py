"""`HostLink`: the robot's host, as the gateway may act on it: the launch that supervises the
robot's services (`zenros.launch.control`), restarted or shut down through its
``<control>/restart`` and ``<control>/shutdown`` services (std_srvs/Trigger)."""

from __future__ import annotations

from zenros.msgs.std_srvs import Trigger, TriggerRequest, TriggerResponse
from zenros.node import Node
from zenros.rpc import Client

from ..errors import Conflict, Unavailable
from .calls import Lazy, call_port

__all__ = ["HostLink"]


class HostLink:
    """Calls on the launch at ``control`` (absolute: ``/launch`` unless the gateway's
    ``launch_control`` parameter says otherwise)."""

    def __init__(self, node: Node, control: str, timeout: float = 10.0) -> None:
        self.control = control.rstrip("/") or "/launch"
        self.timeout = timeout
        self._restart = Lazy(lambda: node.create_client(Trigger, f"{self.control}/restart"))
        self._shutdown = Lazy(lambda: node.create_client(Trigger, f"{self.control}/shutdown"))

    async def restart(self) -> str:
        """Ask the launch to restart every process (the gateway's too); its message."""
        return await self._call(self._restart.get(), "restart")

    async def shutdown(self) -> str:
        """Ask the launch to stop every process (and run its shutdown command)."""
        return await self._call(self._shutdown.get(), "shut down")

    async def _call(self, client: Client[TriggerRequest, TriggerResponse], what: str) -> str:
        res = await call_port(client, TriggerRequest(), self.timeout, lambda: Unavailable(
            f"no launch to {what}: {client.name} is not in the graph (start the robot with "
            "`zenros launch`, whose --control names these services)"))
        if not res.success:
            raise Conflict(f"the launch refused to {what}: {res.message}")
        return str(res.message)
