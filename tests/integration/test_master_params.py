"""The parameter server over Zenoh: every operation, events, nodes' parameters, master down."""

from __future__ import annotations

import logging
import textwrap
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import msgspec
import pytest
from zenros.context import Context
from zenros.errors import (
    InvalidNameError,
    InvalidParameterValueError,
    ParameterError,
    ParameterNotFoundError,
    ServiceUnavailableError,
)
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros import param_backend
from zenros.param_backend import MASTER_IN_LAUNCH, attach_parameter_backend
from zenros.param_protocol import SET_PARAM
from zenros.param_client import ParameterClient, ParamEvent
from zenros.param_protocol import DELETE_PARAM, DeleteParam, DeleteParamRequest
from zenros.rpc import Client
from zenros.services.master.node import MasterNode
from zenros.services.master.param_store import ParamStore
from zenros.testing import Collector, wait_for


def start_master(ctx: Context, data: Path, **params: Any) -> MasterNode:
    return MasterNode(context=ctx, parameter_overrides={"data_dir": str(data), **params})


@pytest.fixture
def master(ctx_pair: list[Context], tmp_path: Path) -> Iterator[MasterNode]:
    m = start_master(ctx_pair[0], tmp_path)
    yield m
    m.close()


@pytest.fixture
def client(ctx_pair: list[Context], master: MasterNode) -> ParameterClient:
    c = ParameterClient(ctx_pair[1], timeout=5.0)
    assert c.wait_for_master(10)
    return c


VALUES: dict[str, Any] = {
    "flag": True, "count": 3, "ratio": 2.0, "label": "base", "blob": b"\x00\xff",
    "poses": [[1.0, 2.0], [3.0, 4.0]], "limits": {"v": 0.5, "w": 1},
}


def test_values_keep_their_types_over_zenoh(client: ParameterClient) -> None:
    for name, value in VALUES.items():
        client.set(f"/cfg/{name}", value)
    for name, value in VALUES.items():
        got = client.get(f"/cfg/{name}")
        assert got == value and type(got) is type(value)
    tree = client.get("/cfg")
    assert tree == VALUES
    assert type(tree["ratio"]) is float and type(tree["count"]) is int


def test_set_dict_replaces_the_subtree_and_delete_removes_it(client: ParameterClient) -> None:
    client.set("/nav", {"max_speed": 0.5, "old": 1})
    client.set("/nav", {"max_speed": 0.7, "costmap": {"inflation": 0.3}})
    assert client.get("/nav") == {"max_speed": 0.7, "costmap": {"inflation": 0.3}}
    assert client.list("/nav") == ["/nav/costmap/inflation", "/nav/max_speed"]
    assert client.has("/nav/costmap") and not client.has("/nav/old")
    client.delete("/nav/costmap", namespace=True)
    assert client.list() == ["/nav/max_speed"]
    with pytest.raises(ParameterNotFoundError, match="/nav/costmap"):
        client.delete("/nav/costmap", namespace=True)


def test_deleting_a_namespace_or_the_root_needs_the_flag(
    ctx_pair: list[Context], client: ParameterClient
) -> None:
    client.set("/nav", {"max_speed": 0.5, "costmap": {"inflation": 0.3}})
    raw = Client(ctx_pair[1], DeleteParam, DELETE_PARAM)
    res = raw.call(DeleteParamRequest())  # `{}`: once resolved to / and deleted everything
    assert res.error_type == "InvalidNameError" and "needs a name" in res.error
    with pytest.raises(InvalidNameError):
        client.delete("")
    with pytest.raises(ParameterError, match="namespace holding 2 parameter"):
        client.delete("/nav")
    with pytest.raises(ParameterError, match="/ is a namespace"):
        client.delete("/")
    assert client.list() == ["/nav/costmap/inflation", "/nav/max_speed"]
    client.delete("/nav/max_speed")  # a leaf needs no flag
    client.delete("/", namespace=True)
    assert client.list() == []


