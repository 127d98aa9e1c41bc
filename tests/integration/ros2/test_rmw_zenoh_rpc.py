"""Services and actions between zenros and rmw_zenoh, through the bridge, against peers
zenros did not write: zenoh-ros2-sdk 0.1.8's service server, and `rmw_peer.RmwPeer` (the SDK's
keys and tokens, the wheels' hashes, rclpy's CDR) for what the SDK lacks (actions, a server
that answers with a wrong sequence number)."""

from __future__ import annotations

import threading
import time
import uuid
from typing import Any

import pytest
from zenros.action import ActionClient, ActionServer, GoalStatus
from zenros.errors import ServiceError
from zenros.msgs.std_srvs import SetBool, SetBoolRequest
from zenros.msgs.test_msgs import Fibonacci
from zenros.msgs.test_msgs import FibonacciFeedback as FibFeedback
from zenros.msgs.test_msgs import FibonacciGoal as FibGoal
from zenros.msgs.test_msgs import FibonacciResult as FibResult
from zenros.node import Node
from zenros.ros2.registry import register_interface
from zenros.services.rmw_zenoh.bridge import RmwZenohBridge
from zenros.testing import Collector, wait_for

sdk = pytest.importorskip("zenoh_ros2_sdk", reason="zenoh-ros2-sdk not installed (extra ros2)")
pytest.importorskip("rclpy", reason="ROS 2 wheels not installed (extra ros2)")

from rmw_peer import RmwPeer, deserialize, serialize
from rosref import SHARE, ros_class


# test_msgs/action/Fibonacci: the action with a wheel (rclpy's classes, the JSON's hashes)
FIB = "test_msgs/action/Fibonacci"


@pytest.fixture(scope="module", autouse=True)
def _test_msgs_definition() -> None:
    register_interface(FIB, (SHARE / "test_msgs" / "action" / "Fibonacci.action").read_text())


@pytest.fixture
def rig(make_rmw_rig: Any) -> tuple[Node, RmwZenohBridge, RmwPeer]:
    node, bridge, peer, _ = make_rmw_rig("zen_node")
    return node, bridge, peer


# ---------------------------------------------------------------- services


def test_zenros_client_calls_an_sdk_service(rig: tuple[Node, RmwZenohBridge, RmwPeer],
                                            router: str) -> None:
    node, bridge, peer = rig
    port = int(router.rsplit(":", 1)[1])
    seen: list[bool] = []

    def handle(req: Any) -> Any:
        seen.append(req.data)
        return response_cls(success=not req.data, message=f"ros saw {req.data}")

    server = sdk.ROS2ServiceServer("/ros_flag", "std_srvs/srv/SetBool", callback=handle,
                                   request_definition="bool data",
                                   response_definition="bool success\nstring message",
                                   domain_id=peer.domain, router_port=port)
    response_cls = server.session_mgr.store.types[server.response_store_type]
    try:
        assert wait_for(lambda: "/ros_flag" in bridge.services_in, 10)
        assert node.context.graph.wait_for_service("/ros_flag", 5)
        client = node.create_client(SetBool, "/ros_flag")
        resp = client.call(SetBoolRequest(data=True), timeout=10)
        assert resp.success is False and resp.message == "ros saw True"
        resp = client.call(SetBoolRequest(data=False), timeout=10)
        assert resp.success is True and resp.message == "ros saw False"
        assert seen == [True, False]
    finally:
        server.close()
    assert wait_for(lambda: "/ros_flag" not in bridge.services_in, 10)


