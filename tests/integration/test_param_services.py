"""Every node's ROS 2 parameter services over real Zenoh (rclpy's names and semantics):
list by prefix and depth, describe with ranges, types, get, set (refusals with their
reasons), set atomically (all or none)."""

from __future__ import annotations

import math
from typing import Annotated, Any

import msgspec
from zenros.msgs.rcl_interfaces import (
    DescribeParameters,
    DescribeParametersRequest,
    GetParameters,
    GetParametersRequest,
    GetParameterTypes,
    GetParameterTypesRequest,
    ListParameters,
    ListParametersRequest,
    Parameter,
    ParameterType,
    SetParameters,
    SetParametersAtomically,
    SetParametersAtomicallyRequest,
    SetParametersRequest,
)
from zenros.param_events import to_parameter_value
from zenros.param_services import list_parameters

T = ParameterType


class Config(msgspec.Struct, kw_only=True):
    rate: Annotated[float, msgspec.Meta(gt=0, le=50, description="messages per second")] = 2.0
    retries: Annotated[int, msgspec.Meta(ge=0, le=9)] = 3
    mode: str = "fast"


def _node(make_node: Any) -> Any:
    node = make_node("talker", 0, namespace="/robot1")
    node.declare_parameters(Config)
    node.declare_parameter("costmap.inflation", 0.3)
    node.declare_parameter("costmap.obstacle.range", 2.5)
    node.declare_parameter("fixed", "x", read_only=True)
    return node


def _p(name: str, value: Any) -> Parameter:
    return Parameter(name=name, value=to_parameter_value(value))


def test_list_describe_types_and_get(make_node: Any) -> None:
    _node(make_node)
    user = make_node("user", 1)
    base = "/robot1/talker/"
    ls = user.create_client(ListParameters, base + "list_parameters")
    res = ls.call(ListParametersRequest(), timeout=10).result
    assert {"rate", "retries", "mode", "costmap.inflation", "costmap.obstacle.range",
            "fixed", "use_sim_time"} <= set(res.names)
    assert set(res.prefixes) == {"costmap", "costmap.obstacle"}
    one = ls.call(ListParametersRequest(prefixes=["costmap"], depth=1), timeout=10).result
    assert one.names == ["costmap.inflation"]
    desc = user.create_client(DescribeParameters, base + "describe_parameters").call(
        DescribeParametersRequest(names=["rate", "retries", "fixed"]), timeout=10).descriptors
    rate, retries, fixed = desc
    assert (rate.type, rate.description) == (T.PARAMETER_DOUBLE, "messages per second")
    assert (rate.floating_point_range[0].from_value, rate.floating_point_range[0].to_value) \
        == (0.0, 50.0)
    assert rate.additional_constraints == '{"gt": 0}'  # the open bound, said
    assert (retries.integer_range[0].from_value, retries.integer_range[0].to_value) == (0, 9)
    assert fixed.read_only and fixed.type == T.PARAMETER_STRING
    assert not user.create_client(DescribeParameters, base + "describe_parameters").call(
        DescribeParametersRequest(names=["rate", "nope"]), timeout=10).descriptors
    types = user.create_client(GetParameterTypes, base + "get_parameter_types").call(
        GetParameterTypesRequest(names=["mode", "retries", "nope"]), timeout=10).types
    assert types == [T.PARAMETER_STRING, T.PARAMETER_INTEGER, T.PARAMETER_NOT_SET]
    values = user.create_client(GetParameters, base + "get_parameters").call(
        GetParametersRequest(names=["rate", "mode"]), timeout=10).values
    assert [v.double_value for v in values[:1]] == [2.0] and values[1].string_value == "fast"


def test_set_refuses_with_reasons_and_atomic_is_all_or_none(make_node: Any) -> None:
    node = _node(make_node)
    user = make_node("user", 1)
    base = "/robot1/talker/"
    results = user.create_client(SetParameters, base + "set_parameters").call(
        SetParametersRequest(parameters=[
            _p("rate", 5.0), _p("rate", 500.0), _p("fixed", "y"), _p("nope", 1),
            _p("mode", 3), _p("retries", 4)]), timeout=10).results
    assert [r.successful for r in results] == [True, False, False, False, False, True]
    assert "rate" in results[1].reason and "50" in results[1].reason
    assert "read-only" in results[2].reason
    assert "not declared" in results[3].reason
    assert (node.get_parameter("rate"), node.get_parameter("retries")) == (5.0, 4)
    atomic = user.create_client(SetParametersAtomically, base + "set_parameters_atomically")
    res = atomic.call(SetParametersAtomicallyRequest(parameters=[
        _p("rate", 7.0), _p("retries", 99)]), timeout=10).result
    assert not res.successful and "retries" in res.reason
    assert (node.get_parameter("rate"), node.get_parameter("retries")) == (5.0, 4)
    assert atomic.call(SetParametersAtomicallyRequest(parameters=[
        _p("rate", 7.0), _p("retries", 1)]), timeout=10).result.successful
    assert (node.get_parameter("rate"), node.get_parameter("retries")) == (7.0, 1)
    assert not math.isnan(node.get_parameter("rate"))


def test_list_parameters_follows_rclpy_rules() -> None:
    names = ["a", "b.c", "b.d.e", "b.d.f.g", "bc"]
    assert list_parameters(names, [], 0).names == names
    assert list_parameters(names, [], 1).names == ["a", "bc"]
    assert list_parameters(names, [], 2).names == ["a", "b.c", "bc"]
    assert list_parameters(names, ["b"], 0).names == ["b.c", "b.d.e", "b.d.f.g"]
    assert list_parameters(names, ["b"], 1).names == ["b.c"]
    assert list_parameters(names, ["b.d"], 2).names == ["b.d.e", "b.d.f.g"]
    assert list_parameters(names, ["b"], 0).prefixes == ["b", "b.d", "b.d.f"]
