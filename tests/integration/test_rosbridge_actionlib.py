"""ROS 1 actionlib over rosbridge topics, bridged onto zenros actions both ways: roslibpy's
``actionlib.ActionClient`` drives a zenros action server, and roslibpy's
``SimpleActionServer`` serves a zenros action that a zenros ActionClient calls."""

from __future__ import annotations

import threading
import time
from typing import Any

import roslibpy
from roslibpy.ros1.actionlib import ActionClient, Goal, GoalStatus, SimpleActionServer
from zenros.action import GoalStatus as Ros2Status
from zenros.context import Context
from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal
from zenros.node import Node
from zenros.services.gateway.rosbridge import RosbridgeServer
from zenros.services.gateway.rosbridge.actionlib import ros1_status, zenros_action_type
from zenros.testing import wait_for

TIMEOUT = 10.0
ROS1_TYPE = "actionlib_tutorials/FibonacciAction"


def fibonacci_server(ctx: Context, period: float) -> Node:
    from zenros.examples.fibonacci_server import FibonacciServer

    return FibonacciServer(context=ctx, parameter_overrides={"period": period})


def test_status_codes_map_onto_actionlib() -> None:
    assert ros1_status(Ros2Status.ACCEPTED, False) == GoalStatus.PENDING
    assert ros1_status(Ros2Status.EXECUTING, True) == GoalStatus.ACTIVE
    assert ros1_status(Ros2Status.SUCCEEDED, True) == GoalStatus.SUCCEEDED
    assert ros1_status(Ros2Status.CANCELED, True) == GoalStatus.PREEMPTED
    assert ros1_status(Ros2Status.CANCELED, False) == GoalStatus.RECALLED
    assert ros1_status(Ros2Status.CANCELING, True) == GoalStatus.PREEMPTING
    assert ros1_status(Ros2Status.ABORTED, True) == GoalStatus.ABORTED
    assert ros1_status(Ros2Status.REJECTED, False) == GoalStatus.REJECTED
    assert ros1_status(Ros2Status.LOST, True) == GoalStatus.LOST
    assert zenros_action_type(ROS1_TYPE.removesuffix("Action")) is Fibonacci
    assert zenros_action_type("actionlib/Test") is None  # zenros has no such action


def test_roslibpy_action_client_drives_a_zenros_action(ctx_pair: list[Context],
                                                       server: RosbridgeServer,
                                                       ros: roslibpy.Ros) -> None:
    fib = fibonacci_server(ctx_pair[1], 0.02)
    try:
        assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
        client = ActionClient(ros, "/fibonacci", ROS1_TYPE)  # waits for a status array
        feedback: list[Any] = []
        goal = Goal(client, roslibpy.Message({"order": 8}))
        goal.on("feedback", feedback.append)
        goal.send()
        result = goal.wait(TIMEOUT)
        assert result["sequence"] == [0, 1, 1, 2, 3, 5, 8, 13, 21]
        assert goal.status["status"] == GoalStatus.SUCCEEDED
        assert goal.status["goal_id"]["id"] == goal.goal_id
        assert feedback and feedback[-1]["sequence"] == [0, 1, 1, 2, 3, 5, 8, 13, 21]
        client.dispose()
    finally:
        fib.close()


def test_roslibpy_action_client_cancels_a_zenros_goal(ctx_pair: list[Context],
                                                      server: RosbridgeServer,
                                                      ros: roslibpy.Ros) -> None:
    fib = fibonacci_server(ctx_pair[1], 0.2)
    try:
        assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
        client = ActionClient(ros, "/fibonacci", ROS1_TYPE)
        feedback: list[Any] = []
        goal = Goal(client, roslibpy.Message({"order": 50}))
        goal.on("feedback", feedback.append)
        goal.send()
        assert wait_for(lambda: len(feedback) >= 1, TIMEOUT)
        goal.cancel()
        result = goal.wait(TIMEOUT)
        assert goal.status["status"] == GoalStatus.PREEMPTED
        assert len(result["sequence"]) < 50
        client.dispose()
    finally:
        fib.close()


