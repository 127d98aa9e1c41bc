"""Foxglove over foxglove-sdk: channels advertised from the graph with JSON schemas named as
the ROS types, messages streamed to a subscribed client, client publishing into zenros.

Skipped when the optional extra (``pip install zenros[foxglove]``) is not installed.
"""

from __future__ import annotations

import json
import socket
import struct
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from websockets.sync.client import connect
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.sensor_msgs import LaserScan
from zenros.node import Node
from zenros.testing import Collector, wait_for

pytest.importorskip("foxglove", reason="foxglove-sdk not installed (pip install zenros[foxglove])")

from zenros.services.gateway.foxglove.bridge import FoxgloveBridge

TIMEOUT = 10.0
SUBPROTOCOL = "foxglove.sdk.v1"


@pytest.fixture
def bridge(ctx_pair: list[Context]) -> Iterator[FoxgloveBridge]:
    node = Node("foxglove", context=ctx_pair[0])
    b = FoxgloveBridge(node, port=0)
    b.start()
    yield b
    b.stop()
    node.close()


@pytest.fixture
def robot(ctx_pair: list[Context]) -> Iterator[Node]:
    node = Node("robot", context=ctx_pair[1])
    yield node
    node.close()


def json_frames(ws: Any, op: str, timeout: float = TIMEOUT) -> dict[str, Any]:
    """The next JSON frame with ``op`` (binary frames in between are skipped)."""
    while True:
        data = ws.recv(timeout)
        if isinstance(data, str):
            frame: dict[str, Any] = json.loads(data)
            if frame["op"] == op:
                return frame


def channel_for(ws: Any, topic: str) -> dict[str, Any]:
    while True:
        for ch in json_frames(ws, "advertise")["channels"]:
            if ch["topic"] == topic:
                return ch


def test_scan_channel_is_advertised_and_streams(bridge: FoxgloveBridge, robot: Node) -> None:
    pub = robot.create_publisher(LaserScan, "/scan")
    assert wait_for(lambda: "/scan" in bridge.channels, TIMEOUT)
    with connect(f"ws://127.0.0.1:{bridge.port}", subprotocols=[SUBPROTOCOL],  # type: ignore[list-item]
                 open_timeout=TIMEOUT) as ws:
        assert ws.subprotocol == SUBPROTOCOL
        info = json_frames(ws, "serverInfo")
        assert "clientPublish" in info["capabilities"]
        ch = channel_for(ws, "/scan")
        assert ch["schemaName"] == "sensor_msgs/msg/LaserScan"
        assert ch["encoding"] == "json" and ch["schemaEncoding"] == "jsonschema"
        schema = json.loads(ch["schema"])
        ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 7, "channelId": ch["id"]}]}))
        assert pub.wait_for_subscribers(1, TIMEOUT)
        scan = LaserScan(angle_min=-1.0, angle_max=1.0, ranges=[1.0, 2.0, 3.0])
        scan.header.frame_id = "laser"
        got: dict[str, Any] = {}

        def arrived() -> bool:
            pub.publish(scan)
            try:
                data = ws.recv(0.2)
            except TimeoutError:
                return False
            if isinstance(data, bytes) and data[0] == 0x01:
                sub_id, _ts = struct.unpack_from("<IQ", data, 1)
                got.update(sub=sub_id, msg=json.loads(data[13:]))
                return True
            return False

        assert wait_for(arrived, TIMEOUT)
        assert got["sub"] == 7
        assert got["msg"]["ranges"] == [1.0, 2.0, 3.0]
        assert got["msg"]["header"]["frame_id"] == "laser"
        jsonschema.validate(got["msg"], schema)


def test_client_publishes_into_zenros(bridge: FoxgloveBridge, robot: Node) -> None:
    got: Collector[Twist] = Collector()
    robot.create_subscription(Twist, "/cmd_vel", got)
    with connect(f"ws://127.0.0.1:{bridge.port}", subprotocols=[SUBPROTOCOL],  # type: ignore[list-item]
                 open_timeout=TIMEOUT) as ws:
        json_frames(ws, "serverInfo")
        ws.send(json.dumps({"op": "advertise", "channels": [{
            "id": 3, "topic": "/cmd_vel", "encoding": "json",
            "schemaName": "geometry_msgs/msg/Twist"}]}))
        assert wait_for(lambda: robot.graph.publishers("/cmd_vel"), TIMEOUT)
        payload = json.dumps({"linear": {"x": 0.25}}).encode()
        assert wait_for(lambda: (ws.send(b"\x01" + struct.pack("<I", 3) + payload),
                                 got.wait(1, 0.1))[1], TIMEOUT)
        assert got.items[0].linear.x == 0.25


def test_vanished_topics_are_unadvertised(bridge: FoxgloveBridge, robot: Node) -> None:
    pub = robot.create_publisher(Twist, "/gone")
    assert wait_for(lambda: "/gone" in bridge.channels, TIMEOUT)
    robot.destroy(pub)
    assert wait_for(lambda: "/gone" not in bridge.channels, TIMEOUT)


def test_the_gateway_serves_foxglove(ctx_pair: list[Context], tmp_path: Path,
                                     robot: Node) -> None:
    from zenros.services.gateway.testing import running_gateway

    robot.create_publisher(LaserScan, "/scan")
    with running_gateway(ctx_pair[0], tmp_path, foxglove_port=0) as gateway:
        assert gateway.foxglove is not None
        assert wait_for(lambda: "/scan" in gateway.foxglove.channels, TIMEOUT)
        with connect(f"ws://127.0.0.1:{gateway.foxglove.port}",
                     subprotocols=[SUBPROTOCOL],  # type: ignore[list-item]
                     open_timeout=TIMEOUT) as ws:
            assert json_frames(ws, "serverInfo")["name"] == "zenros /gateway"
            assert channel_for(ws, "/scan")["schemaName"] == "sensor_msgs/msg/LaserScan"


def test_a_taken_port_is_a_startup_error(ctx_pair: list[Context]) -> None:
    from zenros.errors import StartupError

    node = Node("foxglove2", context=ctx_pair[0])
    try:
        with socket.socket() as taken:
            taken.bind(("127.0.0.1", 0))
            taken.listen()
            with pytest.raises(StartupError, match="Address already in use"):
                FoxgloveBridge(node, port=taken.getsockname()[1]).start()
    finally:
        node.close()
