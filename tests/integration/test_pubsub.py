"""Publish/subscribe across sessions and in-process, QoS, and bad input on a topic."""

from __future__ import annotations

import json
import logging
import threading
import time
from typing import Any

import numpy as np
import pytest
import zenoh
from zenros import QOS_LATCHED, QOS_SENSOR, EncodeError, MutuallyExclusiveCallbackGroup
from zenros.errors import NodeClosedError
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import Int64, String
from zenros.pubsub import MessageInfo
from zenros.qos import QoSProfile
from zenros.testing import Collector, wait_for


def test_remote_subscriber_gets_typed_message(make_node: Any) -> None:
    talker, listener = make_node("talker", 0), make_node("listener", 1)
    got: Collector[Twist] = Collector()
    listener.create_subscription(Twist, "cmd_vel", got)
    pub = talker.create_publisher(Twist, "cmd_vel")
    assert pub.wait_for_subscribers(1, 5)
    pub.publish(Twist(linear=Vector3(x=0.2), angular=Vector3(z=-1.5)))
    assert got.wait(1)
    assert got.items[0] == Twist(linear=Vector3(x=0.2), angular=Vector3(z=-1.5))


def test_intra_process_delivers_the_object_itself(make_node: Any) -> None:
    a, b, remote = make_node("a", 0), make_node("b", 0), make_node("remote", 1)
    local: Collector[Twist] = Collector()
    far: Collector[Twist] = Collector()
    b.create_subscription(Twist, "cmd_vel", local)
    remote.create_subscription(Twist, "cmd_vel", far)
    pub = a.create_publisher(Twist, "cmd_vel")
    assert pub.wait_for_subscribers(2, 5)
    msg = Twist(linear=Vector3(x=1.0))
    pub.publish(msg)
    assert local.wait(1) and far.wait(1)
    assert local.items[0] is msg  # no serialization in-process
    assert far.items[0] == msg and far.items[0] is not msg
    assert len(local.items) == 1  # not delivered twice (locally and over Zenoh)


def test_intra_process_without_remote_subscribers_skips_encoding(make_node: Any) -> None:
    a, b = make_node("a", 0), make_node("b", 0)
    got: Collector[String] = Collector()
    b.create_subscription(String, "chatter", got)
    pub = a.create_publisher(String, "chatter")
    assert not pub._remote
    pub.publish(String(data="hi"))
    assert got.wait(1) and got.items[0].data == "hi"


def test_reliable_loses_nothing_at_full_rate(make_node: Any) -> None:
    a, b = make_node("a", 0), make_node("b", 1)
    got: list[int] = []
    done = threading.Event()
    n = 5000

    def on_msg(m: Int64) -> None:
        got.append(m.data)
        if len(got) == n:
            done.set()

    b.create_subscription(Int64, "seq", on_msg)
    pub = a.create_publisher(Int64, "seq")
    assert pub.wait_for_subscribers(1, 5)
    for i in range(n):
        pub.publish(Int64(data=i))
    assert done.wait(20), f"received {len(got)}/{n}"
    assert got == list(range(n))


def test_best_effort_profile_delivers(make_node: Any) -> None:
    a, b = make_node("a", 0), make_node("b", 1)
    got: Collector[Int64] = Collector()
    b.create_subscription(Int64, "scan_rate", got, QOS_SENSOR)
    pub = a.create_publisher(Int64, "scan_rate", QOS_SENSOR)
    assert pub.wait_for_subscribers(1, 5)
    pub.publish(Int64(data=7))
    assert got.wait(1, timeout=2)


def test_latched_topic_reaches_late_joiners(make_node: Any) -> None:
    a = make_node("map_server", 0)
    qos = QoSProfile(depth=2, durability=QOS_LATCHED.durability)
    pub = a.create_publisher(String, "map", qos)
    for text in ("one", "two", "three"):
        pub.publish(String(data=text))
    late_remote: Collector[String] = Collector()
    late_local: Collector[String] = Collector()
    make_node("late_remote", 1).create_subscription(String, "map", late_remote, qos)
    make_node("late_local", 0).create_subscription(String, "map", late_local, qos)
    assert late_remote.wait(2, timeout=5), late_remote.items
    assert late_local.wait(2, timeout=5)
    assert [m.data for m in late_remote.items] == ["two", "three"]
    assert [m.data for m in late_local.items] == ["two", "three"]


