"""`FoxgloveNode`: the Foxglove server as a node of its own (wiring only)."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from msgspec import Meta
from zenros import Node
from zenros.errors import StartupError

__all__ = ["DEFAULT_PORT", "FoxgloveNode", "FoxgloveParameters"]

DEFAULT_PORT = 8765


class FoxgloveParameters(msgspec.Struct, kw_only=True):
    """The Foxglove node's parameters, read-only (read once, at start)."""

    host: Annotated[str, Meta(description="address to bind")] = "127.0.0.1"
    port: Annotated[int, Meta(ge=0, le=65535, description="TCP port (0: any free one)")] = \
        DEFAULT_PORT


class FoxgloveNode(Node):
    """The live zenros graph for Foxglove on ws://<host>:<port> (needs zenros[foxglove])."""

    node_name = "foxglove"

    def setup(self) -> None:
        p = self.declare_parameters(FoxgloveParameters, read_only=True)
        try:
            from .bridge import FoxgloveBridge
        except ImportError as exc:
            raise StartupError("foxglove-sdk is not installed (pip install 'zenros[foxglove]'): "
                               f"{exc}") from exc
        self.bridge: Any = FoxgloveBridge(self, p.host, p.port)
        self.on_close(self.bridge.stop)
        self.bridge.start()
