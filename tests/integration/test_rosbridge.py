"""rosbridge v2 against roslibpy 2.1 (unmodified): every op, rosapi, errors, reconnects.

The bridge runs on one Zenoh session, the "robot" nodes on another, as two processes would.
"""

from __future__ import annotations

import itertools
import json
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import roslibpy
from roslibpy.core import RosTimeoutError, ServiceException
from websockets.sync.client import connect
from zenros.context import Context
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.rpc import Client
from zenros.services.gateway.rosbridge import RosbridgeServer
from zenros.services.gateway.ws_slices import SLICE
from zenros.services.master.node import MasterNode
from zenros.testing import Collector, free_port, roslibpy_connect, wait_for

TIMEOUT = 10.0


@pytest.fixture
def bridge_node(ctx_pair: list[Context]) -> Iterator[Node]:
    node = Node("rosbridge", context=ctx_pair[0])
    yield node
    node.close()


@pytest.fixture
def server(bridge_node: Node) -> Iterator[RosbridgeServer]:
    srv = RosbridgeServer(bridge_node, port=0)
    srv.start_in_thread()
    yield srv
    srv.stop_in_thread()


# robot and ros: tests/integration/conftest.py (ros connects to the server above)


def raw(server: RosbridgeServer) -> Any:
    """A bare WebSocket to the bridge, to see exactly which frames come back."""
    return connect(f"ws://127.0.0.1:{server.port}/", open_timeout=TIMEOUT)


def recv_json(ws: Any, timeout: float = TIMEOUT) -> dict[str, Any]:
    frame: dict[str, Any] = json.loads(ws.recv(timeout))
    return frame


# ------------------------------------------------------------------ topics


def test_subscribe_receives_a_zenros_topic(server: RosbridgeServer, ros: roslibpy.Ros,
                                           robot: Node) -> None:
    pub = robot.create_publisher(String, "/chatter")
    got: Collector[dict[str, Any]] = Collector()
    topic = roslibpy.Topic(ros, "/chatter", "std_msgs/String")
    topic.subscribe(got)
    assert pub.wait_for_subscribers(1, TIMEOUT)
    assert wait_for(lambda: (pub.publish(String(data="hi")), len(got) > 0)[1], TIMEOUT)
    assert got.items[0] == {"data": "hi"}
    topic.unsubscribe()
    assert wait_for(lambda: not robot.graph.subscribers("/chatter"), TIMEOUT)


def test_roslibpy_receives_a_large_message_whole(server: RosbridgeServer, ros: roslibpy.Ros,
                                                robot: Node) -> None:
    """A message over `SLICE` bytes goes out as a fragmented WebSocket message
    (test_rosbridge_cbor.py shows the frames); roslibpy's WebSocket (autobahn) joins it."""
    pub = robot.create_publisher(String, "/big_whole")
    got: Collector[dict[str, Any]] = Collector()
    topic = roslibpy.Topic(ros, "/big_whole", "std_msgs/String")
    topic.subscribe(got)
    assert pub.wait_for_subscribers(1, TIMEOUT)
    text = "".join(chr(ord("a") + i % 26) for i in range(3 * SLICE + 5))
    assert wait_for(lambda: (pub.publish(String(data=text)), len(got) > 0)[1], TIMEOUT)
    assert got.items[0] == {"data": text}
    topic.unsubscribe()


def test_subscribe_without_type_takes_it_from_the_graph(server: RosbridgeServer,
                                                        ros: roslibpy.Ros, robot: Node) -> None:
    pub = robot.create_publisher(Twist, "/cmd_vel")
    assert wait_for(lambda: "/cmd_vel" in server.node.graph.topics(), TIMEOUT)
    got: Collector[dict[str, Any]] = Collector()
    roslibpy.Topic(ros, "/cmd_vel", None).subscribe(got)
    assert pub.wait_for_subscribers(1, TIMEOUT)
    msg = Twist()
    msg.linear.x = 0.5
    assert wait_for(lambda: (pub.publish(msg), len(got) > 0)[1], TIMEOUT)
    assert got.items[0]["linear"] == {"x": 0.5, "y": 0.0, "z": 0.0}


