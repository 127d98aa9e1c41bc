"""The graphs mirrored through the bridge: zenros nodes and endpoints appear as rmw_zenoh
liveliness tokens (NN/MP/MS/SS/SC, with the wheels' type hashes), and rmw_zenoh nodes and
endpoints in the zenros graph and in ``zenros node list`` / ``zenros topic list``."""

from __future__ import annotations

import subprocess
import sys
from typing import Any

import pytest
from zenros.action import ActionServer
from zenros.context import Context
from zenros.msgs.example_interfaces import Fibonacci
from zenros.msgs.geometry_msgs import Twist
from zenros.msgs.std_msgs import String
from zenros.msgs.std_srvs import SetBool, SetBoolResponse
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.services.rmw_zenoh.bridge import RmwZenohBridge
from zenros.testing import wait_for

EntityKind = pytest.importorskip("zenoh_ros2_sdk.entity",
                                 reason="zenoh-ros2-sdk not installed (extra ros2)").EntityKind
pytest.importorskip("rclpy", reason="ROS 2 wheels not installed (extra ros2)")

from rmw_peer import RmwPeer
from rosref import wheel_hash


@pytest.fixture
def rig(make_rmw_rig: Any) -> tuple[Node, RmwZenohBridge, RmwPeer, Context]:
    rig: tuple[Node, RmwZenohBridge, RmwPeer, Context] = make_rmw_rig(
        "zen_graph", "/robot1", "ros_talker")
    return rig


def _ros_tokens(peer: RmwPeer) -> list[list[str]]:
    replies = peer.session.liveliness().get(f"@ros2_lv/{peer.domain}/**", timeout=2.0)
    return [str(r.ok.key_expr).split("/") for r in replies if r.ok is not None]


def test_zenros_graph_appears_as_rmw_zenoh_tokens(
        rig: tuple[Node, RmwZenohBridge, RmwPeer, Context]) -> None:
    node, _bridge, peer, _ = rig
    node.create_publisher(String, "chatter")
    node.create_publisher(String, "status", QOS_LATCHED)
    node.create_subscription(Twist, "cmd_vel", lambda m: None)
    node.create_service(SetBool, "set_flag", lambda r: SetBoolResponse(success=True))
    ActionServer(node, Fibonacci, "fib", lambda g: None)

    def of_node() -> dict[tuple[str, str], list[str]]:
        # parts: @ros2_lv domain zid nid eid kind enclave namespace node [topic type hash qos]
        return {(p[5], p[9].replace("%", "/") if len(p) > 9 else ""): p
                for p in _ros_tokens(peer) if p[7] == "%robot1" and p[8] == "zen_graph"}

    want = {("NN", ""), ("MP", "/robot1/chatter"), ("MP", "/robot1/status"),
            ("MS", "/robot1/cmd_vel"), ("SS", "/robot1/set_flag"),
            ("SS", "/robot1/fib/_action/send_goal"), ("SS", "/robot1/fib/_action/cancel_goal"),
            ("SS", "/robot1/fib/_action/get_result"), ("MP", "/robot1/fib/_action/feedback"),
            ("MP", "/robot1/fib/_action/status")}
    toks: dict[tuple[str, str], list[str]] = {}

    def complete() -> bool:  # keep the answer that had them all (a later get may be partial)
        toks.clear()
        toks.update(of_node())
        return want <= set(toks)

    assert wait_for(complete, 10), sorted(toks)
    chatter = toks[("MP", "/robot1/chatter")]
    assert chatter[10] == "std_msgs::msg::dds_::String_"
    assert chatter[11] == wheel_hash("std_msgs/msg/String")  # the wheels' hash, not ours
    assert chatter[12] == "::,10:,:,:,,"
    assert toks[("MP", "/robot1/status")][12] == ":1:,1:,:,:,,"  # latched: transient local
    assert toks[("MS", "/robot1/cmd_vel")][11] == wheel_hash("geometry_msgs/msg/Twist")
    assert toks[("SS", "/robot1/set_flag")][10] == "std_srvs::srv::dds_::SetBool_"
    assert toks[("SS", "/robot1/set_flag")][11] == wheel_hash("std_srvs/srv/SetBool")
    assert toks[("MP", "/robot1/fib/_action/status")][11] == \
        wheel_hash("action_msgs/msg/GoalStatusArray")
    # one node id for the node and its endpoints, a distinct entity id each
    assert len({p[3] for p in toks.values()}) == 1
    assert len({p[4] for p in toks.values()}) == len(toks)
    node.close()  # the node leaves: so do its tokens
    assert wait_for(lambda: not of_node(), 10)


