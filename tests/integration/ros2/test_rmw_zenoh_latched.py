"""Transient local (latched) topics between zenros and rmw_zenoh, both ways, through the
bridge: the sample is published before the subscriber on the other side exists, and reaches
it from the publisher's cache (rmw_zenoh_cpp 0.6: an advanced publisher with a cache of
``depth`` samples and publisher detection; an advanced subscriber with history)."""

from __future__ import annotations

import logging
from typing import Any

import pytest
from zenros.context import Context
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.services.rmw_zenoh.bridge import RmwZenohBridge
from zenros.testing import Collector, wait_for

sdk = pytest.importorskip("zenoh_ros2_sdk", reason="zenoh-ros2-sdk not installed (extra ros2)")
pytest.importorskip("rclpy", reason="ROS 2 wheels not installed (extra ros2)")

from rmw_peer import RmwPeer
from rosref import ros_class
from zenoh_ros2_sdk.qos import QosDurability, QosProfile

SDK_ATTEMPTS = 2


@pytest.fixture
def rig(make_rmw_rig: Any) -> tuple[Node, RmwZenohBridge, RmwPeer, Context]:
    rig: tuple[Node, RmwZenohBridge, RmwPeer, Context] = make_rmw_rig("zen_latched")
    return rig


def test_latched_zenros_topic_reaches_late_rmw_zenoh_subscribers(
        rig: tuple[Node, RmwZenohBridge, RmwPeer, Context], router: str,
        caplog: pytest.LogCaptureFixture) -> None:
    node, bridge, peer, _ = rig
    pub = node.create_publisher(String, "/latched_map", QOS_LATCHED)
    pub.publish(String(data="the map"))  # before the bridge has a route, before any subscriber
    assert wait_for(lambda: "/latched_map" in bridge.outbound, 10)
    # the rmw_zenoh peer (an advanced subscriber with history, as rmw_zenoh_cpp declares one)
    got: Collector[Any] = Collector()
    peer.subscribe("/latched_map", "std_msgs/msg/String", got, latched=True, depth=1)
    assert wait_for(lambda: len(got) >= 1, 10)
    assert got.items[0].data == "the map"
    # zenoh-ros2-sdk's transient-local subscriber. It asks for history once, while it is made:
    # a liveliness query for the topic's publishers, then a query of each one's cache, each
    # with a 2 s timeout, and never again. On a loaded box that one window can close before
    # an answer comes (the suite's only failure in two full runs, 2026-12-03 and -04), so a
    # subscriber that got nothing is made again, as its user would: the bridge's cache must
    # answer a late subscriber, whichever attempt asks. Its debug log says which step failed.
    caplog.set_level(logging.DEBUG, logger="zenoh_ros2_sdk")
    port = int(router.rsplit(":", 1)[1])
    got2: Collector[Any] = Collector()
    for _ in range(SDK_ATTEMPTS):
        sub = sdk.ROS2Subscriber("/latched_map", "std_msgs/msg/String", got2,
                                 msg_definition="string data", domain_id=peer.domain,
                                 router_port=port,
                                 qos=QosProfile(durability=QosDurability.TRANSIENT_LOCAL,
                                                history_depth=1))
        try:
            if wait_for(lambda: len(got2) >= 1, 10):
                break
        finally:
            sub.close()
    assert got2.items, f"no history in {SDK_ATTEMPTS} subscribers; the SDK said: {caplog.text}"
    assert got2.items[0].data == "the map"
    assert len(got) == 1  # history once, nothing repeated


def test_latched_rmw_zenoh_topic_reaches_a_late_zenros_subscriber(
        rig: tuple[Node, RmwZenohBridge, RmwPeer, Context]) -> None:
    node, bridge, peer, ctx = rig
    pub = peer.publisher("/ros_latched", "std_msgs/msg/String", latched=True, depth=1)
    pub.publish(ros_class("std_msgs/msg/String")(data="old news"))  # before the bridge routes
    assert wait_for(lambda: bridge.inbound, 10)
    # the bridge republishes it latched: a zenros subscriber that comes later still gets it
    assert wait_for(lambda: any(t.qos.startswith("rel+tl") for t in
                                ctx.graph.publishers("/ros_latched")), 10)
    got: Collector[String] = Collector()
    node.create_subscription(String, "/ros_latched", got, QOS_LATCHED)
    assert wait_for(lambda: len(got) >= 1, 10)
    assert got.items == [String(data="old news")]
