"""A zenros node's parameters driven from ROS 2 through the rmw_zenoh bridge, as rclpy's
parameter client and `ros2 param` on rmw_zenoh do: an rmw_zenoh client (`rmw_peer.RmwPeer`:
rmw_zenoh's keys and tokens, the wheels' hashes, rclpy's CDR and rcl_interfaces classes)
lists, describes (a range with its step), gets and sets (a refusal with its reason) a zenros
node's parameters, and an rmw_zenoh subscription gets its /parameter_events."""

from __future__ import annotations

from typing import Any

import pytest
from zenros.msgs.rcl_interfaces import FloatingPointRange, ParameterDescriptor
from zenros.testing import Collector, wait_for

pytest.importorskip("rclpy", reason="ROS 2 wheels not installed (extra ros2)")
pytest.importorskip("rcl_interfaces", reason="ROS 2 wheels not installed (extra ros2)")

import rmw_peer  # noqa: F401  (puts rosref, tests/unit/ros2, on the path)
from rosref import ros_class

SRV = "rcl_interfaces/srv"
SERVICES = ("list_parameters", "describe_parameters", "get_parameters", "set_parameters")


def test_ros2_client_reads_and_sets_a_zenros_nodes_parameters(make_rmw_rig: Any) -> None:
    node, bridge, peer, _ = make_rmw_rig("tuned")
    events: Collector[Any] = Collector()
    peer.subscribe("/parameter_events", "rcl_interfaces/msg/ParameterEvent", events,
                   depth=1000)
    for name in SERVICES:
        assert wait_for(lambda n=name: f"/tuned/{n}" in bridge.services, 10)
    node.declare_parameter("gain", 0.5, ParameterDescriptor(
        description="controller gain",
        floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0, step=0.25)]))

    def call(service: str, srv: str, **fields: Any) -> Any:
        client = peer.client(f"/tuned/{service}", f"{SRV}/{srv}")
        resp, sent, got = client.call(ros_class(f"{SRV}/{srv}_Request")(**fields),
                                      f"{SRV}/{srv}_Response")
        assert got.sequence_id == sent.sequence_id
        return resp

    names = call("list_parameters", "ListParameters").result.names
    assert {"gain", "use_sim_time"} <= set(names)
    (desc,) = call("describe_parameters", "DescribeParameters", names=["gain"]).descriptors
    r = desc.floating_point_range[0]
    assert (desc.description, r.from_value, r.to_value, r.step) == \
        ("controller gain", 0.0, 1.0, 0.25)
    value = ros_class("rcl_interfaces/msg/ParameterValue")
    param = ros_class("rcl_interfaces/msg/Parameter")
    results = call("set_parameters", "SetParameters", parameters=[
        param(name="gain", value=value(type=3, double_value=0.75)),
        param(name="gain", value=value(type=3, double_value=0.8)),
        param(name="gain", value=value(type=4, string_value="high"))]).results
    assert [r.successful for r in results] == [True, False, False]
    assert "in steps of 0.25" in results[1].reason and "is float" in results[2].reason
    (got,) = call("get_parameters", "GetParameters", names=["gain"]).values
    assert (got.type, got.double_value) == (3, 0.75)
    assert wait_for(lambda: any(
        e.node == "/tuned" and [p.name for p in e.changed_parameters] == ["gain"]
        for e in events.items), 10)
    changed = next(e for e in events.items if e.node == "/tuned" and e.changed_parameters)
    assert changed.changed_parameters[0].value.double_value == 0.75
