"""`RosbridgeNode`: the rosbridge server as a node of its own (wiring only)."""

from __future__ import annotations

from typing import Annotated

import msgspec
from msgspec import Meta
from zenros import Node

from .server import DEFAULT_PORT, RosbridgeServer

__all__ = ["RosbridgeNode", "RosbridgeParameters"]


class RosbridgeParameters(msgspec.Struct, kw_only=True):
    """The rosbridge node's parameters, read-only (read once, at start)."""

    host: Annotated[str, Meta(description="address to bind")] = "127.0.0.1"
    port: Annotated[int, Meta(ge=0, le=65535, description="TCP port (0: any free one)")] = \
        DEFAULT_PORT


class RosbridgeNode(Node):
    """rosbridge v2 on ws://<host>:<port>/ for the zenros graph (roslibpy, roslibjs)."""

    node_name = "rosbridge"

    def setup(self) -> None:
        p = self.declare_parameters(RosbridgeParameters, read_only=True)
        self.server = RosbridgeServer(self, p.host, p.port)
        self.on_close(self.server.stop_in_thread)
        self.server.start_in_thread()
