"""Misrouted samples (`zenros.keytag`): a sample whose key tag names another key is dropped,
counted and logged, whatever its type; untagged samples and other tools' attachments pass."""

from __future__ import annotations

import logging
import threading
from typing import Any

import pytest
import zenoh
from zenros.action import ActionClient, ActionServer
from zenros.action.types import uuid_msg
from zenros.keytag import TAG_SIZE, TYPED_TAG_SIZE, key_tag, misrouted
from zenros.msgs.example_interfaces import (
    Fibonacci,
    FibonacciFeedback,
    FibonacciGoal,
    FibonacciResult,
)
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.testing import Collector, wait_for

TWIST = b'{"linear": {"x": 1.5}}'
ENC = "application/json;geometry_msgs/Twist"
VECTOR3 = "application/json;geometry_msgs/Vector3"


def test_tags_name_their_key_and_only_a_tag_can_be_misrouted() -> None:
    a, b = key_tag("zenros/topic/robot1/odom"), key_tag("zenros/topic/robot6/odom")
    assert len(a) == TAG_SIZE and a != b and a == key_tag("zenros/topic/robot1/odom")
    assert misrouted(zenoh.ZBytes(b), a)
    assert not misrouted(zenoh.ZBytes(a), a)
    assert not misrouted(None, a)
    assert not misrouted(zenoh.ZBytes(b"someone else's attachment"), a)


def test_typed_tags_name_their_key_and_encoding_and_either_kind_tells_the_key() -> None:
    key, other = "zenros/topic/robot1/cmd_vel", "zenros/topic/robot6/cmd_vel"
    twist = key_tag(key, ENC)
    assert len(twist) == TYPED_TAG_SIZE and twist == key_tag(key, ENC)
    assert twist != key_tag(key, VECTOR3) and twist[3:TAG_SIZE] == key_tag(key)[3:]
    # another type on this very key is not misrouted (the encoding check refuses it)
    assert not misrouted(zenoh.ZBytes(key_tag(key, VECTOR3)), twist)
    assert not misrouted(zenoh.ZBytes(key_tag(key)), twist)  # an untyped tag of this key
    assert misrouted(zenoh.ZBytes(key_tag(other, ENC)), twist)
    assert misrouted(zenoh.ZBytes(key_tag(other)), twist)
    assert misrouted(zenoh.ZBytes(twist), key_tag(other))  # an action client's untyped tag


def test_only_a_samples_own_typed_tag_skips_the_encoding_check(
        make_node: Any, ctx_pair: Any) -> None:
    got: Collector[Twist] = Collector()
    sub = make_node("robot1_nav", 1).create_subscription(Twist, "/robot1/cmd_vel", got)
    pub = make_node("teleop", 0).create_publisher(Twist, "/robot1/cmd_vel")
    assert pub.wait_for_subscribers(1, 5)
    raw = ctx_pair[0].session
    # a zenros publisher of another type on this key: a type mismatch, not a misrouted sample
    raw.put(sub.key, b'{"x": 1.0}', encoding=VECTOR3, attachment=key_tag(sub.key, VECTOR3))
    assert wait_for(lambda: sub.errors == 1, 5)
    raw.put(sub.key, TWIST, encoding=ENC, attachment=key_tag(sub.key))  # an older publisher
    raw.put(sub.key, TWIST, encoding=ENC, attachment=key_tag(sub.key.replace("robot1", "robot6"),
                                                             ENC))  # misrouted
    pub.publish(Twist(linear=Vector3(x=2.0)))  # its own typed tag: taken
    assert got.wait(2, 5)
    assert [m.linear.x for m in got.items] == [1.5, 2.0]
    assert sub.errors == 1 and sub.misrouted == 1


def test_a_sample_tagged_for_another_key_is_dropped_counted_and_logged(
        make_node: Any, ctx_pair: Any, caplog: pytest.LogCaptureFixture) -> None:
    got: Collector[Twist] = Collector()
    sub = make_node("robot1_nav", 1).create_subscription(Twist, "/robot1/cmd_vel", got)
    pub = make_node("teleop", 0).create_publisher(Twist, "/robot1/cmd_vel")
    assert pub.wait_for_subscribers(1, 5)
    raw = ctx_pair[0].session
    other = key_tag(sub.key.replace("robot1", "robot6"))
    with caplog.at_level(logging.ERROR, logger="zenros"):
        # the same type, another key's tag: what Zenoh's misrouting looks like
        raw.put(sub.key, TWIST, encoding=ENC, attachment=other)
        assert wait_for(lambda: sub.misrouted == 1, 5)
    assert "published on another key" in caplog.text and sub.key in caplog.text
    raw.put(sub.key, TWIST, encoding=ENC)  # untagged (z_put): taken
    raw.put(sub.key, TWIST, encoding=ENC, attachment=b"tool")  # not a tag: taken
    pub.publish(Twist(linear=Vector3(x=2.0)))  # zenros tags its own key: taken
    assert got.wait(3, 5)
    assert [m.linear.x for m in got.items] == [1.5, 1.5, 2.0]
    assert sub.misrouted == 1 and sub.errors == 0


def test_action_feedback_tagged_for_another_action_is_dropped(
        make_node: Any, ctx_pair: Any, caplog: pytest.LogCaptureFixture) -> None:
    release = threading.Event()

    def execute(gh: Any) -> Any:
        gh.publish_feedback(FibonacciFeedback(sequence=[0, 1]))
        release.wait(10)
        gh.succeed()
        return FibonacciResult(sequence=[0, 1])

    server = ActionServer(make_node("srv", 0), Fibonacci, "/robot1/fib", execute)
    client = ActionClient(make_node("cli", 1), Fibonacci, "/robot1/fib")
    assert client.wait_for_server(5)
    feedback: list[Any] = []
    handle = client.send_goal_async(FibonacciGoal(order=2), feedback.append)
    assert wait_for(lambda: len(feedback) == 1, 10)
    key = ctx_pair[0].keys.action("/robot1/fib", "feedback")
    wire = server._wire.FeedbackMessage(goal_id=uuid_msg(handle.goal_id),
                                        feedback=FibonacciFeedback(sequence=[9]))
    with caplog.at_level(logging.ERROR, logger="zenros"):
        ctx_pair[0].session.put(key, server._fb.encode(wire), encoding=server._fb.encoding,
                                attachment=key_tag(key.replace("robot1", "robot6")))
        assert wait_for(lambda: "published on another key" in caplog.text, 5)
    release.set()
    assert handle.result(10).succeeded
    assert [list(f.feedback.sequence) for f in feedback] == [[0, 1]]
