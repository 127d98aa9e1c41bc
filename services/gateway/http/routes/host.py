"""REST ``/system/restart_robot`` and ``/system/shutdown`` (docs/robot-api.md §3.3): the
robot's software restarted, or stopped, for real, by the launch that supervises it (the
gateway's `HostLink`). Each answers ``{"result": true}`` once the launch has taken the
request; the launch acts a second later, so the answer reaches the client before the gateway
itself stops."""

from __future__ import annotations

from ...ports.host_link import HostLink
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_host_routes"]


def _host(call: Call[None, None]) -> HostLink:
    host = call.ctx.host
    if host is None:
        raise ApiError(501, "this gateway has no robot host to act on")
    return host


async def restart_robot(call: Call[None, None]) -> Answer:
    """Restart the robot's services (every process of its launch, this gateway included)."""
    await _host(call).restart()
    return {"result": True}


async def shutdown(call: Call[None, None]) -> Answer:
    """Stop the robot's services (and power the robot off where the launch was given an
    ``--on-shutdown`` command)."""
    await _host(call).shutdown()
    return {"result": True}


def add_host_routes(api: Api) -> None:
    """Route the host's operations."""
    api.add("GET", "/system/restart_robot", restart_robot)
    api.add("GET", "/system/shutdown", shutdown)
