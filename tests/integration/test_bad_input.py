"""Malformed payloads, wrong types, oversized and wildcard puts: logged, counted, survived."""

from __future__ import annotations

import logging
import math
from typing import Any

import pytest
import zenoh
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.std_msgs import String
from zenros.testing import Collector, wait_for


@pytest.fixture
def setup(make_node: Any, ctx_pair: Any) -> Any:
    chassis = make_node("chassis", 1)
    got: Collector[Twist] = Collector()
    sub = chassis.create_subscription(Twist, "cmd_vel", got)
    sender = make_node("teleop", 0)
    pub = sender.create_publisher(Twist, "cmd_vel")
    assert pub.wait_for_subscribers(1, 5)
    # the receiving side names senders from its own graph view: let it see the publisher
    assert chassis.context.graph.wait_for_publisher("/cmd_vel", 5)
    return ctx_pair[0], sub, got, pub


def _put(ctx: Any, key: str, data: bytes, encoding: str) -> None:
    # BLOCK: a raw put's default (DROP) loses large samples when the machine is busy
    ctx.session.put(key, data, encoding=encoding, congestion_control=zenoh.CongestionControl.BLOCK)


def _recovers(pub: Any, got: Collector[Twist]) -> None:
    before = len(got)
    pub.publish(Twist(linear=Vector3(x=1.0)))
    assert got.wait(before + 1, 2), "subscription stopped working"


def test_malformed_json_is_logged_with_key_sender_and_kept_running(
    setup: Any, caplog: pytest.LogCaptureFixture
) -> None:
    ctx, sub, got, pub = setup
    with caplog.at_level(logging.ERROR, logger="zenros"):
        _put(ctx, sub.key, b'{"linear": {"x": ', "application/json;geometry_msgs/Twist")
        assert wait_for(lambda: sub.errors == 1, 2)
    assert sub.key in caplog.text
    assert "/teleop" in caplog.text  # the sender, found through its session id
    _recovers(pub, got)


def test_wrong_field_type_names_the_path(setup: Any, caplog: pytest.LogCaptureFixture) -> None:
    ctx, sub, got, pub = setup
    with caplog.at_level(logging.ERROR, logger="zenros"):
        _put(ctx, sub.key, b'{"linear": {"x": "fast"}}', "application/json;geometry_msgs/Twist")
        assert wait_for(lambda: sub.errors == 1, 2)
    assert "$.linear.x" in caplog.text and "Expected `float`, got `str`" in caplog.text
    assert len(got) == 0
    _recovers(pub, got)


def test_null_in_a_float_field_arrives_as_nan(setup: Any) -> None:
    # msgspec and rosbridge write NaN as null: the fast decoder refuses it, the retry takes it
    ctx, sub, got, pub = setup
    _put(ctx, sub.key, b'{"linear": {"x": null, "y": 2.0}}', "application/json;geometry_msgs/Twist")
    assert got.wait(1, 2)
    assert math.isnan(got.items[0].linear.x) and got.items[0].linear.y == 2.0
    assert sub.errors == 0
    _recovers(pub, got)


def test_wrong_type_name_is_a_type_mismatch_not_a_misdecode(
    setup: Any, caplog: pytest.LogCaptureFixture
) -> None:
    ctx, sub, got, pub = setup
    with caplog.at_level(logging.ERROR, logger="zenros"):
        # A Vector3 JSON would decode "fine" into a Twist with defaults: must be refused.
        _put(ctx, sub.key, b'{"x": 1.0, "y": 2.0, "z": 3.0}', "application/json;geometry_msgs/Vector3")
        assert wait_for(lambda: sub.errors == 1, 2)
    assert "type mismatch: expected geometry_msgs/Twist, got geometry_msgs/Vector3" in caplog.text
    assert len(got) == 0
    _recovers(pub, got)


def test_publisher_of_another_type_in_process_is_refused(
    make_node: Any, caplog: pytest.LogCaptureFixture
) -> None:
    a, b = make_node("a", 0), make_node("b", 0)
    got: Collector[Twist] = Collector()
    sub = b.create_subscription(Twist, "cmd_vel", got)
    pub = a.create_publisher(String, "cmd_vel")
    with caplog.at_level(logging.ERROR, logger="zenros"):
        pub.publish(String(data="hi"))
    assert sub.errors == 1 and len(got) == 0
    assert "type mismatch" in caplog.text


def test_oversized_garbage_payload(setup: Any) -> None:
    ctx, sub, got, pub = setup
    _put(ctx, sub.key, b"\xff" * (4 << 20), "application/json;geometry_msgs/Twist")
    assert wait_for(lambda: sub.errors == 1, 5)
    _recovers(pub, got)


def test_errors_are_rate_limited_per_sender(setup: Any, caplog: pytest.LogCaptureFixture) -> None:
    ctx, sub, _, _ = setup
    with caplog.at_level(logging.ERROR, logger="zenros"):
        for _ in range(50):
            _put(ctx, sub.key, b"not json", "application/json;geometry_msgs/Twist")
        assert wait_for(lambda: sub.errors == 50, 5)
    assert caplog.text.count("cannot decode") == 1
