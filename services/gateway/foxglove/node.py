"""`FoxgloveNode`: the Foxglove server as a node of its own (wiring only)."""

from __future__ import annotations

from zenros import Node

from .bridge import DEFAULT_PORT, FoxgloveBridge

__all__ = ["FoxgloveNode"]


class FoxgloveNode(Node):
    """The live zenros graph for Foxglove on ws://<host>:<port> (needs zenros[foxglove])."""

    node_name = "foxglove"

    def setup(self) -> None:
        host = str(self.declare_parameter("host", "127.0.0.1", description="address to bind",
                                          read_only=True))
        port = int(self.declare_parameter("port", DEFAULT_PORT,
                                          description="TCP port (0: any free one)",
                                          read_only=True))
        self.bridge = FoxgloveBridge(self, host, port)
        self.bridge.start()

    def close(self) -> None:
        bridge = getattr(self, "bridge", None)
        if bridge is not None:
            bridge.stop()
        super().close()
