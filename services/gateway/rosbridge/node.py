"""`RosbridgeNode`: the rosbridge server as a node of its own (wiring only)."""

from __future__ import annotations

from zenros import Node

from .server import DEFAULT_PORT, RosbridgeServer

__all__ = ["RosbridgeNode"]


class RosbridgeNode(Node):
    """rosbridge v2 on ws://<host>:<port>/ for the zenros graph (roslibpy, roslibjs)."""

    node_name = "rosbridge"

    def setup(self) -> None:
        host = str(self.declare_parameter("host", "127.0.0.1",
                                          description="address to bind", read_only=True))
        port = int(self.declare_parameter("port", DEFAULT_PORT,
                                          description="TCP port (0: any free one)",
                                          read_only=True))
        self.server = RosbridgeServer(self, host, port)
        self.on_close(self.server.stop_in_thread)
        self.server.start_in_thread()
