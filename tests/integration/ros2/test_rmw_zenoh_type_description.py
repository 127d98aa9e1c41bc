"""A zenros node's ``~/get_type_description`` from ROS 2 through the rmw_zenoh bridge, as
`ros2` tools and rclpy ask it: an rmw_zenoh client (`rmw_peer.RmwPeer`, rclpy's CDR and the
wheels' type_description_interfaces classes) gets the description of a type the node uses,
and it is the one rosidl generated for the wheels (share/<pkg>/msg/<Name>.json), field for
field, nested types included."""

from __future__ import annotations

import json
from typing import Any

import pytest
from zenros.msgs.geometry_msgs import PoseStamped
from zenros.testing import wait_for

pytest.importorskip("rclpy", reason="ROS 2 wheels not installed (extra ros2)")
pytest.importorskip("type_description_interfaces", reason="ROS 2 wheels not installed")

import rmw_peer  # noqa: F401  (puts rosref, tests/unit/ros2, on the path)
from rosref import SHARE, ros_class, wheel_hash

SRV = "type_description_interfaces/srv/GetTypeDescription"


def _plain(d: Any) -> dict[str, Any]:
    return {"type_name": d.type_name, "fields": [
        {"name": f.name, "type": {"type_id": f.type.type_id, "capacity": f.type.capacity,
                                  "string_capacity": f.type.string_capacity,
                                  "nested_type_name": f.type.nested_type_name}}
        for f in d.fields]}


def _without_defaults(d: dict[str, Any]) -> dict[str, Any]:
    return {"type_name": d["type_name"], "fields": [
        {"name": f["name"], "type": f["type"]} for f in d["fields"]]}


def test_ros2_client_gets_the_description_rosidl_generates(make_rmw_rig: Any) -> None:
    node, bridge, peer, _ = make_rmw_rig("described")
    node.create_publisher(PoseStamped, "goal")
    assert wait_for(lambda: "/described/get_type_description" in bridge.services, 10)
    name = "geometry_msgs/msg/PoseStamped"
    client = peer.client("/described/get_type_description", SRV)
    req = ros_class(f"{SRV}_Request")(type_name=name, type_hash=wheel_hash(name),
                                      include_type_sources=True)
    answered: list[Any] = []

    def ask() -> bool:  # until the bridge's queryable is routable from this peer
        try:
            answered.append(client.call(req, f"{SRV}_Response", timeout=2.0))
        except TimeoutError:
            return False
        return True

    assert wait_for(ask, 10)
    resp, sent, got = answered[0]
    assert got.sequence_id == sent.sequence_id
    assert resp.successful, resp.failure_reason
    want = json.loads((SHARE / "geometry_msgs" / "msg" / "PoseStamped.json").read_text())
    want = want["type_description_msg"]
    assert _plain(resp.type_description.type_description) == \
        _without_defaults(want["type_description"])
    assert [_plain(d) for d in resp.type_description.referenced_type_descriptions] == \
        [_without_defaults(d) for d in want["referenced_type_descriptions"]]
    assert resp.type_sources[0].type_name == name and resp.type_sources[0].encoding == "msg"
