"""Parameters declared with a ROS 2 ``ParameterDescriptor`` (rclpy's rules): a range with its
step checked on declare and on every set, read-only, dynamic typing (a set may change the
type; PARAMETER_NOT_SET undeclares, a ``deleted_parameters`` event), `undeclare_parameter`
(no event), and the descriptor ``~/describe_parameters`` gives back, over real Zenoh."""

from __future__ import annotations

import math
from typing import Any

import pytest
from zenros.errors import (
    InvalidParameterValueError,
    ParameterImmutableError,
    ParameterNotDeclaredError,
)
from zenros.msgs.rcl_interfaces import (
    DescribeParameters,
    DescribeParametersRequest,
    FloatingPointRange,
    IntegerRange,
    Parameter,
    ParameterDescriptor,
    ParameterEvent,
    ParameterType,
    ParameterValue,
    SetParameters,
    SetParametersRequest,
)
from zenros.param_events import to_parameter_value
from zenros.param_limits import check_value
from zenros.testing import Collector, wait_for

T = ParameterType


def _p(name: str, value: Any) -> Parameter:
    return Parameter(name=name, value=to_parameter_value(value))


def test_integer_step_counts_from_the_lower_bound_and_the_bounds_always_pass() -> None:
    # specs/rclpy-parity.md: {2, 5, step 2} allows 2, 4, 5
    c = {"ge": 2, "le": 5, "step": 2}
    assert [v for v in range(8) if check_value(v, c) is None] == [2, 4, 5]
    why = check_value(3, c)
    assert why is not None and "in steps of 2 from 2" in why


def test_double_step_within_rclpys_tolerance() -> None:
    c = {"ge": 0.0, "le": 1.0, "step": 0.1}
    assert check_value(0.3, c) is None  # 0.1 * 3 is 0.30000000000000004
    assert check_value(0.3 + 1e-9, c) is None
    assert check_value(0.35, c) is not None
    assert check_value(1.0, c) is None and check_value(1.05, c) is not None


def test_a_descriptor_range_is_checked_on_declare_and_set(make_node: Any) -> None:
    node = make_node("ranged", 0)
    d = ParameterDescriptor(description="wheel count", integer_range=[
        IntegerRange(from_value=2, to_value=8, step=2)])
    assert node.declare_parameter("wheels", 4, d) == 4
    node.set_parameter("wheels", 8)
    with pytest.raises(InvalidParameterValueError, match="in steps of 2 from 2, got 5"):
        node.set_parameter("wheels", 5)
    with pytest.raises(InvalidParameterValueError, match="got 10"):
        node.set_parameter("wheels", 10)
    assert node.get_parameter("wheels") == 8
    with pytest.raises(InvalidParameterValueError, match="'odd'"):
        node.declare_parameter("odd", 3, d)  # a default off the step: nothing declared
    assert not node.has_parameter("odd")


def test_dynamic_typing_retypes_and_not_set_deletes_with_an_event(make_node: Any) -> None:
    watcher = make_node("watcher", 1)
    events: Collector[ParameterEvent] = Collector()
    watcher.create_subscription(ParameterEvent, "/parameter_events", events, 1000)
    node = make_node("dyn", 0)
    assert wait_for(lambda: any(e.node == "/dyn" for e in events.items), 5)
    assert node.declare_parameter("anything", 1, ParameterDescriptor(dynamic_typing=True)) == 1
    node.set_parameter("anything", "now a string")
    assert node.get_parameter("anything") == "now a string"
    node.declare_parameter("static", 1.5)
    with pytest.raises(InvalidParameterValueError, match="is float, got string"):
        node.set_parameter("static", "x")
    with pytest.raises(InvalidParameterValueError, match="statically typed"):
        node.set_parameter("static", None)
    node.set_parameter("anything", None)  # PARAMETER_NOT_SET: undeclared
    assert not node.has_parameter("anything")
    mine = lambda: [e for e in events.items if e.node == "/dyn"]
    assert wait_for(lambda: any(e.deleted_parameters for e in mine()), 5)
    deleted = next(e for e in mine() if e.deleted_parameters)
    assert [p.name for p in deleted.deleted_parameters] == ["anything"]
    changed = [e.changed_parameters[0].value for e in mine() if e.changed_parameters]
    assert changed == [ParameterValue(type=T.PARAMETER_STRING, string_value="now a string")]


def test_undeclare_publishes_nothing_and_a_read_only_one_stays(make_node: Any) -> None:
    node = make_node("undecl", 0)
    node.declare_parameter("gone", 2)
    node.declare_parameter("kept", "x", ParameterDescriptor(read_only=True))
    node.undeclare_parameter("gone")
    assert not node.has_parameter("gone")
    with pytest.raises(ParameterNotDeclaredError):
        node.undeclare_parameter("gone")
    with pytest.raises(ParameterImmutableError, match="read-only"):
        node.undeclare_parameter("kept")
    assert node.get_parameter("kept") == "x"
    node.declare_parameter("gone", 3.0)  # the name is free again, with another type
    assert node.get_parameter("gone") == 3.0


def test_describe_and_set_over_the_services(make_node: Any) -> None:
    node = make_node("svc", 0, namespace="/robot1")
    node.declare_parameter("gain", 0.5, ParameterDescriptor(
        floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0, step=0.25)],
        additional_constraints="a quarter at a time"))
    node.declare_parameter("open", 1, ParameterDescriptor(integer_range=[
        IntegerRange(from_value=0, to_value=2**63 - 1)]))
    node.declare_parameter("any", "x", ParameterDescriptor(dynamic_typing=True))
    user = make_node("user", 1)
    base = "/robot1/svc/"
    gain, opened, anything = user.create_client(
        DescribeParameters, base + "describe_parameters").call(
        DescribeParametersRequest(names=["gain", "open", "any"]), timeout=10).descriptors
    r = gain.floating_point_range[0]
    assert (r.from_value, r.to_value, r.step) == (0.0, 1.0, 0.25)
    assert gain.additional_constraints == "a quarter at a time"
    assert (opened.integer_range[0].from_value, opened.integer_range[0].to_value,
            opened.integer_range[0].step) == (0, 2**63 - 1, 0)
    assert anything.dynamic_typing and not gain.dynamic_typing
    setter = user.create_client(SetParameters, base + "set_parameters")
    results = setter.call(SetParametersRequest(parameters=[
        _p("gain", 0.75), _p("gain", 0.8), _p("any", 7), _p("gain", None), _p("any", None)]),
        timeout=10).results
    assert [r.successful for r in results] == [True, False, True, False, True]
    assert "in steps of 0.25" in results[1].reason
    assert "statically typed" in results[3].reason
    assert node.get_parameter("gain") == 0.75 and not node.has_parameter("any")
    assert not math.isnan(node.get_parameter("gain"))
