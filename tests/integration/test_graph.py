"""The graph without a master: nodes, topics, services, conflicts, duplicates, departures."""

from __future__ import annotations

import logging
from typing import Any

import pytest
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsResponse, Fibonacci
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.std_msgs import String
from zenros.node import Node


def test_graph_lists_nodes_topics_and_services(make_node: Any, ctx_pair: Any) -> None:
    a = make_node("teleop", 0, namespace="robot1")
    b = make_node("chassis", 1, namespace="robot1")
    a.create_publisher(Twist, "cmd_vel")
    b.create_subscription(Twist, "cmd_vel", lambda m: None)
    b.create_service(AddTwoInts, "add", lambda r: AddTwoIntsResponse())
    g = ctx_pair[0].graph
    assert g.wait_for_service("/robot1/add", 5)
    assert g.wait_for_subscriber("/robot1/cmd_vel", 5)
    assert {"/robot1/teleop", "/robot1/chassis"} <= set(g.node_names())
    assert g.topics()["/robot1/cmd_vel"] == ["geometry_msgs/Twist"]
    assert g.services()["/robot1/add"] == ["example_interfaces/AddTwoInts"]
    assert [t.node for t in g.publishers("/robot1/cmd_vel")] == ["/robot1/teleop"]
    info = g.endpoints_of("/robot1/chassis")
    assert [t.name for t in info["sub"]] == ["/robot1/cmd_vel"]
    # and the six parameter services and the type description service every node serves
    # (as `ros2 node info` lists them)
    assert sorted(t.name for t in info["srv"]) == sorted(["/robot1/add", *(
        f"/robot1/chassis/{s}" for s in ("list_parameters", "describe_parameters",
                                         "get_parameter_types", "get_parameters",
                                         "set_parameters", "set_parameters_atomically",
                                         "get_type_description"))])
    node = next(n for n in g.nodes() if n.name == "/robot1/chassis")
    assert node.pid > 0 and node.host and node.zid == ctx_pair[1].zid


def test_service_and_action_clients_are_in_the_graph(make_node: Any, ctx_pair: Any) -> None:
    a = make_node("teleop", 0, namespace="robot1")
    client = a.create_client(AddTwoInts, "add")
    actions = a.create_action_client(Fibonacci, "/fibonacci")
    g = ctx_pair[1].graph
    assert g.wait_for(lambda: bool(g.clients("/robot1/add") and g.action_clients("/fibonacci")), 5)
    assert [(t.node, t.type) for t in g.clients("/robot1/add")] == [
        ("/robot1/teleop", "example_interfaces/AddTwoInts")]
    assert [t.node for t in g.action_clients("/fibonacci")] == ["/robot1/teleop"]
    info = g.endpoints_of("/robot1/teleop")
    assert [t.name for t in info["cli"]] == ["/robot1/add"]
    assert [t.name for t in info["actc"]] == ["/fibonacci"]
    assert "/robot1/add" not in g.services() and "/fibonacci" not in g.actions()  # servers only
    client.close()
    actions.close()
    assert g.wait_for(lambda: not g.clients("/robot1/add") and not g.action_clients("/fibonacci"), 5)


def test_closed_node_leaves_the_graph(make_node: Any, ctx_pair: Any) -> None:
    b = make_node("gone", 1)
    b.create_publisher(String, "chatter")
    g = ctx_pair[0].graph
    assert g.wait_for_node("/gone", 5)
    b.close()
    assert g.wait_for(lambda: "/gone" not in g.node_names() and "/chatter" not in g.topics(), 5)


def test_type_conflict_is_reported(make_node: Any, ctx_pair: Any,
                                   caplog: pytest.LogCaptureFixture) -> None:
    a, b = make_node("a", 0), make_node("b", 1)
    g = ctx_pair[0].graph
    a.create_publisher(Twist, "cmd_vel")
    assert ctx_pair[1].graph.wait_for_publisher("/cmd_vel", 5)
    with caplog.at_level(logging.WARNING, logger="zenros"):
        b.create_subscription(String, "cmd_vel", lambda m: None)
    assert "type conflict on /cmd_vel" in caplog.text
    assert g.wait_for(lambda: "/cmd_vel" in g.type_conflicts(), 5)
    assert g.type_conflicts()["/cmd_vel"] == ["geometry_msgs/Twist", "std_msgs/String"]


def test_duplicate_node_names_are_reported(make_node: Any, ctx_pair: Any) -> None:
    make_node("twin", 0)
    make_node("twin", 1)
    g = ctx_pair[0].graph
    assert g.wait_for(lambda: "/twin" in g.duplicate_nodes(), 5)
    assert len(g.duplicate_nodes()["/twin"]) == 2


def test_graph_listener_sees_puts_and_deletes(ctx_pair: Any) -> None:
    events: list[tuple[str, str]] = []
    g = ctx_pair[0].graph
    g.add_listener(lambda ev, tok: events.append((ev, tok.node)) if tok.kind == "node" else None)
    n = Node("watched", context=ctx_pair[1])
    assert g.wait_for(lambda: ("put", "/watched") in events, 5)
    n.close()
    assert g.wait_for(lambda: ("delete", "/watched") in events, 5)


def test_removed_listener_is_not_called(ctx_pair: Any) -> None:
    seen: list[str] = []
    g = ctx_pair[0].graph
    remove = g.add_listener(lambda ev, tok: seen.append(tok.node))
    remove()
    n = Node("quiet", context=ctx_pair[1])
    try:
        assert g.wait_for_node("/quiet", 5)
        assert seen == []
    finally:
        n.close()
