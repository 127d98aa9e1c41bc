"""The rmw_zenoh bridge against a live peer nobody here wrote: zenoh-ros2-sdk 0.1.8, an
independent Python implementation of rmw_zenoh's protocol, on one zenros router."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from zenros.context import Context
from zenros.msgs.std_msgs import String
from zenros.msgs.std_srvs import SetBool, SetBoolRequest, SetBoolResponse
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import Collector, wait_for

from zenros.services.rmw_zenoh.bridge import RmwZenohBridge

sdk = pytest.importorskip("zenoh_ros2_sdk", reason="zenoh-ros2-sdk not installed (extra ros2)")


@pytest.fixture
def bridged(router: str, prefix: str) -> Iterator[tuple[Node, RmwZenohBridge, int]]:
    """A zenros node and the bridge, each in its own session on the router; the router port."""
    port = int(router.rsplit(":", 1)[1])
    ctx_b = Context(SessionOptions(connect=[router]), prefix=prefix)
    ctx_n = Context(SessionOptions(connect=[router]), prefix=prefix)
    bridge = RmwZenohBridge(context=ctx_b, parameter_overrides={"domain_id": 7})
    node = Node("zen_talker", context=ctx_n)
    try:
        yield node, bridge, port
    finally:
        node.close()
        bridge.close()
        ctx_n.close()
        ctx_b.close()
        if sdk.ZenohSession._instance is not None:  # the SDK keeps one session per process
            sdk.ZenohSession._instance.close()


def _close_sdk(*objs: Any) -> None:
    for o in objs:
        o.close()


def test_zenros_topic_reaches_an_rmw_zenoh_subscriber(bridged: tuple[Node, RmwZenohBridge, int]) -> None:
    node, bridge, port = bridged
    pub = node.create_publisher(String, "/chatter")
    got: Collector[Any] = Collector()
    sub = sdk.ROS2Subscriber("/chatter", "std_msgs/msg/String", got, msg_definition="string data",
                             domain_id=7, router_port=port)
    try:
        assert wait_for(lambda: "/chatter" in bridge.outbound, 10)

        def sent() -> bool:
            pub.publish(String(data="hello ros"))
            return len(got) > 0
        assert wait_for(sent, 10, interval=0.1)
        assert got.items[0].data == "hello ros"
    finally:
        _close_sdk(sub)


def test_rmw_zenoh_publisher_reaches_a_zenros_subscriber(bridged: tuple[Node, RmwZenohBridge, int]) -> None:
    node, bridge, port = bridged
    got: Collector[String] = Collector()
    node.create_subscription(String, "/ros_chatter", got)
    pub = sdk.ROS2Publisher("/ros_chatter", "std_msgs/msg/String", msg_definition="string data",
                            domain_id=7, router_port=port)
    try:
        assert wait_for(lambda: bridge.inbound, 10)

        def sent() -> bool:
            pub.publish(data="from rmw_zenoh")
            return len(got) > 0
        assert wait_for(sent, 10, interval=0.1)
        assert got.items[0] == String(data="from rmw_zenoh")
        # the bridge is the topic's publisher in the zenros graph
        graph = node.context.graph
        assert wait_for(lambda: any(p.node == bridge.fqn for p in graph.publishers("/ros_chatter")), 5)
    finally:
        _close_sdk(pub)
    assert wait_for(lambda: not bridge.inbound, 10)  # the ROS 2 publisher left: so did the route


def test_rmw_zenoh_client_calls_a_zenros_service(bridged: tuple[Node, RmwZenohBridge, int]) -> None:
    node, bridge, port = bridged

    def handle(req: SetBoolRequest) -> SetBoolResponse:
        return SetBoolResponse(success=req.data, message=f"set to {req.data}")

    node.create_service(SetBool, "/set_flag", handle)
    assert wait_for(lambda: "/set_flag" in bridge.services, 10)
    client = sdk.ROS2ServiceClient("/set_flag", "std_srvs/srv/SetBool",
                                   request_definition="bool data",
                                   response_definition="bool success\nstring message",
                                   domain_id=7, router_port=port, timeout=10.0)
    try:
        resp = None
        for _ in range(3):
            resp = client.call(data=True)
            if resp is not None:
                break
        assert resp is not None
        assert resp.success is True and resp.message == "set to True"
    finally:
        _close_sdk(client)
