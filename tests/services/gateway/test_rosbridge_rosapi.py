"""rosapi answered from a graph view and a parameter store (no Zenoh)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import pytest
from zenros.errors import ParameterNotFoundError
from zenros.msgs.builtin_interfaces import Time
from zenros.services.gateway.rosbridge.rosapi import Rosapi, RosapiError, param_name


@dataclass
class Tok:
    kind: str
    node: str
    name: str
    type: str = ""


class Graph:
    toks: ClassVar[list[Tok]] = [Tok("pub", "/a", "/chatter", "std_msgs/String"),
            Tok("sub", "/b", "/chatter", "std_msgs/String"),
            Tok("srv", "/a", "/add", "example_interfaces/AddTwoInts"),
            Tok("act", "/a", "/fib", "example_interfaces/Fibonacci")]

    def _of(self, kind: str) -> dict[str, list[str]]:
        return {t.name: [t.type] for t in self.toks if t.kind == kind}

    def topics(self) -> dict[str, list[str]]:
        return {**self._of("pub"), **self._of("sub")}

    def services(self) -> dict[str, list[str]]:
        return self._of("srv")

    def actions(self) -> dict[str, list[str]]:
        return self._of("act")

    def node_names(self) -> list[str]:
        return ["/a", "/b"]

    def endpoints_of(self, node: str) -> dict[str, list[Any]]:
        out: dict[str, list[Any]] = {}
        for t in self.toks:
            if t.node == node:
                out.setdefault(t.kind, []).append(t)
        return out

    def publishers(self, topic: str) -> list[Any]:
        return [t for t in self.toks if t.kind == "pub" and t.name == topic]

    def subscribers(self, topic: str) -> list[Any]:
        return [t for t in self.toks if t.kind == "sub" and t.name == topic]

    def servers(self, service: str) -> list[Any]:
        return [t for t in self.toks if t.kind == "srv" and t.name == service]


class Params:
    def __init__(self) -> None:
        self.values: dict[str, Any] = {}

    def lookup(self, name: str) -> tuple[bool, Any]:
        return (name in self.values, self.values.get(name))

    def set(self, name: str, value: Any) -> None:
        self.values[name] = value

    def delete(self, name: str) -> None:
        if name not in self.values:
            raise ParameterNotFoundError(f"{name} is not set")
        del self.values[name]

    def has(self, name: str) -> bool:
        return name in self.values

    def list(self, prefix: str = "/") -> list[str]:
        return sorted(self.values)


@pytest.fixture
def api() -> Rosapi:
    return Rosapi(Graph(), Params(), lambda: Time(sec=3, nanosec=4))


def test_graph_services(api: Rosapi) -> None:
    assert api.call("/rosapi/topics", {}) == {"topics": ["/chatter"],
                                              "types": ["std_msgs/msg/String"]}
    assert api.call("/rosapi/topic_type", {"topic": "chatter"}) == {"type": "std_msgs/msg/String"}
    assert api.call("/rosapi/topic_type", {"topic": "/x"}) == {"type": ""}
    assert api.call("/rosapi/topics_for_type", {"type": "std_msgs/String"}) == {
        "topics": ["/chatter"]}
    services = api.call("/rosapi/services", {})["services"]
    assert "/add" in services and "/rosapi/get_param" in services
    assert api.call("/rosapi/service_type", {"service": "/add"}) == {
        "type": "example_interfaces/srv/AddTwoInts"}
    assert api.call("/rosapi/service_type", {"service": "/rosapi/topics"}) == {
        "type": "rosapi/srv/Topics"}
    assert api.call("/rosapi/nodes", {}) == {"nodes": ["/a", "/b"]}
    assert api.call("/rosapi/node_details", {"node": "/a"}) == {
        "subscribing": [], "publishing": ["/chatter"], "services": ["/add"]}
    assert api.call("/rosapi/publishers", {"topic": "/chatter"}) == {"publishers": ["/a"]}
    assert api.call("/rosapi/subscribers", {"topic": "/chatter"}) == {"subscribers": ["/b"]}
    assert api.call("/rosapi/action_servers", {}) == {"action_servers": ["/fib"]}
    assert api.call("/rosapi/service_node", {"service": "/add"}) == {"node": "/a"}


def test_time_has_both_spellings(api: Rosapi) -> None:
    assert api.call("/rosapi/get_time", {}) == {
        "time": {"sec": 3, "nanosec": 4, "secs": 3, "nsecs": 4}}


def test_params_round_trip_as_json_text(api: Rosapi) -> None:
    assert api.call("/rosapi/set_param", {"name": "/n:speed", "value": "1.5"})["successful"]
    assert api.call("/rosapi/get_param", {"name": "/n/speed"}) == {
        "value": "1.5", "successful": True, "reason": ""}
    assert api.call("/rosapi/has_param", {"name": "/n:speed"}) == {"exists": True}
    assert api.call("/rosapi/get_param_names", {}) == {"names": ["/n/speed"]}
    assert api.call("/rosapi/delete_param", {"name": "/n:speed"})["successful"]
    missing = api.call("/rosapi/delete_param", {"name": "/n:speed"})
    assert missing["successful"] is False and "not set" in missing["reason"]
    got = api.call("/rosapi/get_param", {"name": "/n:speed", "default_value": "2"})
    assert got["value"] == "2"
    got = api.call("/rosapi/get_param", {"name": "/n:speed"})
    assert got["successful"] is False
    bad = api.call("/rosapi/set_param", {"name": "/n:speed", "value": "nope"})
    assert bad["successful"] is False and "JSON" in bad["reason"]
    deep = api.call("/rosapi/set_param", {"name": "/n:speed", "value": "[" * 3000 + "]" * 3000})
    assert deep["successful"] is False and "nested too deep" in deep["reason"]
    assert api.call("/rosapi/get_ros_version", {}) == {"version": 2, "distro": "zenros"}


def test_param_names() -> None:
    assert param_name("/talker:use_sim_time") == "/talker/use_sim_time"
    assert param_name("talker:a.b") == "/talker/a/b"
    assert param_name("x/y") == "/x/y"
    with pytest.raises(RosapiError):
        param_name(" ")


def test_bad_requests(api: Rosapi) -> None:
    with pytest.raises(RosapiError, match="does not exist"):
        api.call("/rosapi/nope", {})
    with pytest.raises(RosapiError, match="missing argument 'topic'"):
        api.call("/rosapi/topic_type", {})
    with pytest.raises(RosapiError, match="must be a string"):
        api.call("/rosapi/topic_type", {"topic": 3})


def test_message_details(api: Rosapi) -> None:
    defs = api.call("/rosapi/message_details", {"type": "geometry_msgs/PoseStamped"})["typedefs"]
    by_type = {d["type"]: d for d in defs}
    assert defs[0]["type"] == "geometry_msgs/msg/PoseStamped"
    assert defs[0]["fieldnames"] == ["header", "pose"]
    assert defs[0]["fieldtypes"] == ["std_msgs/msg/Header", "geometry_msgs/msg/Pose"]
    assert by_type["geometry_msgs/msg/Quaternion"]["examples"] == ["0.0", "0.0", "0.0", "1.0"]
    assert len(defs) == len(by_type)  # each nested type once
    grid = api.call("/rosapi/message_details", {"type": "nav_msgs/msg/OccupancyGrid"})
    assert grid["typedefs"][0]["fieldarraylen"] == [-1, -1, 0]
    request = api.call("/rosapi/service_request_details",
                       {"type": "example_interfaces/srv/AddTwoInts"})["typedefs"][0]
    assert request["fieldnames"] == ["a", "b"] and request["fieldtypes"] == ["int64", "int64"]
    goal = api.call("/rosapi/action_goal_details",
                    {"type": "example_interfaces/action/Fibonacci"})["typedefs"][0]
    assert goal["fieldnames"] == ["order"]
    with pytest.raises(RosapiError, match="unknown message type"):
        api.call("/rosapi/message_details", {"type": "no/Such"})
