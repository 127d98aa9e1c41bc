"""The registry over Zenoh: system state, node lookup, topic types, duplicate node names."""

from __future__ import annotations

import logging
import os
import socket
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from zenros.context import Context
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsResponse
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.rpc import Client
from zenros.services.master.messages import (
    GET_PUBLISHED_TOPICS,
    GET_SYSTEM_STATE,
    GET_TOPIC_TYPES,
    LOOKUP_NODE,
    GetPublishedTopics,
    GetPublishedTopicsRequest,
    GetSystemState,
    GetSystemStateRequest,
    GetTopicTypes,
    GetTopicTypesRequest,
    LookupNode,
    LookupNodeRequest,
)
from zenros.services.master.node import MasterNode
from zenros.shutdown import install_shutdown_listener
from zenros.testing import wait_for


@pytest.fixture
def early(ctx_pair: list[Context]) -> Iterator[Node]:
    """A node started before master: the registry must still list it."""
    node = Node("teleop", namespace="/robot1", context=ctx_pair[1])
    node.create_publisher(Twist, "cmd_vel")
    yield node
    node.close()


@pytest.fixture
def master(ctx_pair: list[Context], tmp_path: Path, early: Node) -> Iterator[MasterNode]:
    assert ctx_pair[0].graph.wait_for_publisher("/robot1/cmd_vel", 5)
    m = MasterNode(context=ctx_pair[0], parameter_overrides={
        "data_dir": str(tmp_path), "registry_grace": 0.3})
    yield m
    m.close()


def call(ctx: Context, srv: Any, name: str, req: Any) -> Any:
    client = Client(ctx, srv, name)
    assert client.wait_for_service(10)
    return client.call(req, 5.0)


def state(ctx: Context) -> Any:
    return call(ctx, GetSystemState, GET_SYSTEM_STATE, GetSystemStateRequest())


def test_system_state_lists_nodes_topics_services(
    ctx_pair: list[Context], make_node: Any, master: MasterNode
) -> None:
    chassis = make_node("chassis", 1, namespace="/robot1")
    chassis.create_subscription(Twist, "cmd_vel", lambda m: None)
    chassis.create_service(AddTwoInts, "add", lambda r: AddTwoIntsResponse())
    ctx = ctx_pair[1]
    assert wait_for(lambda: "/robot1/add" in [s.name for s in state(ctx).services], 10)
    s = state(ctx)
    nodes = {n.name: n for n in s.nodes}
    assert {"/robot1/teleop", "/robot1/chassis", "/master"} <= set(nodes)
    teleop = nodes["/robot1/teleop"]
    assert teleop.pid == os.getpid() and teleop.host == socket.gethostname()
    assert teleop.start.sec > 0 and teleop.zid == ctx.zid
    topic = next(t for t in s.topics if t.name == "/robot1/cmd_vel")
    assert (topic.types, topic.publishers, topic.subscribers) == (
        ["geometry_msgs/Twist"], ["/robot1/teleop"], ["/robot1/chassis"])
    add = next(v for v in s.services if v.name == "/robot1/add")
    assert add.servers == ["/robot1/chassis"] and add.types == ["example_interfaces/AddTwoInts"]
    assert "/master/set_param" in [v.name for v in s.services]

    found = call(ctx, LookupNode, LOOKUP_NODE, LookupNodeRequest(name="/robot1/chassis"))
    assert found.found and found.node.pid == os.getpid()
    assert not call(ctx, LookupNode, LOOKUP_NODE, LookupNodeRequest(name="/ghost")).found
    types = call(ctx, GetTopicTypes, GET_TOPIC_TYPES, GetTopicTypesRequest())
    assert {t.name: t.types for t in types.topics}["/robot1/cmd_vel"] == ["geometry_msgs/Twist"]
    published = call(ctx, GetPublishedTopics, GET_PUBLISHED_TOPICS,
                     GetPublishedTopicsRequest(subgraph="/robot1"))
    assert [t.name for t in published.topics] == ["/robot1/cmd_vel"]

    chassis.close()
    assert wait_for(lambda: "/robot1/chassis" not in [n.name for n in state(ctx).nodes], 10)


def test_type_conflicts_are_reported(ctx_pair: list[Context], make_node: Any,
                                     master: MasterNode, caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.WARNING, logger="zenros.node.master"):
        make_node("odd", 1).create_subscription(String, "/robot1/cmd_vel", lambda m: None)
        assert wait_for(lambda: state(ctx_pair[1]).type_conflicts, 10)
    [conflict] = state(ctx_pair[1]).type_conflicts
    assert conflict.types == ["geometry_msgs/Twist", "std_msgs/String"]
    assert "type conflict on /robot1/cmd_vel" in caplog.text


def test_the_older_of_two_same_named_nodes_is_told_to_shut_down(
    ctx_pair: list[Context], master: MasterNode, caplog: pytest.LogCaptureFixture
) -> None:
    older = Node("twin", context=ctx_pair[1])
    newer: Node | None = None
    stopped = threading.Event()
    newer_stopped = threading.Event()
    try:
        install_shutdown_listener(older, stopped.set)
        assert ctx_pair[0].graph.wait_for_node("/twin", 5)
        with caplog.at_level(logging.WARNING, logger="zenros"):
            newer = Node("twin", context=ctx_pair[0])
            install_shutdown_listener(newer, newer_stopped.set)
            assert stopped.wait(10)
        assert not newer_stopped.is_set()
        assert "duplicate node name /twin" in caplog.text  # the master's side
        assert "shutting down: a newer node took the name /twin" in caplog.text  # the node's
        records = {r.name for r in caplog.records}
        assert {"zenros.node.master", "zenros.node.twin"} <= records
    finally:
        older.close()
        if newer is not None:
            newer.close()
