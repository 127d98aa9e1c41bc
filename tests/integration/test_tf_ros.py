"""Broadcasters and listener across two Zenoh sessions: /tf, latched /tf_static, sim time."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import pytest
from zenros.errors import ExtrapolationException
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.msgs.tf2_msgs import TFMessage
from zenros.node import Node
from zenros.testing import Collector
from zenros.tf import (
    LATEST,
    Buffer,
    StaticTransformBroadcaster,
    TransformBroadcaster,
    TransformListener,
    transform_stamped,
)
from zenros.tf.listener import STATIC_LISTENER_QOS


def link(parent: str, child: str, x: float, sec: int = 0) -> TransformStamped:
    return transform_stamped(parent, child, (x, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0), Time(sec=sec))


def send_until(send: Callable[[int], None], done: Callable[[], bool], tries: int = 100) -> None:
    """Send (with a growing index) until ``done()``, which waits on the buffer's condition:
    the first messages may go out before Zenoh routes /tf to the other session."""
    for i in range(tries):
        send(i)
        if done():
            return
    pytest.fail("the listener never got the transform")


def test_broadcaster_fills_a_listener_buffer_in_another_session(make_node: Any) -> None:
    chassis, user = make_node("chassis", 0), make_node("user", 1)
    buf = Buffer()
    TransformListener(buf, user)
    br = TransformBroadcaster(chassis)
    send_until(
        lambda i: br.send_transform([link("odom", "base_link", 1.0, 10 + i),
                                     link("base_link", "wheel", 0.5, 10 + i)]),
        lambda: buf.can_transform("odom", "wheel", LATEST, timeout=0.1),
    )
    t = buf.lookup_transform("odom", "wheel", LATEST)
    assert t.transform.translation.x == pytest.approx(1.5)
    assert t.header.frame_id == "odom" and t.child_frame_id == "wheel"
    assert "default_authority" in buf.all_frames_as_yaml()
    # Later samples keep coming through, and time-indexed lookups interpolate between them.
    newest = t.header.stamp.sec
    br.send_transform(link("odom", "base_link", 3.0, newest + 2))
    br.send_transform(link("base_link", "wheel", 0.5, newest + 2))
    assert buf.can_transform("odom", "wheel", Time(sec=newest + 2), timeout=5)
    mid = buf.lookup_transform("odom", "base_link", Time(sec=newest + 1))
    assert mid.transform.translation.x == pytest.approx(2.0)


def test_broadcaster_rejects_what_is_not_a_transform(make_node: Any) -> None:
    br = TransformBroadcaster(make_node("chassis", 0))
    with pytest.raises(TypeError, match="TransformStamped"):
        br.send_transform([TFMessage()])  # type: ignore[list-item]
    br.close()


def test_late_joiner_gets_every_static_link(make_node: Any) -> None:
    robot = make_node("robot_state_publisher", 0)
    sb = StaticTransformBroadcaster(robot)
    sb.send_transform(link("base_link", "laser", 0.1))  # one send per link: each republishes
    sb.send_transform(link("base_link", "imu", 0.2))  # the whole set (depth-1 latching)
    sb.send_transform(link("base_link", "laser", 0.3))  # same child: replaces
    other = StaticTransformBroadcaster(make_node("camera_driver", 0))
    other.send_transform(link("base_link", "camera", 0.4))
    assert [t.child_frame_id for t in sb.transforms] == ["laser", "imu"]

    late = make_node("late", 1)
    raw: Collector[TFMessage] = Collector()
    buf = Buffer()
    TransformListener(buf, late)
    for child, x in (("laser", 0.3), ("imu", 0.2), ("camera", 0.4)):
        assert buf.can_transform("base_link", child, LATEST, timeout=10), buf.all_frames_as_string()
        assert buf.lookup_transform("base_link", child, LATEST).transform.translation.x == x
    # A latched subscription sees the last message of each broadcaster: all links at once.
    late.create_subscription(TFMessage, "/tf_static", raw, STATIC_LISTENER_QOS)
    assert raw.wait(2, timeout=10)
    assert sorted(len(m.transforms) for m in raw.items[:2]) == [1, 2]


def test_listener_in_the_same_process_gets_statics_too(make_node: Any) -> None:
    sb = StaticTransformBroadcaster(make_node("urdf", 0))
    sb.send_transform(link("base_link", "laser", 0.1))
    buf = Buffer()
    TransformListener(buf, make_node("local_user", 0))
    assert buf.can_transform("base_link", "laser", LATEST, timeout=10)


def test_listener_with_sim_time_clears_the_buffer_when_time_jumps_back(
    make_node: Any,
) -> None:
    sim: Node = make_node("sim_user", 1, parameter_overrides={"use_sim_time": True})
    clock = sim.get_clock()
    clock.set(Time(sec=100))  # type: ignore[attr-defined]  # a ManualClock under sim time
    buf = Buffer()
    listener = TransformListener(buf, sim)
    sb = StaticTransformBroadcaster(make_node("urdf", 0))
    sb.send_transform(link("base_link", "laser", 0.1))
    br = TransformBroadcaster(make_node("sim_chassis", 0))
    send_until(lambda i: br.send_transform(link("odom", "base_link", 1.0, 100)),
               lambda: buf.can_transform("odom", "base_link", Time(sec=100), timeout=0.1))
    assert buf.can_transform("odom", "laser", LATEST, timeout=10)
    assert listener.guard.active and listener.guard.jumps == 0

    clock.set(Time(sec=5))  # type: ignore[attr-defined]  # the simulation restarts
    br.send_transform(link("odom", "base_link", 2.0, 5))
    assert buf.can_transform("odom", "base_link", Time(sec=5), timeout=5)
    assert listener.guard.jumps == 1
    with pytest.raises(ExtrapolationException):  # the old history is gone...
        buf.lookup_transform("odom", "base_link", Time(sec=100))
    t = buf.lookup_transform("odom", "laser", LATEST)  # ...statics stay
    assert t.header.stamp == Time(sec=5) and t.transform.translation.x == pytest.approx(2.1)


def test_listener_on_wall_time_ignores_the_clock(make_node: Any) -> None:
    buf = Buffer()
    listener = TransformListener(buf, make_node("wall", 1))
    assert not listener.guard.active
    listener.unregister()
