"""Every node's ``~/get_type_description`` (type_description_interfaces/GetTypeDescription,
as ROS 2 Jazzy+ nodes serve it) over real Zenoh: the types the node uses, by name and RIHS01
hash, their REP 2011 description and interface text; rclpy's refusals otherwise."""

from __future__ import annotations

from typing import Any

from zenros.msgs.std_msgs import String
from zenros.msgs.std_srvs import SetBool, SetBoolResponse
from zenros.msgs.type_description_interfaces import (
    GetTypeDescription,
    GetTypeDescriptionRequest,
)
from zenros.ros2.typehash import type_description, type_hash
from zenros.testing import wait_for


def _ask(make_node: Any, **req: Any) -> Any:
    user = make_node("tool", 1)
    client = user.create_client(GetTypeDescription, "/talker/get_type_description")
    return client.call(GetTypeDescriptionRequest(**req), timeout=10)


def test_a_type_in_use_is_described_with_its_sources(make_node: Any) -> None:
    node = make_node("talker", 0)
    node.create_publisher(String, "chatter")
    node.create_service(SetBool, "flag", lambda req: SetBoolResponse(success=True))
    assert wait_for(lambda: node.graph.endpoints_of("/talker")["pub"], 5)
    res = _ask(make_node, type_name="std_msgs/msg/String",
               type_hash=type_hash("std_msgs/msg/String"))
    assert res.successful, res.failure_reason
    d = res.type_description.type_description
    assert d.type_name == "std_msgs/msg/String"
    assert [(f.name, f.type.type_id) for f in d.fields] == [("data", 17)]  # FIELD_TYPE_STRING
    assert [(s.type_name, s.encoding, s.raw_file_contents) for s in res.type_sources] == [
        ("std_msgs/msg/String", "msg", "string data\n")]


def test_a_service_type_and_its_parts_are_in_use(make_node: Any) -> None:
    node = make_node("talker", 0)
    node.create_service(SetBool, "flag", lambda req: SetBoolResponse(success=True))
    assert wait_for(lambda: node.graph.endpoints_of("/talker")["srv"], 5)
    res = _ask(make_node, type_name="std_srvs/srv/SetBool_Request",
               type_hash=type_hash("std_srvs/srv/SetBool_Request"), include_type_sources=False)
    assert res.successful and res.type_sources == []
    want = type_description("std_srvs/srv/SetBool_Request")["type_description"]
    assert [f.name for f in res.type_description.type_description.fields] == \
        [f["name"] for f in want["fields"]]


def test_refusals_are_rclpys(make_node: Any) -> None:
    node = make_node("talker", 0)
    node.create_publisher(String, "chatter")
    assert wait_for(lambda: node.graph.endpoints_of("/talker")["pub"], 5)
    res = _ask(make_node, type_name="geometry_msgs/msg/Twist")
    assert not res.successful
    assert res.failure_reason == "Type not currently in use by this node"
    res = _ask(make_node, type_name="std_msgs/msg/String", type_hash="RIHS01_" + "0" * 64)
    assert not res.successful and "does not match" in res.failure_reason