def test_reply_must_echo_the_request(rig: tuple[Node, RmwZenohBridge, RmwPeer]) -> None:
    """rmw_zenoh matches a reply to its request by the echoed sequence number and GID: a reply
    that echoes neither right is refused (the zenros caller gets an error), one that does is
    taken."""
    node, bridge, peer = rig
    res_cls = ros_class("std_srvs/srv/SetBool_Response")
    req_seen: list[Any] = []

    def answer(payload: bytes) -> bytes:
        req_seen.append(deserialize(payload, "std_srvs/srv/SetBool_Request"))
        return serialize(res_cls(success=True, message="peer"))

    peer.serve("/bad_echo", "std_srvs/srv/SetBool", answer, echo=False)
    peer.serve("/good_echo", "std_srvs/srv/SetBool", answer)
    assert wait_for(lambda: {"/bad_echo", "/good_echo"} <= set(bridge.services_in), 10)
    bad, good = node.create_client(SetBool, "/bad_echo"), node.create_client(SetBool, "/good_echo")
    # the bridge lists a peer's service before its zenros server is routed to this session
    assert bad.wait_for_service(10) and good.wait_for_service(10)
    with pytest.raises(ServiceError, match="does not echo the request"):
        bad.call(SetBoolRequest(data=True), timeout=10)
    resp = good.call(SetBoolRequest(data=True), timeout=10)
    assert resp.success is True and resp.message == "peer"
    assert [r.data for r in req_seen] == [True, True]


# ---------------------------------------------------------------- actions


def _fib_server(node: Node, name: str) -> ActionServer:
    def execute(goal: Any) -> FibResult:
        seq = [0, 1]
        for _ in range(goal.goal.order - 1):
            if goal.is_cancel_requested:
                goal.canceled()
                return FibResult(sequence=seq)
            seq.append(seq[-1] + seq[-2])
            goal.publish_feedback(FibFeedback(sequence=list(seq)))
            time.sleep(0.05)
        goal.succeed()
        return FibResult(sequence=seq)

    return ActionServer(node, Fibonacci, name, execute)


class PeerActionClient:
    """rcl_action's client on rmw_zenoh: three clients and two subscriptions under
    ``<name>/_action/``."""

    def __init__(self, peer: RmwPeer, name: str) -> None:
        base = f"{name}/_action/"
        self.send = peer.client(base + "send_goal", f"{FIB}_SendGoal")
        self.cancel = peer.client(base + "cancel_goal", "action_msgs/srv/CancelGoal")
        self.result = peer.client(base + "get_result", f"{FIB}_GetResult")
        self.feedback: Collector[Any] = Collector()
        self.status: Collector[Any] = Collector()
        peer.subscribe(base + "feedback", f"{FIB}_FeedbackMessage", self.feedback)
        peer.subscribe(base + "status", "action_msgs/msg/GoalStatusArray", self.status,
                       latched=True, depth=1)

    def send_goal(self, order: int) -> tuple[Any, Any]:
        req_cls = ros_class(f"{FIB}_SendGoal_Request")
        goal_id = ros_class("unique_identifier_msgs/msg/UUID")(uuid=list(uuid.uuid4().bytes))
        req = req_cls(goal_id=goal_id, goal=ros_class(f"{FIB}_Goal")(order=order))
        resp, sent, got = self.send.call(req, f"{FIB}_SendGoal_Response")
        assert (got.sequence_id, got.gid) == (sent.sequence_id, sent.gid)
        return goal_id, resp

    def get_result(self, goal_id: Any) -> Any:
        req = ros_class(f"{FIB}_GetResult_Request")(goal_id=goal_id)
        resp, sent, got = self.result.call(req, f"{FIB}_GetResult_Response", timeout=20)
        assert (got.sequence_id, got.gid) == (sent.sequence_id, sent.gid)
        return resp

    def cancel_goal(self, goal_id: Any) -> Any:
        info = ros_class("action_msgs/msg/GoalInfo")(goal_id=goal_id)
        req = ros_class("action_msgs/srv/CancelGoal_Request")(goal_info=info)
        resp, _, _ = self.cancel.call(req, "action_msgs/srv/CancelGoal_Response")
        return resp