def test_advertise_and_publish_reach_zenros(server: RosbridgeServer, ros: roslibpy.Ros,
                                            robot: Node) -> None:
    got: Collector[String] = Collector()
    robot.create_subscription(String, "/from_browser", got)
    topic = roslibpy.Topic(ros, "/from_browser", "std_msgs/msg/String")
    topic.advertise()
    assert wait_for(lambda: robot.graph.publishers("/from_browser"), TIMEOUT)
    assert wait_for(lambda: (topic.publish(roslibpy.Message({"data": "x"})), len(got) > 0)[1],
                    TIMEOUT)
    assert got.items[0] == String(data="x")
    topic.unadvertise()
    assert wait_for(lambda: not robot.graph.publishers("/from_browser"), TIMEOUT)


def test_two_clients_talk_through_the_bridge(server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    other = roslibpy_connect("127.0.0.1", server.port, TIMEOUT)
    try:
        got: Collector[dict[str, Any]] = Collector()
        roslibpy.Topic(other, "/relay", "std_msgs/String").subscribe(got)
        talker = roslibpy.Topic(ros, "/relay", "std_msgs/String")
        assert wait_for(lambda: (talker.publish(roslibpy.Message({"data": "a"})),
                                 len(got) > 0)[1], TIMEOUT)
        assert got.items[0] == {"data": "a"}
    finally:
        other.close()


def test_throttle_rate_spaces_frames_and_queue_length_keeps_the_newest(
        server: RosbridgeServer, robot: Node) -> None:
    pub = robot.create_publisher(String, "/fast")
    with raw(server) as ws:
        ws.send(json.dumps({"op": "subscribe", "id": "s1", "topic": "/fast",
                            "type": "std_msgs/String", "throttle_rate": 300,
                            "queue_length": 1}))
        assert pub.wait_for_subscribers(1, TIMEOUT)
        pub.publish(String(data="0"))
        first = recv_json(ws)
        assert first["op"] == "publish" and first["msg"] == {"data": "0"}
        for i in range(1, 50):
            pub.publish(String(data=str(i)))
        seen, times = [], []
        while not seen or seen[-1] != "49":
            seen.append(recv_json(ws)["msg"]["data"])
            times.append(time.monotonic())
        assert len(seen) < 10  # most of the 49 were dropped: the newest one always arrives
        assert all(b - a > 0.25 for a, b in itertools.pairwise(times))
        with pytest.raises(TimeoutError):
            ws.recv(0.4)


def test_fragment_size_splits_large_frames(server: RosbridgeServer, robot: Node) -> None:
    pub = robot.create_publisher(String, "/big")
    with raw(server) as ws:
        ws.send(json.dumps({"op": "subscribe", "topic": "/big", "type": "std_msgs/String",
                            "fragment_size": 100}))
        assert pub.wait_for_subscribers(1, TIMEOUT)
        pub.publish(String(data="y" * 450))
        parts = [recv_json(ws)]
        while parts[-1]["num"] < parts[-1]["total"] - 1:
            parts.append(recv_json(ws))
        assert all(p["op"] == "fragment" and len(p["data"]) <= 100 for p in parts)
        assert json.loads("".join(p["data"] for p in parts))["msg"] == {"data": "y" * 450}


def test_incoming_fragments_are_joined(server: RosbridgeServer, robot: Node) -> None:
    got: Collector[String] = Collector()
    robot.create_subscription(String, "/joined", got)
    text = json.dumps({"op": "publish", "topic": "/joined", "msg": {"data": "z"}})
    with raw(server) as ws:
        ws.send(json.dumps({"op": "advertise", "topic": "/joined", "type": "std_msgs/String"}))
        assert wait_for(lambda: robot.graph.publishers("/joined"), TIMEOUT)
        for i in range(0, len(text), 10):
            ws.send(json.dumps({"op": "fragment", "id": "f", "data": text[i:i + 10],
                                "num": i // 10, "total": (len(text) + 9) // 10}))
        assert got.wait(1, TIMEOUT)


def test_a_slow_client_never_stalls_the_publisher(server: RosbridgeServer, robot: Node) -> None:
    pub = robot.create_publisher(String, "/flood")
    payload = "p" * 20_000
    with raw(server) as ws:  # never reads until the end: its socket backs up
        ws.send(json.dumps({"op": "subscribe", "topic": "/flood", "type": "std_msgs/String",
                            "queue_length": 2}))
        assert pub.wait_for_subscribers(1, TIMEOUT)
        done = threading.Event()

        def flood() -> None:
            for i in range(3000):
                pub.publish(String(data=f"{i}:{payload}"))
            pub.publish(String(data="last"))
            done.set()

        threading.Thread(target=flood, daemon=True).start()
        assert done.wait(30), "the publisher was held up by a slow rosbridge client"
        seen = []
        while True:
            seen.append(recv_json(ws)["msg"]["data"])
            if seen[-1] == "last":
                break
        assert len(seen) < 3001  # the backlog was cut down to the newest


# ------------------------------------------------------------------ services


def test_call_service_on_a_zenros_service(server: RosbridgeServer, ros: roslibpy.Ros,
                                          robot: Node) -> None:
    robot.create_service(AddTwoInts, "/add_two_ints",
                         lambda r: AddTwoIntsResponse(sum=r.a + r.b))
    assert wait_for(lambda: server.node.graph.servers("/add_two_ints"), TIMEOUT)
    svc = roslibpy.Service(ros, "/add_two_ints", "example_interfaces/srv/AddTwoInts")
    assert svc.call(roslibpy.ServiceRequest({"a": 2, "b": 3}), timeout=TIMEOUT) == {"sum": 5}


def test_call_service_errors_carry_the_id(server: RosbridgeServer, robot: Node) -> None:
    robot.create_service(AddTwoInts, "/add", lambda r: AddTwoIntsResponse(sum=r.a // r.b))
    assert wait_for(lambda: server.node.graph.servers("/add"), TIMEOUT)
    with raw(server) as ws:
        ws.send(json.dumps({"op": "call_service", "id": "c1", "service": "/nope"}))
        reply = recv_json(ws)
        assert reply == {"op": "service_response", "service": "/nope", "id": "c1",
                         "values": "Service /nope does not exist", "result": False}
        ws.send(json.dumps({"op": "call_service", "id": 7, "service": "/add",
                            "args": {"a": 1, "c": 2}}))
        reply = recv_json(ws)
        assert reply["id"] == 7 and reply["result"] is False and "'c'" in reply["values"]
        ws.send(json.dumps({"op": "call_service", "id": "c3", "service": "/add",
                            "args": {"a": 1, "b": 0}}))
        reply = recv_json(ws)
        assert reply["id"] == "c3" and reply["result"] is False
        assert "ZeroDivisionError" in reply["values"]
        ws.send(json.dumps({"op": "call_service", "service": "/add#legacy", "args": [4, 2]}))
        assert recv_json(ws) == {"op": "service_response", "service": "/add#legacy",
                                 "id": "legacy", "values": {"sum": 2}, "result": True}


def test_roslibpy_raises_service_exception(server: RosbridgeServer, ros: roslibpy.Ros) -> None:
    svc = roslibpy.Service(ros, "/missing", "example_interfaces/AddTwoInts")
    with pytest.raises(ServiceException, match="does not exist"):
        svc.call(roslibpy.ServiceRequest({}), timeout=TIMEOUT)


def test_a_browser_serves_a_zenros_service(server: RosbridgeServer, ros: roslibpy.Ros,
                                           robot: Node) -> None:
    def handler(request: dict[str, Any], response: dict[str, Any]) -> bool:
        response["sum"] = request["a"] + request["b"]
        return True

    svc = roslibpy.Service(ros, "/browser_add", "example_interfaces/AddTwoInts")
    svc.advertise(handler)
    client = Client(robot.context, AddTwoInts, "/browser_add")
    assert client.wait_for_service(TIMEOUT)
    assert client.call(AddTwoIntsRequest(a=2, b=5), TIMEOUT) == AddTwoIntsResponse(sum=7)
    svc.unadvertise()
    assert wait_for(lambda: not robot.graph.servers("/browser_add"), TIMEOUT)


def test_a_browser_service_that_fails(server: RosbridgeServer, robot: Node) -> None:
    from zenros.errors import ServiceError

    with raw(server) as ws:
        ws.send(json.dumps({"op": "advertise_service", "service": "/fails",
                            "type": "example_interfaces/AddTwoInts"}))
        client = Client(robot.context, AddTwoInts, "/fails")
        assert client.wait_for_service(TIMEOUT)
        result: list[Any] = []
        t = threading.Thread(target=lambda: result.append(
            _catch(lambda: client.call(AddTwoIntsRequest(a=1), TIMEOUT))))
        t.start()
        call = recv_json(ws)
        assert call["op"] == "call_service" and call["service"] == "/fails"
        assert call["id"].startswith("service_request:/fails:")
        assert call["args"] == {"a": 1, "b": 0}
        ws.send(json.dumps({"op": "service_response", "service": "/fails", "id": call["id"],
                            "result": False, "values": "no can do"}))
        t.join(TIMEOUT)
        assert isinstance(result[0], ServiceError) and "no can do" in str(result[0])


def _catch(fn: Any) -> Any:
    try:
        return fn()
    except Exception as exc:  # noqa: BLE001 (the test inspects it)
        return exc


# ------------------------------------------------------------------ actions


@pytest.fixture
def fibonacci(ctx_pair: list[Context]) -> Iterator[Node]:
    from zenros.examples.fibonacci_server import FibonacciServer

    node = FibonacciServer(context=ctx_pair[1], parameter_overrides={"period": 0.02})
    yield node
    node.close()


def test_action_goal_with_feedback_and_result(server: RosbridgeServer, ros: roslibpy.Ros,
                                              fibonacci: Node) -> None:
    assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
    client = roslibpy.ActionClient(ros, "/fibonacci", "example_interfaces/action/Fibonacci")
    feedback: Collector[Any] = Collector()
    results: Collector[Any] = Collector()
    errors: Collector[Any] = Collector()
    goal_id = client.send_goal(roslibpy.Goal({"order": 5}), results, feedback, errors)
    client.wait_goal(goal_id, TIMEOUT)
    assert not errors.items
    assert results.items[0]["values"] == {"sequence": [0, 1, 1, 2, 3, 5]}
    assert results.items[0]["status"] == roslibpy.GoalStatus.SUCCEEDED
    assert len(feedback) >= 3
    goal_id = client.send_goal(roslibpy.Goal({"order": -3}), results, feedback, errors)
    client.wait_goal(goal_id, TIMEOUT)
    assert "order must be in" in errors.items[0]["values"]


def test_action_cancel_and_failure(server: RosbridgeServer, fibonacci: Node) -> None:
    assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
    with raw(server) as ws:
        ws.send(json.dumps({"op": "send_action_goal", "id": "g1", "action": "/fibonacci",
                            "action_type": "example_interfaces/Fibonacci",
                            "args": {"order": 1000}, "feedback": True}))
        assert recv_json(ws)["op"] == "action_feedback"
        ws.send(json.dumps({"op": "cancel_action_goal", "id": "g1", "action": "/fibonacci"}))
        while (frame := recv_json(ws))["op"] == "action_feedback":
            assert frame["id"] == "g1"
        assert frame["op"] == "action_result" and frame["id"] == "g1"
        assert frame["status"] == 5 and frame["result"] is True
        ws.send(json.dumps({"op": "send_action_goal", "id": "g2", "action": "/fibonacci",
                            "action_type": "example_interfaces/Fibonacci",
                            "args": {"order": -1}}))
        frame = recv_json(ws)
        assert frame["op"] == "action_result" and frame["id"] == "g2"
        assert frame["result"] is False and frame["status"] == 0 and "order" in frame["values"]
        ws.send(json.dumps({"op": "send_action_goal", "id": "g3", "action": "/fibonacci",
                            "action_type": "nope/Nope"}))
        frame = recv_json(ws)
        assert frame["result"] is False and "unknown action type" in frame["values"]


def test_a_goal_in_the_ros2_tutorial_type_reaches_the_example_interfaces_server(
        server: RosbridgeServer, fibonacci: Node) -> None:
    # roslibjs's ROS 2 example names action_tutorials_interfaces/action/Fibonacci for /fibonacci
    assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
    with raw(server) as ws:
        ws.send(json.dumps({"op": "send_action_goal", "id": "t1", "action": "/fibonacci",
                            "action_type": "action_tutorials_interfaces/action/Fibonacci",
                            "args": {"order": 8}, "feedback": True}))
        feedback: list[Any] = []
        while (frame := recv_json(ws))["op"] == "action_feedback":
            feedback.append(frame["values"])
        assert frame["op"] == "action_result" and frame["id"] == "t1", frame
        assert frame["values"] == {"sequence": [0, 1, 1, 2, 3, 5, 8, 13, 21]}, frame
        assert frame["status"] == 4 and frame["result"] is True
        # the tutorial's feedback field, as a server of that type sends it
        assert feedback[0] == {"partial_sequence": [0, 1, 1]}, feedback
        assert feedback[-1] == {"partial_sequence": [0, 1, 1, 2, 3, 5, 8, 13, 21]}, feedback
        # a type of another layout is not converted: the server refuses what it cannot read
        ws.send(json.dumps({"op": "send_action_goal", "id": "t2", "action": "/fibonacci",
                            "action_type": "nav2_msgs/action/Wait", "args": {}}))
        frame = recv_json(ws)
        assert frame["id"] == "t2" and frame["result"] is False, frame


def test_the_hidden_cancel_goal_service_cancels_every_goal(server: RosbridgeServer,
                                                           ctx_pair: list[Context]) -> None:
    # roslibjs's Action.cancelAllGoals: call_service <action>/_action/cancel_goal with {}
    from zenros.examples.fibonacci_server import FibonacciServer

    fibonacci = FibonacciServer(context=ctx_pair[1],
                                parameter_overrides={"period": 0.02, "policy": "parallel"})
    assert wait_for(lambda: server.node.graph.actions().get("/fibonacci"), TIMEOUT)
    with fibonacci, raw(server) as ws:
        for gid in ("a", "b"):
            ws.send(json.dumps({"op": "send_action_goal", "id": gid, "action": "/fibonacci",
                                "action_type": "example_interfaces/action/Fibonacci",
                                "args": {"order": 1000}, "feedback": True}))
        seen: set[str] = set()
        while seen != {"a", "b"}:
            frame = recv_json(ws)
            assert frame["op"] == "action_feedback", frame
            seen.add(frame["id"])
        ws.send(json.dumps({"op": "call_service", "id": "c1",
                            "service": "/fibonacci/_action/cancel_goal", "args": {}}))
        ended: dict[str, dict[str, Any]] = {}
        answer: dict[str, Any] = {}
        while len(ended) < 2 or not answer:
            frame = recv_json(ws)
            if frame["op"] == "action_result":
                ended[frame["id"]] = frame
            elif frame["op"] == "service_response":
                answer = frame
        assert answer["id"] == "c1" and answer["result"] is True, answer
        assert answer["values"]["return_code"] == 0
        assert len(answer["values"]["goals_canceling"]) == 2
        assert all(len(g["goal_id"]["uuid"]) == 16 for g in answer["values"]["goals_canceling"])
        assert {k: (f["status"], f["result"]) for k, f in ended.items()} == {
            "a": (5, True), "b": (5, True)}  # CANCELED
        # a goal that is not there: ERROR_UNKNOWN_GOAL_ID (2), nothing canceling
        ws.send(json.dumps({"op": "call_service", "id": "c2",
                            "service": "/fibonacci/_action/cancel_goal",
                            "args": {"goal_info": {"goal_id": {"uuid": [7] * 16}}}}))
        answer = recv_json(ws)
        assert answer["id"] == "c2" and answer["values"]["return_code"] == 2, answer
        assert answer["values"]["goals_canceling"] == []
        # no such action: the service does not exist, as any unknown service
        ws.send(json.dumps({"op": "call_service", "id": "c3",
                            "service": "/nothing/_action/cancel_goal", "args": {}}))
        answer = recv_json(ws)
        assert answer["result"] is False and "does not exist" in answer["values"], answer
        ws.send(json.dumps({"op": "call_service", "id": "c4",
                            "service": "/fibonacci/_action/cancel_goal",
                            "args": {"goal_info": {"goal_id": {"uuid": "x"}}}}))
        answer = recv_json(ws)
        assert answer["id"] == "c4" and answer["result"] is False, answer


def test_a_browser_serves_a_zenros_action(server: RosbridgeServer, robot: Node) -> None:
    from zenros.action import ActionClient, GoalStatus
    from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal, FibonacciResult

    with raw(server) as ws:
        ws.send(json.dumps({"op": "advertise_action", "action": "/browser_fib",
                            "type": "example_interfaces/action/Fibonacci"}))
        client = ActionClient(robot, Fibonacci, "/browser_fib")
        assert client.wait_for_server(TIMEOUT)
        feedback: Collector[Any] = Collector()
        handle = client.send_goal_async(FibonacciGoal(order=3), feedback)
        goal = recv_json(ws)
        assert goal["op"] == "send_action_goal" and goal["action"] == "/browser_fib"
        assert goal["id"].startswith("action_goal:/browser_fib:")
        assert goal["args"] == {"order": 3} and goal["feedback"] is True
        ws.send(json.dumps({"op": "action_feedback", "id": goal["id"], "action": "/browser_fib",
                            "values": {"sequence": [0, 1]}}))
        ws.send(json.dumps({"op": "action_result", "id": goal["id"], "action": "/browser_fib",
                            "values": {"sequence": [0, 1, 1, 2]}, "status": 4,
                            "result": True}))
        done = handle.result(TIMEOUT)
        assert done.status is GoalStatus.SUCCEEDED
        assert done.result == FibonacciResult(sequence=[0, 1, 1, 2])
        assert feedback.wait(1, TIMEOUT) and feedback.items[0].feedback.sequence == [0, 1]

        handle = client.send_goal_async(FibonacciGoal(order=9))
        goal = recv_json(ws)
        assert handle.wait_accepted(TIMEOUT)
        threading.Thread(target=handle.cancel, daemon=True).start()
        cancel = recv_json(ws)
        assert cancel == {"op": "cancel_action_goal", "id": goal["id"], "action": "/browser_fib"}
        ws.send(json.dumps({"op": "action_result", "id": goal["id"], "action": "/browser_fib",
                            "values": {"sequence": [0]}, "status": 5, "result": True}))
        assert handle.result(TIMEOUT).status is GoalStatus.CANCELED

        handle = client.send_goal_async(FibonacciGoal(order=1))
        goal = recv_json(ws)
        ws.send(json.dumps({"op": "unadvertise_action", "action": "/browser_fib"}))
        assert handle.result(TIMEOUT).status is GoalStatus.ABORTED
        assert wait_for(lambda: not robot.graph.action_servers("/browser_fib"), TIMEOUT)


# ------------------------------------------------------------------ rosapi


def test_rosapi_graph_queries(server: RosbridgeServer, ros: roslibpy.Ros, robot: Node) -> None:
    robot.create_publisher(String, "/talk")
    robot.create_subscription(Twist, "/cmd", lambda m: None)
    robot.create_service(AddTwoInts, "/adder", lambda r: AddTwoIntsResponse())
    assert wait_for(lambda: "/adder" in server.node.graph.services(), TIMEOUT)
    assert wait_for(lambda: "/talk" in ros.get_topics(), TIMEOUT)
    assert ros.get_topic_type("/talk") == "std_msgs/msg/String"
    assert "/adder" in ros.get_services() and "/rosapi/topics" in ros.get_services()
    assert ros.get_service_type("/adder") == "example_interfaces/srv/AddTwoInts"
    assert "/robot" in ros.get_nodes() and "/rosbridge" in ros.get_nodes()
    details = ros.get_node_details("/robot")
    assert "/talk" in details["publishing"] and "/cmd" in details["subscribing"]
    assert "/adder" in details["services"]
    t = ros.get_time()
    assert t.secs > 1_600_000_000


def test_rosapi_parameters(ctx_pair: list[Context], tmp_path: Path, server: RosbridgeServer,
                           ros: roslibpy.Ros) -> None:
    master = MasterNode(context=ctx_pair[1], parameter_overrides={"data_dir": str(tmp_path)})
    try:
        assert server.bridge.params.wait_for_master(TIMEOUT)
        param = roslibpy.Param(ros, "/talker:max_speed")
        param.set(1.5, timeout=TIMEOUT)
        assert param.get(timeout=TIMEOUT) == 1.5
        assert master_value(server, "/talker/max_speed") == 1.5
        assert "/talker/max_speed" in ros.get_params()
        svc = roslibpy.Service(ros, "/rosapi/has_param", "rosapi/HasParam")
        assert svc.call(roslibpy.ServiceRequest({"name": "/talker/max_speed"}),
                        timeout=TIMEOUT) == {"exists": True}
        param.delete(timeout=TIMEOUT)
        assert svc.call(roslibpy.ServiceRequest({"name": "/talker:max_speed"}),
                        timeout=TIMEOUT) == {"exists": False}
        get = roslibpy.Service(ros, "/rosapi/get_param", "rosapi/GetParam")
        values = get.call(roslibpy.ServiceRequest({"name": "/talker:max_speed",
                                                   "default_value": "3"}), timeout=TIMEOUT)
        assert values["value"] == "3"
    finally:
        master.close()


def test_rosapi_calls_of_one_client_are_answered_in_order(
        ctx_pair: list[Context], tmp_path: Path, server: RosbridgeServer) -> None:
    # roslibjs's Param.set then Param.get, back to back: the get sees the value just set
    master = MasterNode(context=ctx_pair[1], parameter_overrides={"data_dir": str(tmp_path)})
    try:
        assert server.bridge.params.wait_for_master(TIMEOUT)
        with raw(server) as ws:
            for i in range(20):
                ws.send(json.dumps({"op": "call_service", "id": f"set{i}",
                                    "service": "/rosapi/set_param",
                                    "args": {"name": "/order_test", "value": json.dumps(i)}}))
                ws.send(json.dumps({"op": "call_service", "id": f"get{i}",
                                    "service": "/rosapi/get_param",
                                    "args": {"name": "/order_test"}}))
            answers = [recv_json(ws) for _ in range(40)]
        assert [a["id"] for a in answers] == [f"{op}{i}" for i in range(20)
                                              for op in ("set", "get")]
        assert [json.loads(a["values"]["value"]) for a in answers[1::2]] == list(range(20))
    finally:
        master.close()


def master_value(server: RosbridgeServer, name: str) -> Any:
    return server.bridge.params.lookup(name)[1]


# ------------------------------------------------------------------ errors, status, reconnect


def test_bad_frames_are_logged_not_answered_and_the_connection_stays(
        server: RosbridgeServer, caplog: pytest.LogCaptureFixture) -> None:
    with raw(server) as ws:
        for frame in ("not json", "[1, 2]", json.dumps({"id": "x"}),
                      json.dumps({"op": "bogus", "id": "b1"}),
                      json.dumps({"op": "subscribe", "id": "s", "topic": "/t", "type": "no/Such"}),
                      json.dumps({"op": "subscribe", "topic": "/never_advertised"}),
                      json.dumps({"op": "publish", "topic": "/unknown", "msg": {}}),
                      json.dumps({"op": "advertise", "topic": "bad topic!", "type": "std_msgs/String"}),
                      "[" * 3000 + "]" * 3000):
            ws.send(frame)
        ws.send(b"\x00binary")
        ws.send(json.dumps({"op": "call_service", "id": "alive", "service": "/rosapi/get_time"}))
        reply = recv_json(ws)  # nothing else came back: the first frame is this reply
        assert reply["id"] == "alive" and reply["result"] is True
        assert "/t" in server.bridge.opaque.topics  # a type zenros does not know: unchecked
    text = caplog.text
    assert "Unknown operation: bogus" in text
    assert "Cannot infer topic type for topic /never_advertised" in text
    assert "nested too deep" in text


def test_status_frames_only_after_set_level(server: RosbridgeServer) -> None:
    with raw(server) as ws:
        ws.send(json.dumps({"op": "set_level", "level": "error"}))
        ws.send(json.dumps({"op": "bogus", "id": "b1"}))
        status = recv_json(ws)
        assert status["op"] == "status" and status["level"] == "error" and status["id"] == "b1"
        assert "Unknown operation: bogus" in status["msg"]
        ws.send(json.dumps({"op": "publish", "id": "p1", "topic": "/typed", "msg": {"x": 1}}))
        assert recv_json(ws)["id"] == "p1"
        ws.send(json.dumps({"op": "action_result", "id": "a1", "action": "/x", "status": 4,
                            "result": True, "values": {}}))
        status = recv_json(ws)
        assert status["id"] == "a1" and "/x has not been advertised via rosbridge" in status["msg"]
        ws.send(json.dumps({"op": "set_level", "level": "none"}))
        ws.send(json.dumps({"op": "bogus"}))
        ws.send(json.dumps({"op": "call_service", "id": "t", "service": "/rosapi/get_time"}))
        assert recv_json(ws)["id"] == "t"


def test_malformed_message_is_reported_with_the_path(server: RosbridgeServer,
                                                     robot: Node) -> None:
    robot.create_subscription(Twist, "/cmd_vel", lambda m: None)
    with raw(server) as ws:
        ws.send(json.dumps({"op": "set_level", "level": "warning"}))
        ws.send(json.dumps({"op": "advertise", "topic": "/cmd_vel",
                            "type": "geometry_msgs/Twist"}))
        ws.send(json.dumps({"op": "publish", "id": "m", "topic": "/cmd_vel",
                            "msg": {"linear": {"x": "fast"}}}))
        status = recv_json(ws)
        assert status["id"] == "m" and "$.linear.x" in status["msg"]


def test_resubscribe_after_the_server_restarts(bridge_node: Node, robot: Node) -> None:
    first = RosbridgeServer(bridge_node, port=0)
    first.start_in_thread()
    port = first.port
    ros = roslibpy_connect("127.0.0.1", port, TIMEOUT)
    try:
        pub = robot.create_publisher(String, "/again")
        got: Collector[dict[str, Any]] = Collector()
        roslibpy.Topic(ros, "/again", "std_msgs/String").subscribe(got)
        assert pub.wait_for_subscribers(1, TIMEOUT)
        assert wait_for(lambda: (pub.publish(String(data="1")), len(got) > 0)[1], TIMEOUT)
        first.stop_in_thread()
        assert wait_for(lambda: not ros.is_connected, TIMEOUT)
        second = RosbridgeServer(bridge_node, port=port)
        second.start_in_thread()
        try:
            assert wait_for(lambda: ros.is_connected, 20)
            n = len(got)
            assert wait_for(lambda: (pub.publish(String(data="2")), len(got) > n)[1], 20)
            assert got.items[-1] == {"data": "2"}
            assert len(second.clients) == 1
            assert len(next(iter(second.clients)).topics.subs["/again"]) == 1  # replay: once
        finally:
            second.stop_in_thread()
    finally:
        ros.close()


def test_roslibjs_2_frames(server: RosbridgeServer, robot: Node) -> None:
    """roslibjs 2.x: uuid ids, rosapi names without the leading slash, a `timeout` field,
    `subscribe` then `unsubscribe` by id."""
    robot.create_service(AddTwoInts, "/add", lambda r: AddTwoIntsResponse(sum=r.a + r.b))
    pub = robot.create_publisher(String, "/news")
    assert wait_for(lambda: server.node.graph.servers("/add"), TIMEOUT)
    with raw(server) as ws:
        ws.send(json.dumps({"op": "call_service", "id": "call_service:rosapi/topics:7f3c9b1e",
                            "service": "rosapi/topics", "args": {}, "timeout": 5}))
        reply = recv_json(ws)
        assert reply["service"] == "rosapi/topics" and reply["result"] is True
        assert "/news" in reply["values"]["topics"]
        ws.send(json.dumps({"op": "call_service", "id": "call_service:/add:9a1d", "type":
                            "example_interfaces/srv/AddTwoInts", "service": "/add",
                            "args": {"a": 20, "b": 22}, "timeout": 5}))
        assert recv_json(ws)["values"] == {"sum": 42}
        sid = "subscribe:/news:1b7e2c44-0d6f-4f1a-9b0e-6f1d2c3b4a59"
        ws.send(json.dumps({"op": "subscribe", "id": sid, "type": "std_msgs/msg/String",
                            "topic": "/news", "compression": "none", "throttle_rate": 0,
                            "queue_length": 0}))
        assert pub.wait_for_subscribers(1, TIMEOUT)
        pub.publish(String(data="extra"))
        assert recv_json(ws) == {"op": "publish", "topic": "/news", "msg": {"data": "extra"}}
        ws.send(json.dumps({"op": "unsubscribe", "id": sid, "topic": "/news"}))
        assert wait_for(lambda: not robot.graph.subscribers("/news"), TIMEOUT)


def test_roslibpy_connect_takes_a_connection_that_run_missed(
        server: RosbridgeServer, monkeypatch: pytest.MonkeyPatch) -> None:
    """roslibpy's `run` can time out on a connection its reactor made meanwhile (a race in
    its ready check); the helper then takes the connected client, and still fails on none."""
    real_run = roslibpy.Ros.run

    def run_missing_ready(self: roslibpy.Ros, timeout: float = 10) -> None:
        real_run(self, timeout)
        raise RosTimeoutError("Failed to connect to ROS")  # what the race looks like

    monkeypatch.setattr(roslibpy.Ros, "run", run_missing_ready)
    ros = roslibpy_connect("127.0.0.1", server.port, TIMEOUT)
    try:
        assert ros.is_connected and "/rosapi/topics" in ros.get_services()
    finally:
        ros.close()
    monkeypatch.setattr(roslibpy.Ros, "run", real_run)
    with pytest.raises(RosTimeoutError):
        roslibpy_connect("127.0.0.1", free_port(), 1.0)
