"""rosbridge v2 for roslibpy and roslibjs: topics, services, actions and rosapi over the zenros
graph, on a WebSocket (port 9090 by default); see docs/rosbridge.md."""

from .bridge import qos_for_publishers
from .convert import encode_message, message_from_json
from .server import DEFAULT_PORT, RosbridgeServer

# the server, and what the foxglove door shares with it (JSON conversion, subscription QoS)
__all__ = ["DEFAULT_PORT", "RosbridgeServer", "encode_message", "message_from_json",
           "qos_for_publishers"]