def test_private_and_relative_names_resolve_against_the_caller(
    ctx_pair: list[Context], client: ParameterClient
) -> None:
    pr2 = ParameterClient(ctx_pair[1], node="/pr2/foo")
    assert pr2.set("~gain", 1.5).name == "/pr2/foo/gain"
    assert pr2.set("robot_description", "urdf").name == "/pr2/robot_description"
    assert client.get("/pr2/foo/gain") == 1.5
    assert pr2.get("~gain") == 1.5 and pr2.has("robot_description")
    client.set("/robot_description", "global")
    assert pr2.search("robot_description") == "/pr2/robot_description"
    assert ParameterClient(ctx_pair[1], node="/other/foo").search("robot_description/arm") == \
        "/robot_description/arm"
    assert pr2.search("nothing_here") is None


def test_errors_arrive_as_their_own_classes(client: ParameterClient) -> None:
    client.set("/a/b", 1)
    with pytest.raises(ParameterNotFoundError) as info:
        client.get("/a/c")
    assert "/a/c is not set; /a holds: b" in str(info.value)  # the master's own hint
    with pytest.raises(InvalidParameterValueError, match="unsupported value null"):
        client.set("/a/none", None)
    with pytest.raises(InvalidNameError):
        client.set("/a/bad name", 1)
    with pytest.raises(InvalidNameError):
        client.search("/absolute")
    assert client.lookup("/nothing") == (False, None)


def test_a_plain_zenoh_get_reads_json(ctx_pair: list[Context], client: ParameterClient) -> None:
    client.set("/nav/max_speed", 0.5)
    client.set("/nav/name", "robot")
    session, keys = ctx_pair[1].session, ctx_pair[1].keys
    [reply] = list(session.get(keys.param("/nav/max_speed")))
    assert reply.ok is not None and reply.ok.payload.to_bytes() == b"0.5"
    assert str(reply.ok.encoding).startswith("application/json")
    [reply] = list(session.get(keys.param("/nav")))
    assert reply.ok is not None
    assert msgspec.json.decode(reply.ok.payload.to_bytes()) == {"max_speed": 0.5, "name": "robot"}
    leaves = {str(r.ok.key_expr): r.ok.payload.to_bytes()
              for r in session.get(keys.param("/**")) if r.ok is not None}
    assert leaves == {keys.param("/nav/max_speed"): b"0.5", keys.param("/nav/name"): b'"robot"'}


def test_reads_after_a_write_see_it(client: ParameterClient) -> None:
    """The master caches encoded answers; every change must invalidate them."""
    client.set("/c/x", 1)
    for i in range(2, 6):
        assert client.get("/c") == {"x": i - 1} and client.get("/c/x") == i - 1
        client.set("/c/x", i)
    client.delete("/c", namespace=True)
    assert client.lookup("/c") == (False, None)
    client.set("/c", "leaf")
    assert client.get("/c") == "leaf"


def test_subscribers_get_change_events(client: ParameterClient) -> None:
    events: Collector[ParamEvent] = Collector()
    sub = client.subscribe("/nav", events)
    try:
        client.set("/other", 1)
        client.set("/nav/a", 1)
        client.set("/nav", {"b": b"x"})
        assert events.wait(3)
        got = [(e.name, e.value, e.deleted) for e in events.items]
        assert got == [("/nav/a", 1, False), ("/nav/a", None, True), ("/nav/b", b"x", False)]
        assert all(e.time > 0 and e.source for e in events.items)
    finally:
        sub.close()


def test_yaml_load_and_dump(client: ParameterClient) -> None:
    doc = textwrap.dedent("""\
        /nav:
          ros__parameters:
            max_speed: 0.5
            costmap.inflation: 0.3
        robot1:
          chassis:
            ros__parameters:
              wheel_base: 0.3
    """)
    assert sorted(client.load(doc)) == [
        "/nav/costmap/inflation", "/nav/max_speed", "/robot1/chassis/wheel_base"]
    assert client.get("/robot1/chassis/wheel_base") == 0.3
    dumped = client.dump("/nav")
    assert "ros__parameters" in dumped and "inflation: 0.3" in dumped
    client.delete("/nav", namespace=True)
    client.load(dumped)
    assert client.get("/nav") == {"max_speed": 0.5, "costmap": {"inflation": 0.3}}


