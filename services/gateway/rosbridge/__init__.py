"""rosbridge v2 for roslibpy and roslibjs: topics, services, actions and rosapi over the zenros
graph, on a WebSocket (port 9090 by default); see docs/rosbridge.md."""

from .server import DEFAULT_PORT, RosbridgeServer

__all__ = ["DEFAULT_PORT", "RosbridgeServer"]
