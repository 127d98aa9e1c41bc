"""`BridgeHost`: what the bridge's helpers (actionlib.py, tf_republisher.py) use of the
`bridge.Bridge` that makes them, as a protocol, so they import no module above them (as
`zenros.action.host.ActionHost` does for the action server and client)."""

from __future__ import annotations

import asyncio
from typing import Any, Protocol

from zenros.message import ActionType
from zenros.node import Node

from .opaque import OpaqueTopics

__all__ = ["BridgeHost"]


class BridgeHost(Protocol):
    """The bridge as its helpers see it: its node, its loop, the unchecked topics, the
    background tasks it keeps and its shared action clients."""

    node: Node
    loop: asyncio.AbstractEventLoop
    opaque: OpaqueTopics
    background: set[asyncio.Task[Any]]

    def action_client(self, action_type: ActionType, name: str) -> Any: ...