# ---------------------------------------------------------------- nodes' parameters


def test_node_parameters_read_write_and_follow_master(
    make_node: Any, client: ParameterClient
) -> None:
    client.set("/nav/planner/costmap/inflation", 0.7)
    node = make_node("planner", 1, namespace="/nav")
    attach_parameter_backend(node)
    assert node.declare_parameter("costmap.inflation", 0.3) == 0.7
    assert node.declare_parameter("max_speed", 1.0) == 1.0  # nothing stored: the default
    node.set_parameter("max_speed", 0.4)
    assert client.get("/nav/planner/max_speed") == 0.4  # written through, durably
    changes: Collector[Any] = Collector()
    node.on_parameter_change(changes, "costmap.inflation")
    client.set("/nav/planner/costmap/inflation", 0.9)
    assert changes.wait(1, 5)
    assert changes.items[0].value == 0.9 and node.get_parameter("costmap.inflation") == 0.9
    client.set("/nav/planner/costmap/inflation", "wrong type")  # refused by the node
    client.set("/nav/planner/max_speed", 0.6)
    assert wait_for(lambda: node.get_parameter("max_speed") == 0.6, 5)
    assert node.get_parameter("costmap.inflation") == 0.9


def test_dict_parameters_follow_changes_inside_them(
    make_node: Any, client: ParameterClient
) -> None:
    node = make_node("ctl", 1)
    attach_parameter_backend(node)
    assert node.declare_parameter("limits", {"v": 1.0, "w": 2.0}) == {"v": 1.0, "w": 2.0}
    node.set_parameter("limits", {"v": 0.5, "w": 2.0})
    assert client.get("/ctl/limits") == {"v": 0.5, "w": 2.0}
    client.set("/ctl/limits/w", 3.0)
    assert wait_for(lambda: node.get_parameter("limits") == {"v": 0.5, "w": 3.0}, 5)


class Planner(Node):
    """Declares in setup: whatever was stored must win once the backend is attached."""

    def setup(self) -> None:
        self.speed = self.declare_parameter("speed", 1.0)


def test_attach_after_declaring_fetches_the_declared_parameters(
    ctx_pair: list[Context], client: ParameterClient
) -> None:
    class Unattached(Planner):
        uses_parameter_server = False  # a node built before the backend is attached

    client.set("/planner/speed", 2.5)
    node = Unattached("planner", context=ctx_pair[1])
    try:
        assert node.get_parameter("speed") == 1.0
        attach_parameter_backend(node)
        assert node.get_parameter("speed") == 2.5
    finally:
        node.close()


# ---------------------------------------------------------------- master down


