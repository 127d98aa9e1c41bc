"""A bag recorded with ROS (rosbag2 and ROS 1, written by rosbags' own writers) played into
real zenros subscribers over Zenoh: the values and their order as recorded, the map latched."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from ros_bags import make
from zenros.bag import Player, PlayOptions, bag_files
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.tf2_msgs import TFMessage
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.testing import Collector, wait_for

pytest.importorskip("rosbags", reason="rosbags not installed (pip install -e '.[rosbags]')")

N = 20
T0, STEP = 1_700_000_000 * 10**9, 100_000_000  # scripts/make_ros_bag.py's


@pytest.fixture
def listener(ctx_pair: list[Context]) -> Iterator[Node]:
    node = Node("ros_bag_listener", context=ctx_pair[0])
    yield node
    node.close()


@pytest.mark.parametrize("storage", ["sqlite3", "ros1"])
def test_play_a_ros_bag_into_zenros_subscribers(ctx_pair: list[Context], listener: Node,
                                                 tmp_path: Path, storage: str) -> None:
    bag = make(tmp_path, storage, N, unknown=True)
    arrivals: Collector[tuple[str, int]] = Collector()  # (topic, step) as they come
    twists: Collector[Twist] = Collector()
    scans: Collector[LaserScan] = Collector()
    odoms: Collector[Odometry] = Collector()

    def step(topic: str, x: float, scale: float, sink: Collector[Any], m: Any) -> None:
        sink(m)
        arrivals((topic, round(x / scale)))

    listener.create_subscription(
        Twist, "/cmd_vel", lambda m: step("/cmd_vel", m.linear.x, 0.1, twists, m))
    listener.create_subscription(
        LaserScan, "/scan", lambda m: step("/scan", m.ranges[0] - 1.0, 0.1, scans, m))
    listener.create_subscription(
        Odometry, "/odom", lambda m: step("/odom", m.pose.pose.position.x, 0.5, odoms, m))
    listener.create_subscription(
        TFMessage, "/tf",
        lambda m: step("/tf", m.transforms[0].transform.translation.x, 0.5, Collector(), m))
    for topic in ("/cmd_vel", "/scan", "/odom", "/tf"):
        assert wait_for(lambda t=topic: any(  # type: ignore[misc]
            s.node.endswith("ros_bag_listener") for s in ctx_pair[1].graph.subscribers(t)), 10)
    player = Player(ctx_pair[1], bag_files(bag), PlayOptions(rate=4.0))
    try:
        assert player.duration == pytest.approx((N - 1) * 0.1)
        sent: list[int] = []  # the log time of each message as the player sends it
        assert player.play(lambda p: sent.append(p.position)) == 4 * N + 2  # not /custom
        assert wait_for(lambda: len(arrivals) >= 4 * N, 10), len(arrivals)
        # the map is latched: a subscriber that comes after the play still gets it
        grids: Collector[OccupancyGrid] = Collector()
        listener.create_subscription(OccupancyGrid, "/map", grids, QOS_LATCHED)
        assert grids.wait(1, 10)
    finally:
        player.close()
    assert [tw.linear.x for tw in twists.items] == pytest.approx([0.1 * i for i in range(N)])
    assert [o.header.stamp.nanosec for o in odoms.items] == [
        (i * 100_000_000) % 10**9 for i in range(N)]
    np.testing.assert_array_equal(
        scans.items[-1].ranges, (1.0 + 0.01 * np.arange(36) + 0.1 * (N - 1)).astype(np.float32))
    assert grids.items[0].data.tolist() == [0, 100, -1, 0] * 3
    # sent in the bag's log-time order (every step's four messages, then the next step), and
    # each topic received in order (Zenoh orders a topic's samples, not one topic's against
    # another's: on a loaded box a callback may run after the next step's of another topic)
    assert sent == sorted(sent)
    assert [sent.count(T0 + i * STEP) for i in range(N)] == [6] + [4] * (N - 1)
    for topic in ("/cmd_vel", "/scan", "/odom", "/tf"):
        assert [k for t, k in arrivals.items if t == topic] == list(range(N)), topic