def test_bulk_type_travels_as_msgpack_with_numpy(make_node: Any) -> None:
    a, b = make_node("laser", 0), make_node("viewer", 1)
    got: Collector[LaserScan] = Collector()
    b.create_subscription(LaserScan, "scan", got)
    pub = a.create_publisher(LaserScan, "scan")
    assert pub.wait_for_subscribers(1, 5)
    ranges = np.linspace(0.1, 10.0, 720, dtype=np.float32)
    pub.publish(LaserScan(ranges=ranges, range_max=10.0))
    assert got.wait(1, timeout=2)
    assert isinstance(got.items[0].ranges, np.ndarray)
    np.testing.assert_array_equal(got.items[0].ranges, ranges)


def test_async_callbacks_run_in_order_on_the_executor(make_node: Any) -> None:
    a, b = make_node("a", 0), make_node("b", 1)
    seen: list[tuple[int, str]] = []
    done = threading.Event()

    async def on_msg(m: Int64) -> None:
        seen.append((m.data, threading.current_thread().name))
        if len(seen) == 20:
            done.set()

    b.create_subscription(Int64, "n", on_msg, 100)
    pub = a.create_publisher(Int64, "n")
    assert pub.wait_for_subscribers(1, 5)
    for i in range(20):
        pub.publish(Int64(data=i))
    assert done.wait(5)
    assert [i for i, _ in seen] == list(range(20))
    assert {t for _, t in seen} == {"zenros-executor"}


def test_mutually_exclusive_group_serializes_callbacks(make_node: Any) -> None:
    a, b = make_node("a", 0), make_node("b", 1)
    group = MutuallyExclusiveCallbackGroup()
    active = 0
    overlap = False
    count = 0
    lock = threading.Lock()

    def cb(_: Any) -> None:
        nonlocal active, overlap, count
        with lock:
            active += 1
            overlap = overlap or active > 1
        with lock:
            active -= 1
            count += 1

    b.create_subscription(Int64, "x", cb, callback_group=group)
    b.create_subscription(String, "y", cb, callback_group=group)
    p1, p2 = a.create_publisher(Int64, "x"), a.create_publisher(String, "y")
    assert p1.wait_for_subscribers(1, 5) and p2.wait_for_subscribers(1, 5)
    for i in range(200):
        p1.publish(Int64(data=i))
        p2.publish(String(data=str(i)))
    assert wait_for(lambda: count == 400, 10)
    assert not overlap


def test_publishing_the_wrong_type_raises(make_node: Any) -> None:
    pub = make_node("a", 0).create_publisher(Twist, "cmd_vel")
    with pytest.raises(EncodeError, match="geometry_msgs/Twist"):
        pub.publish(String(data="oops"))  # type: ignore[arg-type]


@pytest.mark.parametrize("latched", [False, True])
def test_close_while_another_thread_publishes(make_node: Any, latched: bool) -> None:
    """close() from one thread while another is in publish(): zenoh-python refused to
    undeclare a publisher mid-put ("Already borrowed"), leaving it half closed. Now close()
    returns, and the publishing thread's next publish() says the publisher is closed."""
    talker, listener = make_node("talker", 0), make_node("listener", 1)
    got = Collector[String]()
    listener.create_subscription(String, "chatter", got)
    qos = QOS_LATCHED if latched else QoSProfile()
    for _ in range(5):
        pub = talker.create_publisher(String, "chatter", qos)
        assert pub.wait_for_subscribers(1, 5)
        ended: list[BaseException] = []
        sent = threading.Event()

        def flood(p: Any = pub, out: list[BaseException] = ended, ev: threading.Event = sent
                  ) -> None:
            try:
                while True:
                    p.publish(String(data="x" * 100))
                    ev.set()
            except BaseException as exc:  # noqa: BLE001 what ended it is the point
                out.append(exc)

        thread = threading.Thread(target=flood, daemon=True)
        thread.start()
        assert sent.wait(5)
        pub.close()
        thread.join(5)
        assert not thread.is_alive()
        assert [type(e) for e in ended] == [NodeClosedError], ended
        assert "closed" in str(ended[0])
    assert got.wait(1, 5)