def test_nodes_work_without_master_and_catch_up_when_it_returns(
    ctx_pair: list[Context], make_node: Any, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    with ParamStore(tmp_path / "params.db") as store:  # what master stored before it died
        store.set("/planner/speed", 2.5)
    with caplog.at_level(logging.WARNING, logger="zenros"):
        node = make_node("planner", 1)
        attach_parameter_backend(node)
        assert node.declare_parameter("speed", 1.0) == 1.0
        assert node.declare_parameter("gain", 1.0) == 1.0
    assert "parameter server unreachable" in caplog.text
    assert "using declared defaults" in caplog.text
    node.set_parameter("gain", 3.0)  # kept, pushed when master returns
    with pytest.raises(ServiceUnavailableError):
        ParameterClient(ctx_pair[1]).get("/planner/speed")
    # messages flow without master
    talker = make_node("talker", 0)
    heard: Collector[String] = Collector()
    make_node("listener", 1).create_subscription(String, "chatter", heard)
    pub = talker.create_publisher(String, "chatter")
    assert pub.wait_for_subscribers(1, 5)
    pub.publish(String(data="hi"))
    assert heard.wait(1, 5)

    changed: Collector[Any] = Collector()
    node.on_parameter_change(changed, "speed")
    master = start_master(ctx_pair[0], tmp_path)
    try:
        assert changed.wait(1, 10)
        assert node.get_parameter("speed") == 2.5
        client = ParameterClient(ctx_pair[1])
        assert wait_for(lambda: client.lookup("/planner/gain") == (True, 3.0), 5)
    finally:
        master.close()


def test_a_node_launched_after_master_waits_for_its_services_before_reading(
    ctx_pair: list[Context], tmp_path: Path, caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Launch started master first and says so; the node's own session may not know master's
    services yet at its first read: it waits for them instead of warning and reading nothing."""
    with ParamStore(tmp_path / "params.db") as store:
        store.set("/planner/speed", 2.5)
    monkeypatch.setenv(MASTER_IN_LAUNCH, "1")

    class Unattached(Planner):
        uses_parameter_server = False

    node = Unattached("planner", context=ctx_pair[1])
    attached = threading.Event()

    def attach() -> None:
        attach_parameter_backend(node)
        attached.set()

    with caplog.at_level(logging.WARNING, logger="zenros"):
        worker = threading.Thread(target=attach, daemon=True)
        worker.start()
        assert not attached.wait(0.2)  # no master in the graph yet: it waits
        master = start_master(ctx_pair[0], tmp_path)
        try:
            assert attached.wait(10)
            assert node.get_parameter("speed") == 2.5
        finally:
            worker.join(5)
            node.close()
            master.close()
    assert "parameter server unreachable" not in caplog.text


def _master_gone(make_node: Any, ctx: Context, data: Path, monkeypatch: pytest.MonkeyPatch,
                 grace: float) -> Node:
    """A planner whose parameters follow a master, then that master closed (with the grace
    ``grace``): returns once the planner's graph lists no master."""
    monkeypatch.setattr(param_backend, "MASTER_GONE_GRACE", grace)
    master = start_master(ctx, data)
    node: Node = make_node("planner", 1)
    assert node.graph.wait_for_service(SET_PARAM, 10)
    attach_parameter_backend(node)
    node.declare_parameter("speed", 1.0)
    master.close()
    assert node.graph.wait_for(lambda: not node.graph.servers(SET_PARAM), 10)
    return node


def test_master_gone_and_back_within_the_grace_is_not_reported(
    ctx_pair: list[Context], make_node: Any, tmp_path: Path, caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # issue 37.7: every node logged "parameter server unreachable (master left the graph)"
    # and "reachable again" a moment later while master never exited: master's tokens left
    # the graph and came back (a link made again). Here master's tokens go and come back (a
    # master restarted on the same session) well within the grace.
    with caplog.at_level(logging.INFO, logger="zenros"):
        node = _master_gone(make_node, ctx_pair[0], tmp_path, monkeypatch, 30.0)
        master = start_master(ctx_pair[0], tmp_path)
        try:
            assert node.graph.wait_for_service(SET_PARAM, 10)
            ParameterClient(ctx_pair[1]).set("/planner/speed", 4.0)
            assert wait_for(lambda: node.get_parameter("speed") == 4.0, 10)
        finally:
            master.close()
    assert "parameter server unreachable" not in caplog.text
    assert "reachable again" not in caplog.text


def test_master_gone_for_good_is_reported_after_the_grace(
    ctx_pair: list[Context], make_node: Any, tmp_path: Path, caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    with caplog.at_level(logging.WARNING, logger="zenros"):
        _master_gone(make_node, ctx_pair[0], tmp_path, monkeypatch, 0.5)
        assert wait_for(lambda: "parameter server unreachable (master left the graph 0.5 s ago)"
                        in caplog.text, 10), caplog.text