def test_rmw_zenoh_action_client_drives_a_zenros_server(
        rig: tuple[Node, RmwZenohBridge, RmwPeer]) -> None:
    node, bridge, peer = rig
    _fib_server(node, "/fibonacci")
    assert wait_for(lambda: "/fibonacci" in bridge.actions, 10)
    client = PeerActionClient(peer, "/fibonacci")
    # the action's five endpoints are in the rmw_zenoh graph as rmw_zenoh declares a server's
    # (the bridge lists the action before its tokens reach the peer: wait for them)
    want = {("SS", "send_goal"), ("SS", "cancel_goal"), ("SS", "get_result"),
            ("MP", "feedback"), ("MP", "status")}
    assert wait_for(lambda: {(k, n.rsplit("/", 1)[-1])
                             for k, n in _tokens(peer, "/fibonacci/_action/")} >= want, 10)

    goal_id, resp = client.send_goal(6)
    assert resp.accepted is True and resp.stamp.sec > 0
    result = client.get_result(goal_id)
    assert result.status == GoalStatus.SUCCEEDED
    assert list(result.result.sequence) == [0, 1, 1, 2, 3, 5, 8]
    assert wait_for(lambda: len(client.feedback) >= 5, 10)
    fb = client.feedback.items
    assert all(bytes(f.goal_id.uuid) == bytes(goal_id.uuid) for f in fb)
    assert list(fb[-1].feedback.sequence) == [0, 1, 1, 2, 3, 5, 8]
    assert wait_for(lambda: any(s.status == GoalStatus.SUCCEEDED for m in client.status.items
                                for s in m.status_list), 10)

    # cancel a long goal while it runs
    goal_id, resp = client.send_goal(400)
    assert resp.accepted
    assert wait_for(lambda: any(bytes(f.goal_id.uuid) == bytes(goal_id.uuid)
                                for f in client.feedback.items), 10)
    cancel = client.cancel_goal(goal_id)
    assert cancel.return_code == 0
    assert [bytes(g.goal_id.uuid) for g in cancel.goals_canceling] == [bytes(goal_id.uuid)]
    assert client.get_result(goal_id).status == GoalStatus.CANCELED

    # a goal id the server never saw
    unknown = ros_class("unique_identifier_msgs/msg/UUID")(uuid=list(uuid.uuid4().bytes))
    assert client.get_result(unknown).status == 0


def test_zenros_action_client_drives_an_rmw_zenoh_server(
        rig: tuple[Node, RmwZenohBridge, RmwPeer]) -> None:
    node, bridge, peer = rig
    server = PeerFibServer(peer, "/ros_fib")
    assert wait_for(lambda: "/ros_fib" in bridge.actions_in, 10)
    client = ActionClient(node, Fibonacci, "/ros_fib")
    assert client.wait_for_server(5)
    feedback: list[Any] = []
    result = client.send_goal(FibGoal(order=5), feedback_callback=feedback.append, timeout=20)
    assert result.status == GoalStatus.SUCCEEDED
    assert result.result == FibResult(sequence=[0, 1, 1, 2, 3, 5])
    assert wait_for(lambda: len(feedback) >= 4, 5)
    assert feedback[-1].feedback == FibFeedback(sequence=[0, 1, 1, 2, 3, 5])
    # the goal id is the client's on both sides
    assert len(server.goals) == 1

    # cancel
    handle = client.send_goal_async(FibGoal(order=10_000))
    assert wait_for(lambda: len(server.goals) == 2, 10)
    assert handle.cancel(timeout=10)
    res = handle.result(20)
    assert res.status == GoalStatus.CANCELED

    # rejected: the ROS 2 server refuses orders over 50 000
    rejected = client.send_goal_async(FibGoal(order=60_000))
    with pytest.raises(Exception, match="(?i)reject"):
        rejected.result(10)


