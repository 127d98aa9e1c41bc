"""/parameter_events over real Zenoh (rclpy's semantics): a node publishes an event when it
declares a parameter and when one changes, whoever changed it (its code, the parameter
server); `ParameterEventHandler` follows another node's parameters."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from test_master_params import start_master
from zenros.context import Context
from zenros.msgs.rcl_interfaces import Parameter as ParameterMsg
from zenros.msgs.rcl_interfaces import ParameterEvent, ParameterType, ParameterValue
from zenros.param_backend import attach_parameter_backend
from zenros.param_client import ParameterClient
from zenros.param_events import ParameterEventHandler, from_parameter_value, to_parameter_value
from zenros.params import SetParametersResult
from zenros.testing import Collector, wait_for


def _names(events: list[ParameterEvent], node: str) -> list[tuple[list[str], list[str]]]:
    return [([p.name for p in e.new_parameters], [p.name for p in e.changed_parameters])
            for e in events if e.node == node]


def test_declare_and_change_publish_events_and_a_refused_or_same_value_none(
        make_node: Any) -> None:
    watcher = make_node("watcher", 1)
    events: Collector[ParameterEvent] = Collector()
    watcher.create_subscription(ParameterEvent, "/parameter_events", events, 1000)
    node = make_node("talker", 0, namespace="/robot1")
    assert wait_for(lambda: _names(events.items, "/robot1/talker"), 5)  # use_sim_time
    node.declare_parameter("speed", 1.5)
    node.add_on_set_parameters_callback(
        lambda ps: SetParametersResult(all(p.value < 10 for p in ps), "too fast"))
    node.set_parameter("speed", 2.5)
    node.set_parameter("speed", 2.5)  # the same value: no event
    with pytest.raises(Exception, match="too fast"):
        node.set_parameter("speed", 11.0)
    node.declare_parameter("tags", ["a", "b"])
    assert wait_for(lambda: len(_names(events.items, "/robot1/talker")) >= 4, 5)
    assert _names(events.items, "/robot1/talker") == [
        (["use_sim_time"], []), (["speed"], []), ([], ["speed"]), (["tags"], [])]
    mine = [e for e in events.items if e.node == "/robot1/talker"]
    assert mine[2].changed_parameters[0].value == ParameterValue(
        type=ParameterType.PARAMETER_DOUBLE, double_value=2.5)
    assert mine[3].new_parameters[0].value.string_array_value == ["a", "b"]
    assert all(e.stamp.sec > 0 for e in mine)


def test_the_handler_follows_one_parameter_of_one_node_and_every_event(
        make_node: Any) -> None:
    watcher = make_node("watcher", 1, namespace="/robot1")
    handler = ParameterEventHandler(watcher)
    speeds: Collector[ParameterMsg] = Collector()
    others: Collector[ParameterMsg] = Collector()
    every: Collector[ParameterEvent] = Collector()
    handle = handler.add_parameter_callback("speed", "talker", speeds)  # /robot1/talker
    handler.add_parameter_callback("speed", "/elsewhere/talker", others)
    handler.add_parameter_event_callback(every)
    node = make_node("talker", 0, namespace="/robot1")
    node.declare_parameter("speed", 1.5)
    node.declare_parameter("name", "r1")
    node.set_parameter("speed", 0.5)
    assert speeds.wait(2, 5)
    assert [from_parameter_value(p.value) for p in speeds.items] == [1.5, 0.5]
    assert wait_for(lambda: len(_names(every.items, "/robot1/talker")) == 4, 5)
    handler.remove_parameter_callback(handle)
    with pytest.raises(RuntimeError):
        handler.remove_parameter_callback(handle)
    node.set_parameter("speed", 0.7)
    assert wait_for(lambda: len(_names(every.items, "/robot1/talker")) == 5, 5)
    assert len(speeds.items) == 2 and not others.items
    event = every.items[-1]
    assert ParameterEventHandler.get_parameter_from_event(event, "speed", "/robot1/talker")
    assert ParameterEventHandler.get_parameter_from_event(event, "speed", "/x") is None
    assert [p.name for p in ParameterEventHandler.get_parameters_from_event(event)] == ["speed"]


def test_a_change_through_the_parameter_server_is_an_event(
        make_node: Any, ctx_pair: list[Context], tmp_path: Path) -> None:
    master = start_master(ctx_pair[0], tmp_path)
    try:
        client = ParameterClient(ctx_pair[1], timeout=5.0)
        assert client.wait_for_master(10)
        handler = ParameterEventHandler(make_node("watcher", 1))
        seen: Collector[ParameterMsg] = Collector()
        handler.add_parameter_callback("max_speed", "/nav/planner", seen)
        node = make_node("planner", 0, namespace="/nav")
        attach_parameter_backend(node)
        node.declare_parameter("max_speed", 1.0)
        client.set("/nav/planner/max_speed", 0.6)  # `zenros param set`, rosparam set
        assert seen.wait(2, 5)
        assert [from_parameter_value(p.value) for p in seen.items] == [1.0, 0.6]
    finally:
        master.close()


@pytest.mark.parametrize(("value", "kind"), [
    (True, ParameterType.PARAMETER_BOOL), (3, ParameterType.PARAMETER_INTEGER),
    (2.5, ParameterType.PARAMETER_DOUBLE), ("x", ParameterType.PARAMETER_STRING),
    (b"\x00\xff", ParameterType.PARAMETER_BYTE_ARRAY),
    ([True, False], ParameterType.PARAMETER_BOOL_ARRAY),
    ([1, 2], ParameterType.PARAMETER_INTEGER_ARRAY),
    ([1.5, 2.0], ParameterType.PARAMETER_DOUBLE_ARRAY),
    (["a"], ParameterType.PARAMETER_STRING_ARRAY),
])
def test_values_round_trip_as_ros2_parameter_values(value: Any, kind: int) -> None:
    pv = to_parameter_value(value)
    assert pv.type == kind
    assert from_parameter_value(pv) == value


def test_values_ros2_cannot_hold_travel_as_json_text() -> None:
    assert to_parameter_value({"v": 0.5}).string_value == '{"v": 0.5}'
    assert to_parameter_value([1, 2.5]).double_array_value == [1.0, 2.5]
    assert to_parameter_value([[1.0, 2.0]]).string_value == "[[1.0, 2.0]]"
    assert to_parameter_value([]).type == ParameterType.PARAMETER_STRING_ARRAY
    with pytest.raises(ValueError, match="unknown parameter type 42"):
        from_parameter_value(ParameterValue(type=42))