def test_roslibpy_simple_action_server_serves_a_zenros_action(
        ctx_pair: list[Context], server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    action_server = SimpleActionServer(ros, "/ros1_fibonacci", ROS1_TYPE)
    done = threading.Event()

    def execute(goal: dict[str, Any]) -> None:
        seq = [0, 1]
        for i in range(1, goal["order"]):
            seq.append(seq[i] + seq[i - 1])
            action_server.send_feedback({"sequence": list(seq)})
            time.sleep(0.01)
        action_server.set_succeeded({"sequence": seq})
        done.set()

    action_server.start(execute)
    caller = Node("caller", context=ctx_pair[1])
    try:
        client = caller.create_action_client(Fibonacci, "/ros1_fibonacci")
        assert client.wait_for_server(TIMEOUT)
        feedback: list[Any] = []
        handle = client.send_goal_async(FibonacciGoal(order=6), feedback.append)
        result = handle.result(TIMEOUT)
        assert result.status is Ros2Status.SUCCEEDED
        assert list(result.result.sequence) == [0, 1, 1, 2, 3, 5, 8]
        assert feedback and list(feedback[-1].feedback.sequence) == [0, 1, 1, 2, 3, 5, 8]
        assert done.wait(TIMEOUT)
    finally:
        caller.close()


def test_a_goal_that_does_not_fit_is_rejected_and_the_connection_stays(
        ctx_pair: list[Context], server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    fib = fibonacci_server(ctx_pair[1], 0.02)
    try:
        assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
        client = ActionClient(ros, "/fibonacci", ROS1_TYPE)
        bad = Goal(client, roslibpy.Message({"order": 3, "no_such_field": 1}))
        bad.send()
        assert wait_for(lambda: bad.status is not None
                        and bad.status["status"] == GoalStatus.REJECTED, TIMEOUT)
        good = Goal(client, roslibpy.Message({"order": 3}))
        good.send()
        assert good.wait(TIMEOUT)["sequence"] == [0, 1, 1, 2]
        client.dispose()
    finally:
        fib.close()


def test_a_ros1_server_without_a_zenros_type_stays_between_clients(
        server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    SimpleActionServer(ros, "/ros1_test", "actionlib/TestAction")
    assert wait_for(lambda: "/ros1_test/goal" in server.bridge.opaque.topics, TIMEOUT)
    assert "/ros1_test" not in server.bridge.actionlib.served
    assert not server.node.graph.actions().get("/ros1_test")


def test_a_zenros_cancel_preempts_the_ros1_server_goal(
        ctx_pair: list[Context], server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    action_server = SimpleActionServer(ros, "/ros1_slow", ROS1_TYPE)
    started = threading.Event()

    def execute(goal: dict[str, Any]) -> None:
        started.set()
        deadline = time.monotonic() + TIMEOUT
        while not action_server.is_preempt_requested() and time.monotonic() < deadline:
            action_server.send_feedback({"sequence": [0, 1]})
            time.sleep(0.02)
        action_server.set_preempted()

    action_server.start(execute)
    caller = Node("caller", context=ctx_pair[1])
    try:
        client = caller.create_action_client(Fibonacci, "/ros1_slow")
        assert client.wait_for_server(TIMEOUT)
        handle = client.send_goal_async(FibonacciGoal(order=60))
        assert started.wait(TIMEOUT)
        assert handle.cancel()
        result = handle.result(TIMEOUT)
        assert result.status is Ros2Status.CANCELED
    finally:
        caller.close()


def test_the_ros1_tutorial_server_answers_the_ros1_door(ctx_pair: list[Context],
                                                        server: RosbridgeServer,
                                                        ros: roslibpy.Ros) -> None:
    """roslibjs's examples (setup_examples.launch) run ROS 1's actionlib_tutorials server:
    order 7 is 7 feedbacks and 9 numbers. The sim's ROS 1 door is that node, a rosbridge
    client; the ROS 2 action /fibonacci beside it keeps its own answer (8 numbers)."""
    from zenros.examples.actionlib_fibonacci_server import ActionlibFibonacciServer

    fib = fibonacci_server(ctx_pair[1], 0.02)
    ros1 = ActionlibFibonacciServer(context=ctx_pair[1], parameter_overrides={
        "url": f"ws://127.0.0.1:{server.port}/", "period": 0.02})
    caller = Node("caller", context=ctx_pair[1])
    try:
        assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
        assert wait_for(lambda: "/fibonacci/goal" in server.bridge.opaque.topics, TIMEOUT)
        client = ActionClient(ros, "/fibonacci", ROS1_TYPE)  # waits for a status array
        feedback: list[Any] = []
        goal = Goal(client, roslibpy.Message({"order": 7}))
        goal.on("feedback", feedback.append)
        goal.send()
        result = goal.wait(TIMEOUT)
        assert result["sequence"] == [0, 1, 1, 2, 3, 5, 8, 13, 21]
        assert goal.status["status"] == GoalStatus.SUCCEEDED
        assert [f["sequence"] for f in feedback] == [
            [0, 1, 1], [0, 1, 1, 2], [0, 1, 1, 2, 3], [0, 1, 1, 2, 3, 5],
            [0, 1, 1, 2, 3, 5, 8], [0, 1, 1, 2, 3, 5, 8, 13], [0, 1, 1, 2, 3, 5, 8, 13, 21]]
        assert "/fibonacci" not in server.bridge.actionlib.proxies  # not the ROS 2 action

        slow = Goal(client, roslibpy.Message({"order": 500}))
        slow.send()
        assert wait_for(lambda: slow.status and slow.status["status"] == GoalStatus.ACTIVE,
                        TIMEOUT)
        slow.cancel()
        slow.wait(TIMEOUT)
        assert slow.status["status"] == GoalStatus.PREEMPTED
        client.dispose()

        zenros_client = caller.create_action_client(Fibonacci, "/fibonacci")
        handle = zenros_client.send_goal_async(FibonacciGoal(order=7))
        assert list(handle.result(TIMEOUT).result.sequence) == [0, 1, 1, 2, 3, 5, 8, 13]
    finally:
        caller.close()
        ros1.close()
        fib.close()


def test_get_topics_lists_the_actionlib_topics_of_the_offered_actions(
        ctx_pair: list[Context], server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    """As a ROS 1 master lists an actionlib server's topics from its start (roslibjs's ROS 1
    check-topics example expects them before any goal): each zenros action a ROS 1 client
    can use through the bridge shows its ``status``, ``feedback`` and ``result`` in rosapi's
    ``topics`` under ROS 1 types, and so does the bridge's own tf2_web_republisher."""
    fib = fibonacci_server(ctx_pair[1], 0.02)
    try:
        assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
        want = {"/fibonacci/feedback", "/fibonacci/status", "/fibonacci/result",
                "/tf2_web_republisher/status", "/tf2_web_republisher/feedback"}
        topics = ros.get_topics()  # roslibpy's ROS 1 style call of /rosapi/topics
        assert want <= set(topics), sorted(want - set(topics))
        assert ros.get_topic_type("/fibonacci/feedback") == \
            "actionlib_tutorials/msg/FibonacciActionFeedback"
        assert ros.get_topic_type("/fibonacci/result") == \
            "actionlib_tutorials/msg/FibonacciActionResult"
        assert ros.get_topic_type("/fibonacci/status") == "actionlib_msgs/msg/GoalStatusArray"
        assert ros.get_topic_type("/tf2_web_republisher/feedback") == \
            "tf2_web_republisher/msg/TFSubscriptionActionFeedback"
        assert "/fibonacci/status" in ros.get_topics_for_type("actionlib_msgs/GoalStatusArray")
    finally:
        fib.close()
    assert wait_for(lambda: "/fibonacci/status" not in ros.get_topics(), TIMEOUT)
