"""`PolledSubscription`: samples wait in Zenoh until taken; only the newest is decoded."""

from __future__ import annotations

import threading
import time
from typing import Any

import zenoh
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.std_msgs import String
from zenros.polled import Taken
from zenros.testing import wait_for


def _take_until(sub: Any, n: int, timeout: float = 5.0) -> Taken[Any]:
    """Take repeatedly until ``n`` samples were counted in all; the last newest kept."""
    total: Taken[Any] = Taken()

    def more() -> bool:
        t = sub.take()
        total.count += t.count
        total.arrivals += t.arrivals
        if t.latest is not None:
            total.latest = t.latest
        return total.count >= n

    assert wait_for(more, timeout), f"counted {total.count} of {n}"
    return total


def test_remote_samples_are_counted_and_only_the_newest_decoded(make_node: Any) -> None:
    talker, reader = make_node("talker", 0), make_node("reader", 1)
    sub = reader.create_polled_subscription(Twist, "cmd_vel", 10)
    pub = talker.create_publisher(Twist, "cmd_vel")
    assert pub.wait_for_subscribers(1, 5)
    t0 = time.monotonic()
    for k in range(5):
        pub.publish(Twist(linear=Vector3(x=float(k))))
    got = _take_until(sub, 5)
    assert got.count == 5 and got.latest == Twist(linear=Vector3(x=4.0))
    assert all(t0 - 1.0 <= a <= time.monotonic() + 0.1 for a in got.arrivals)
    assert got.arrivals == sorted(got.arrivals)
    empty = sub.take()
    assert empty.count == 0 and empty.latest is None and empty.arrivals == []


def test_the_ring_keeps_the_last_depth_samples(make_node: Any) -> None:
    talker, reader = make_node("talker", 0), make_node("reader", 1)
    sub = reader.create_polled_subscription(String, "chatter", 3)
    pub = talker.create_publisher(String, "chatter")
    assert pub.wait_for_subscribers(1, 5)
    for k in range(10):
        pub.publish(String(data=str(k)))
    got: Taken[Any] = Taken()
    assert wait_for(lambda: _drain_into(sub, got, "9"), 5)
    assert got.count <= 10 and got.latest == String(data="9")


def _drain_into(sub: Any, got: Taken[Any], last: str) -> bool:
    t = sub.take()
    got.count += t.count
    assert t.count <= 3  # never more than the ring holds
    if t.latest is not None:
        got.latest = t.latest
    return got.latest is not None and got.latest.data == last


def test_a_take_while_samples_keep_coming_returns_at_most_a_ring(make_node: Any) -> None:
    """Samples arriving while `take` drains are the next take's (a take under load once
    counted depth + 1)."""
    talker, reader = make_node("talker", 0), make_node("reader", 1)
    sub = reader.create_polled_subscription(String, "chatter", 3)
    pub = talker.create_publisher(String, "chatter")
    assert pub.wait_for_subscribers(1, 5)
    done = threading.Event()

    def flood() -> None:
        for k in range(3000):
            pub.publish(String(data=str(k)))
        done.set()

    threading.Thread(target=flood, daemon=True).start()
    counts: list[int] = []
    while True:  # takes while the flood goes on, leaving it the GIL between (and one after:
        counts.append(sub.take(decode=False).count)  # beside a CPU hog the flood may end first)
        if done.wait(0.0002):
            counts.append(sub.take(decode=False).count)
            break
    # a loaded box may deliver none before the flood ends: they come in later takes
    assert wait_for(lambda: counts.append(sub.take(decode=False).count) or sum(counts) > 0,
                    5), counts[:50]
    assert max(counts) <= 3, counts[:50]
    # and it goes on (the flood's last sample may have been dropped on the way: a marker)
    after: Taken[Any] = Taken()

    def marker_taken() -> bool:
        pub.publish(String(data="end"))
        return _drain_into(sub, after, "end")

    assert wait_for(marker_taken, 5)


def test_without_decode_arrivals_are_counted(make_node: Any) -> None:
    talker, reader = make_node("talker", 0), make_node("reader", 1)
    sub = reader.create_polled_subscription(String, "chatter", 10)
    pub = talker.create_publisher(String, "chatter")
    assert pub.wait_for_subscribers(1, 5)
    pub.publish(String(data="a"))
    pub.publish(String(data="b"))
    seen = 0

    def two() -> bool:
        nonlocal seen
        t = sub.take(decode=False)
        assert t.latest is None
        seen += t.count
        return seen >= 2

    assert wait_for(two, 5)


def test_in_process_publisher_hands_the_object_over(make_node: Any) -> None:
    a, b = make_node("a", 0), make_node("b", 0)
    sub = b.create_polled_subscription(Twist, "cmd_vel", 10)
    pub = a.create_publisher(Twist, "cmd_vel")
    assert pub.subscription_count >= 1  # the graph and the publisher see a subscriber
    msg = Twist(linear=Vector3(x=1.0))
    pub.publish(Twist())
    pub.publish(msg)
    got = sub.take()
    assert got.count == 2 and got.latest is msg  # no serialization in-process


def test_graph_shows_it_as_a_subscription(make_node: Any) -> None:
    talker, reader = make_node("talker", 0), make_node("reader", 1)
    sub = reader.create_polled_subscription(Twist, "cmd_vel")
    pub = talker.create_publisher(Twist, "cmd_vel")
    assert pub.wait_for_subscribers(1, 5)
    sub.close()
    assert wait_for(lambda: pub.subscription_count == 0, 5)
    assert sub.take().count == 0  # closed: nothing, no error


def test_another_type_on_the_topic_is_refused_and_counted(make_node: Any,
                                                          ctx_pair: Any) -> None:
    reader = make_node("reader", 1)
    sub = reader.create_polled_subscription(Twist, "cmd_vel", 10)
    pub = ctx_pair[0].session.declare_publisher(
        sub.key, encoding=zenoh.Encoding("application/json").with_schema("std_msgs/String"))
    assert wait_for(lambda: pub.matching_status.matching, 5)
    pub.put(b'{"data": "x"}')
    assert wait_for(lambda: (sub.take().count, sub.errors)[1] >= 1, 5)
    pub.undeclare()
