"""zenros.message_filters over real Zenoh topics: Subscribers into a synchronizer and a Cache."""

from __future__ import annotations

from typing import Any

from zenros.message_filters import ApproximateTimeSynchronizer, Cache, Subscriber
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import PointStamped
from zenros.msgs.std_msgs import Header
from zenros.waiting import wait_until


def stamped(sec: float, frame: str) -> PointStamped:
    return PointStamped(header=Header(stamp=Time.from_seconds(sec), frame_id=frame))


def test_three_topics_synchronize_across_sessions(make_node: Any) -> None:
    sender = make_node("sender", 0)
    receiver = make_node("receiver", 1)
    names = ["scan", "odom", "imu"]
    pubs = [sender.create_publisher(PointStamped, n) for n in names]
    subs = [Subscriber(receiver, PointStamped, n) for n in names]
    assert subs[0].getTopic().endswith("/scan")
    sync = ApproximateTimeSynchronizer(subs, 10, 0.05)
    cache = Cache(subs[1], 3)
    got: list[tuple[Any, ...]] = []
    sync.registerCallback(lambda *ms: got.append(ms))
    for p in pubs:
        assert p.wait_for_subscribers(1, 10)
    for k in range(6):
        for i, p in enumerate(pubs):
            p.publish(stamped(k + 0.01 * i, names[i]))
    wait_until(lambda: len(got) >= 5, 10)
    first = got[0]
    assert [m.header.frame_id for m in first] == names
    assert [m.header.stamp for m in first] == [Time.from_seconds(0.01 * i) for i in range(3)]
    assert [m[0].header.stamp.sec for m in got[:5]] == [0, 1, 2, 3, 4]
    wait_until(lambda: cache.getLatestTime() == Time.from_seconds(5.01), 10)
    assert cache.getOldestTime() == Time.from_seconds(3.01)  # 3 kept
    subs[2].close()
