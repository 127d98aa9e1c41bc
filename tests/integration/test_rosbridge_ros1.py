"""rosbridge for ROS 1 clients (roslibpy's ros1 side, roslibjs's ROS 1 examples): ROS 1 time
names, parameters through rosapi, client-advertised topics in rosapi, and types zenros has no
definition for, carried between rosbridge clients unchecked."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import roslibpy
from zenros.context import Context
from zenros.msgs.geometry_msgs import PointStamped
from zenros.node import Node
from zenros.services.gateway.rosbridge import RosbridgeServer
from zenros.services.master.node import MasterNode
from zenros.testing import Collector, roslibpy_connect, wait_for

TIMEOUT = 10.0


def test_ros1_header_with_seq_and_secs_nsecs_is_published(server: RosbridgeServer,
                                                          ros: roslibpy.Ros, robot: Node) -> None:
    got: Collector[PointStamped] = Collector()
    robot.create_subscription(PointStamped, "/points", got)
    pub = roslibpy.Topic(ros, "/points", "geometry_msgs/PointStamped")
    pub.advertise()
    assert wait_for(lambda: robot.graph.publishers("/points"), TIMEOUT)
    stamp = roslibpy.Time(12, 34)
    msg = roslibpy.Message({"header": roslibpy.Header(seq=3, stamp=stamp, frame_id="base"),
                            "point": {"x": 0.0, "y": 1.0, "z": 2.0}})
    assert dict(msg)["header"]["stamp"] == {"secs": 12, "nsecs": 34}  # what roslibpy sends
    assert wait_for(lambda: (pub.publish(msg), len(got) > 0)[1], TIMEOUT)
    assert got.items[0].header.stamp.sec == 12
    assert got.items[0].header.stamp.nanosec == 34
    assert got.items[0].header.frame_id == "base"
    assert got.items[0].point.z == 2.0


def test_get_param_of_an_unset_name_is_none(ctx_pair: list[Context], tmp_path: Path,
                                            server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    master = MasterNode(context=ctx_pair[1], parameter_overrides={"data_dir": str(tmp_path)})
    try:
        assert server.bridge.params.wait_for_master(TIMEOUT)
        param = roslibpy.Param(ros, "test_param")
        assert param.get(timeout=TIMEOUT) is None
        param.set("test_value", timeout=TIMEOUT)
        assert param.get(timeout=TIMEOUT) == "test_value"
        param.delete(timeout=TIMEOUT)
        assert param.get(timeout=TIMEOUT) is None
    finally:
        master.close()


def test_get_topics_lists_a_client_advertised_topic_until_unadvertise(
        server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    for type_name in ("std_msgs/String", "rospy_tutorials/Floats"):  # known, and unknown
        name = "/some_test_topic_" + type_name.split("/")[0]
        topic = roslibpy.Topic(ros, name, type_name)
        assert name not in ros.get_topics()
        topic.advertise()
        assert wait_for(lambda: name in ros.get_topics(), TIMEOUT)
        topic.unadvertise()
        assert wait_for(lambda: name not in ros.get_topics(), TIMEOUT)


def test_a_service_of_an_unknown_type_is_served_between_clients(
        server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    def add_two_ints(request: dict[str, Any], response: dict[str, Any]) -> bool:
        response["sum"] = request["a"] + request["b"]
        return False  # as roslibpy's own test: the reference servers answer with the values

    service = roslibpy.Service(ros, "/test_sum_service", "rospy_tutorials/AddTwoInts")
    service.advertise(add_two_ints)
    other = roslibpy_connect("127.0.0.1", server.port, TIMEOUT)
    try:
        client = roslibpy.Service(other, "/test_sum_service", "rospy_tutorials/AddTwoInts")
        assert wait_for(lambda: "/test_sum_service" in other.get_services(),
                        TIMEOUT)
        assert other.get_service_type("/test_sum_service") == \
            "rospy_tutorials/srv/AddTwoInts"
        assert client.call(roslibpy.ServiceRequest({"a": 2, "b": 40}),
                           timeout=TIMEOUT)["sum"] == 42
        service.unadvertise()
        assert wait_for(lambda: "/test_sum_service" not in other.get_services(),
                        TIMEOUT)
        with pytest.raises(roslibpy.core.ServiceException, match="does not exist"):
            client.call(roslibpy.ServiceRequest({"a": 1, "b": 1}), timeout=TIMEOUT)
    finally:
        other.close()


def test_a_topic_of_an_unknown_type_is_carried_between_clients(
        server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    other = roslibpy_connect("127.0.0.1", server.port, TIMEOUT)
    try:
        got: Collector[dict[str, Any]] = Collector()
        listener = roslibpy.Topic(other, "/test_action/status", "actionlib_msgs/GoalStatusArray")
        listener.subscribe(got)
        talker = roslibpy.Topic(ros, "/test_action/status", "actionlib_msgs/GoalStatusArray")
        msg = {"header": {"seq": 1, "stamp": {"secs": 1, "nsecs": 2}, "frame_id": ""},
               "status_list": [{"goal_id": {"id": "g1"}, "status": 3, "text": ""}]}
        assert wait_for(lambda: (talker.publish(roslibpy.Message(msg)), len(got) > 0)[1],
                        TIMEOUT)
        assert got.items[0] == msg  # as the publisher wrote it
        talker.unadvertise()
        listener.unsubscribe()
        assert wait_for(lambda: not server.bridge.opaque.topics, TIMEOUT)
    finally:
        other.close()


def test_a_ros1_action_of_an_unknown_type_between_clients(server: RosbridgeServer,
                                                          ros: roslibpy.Ros) -> None:
    """roslibpy's SimpleActionServer and ActionClient (actionlib over topics) on two
    connections, in a type zenros does not know; a cancel without a stamp gets the
    reference's default (roslibpy's server reads it)."""
    from roslibpy.ros1.actionlib import ActionClient, Goal, GoalStatus, SimpleActionServer

    action_server = SimpleActionServer(ros, "/count_action", "actionlib/TestAction")

    def execute(goal: dict[str, Any]) -> None:
        if goal["goal"] < 0:
            while not action_server.is_preempt_requested():
                wait_for(action_server.is_preempt_requested, 0.1)
            action_server.set_preempted()
        else:
            action_server.set_succeeded({"result": goal["goal"] * 2})

    action_server.start(execute)
    other = roslibpy_connect("127.0.0.1", server.port, TIMEOUT)
    try:
        client = ActionClient(other, "/count_action", "actionlib/TestAction")
        done = Goal(client, {"goal": 21})
        done.send()
        assert done.wait(TIMEOUT)["result"] == 42
        assert done.status["status"] == GoalStatus.SUCCEEDED
        stopped = Goal(client, {"goal": -1})
        stopped.send()
        assert wait_for(lambda: stopped.status["status"] == GoalStatus.ACTIVE, TIMEOUT)
        stopped.cancel()
        assert stopped.wait(TIMEOUT)["result"] == 0
        assert stopped.status["status"] == GoalStatus.PREEMPTED
        client.dispose()
    finally:
        other.close()