class PeerFibServer:
    """rcl_action's server on rmw_zenoh: three services and two publishers under
    ``<name>/_action/``; goals run on threads, feedback every 20 ms, status published latched."""

    def __init__(self, peer: RmwPeer, name: str) -> None:
        base = f"{name}/_action/"
        self.goals: dict[bytes, dict[str, Any]] = {}
        self.lock = threading.Lock()
        self.feedback = peer.publisher(base + "feedback", f"{FIB}_FeedbackMessage")
        self.status = peer.publisher(base + "status", "action_msgs/msg/GoalStatusArray",
                                     latched=True, depth=1)
        peer.serve(base + "send_goal", f"{FIB}_SendGoal", self._send_goal)
        peer.serve(base + "cancel_goal", "action_msgs/srv/CancelGoal", self._cancel)
        peer.serve(base + "get_result", f"{FIB}_GetResult", self._get_result)

    def _send_goal(self, payload: bytes) -> bytes:
        req = deserialize(payload, f"{FIB}_SendGoal_Request")
        res_cls = ros_class(f"{FIB}_SendGoal_Response")
        if req.goal.order > 50_000:
            return serialize(res_cls(accepted=False))
        gid = bytes(req.goal_id.uuid)
        goal = {"id": req.goal_id, "status": 2, "cancel": False, "done": threading.Event(),
                "seq": [0, 1]}
        with self.lock:
            self.goals[gid] = goal
        threading.Thread(target=self._run, args=(goal, req.goal.order), daemon=True).start()
        stamp = ros_class("builtin_interfaces/msg/Time")(sec=int(time.time()), nanosec=0)
        return serialize(res_cls(accepted=True, stamp=stamp))

    def _run(self, goal: dict[str, Any], order: int) -> None:
        fb_cls = ros_class(f"{FIB}_FeedbackMessage")
        seq = goal["seq"]
        for _ in range(order - 1):
            if goal["cancel"]:
                goal["status"] = GoalStatus.CANCELED
                break
            seq.append(seq[-1] + seq[-2])
            self.feedback.publish(fb_cls(goal_id=goal["id"],
                                         feedback=ros_class(f"{FIB}_Feedback")(sequence=seq)))
            time.sleep(0.02)
        else:
            goal["status"] = GoalStatus.SUCCEEDED
        self._publish_status()
        goal["done"].set()

    def _publish_status(self) -> None:
        st = ros_class("action_msgs/msg/GoalStatus")
        info = ros_class("action_msgs/msg/GoalInfo")
        with self.lock:
            lst = [st(goal_info=info(goal_id=g["id"]), status=int(g["status"]))
                   for g in self.goals.values()]
        self.status.publish(ros_class("action_msgs/msg/GoalStatusArray")(status_list=lst))

    def _cancel(self, payload: bytes) -> bytes:
        req = deserialize(payload, "action_msgs/srv/CancelGoal_Request")
        res_cls = ros_class("action_msgs/srv/CancelGoal_Response")
        goal = self.goals.get(bytes(req.goal_info.goal_id.uuid))
        if goal is None:
            return serialize(res_cls(return_code=2))
        goal["cancel"] = True
        return serialize(res_cls(return_code=0, goals_canceling=[req.goal_info]))

    def _get_result(self, payload: bytes) -> bytes:
        req = deserialize(payload, f"{FIB}_GetResult_Request")
        res_cls = ros_class(f"{FIB}_GetResult_Response")
        goal = self.goals.get(bytes(req.goal_id.uuid))
        if goal is None:
            return serialize(res_cls(status=0))
        goal["done"].wait(30)
        return serialize(res_cls(status=int(goal["status"]),
                                 result=ros_class(f"{FIB}_Result")(sequence=goal["seq"])))


def _tokens(peer: RmwPeer, under: str) -> list[tuple[str, str]]:
    """(kind, name) of the rmw_zenoh tokens of the domain whose name starts with ``under``."""
    out = []
    for reply in peer.session.liveliness().get(f"@ros2_lv/{peer.domain}/**", timeout=2.0):
        if reply.ok is None:
            continue
        parts = str(reply.ok.key_expr).split("/")
        if len(parts) > 9 and parts[9].replace("%", "/").startswith(under):
            out.append((parts[5], parts[9].replace("%", "/")))
    return out


