"""`BridgeHost`: what the bridge's routes and mirror (actions.py, graph_mirror.py,
service_in.py) use of the `bridge.RmwZenohBridge` that makes them, as a protocol, so they
import no module above them (as `zenros.action.host.ActionHost` does for the action server
and client)."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Protocol

import zenoh
from zenros.log import LogOnce
from zenros.owner import Owner
from zenros.ros2.rmw_zenoh import Entity, EntityKind, Qos

__all__ = ["BridgeHost"]


class BridgeHost(Owner, Protocol):
    """The rmw_zenoh bridge node as its helpers see it."""

    session: zenoh.Session
    domain: int
    zid: str
    call_timeout: float
    result_timeout: float
    pool: ThreadPoolExecutor
    problems: LogOnce

    def wanted(self, name: str) -> bool:
        """Whether the bridge carries ``name`` (its name filter)."""
        ...

    def entity(self, kind: EntityKind, name: str, ros_type: str, qos: Qos) -> Entity:
        """An rmw_zenoh entity of the bridge's node (its liveliness token's fields)."""
        ...