def test_rmw_zenoh_graph_appears_in_zenros(
        rig: tuple[Node, RmwZenohBridge, RmwPeer, Context], router: str, prefix: str) -> None:
    _, _bridge, peer, ctx = rig
    peer.token(EntityKind.PUBLISHER, "/r_chatter", "std_msgs/msg/String", ":1:,1:,:,:,,")
    peer.token(EntityKind.SUBSCRIPTION, "/r_cmd", "geometry_msgs/msg/Twist", "::,10:,:,:,,")
    peer.token(EntityKind.SERVICE, "/r_flag", "std_srvs/srv/SetBool")
    peer.token(EntityKind.CLIENT, "/r_trigger", "std_srvs/srv/Trigger")
    base = "/r_fib/_action/"
    for part, t in (("send_goal", "test_msgs/action/Fibonacci_SendGoal"),
                    ("cancel_goal", "action_msgs/srv/CancelGoal"),
                    ("get_result", "test_msgs/action/Fibonacci_GetResult")):
        peer.token(EntityKind.SERVICE, base + part, t)
    peer.token(EntityKind.PUBLISHER, base + "feedback", "test_msgs/action/Fibonacci_FeedbackMessage")
    peer.token(EntityKind.PUBLISHER, base + "status", "action_msgs/msg/GoalStatusArray")
    g = ctx.graph
    assert g.wait_for_node("/ros_talker", 10)
    # the bridge mirrors each token as it comes, in no set order: wait for the last of them
    assert wait_for(lambda: "/r_fib" in g.actions() and {"/r_chatter", "/r_cmd"} <= set(
        g.topics()) and "/r_flag" in g.services() and bool(g.clients("/r_trigger")), 10)
    assert g.topics()["/r_chatter"] == ["std_msgs/String"]
    assert g.topics()["/r_cmd"] == ["geometry_msgs/Twist"]
    assert g.services()["/r_flag"] == ["std_srvs/SetBool"]
    assert [t.type for t in g.clients("/r_trigger")] == ["std_srvs/Trigger"]
    assert g.actions()["/r_fib"] == ["test_msgs/Fibonacci"]
    assert not any("/_action/" in n for n in g.topics())  # hidden, as ros2 topic list does
    pubs = [t for t in g.publishers("/r_chatter") if t.node == "/ros_talker"]
    assert [t.qos for t in pubs] == ["rel+tl+1"]
    ends = g.endpoints_of("/ros_talker")
    assert {t.name for t in ends["sub"]} == {"/r_cmd"}

    # and the CLI shows them
    def cli(*args: str) -> str:
        return subprocess.run([sys.executable, "-m", "zenros.cli", *args, "-e", router,
                               "--prefix", prefix], capture_output=True, text=True,
                              timeout=60, check=True).stdout

    assert "/ros_talker" in cli("node", "list").split()
    topics = cli("topic", "list").split()
    assert "/r_chatter" in topics and "/r_cmd" in topics

    peer.close()  # the ROS 2 node leaves: so does its mirror
    assert wait_for(lambda: "/ros_talker" not in g.node_names(), 10)
    assert "/r_fib" not in g.actions()


def test_bridge_process_knows_a_type_whose_module_loads_on_demand(router: str,
                                                                 prefix: str) -> None:
    """An rmw_zenoh action server of test_msgs/action/Fibonacci (a module `zenros.msgs` leaves
    out) is routed into zenros by a bridge process given no ``types`` (issue 37.6)."""
    from zenros.testing import Proc

    domain = 59  # below make_rmw_rig's domains
    proc = Proc([sys.executable, "-m", "zenros.services.rmw_zenoh", "-e", router,
                 "--prefix", prefix, "-p", f"domain_id:={domain}"])
    peer = RmwPeer(router, domain, node="ros_fib")
    try:
        assert proc.wait_line("bridging zenros and rmw_zenoh", 20), proc.output
        base = "/r_fib/_action/"
        for part, t in (("send_goal", "test_msgs/action/Fibonacci_SendGoal"),
                        ("cancel_goal", "action_msgs/srv/CancelGoal"),
                        ("get_result", "test_msgs/action/Fibonacci_GetResult")):
            peer.token(EntityKind.SERVICE, base + part, t)
        assert proc.wait_line("rmw_zenoh action /r_fib (test_msgs/action/Fibonacci) -> zenros",
                              20), proc.output
        assert "not bridged" not in proc.output
    finally:
        peer.close()
        proc.stop()