def test_stock_zenoh_subscriber_reads_json(make_node: Any, ctx_pair: Any) -> None:
    """What `z_sub -k 'zenros/topic/**'` prints: readable JSON with the type in the schema."""
    ctx = ctx_pair[1]
    got: Collector[zenoh.Sample] = Collector()
    # the ** of the docs' command, here only this test's topic: a node also publishes
    # /parameter_events as it declares its parameters
    raw = ctx.session.declare_subscriber(f"{ctx.keys.prefix}/topic/robot1/**", got)
    try:
        pub = make_node("a", 0).create_publisher(Twist, "robot1/cmd_vel")
        assert wait_for(lambda: pub._remote, 5)
        pub.publish(Twist(linear=Vector3(x=0.5)))
        assert got.wait(1)
        sample = got.items[0]
        assert str(sample.key_expr) == f"{ctx.keys.prefix}/topic/robot1/cmd_vel"
        assert str(sample.encoding) == "application/json;geometry_msgs/Twist"
        body = json.loads(sample.payload.to_string())
        assert body["linear"] == {"x": 0.5, "y": 0.0, "z": 0.0}
    finally:
        raw.undeclare()


def test_callback_exception_is_logged_and_node_keeps_running(
    make_node: Any, caplog: pytest.LogCaptureFixture
) -> None:
    a, b = make_node("a", 0), make_node("b", 1)
    good: Collector[Int64] = Collector()

    def flaky(m: Int64) -> None:
        if m.data == 0:
            raise RuntimeError("callback bug")
        good(m)

    b.create_subscription(Int64, "n", flaky)
    pub = a.create_publisher(Int64, "n")
    assert pub.wait_for_subscribers(1, 5)
    with caplog.at_level(logging.ERROR, logger="zenros"):
        pub.publish(Int64(data=0))
        pub.publish(Int64(data=1))
        assert good.wait(1)
    assert "callback bug" in caplog.text


@pytest.mark.parametrize("qos", [QoSProfile(depth=10), QOS_SENSOR, QOS_LATCHED],
                         ids=["reliable", "best_effort", "latched"])
def test_a_two_argument_callback_gets_the_message_info(make_node: Any, qos: QoSProfile) -> None:
    got: list[tuple[String, MessageInfo]] = []
    async_got: list[tuple[String, MessageInfo]] = []

    async def on_async(msg: String, info: MessageInfo) -> None:
        async_got.append((msg, info))

    listener = make_node("listener", 1)
    listener.create_subscription(String, "chatter", lambda m, i: got.append((m, i)), qos)
    listener.create_subscription(String, "chatter", on_async, qos)
    local: list[tuple[String, MessageInfo]] = []
    talker = make_node("talker", 0)
    talker.create_subscription(String, "chatter", lambda m, i: local.append((m, i)), qos)
    pub = talker.create_publisher(String, "chatter", qos)
    assert pub.wait_for_subscribers(3, 5)
    before = time.time_ns()
    pub.publish(String(data="hi"))
    assert wait_for(lambda: got and async_got and local, 5)
    msg, info = got[0]
    assert msg.data == "hi" and not info.from_intra_process
    assert info.publisher_gid == talker.context.zid  # the graph names its nodes from this
    assert talker.graph.nodes_of_zid(info.publisher_gid, "/chatter") == ["/talker"]
    assert before - 1_000_000_000 < info.source_timestamp <= info.received_timestamp
    assert async_got[0][1].publisher_gid == talker.context.zid
    msg, info = local[0]
    assert info.from_intra_process and info.publisher_gid == talker.context.zid
    assert info.source_timestamp == info.received_timestamp
