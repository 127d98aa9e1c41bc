"""tf2_web_republisher in the bridge: roslibpy's TFClient (the /republish_tfs service) and
roslibjs's TFClient (the ROS 1 action /tf2_web_republisher over its topics), from the TF
buffer."""

from __future__ import annotations

import json
import threading
from collections.abc import Iterator
from typing import Any

import pytest
from roslibpy.tf import TFClient
from websockets.sync.client import connect
from zenros.context import Context
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.node import Node
from zenros.services.gateway.rosbridge import RosbridgeServer
from zenros.testing import Collector, roslibpy_connect, wait_for
from zenros.tf import StaticTransformBroadcaster, TransformBroadcaster

TIMEOUT = 10.0


@pytest.fixture
def robot(ctx_pair: list[Context]) -> Iterator[Node]:
    """The robot side, with a static world -> turtle1 (as roslibjs's setup_examples.launch)."""
    node = Node("robot", context=ctx_pair[1])
    StaticTransformBroadcaster(node).send_transform(link("world", "turtle1", 1.0, 2.0))
    yield node
    node.close()


def link(parent: str, child: str, x: float, y: float) -> TransformStamped:
    t = TransformStamped(child_frame_id=child)
    t.header.frame_id = parent
    t.transform.translation.x = x
    t.transform.translation.y = y
    t.transform.rotation.w = 1.0
    return t


def test_roslibpy_tf_client_through_republish_tfs(server: RosbridgeServer, robot: Node) -> None:
    ros = roslibpy_connect("127.0.0.1", server.port, TIMEOUT)
    try:
        got: Collector[dict[str, Any]] = Collector()
        client = TFClient(ros, fixed_frame="world", angular_threshold=0.01,
                          translation_threshold=0.01)
        client.subscribe(frame_id="turtle1", callback=got)
        assert wait_for(lambda: len(got) > 0, TIMEOUT)
        assert got.items[0]["translation"] == {"x": 1.0, "y": 2.0, "z": 0.0}
        assert got.items[0]["rotation"] == {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}
        identity: Collector[dict[str, Any]] = Collector()
        client.subscribe(frame_id="/world", callback=identity)  # the fixed frame itself
        assert wait_for(lambda: len(identity) > 0, TIMEOUT)
        assert identity.items[0]["translation"] == {"x": 0.0, "y": 0.0, "z": 0.0}
        topic = client.current_topic.name
        assert topic.startswith("/tf_repub_")
        assert topic in ros.get_topics()
        assert "/republish_tfs" in ros.get_services()
    finally:
        ros.close()


def test_roslibjs_tf_client_through_the_ros1_action(server: RosbridgeServer,
                                                    robot: Node) -> None:
    """The frames roslibjs 2.1's TFClient sends: the actionlib goal and cancel topics, the
    feedback subscription; feedback follows the trans/angular thresholds."""
    moving = TransformBroadcaster(robot)
    with connect(f"ws://127.0.0.1:{server.port}/", open_timeout=TIMEOUT) as ws:
        def send(**frame: Any) -> None:
            ws.send(json.dumps(frame))

        base = "/tf2_web_republisher"
        act = "tf2_web_republisher/TFSubscriptionAction"
        send(op="subscribe", id="f", topic=base + "/feedback", type=act + "Feedback")
        send(op="advertise", id="g", topic=base + "/goal", type=act + "Goal")
        send(op="advertise", id="c", topic=base + "/cancel", type="actionlib_msgs/GoalID")
        goal = {"goal_id": {"stamp": {"secs": 0, "nsecs": 0}, "id": "goal_1"},
                "goal": {"source_frames": ["turtle1", "robot"], "target_frame": "world",
                         "angular_thres": 0.01, "trans_thres": 0.01, "rate": 20.0}}
        send(op="publish", id="p", topic=base + "/goal", msg=goal)
        stop = threading.Event()

        def move() -> None:
            x = 0.0
            while not stop.wait(0.02):
                moving.send_transform(link("world", "robot", x, 0.0))
                x += 0.001  # below trans_thres per step: sent every 10th step or so
        mover = threading.Thread(target=move)
        mover.start()
        try:
            seen: dict[str, list[float]] = {}
            while len(seen.get("robot", [])) < 3:
                frame = json.loads(ws.recv(TIMEOUT))
                assert frame["op"] == "publish" and frame["topic"] == base + "/feedback"
                msg = frame["msg"]
                assert msg["status"]["goal_id"]["id"] == "goal_1"
                for t in msg["feedback"]["transforms"]:
                    assert t["header"]["frame_id"] == "world"
                    seen.setdefault(t["child_frame_id"], []).append(
                        t["transform"]["translation"]["x"])
            assert seen["turtle1"] == [1.0]  # a static link is sent once
            xs = seen["robot"]
            assert all(b - a > 0.01 for a, b in zip(xs, xs[1:], strict=False))
            send(op="publish", id="p2", topic=base + "/cancel", msg={"id": "goal_1"})
            assert wait_for(lambda: not server.bridge.tf_republisher._goals, TIMEOUT)
        finally:
            stop.set()
            mover.join()
