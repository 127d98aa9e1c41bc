"""`FoxgloveNode`: the Foxglove server as a node of its own (wiring only)."""

from __future__ import annotations

from typing import Any

from zenros import Node
from zenros.errors import StartupError

__all__ = ["DEFAULT_PORT", "FoxgloveNode"]

DEFAULT_PORT = 8765


class FoxgloveNode(Node):
    """The live zenros graph for Foxglove on ws://<host>:<port> (needs zenros[foxglove])."""

    node_name = "foxglove"

    def setup(self) -> None:
        host = str(self.declare_parameter("host", "127.0.0.1", description="address to bind",
                                          read_only=True))
        port = int(self.declare_parameter("port", DEFAULT_PORT,
                                          description="TCP port (0: any free one)",
                                          read_only=True))
        try:
            from .bridge import FoxgloveBridge
        except ImportError as exc:
            raise StartupError("foxglove-sdk is not installed (pip install 'zenros[foxglove]'): "
                               f"{exc}") from exc
        self.bridge: Any = FoxgloveBridge(self, host, port)
        self.on_close(self.bridge.stop)
        self.bridge.start()
