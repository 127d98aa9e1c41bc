"""One DDS bridge scenario, run inside a network namespace by test_dds_bridge.py: starts the
bridge and an rclpy peer as child processes, plays the zenros side itself, and prints one JSON
line of results. ``python dds_scenario.py CASE``."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.std_msgs import String
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.session import SessionOptions
from zenros.testing import Collector, Waited, free_port, unique_prefix, wait_for

HERE = Path(__file__).parent
PY = sys.executable
ENV = {**os.environ, "AMENT_PREFIX_PATH": sys.prefix, "ROS_DOMAIN_ID": "0"}


class Procs:
    def __init__(self) -> None:
        self.procs: list[subprocess.Popen[str]] = []

    def start(self, *args: str, stdout: Any = subprocess.PIPE) -> subprocess.Popen[str]:
        p = subprocess.Popen([PY, *args], stdout=stdout, stderr=subprocess.PIPE, text=True,
                             env=ENV, start_new_session=True)
        self.procs.append(p)
        return p

    def stop(self, p: subprocess.Popen[str], wait: float = 10) -> str:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGINT)
            try:
                p.wait(wait)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(5)
        err = p.stderr.read() if p.stderr else ""
        return err

    def stop_all(self) -> dict[str, str]:
        return {str(i): self.stop(p)[-4000:] for i, p in enumerate(self.procs)}


def lines_of(p: subprocess.Popen[str], n: int, timeout: float,
             until: Callable[[list[dict[str, Any]]], bool] | None = None) -> list[dict[str, Any]]:
    """The first n JSON lines (after the ready line) the rclpy peer printed (read from the
    pipe's descriptor: lines already in a reader's buffer would not wake a select); with
    ``until``, every line read until ``until(lines)`` holds (or n lines, or the timeout)."""
    import selectors
    assert p.stdout is not None
    fd = p.stdout.fileno()
    sel = selectors.DefaultSelector()
    sel.register(fd, selectors.EVENT_READ)
    out: list[dict[str, Any]] = []
    buf = b""
    deadline = time.monotonic() + timeout
    while len(out) < n and time.monotonic() < deadline and not (until and until(out)):
        if not sel.select(deadline - time.monotonic()):
            continue
        chunk = os.read(fd, 65536)
        if not chunk:
            break
        buf += chunk
        *lines, buf = buf.split(b"\n")
        out.extend(d for d in map(json.loads, filter(None, lines)) if "ready" not in d)
    return out if until else out[:n]


def children_of(pid: int) -> list[int]:
    """The PIDs whose parent is ``pid`` (from /proc)."""
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    ppid = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
            if ppid == pid:
                out.append(int(d))
    return out


def sim_cmd_vel() -> dict[str, Any]:
    """``zenros launch deploy/launch/sim.yaml ros2_bridge:=true`` (the whole simulated robot, in
    this namespace its fixed ports are its own) and an rclpy node publishing Twist on
    /cmd_vel: the chassis's odometry moves."""
    import math
    import tempfile

    from zenros.msgs.nav_msgs import Odometry
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    prefix = unique_prefix()
    procs = Procs()
    res: dict[str, Any] = {"case": "sim"}
    with tempfile.TemporaryDirectory() as home:
        sim = subprocess.Popen(
            [PY, "-m", "zenros.cli", "launch", str(HERE.parents[2] / "deploy/launch/sim.yaml"),
             "ros2_bridge:=true"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
            env={**ENV, "ZENROS_HOME": home, "ZENROS_PREFIX": prefix, "ZENROS_CONNECT": endpoint},
            start_new_session=True)
        procs.procs.append(sim)
        ctx = Context(SessionOptions(connect=[endpoint]), prefix=prefix)
        node = Node("zen_side", context=ctx)
        try:
            odom: Collector[Any] = Collector()
            node.create_subscription(Odometry, "/odom", odom)
            res["odom"] = wait_for(lambda: len(odom) > 0, 120)
            res["bridge_up"] = wait_for(
                lambda: "/ros2_dds_bridge" in ctx.graph.node_names(), 60)
            cmds: Collector[Any] = Collector()
            node.create_subscription(Twist, "/cmd_vel", cmds)
            if res["odom"]:
                p0 = odom.items[-1].pose.pose.position
                # a sane command: the chassis refuses (and stops for) one beyond 10x its limits
                procs.start(str(HERE / "rclpy_peer.py"), "pub", "Twist", "/cmd_vel", "--drive")

                def moved() -> float:
                    p = odom.items[-1].pose.pose.position
                    return math.hypot(p.x - p0.x, p.y - p0.y)
                res["moved"] = wait_for(lambda: moved() > 0.05, 90)
                res["distance"] = round(moved(), 3)
                res["cmd_vel_publishers"] = [p.node for p in ctx.graph.publishers("/cmd_vel")]
                # what the chassis was sent (the first bridged commands)
                res["cmd_vel_first"] = [[m.linear.x, m.angular.z] for m in cmds.items[:3]]
        finally:
            node.close()
            ctx.close()
            # the launch runs each node in a session of its own: note them by PID, give the
            # launch time to stop them, then stop any it left
            nodes = children_of(sim.pid)
            res["bridge_log"] = procs.stop(sim, wait=60)[-3000:]
            for pid in nodes:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            procs.stop_all()
    return res


def action_out(procs: Procs, node: Node) -> dict[str, Any]:
    """A zenros ActionClient -> an rclpy test_msgs/Fibonacci ActionServer (rclpy_action_peer.py)
    through the bridge: feedback and success, rejection, abort, cancel, the server leaving."""
    from zenros.action import ActionClient
    from zenros.errors import GoalRejectedError
    from zenros.msgs.test_msgs import Fibonacci
    res: dict[str, Any] = {}
    graph = node.context.graph
    peer = procs.start(str(HERE / "rclpy_action_peer.py"), "/fibonacci")
    client = ActionClient(node, Fibonacci, "/fibonacci")
    res["available"] = client.wait_for_server(60)
    res["servers"] = [t.node for t in graph.action_servers("/fibonacci")]
    feedback: list[list[int]] = []
    r = client.send_goal(Fibonacci.Goal(order=5), lambda m: feedback.append(list(m.feedback.sequence)),
                         timeout=60)
    res["done"] = [r.status.name, list(r.result.sequence)]
    res["feedback"] = feedback
    try:
        client.send_goal(Fibonacci.Goal(order=-1), timeout=30)
        res["rejected"] = False
    except GoalRejectedError as exc:
        res["rejected"] = str(exc)
    r = client.send_goal(Fibonacci.Goal(order=13), timeout=60)
    res["aborted"] = [r.status.name, len(r.result.sequence)]
    fb2: list[list[int]] = []
    h = client.send_goal_async(Fibonacci.Goal(order=50), lambda m: fb2.append(list(m.feedback.sequence)))
    res["long_feedback"] = wait_for(lambda: len(fb2) >= 2, 30)
    res["cancel_accepted"] = h.cancel(10)
    r = h.result(30)
    res["canceled"] = [r.status.name, len(r.result.sequence) < 52]
    # the rclpy server's goal events, in order
    res["served"] = lines_of(peer, 8, 10)
    procs.stop(peer)
    res["route_left"] = wait_for(lambda: not graph.action_servers("/fibonacci"), 30)
    client.close()
    return res


def action_in(procs: Procs, node: Node) -> dict[str, Any]:
    """A zenros test_msgs/Fibonacci ActionServer as rclpy sees it through the bridge: in its
    action graph, feedback and status on its topics; its services are not offered (an rclpy
    client's requests cannot be answered from cyclonedds: docs/ros2.md, "Limits")."""
    import time

    from zenros.action import ActionClient, ActionServer
    from zenros.msgs.test_msgs import Fibonacci
    res: dict[str, Any] = {}

    def execute(gh: Any) -> Any:
        seq = [0, 1]
        for _ in range(gh.request.order):
            seq.append(seq[-1] + seq[-2])
            gh.publish_feedback(Fibonacci.Feedback(sequence=list(seq)))
            time.sleep(0.2)
        gh.succeed()
        return Fibonacci.Result(sequence=seq)

    ActionServer(node, Fibonacci, "/zfib", execute)
    peer = procs.start(str(HERE / "rclpy_action_peer.py"), "/zfib", "--watch")
    res["seen"] = lines_of(peer, 2, 60)  # the action in rclpy's graph, wait_for_server
    client = ActionClient(node, Fibonacci, "/zfib")
    r = client.send_goal(Fibonacci.Goal(order=5), timeout=30)
    res["goal"] = r.goal_id.hex
    res["done"] = [r.status.name, list(r.result.sequence)]
    # the last feedback and a status saying the goal succeeded (two topics: in either
    # order), within 10 s
    got = lines_of(peer, 1000, 10, until=lambda got: (
        any([res["goal"], 4] in g.get("status", []) for g in got)
        and any(g.get("feedback", [0, []])[1] == r.result.sequence for g in got)))
    res["fb"] = [g["feedback"] for g in got if "feedback" in g]
    res["statuses"] = [g["status"] for g in got if "status" in g]
    return res


def main(case: str) -> dict[str, Any]:
    if case == "sim":
        return sim_cmd_vel()
    port = free_port()
    prefix = unique_prefix()
    procs = Procs()
    res: dict[str, Any] = {"case": case}
    started = time.monotonic()
    bridge = procs.start("-m", "zenros.services.gateway.ros2", "-l", f"tcp/127.0.0.1:{port}",
                         "--prefix", prefix, "-p", "domain_id:=0", stdout=subprocess.DEVNULL)
    # no types:= for test_msgs (act_out, act_in): a shipped package loads by its name
    ctx = Context(SessionOptions(connect=[f"tcp/127.0.0.1:{port}"]), prefix=prefix)
    node = Node("zen_side", context=ctx)
    graph = ctx.graph
    try:
        if case in ("talker", "twist_in", "scan", "grid"):
            kind, cls, topic = {
                "talker": ("String", String, "/chatter"), "twist_in": ("Twist", Twist, "/cmd_vel"),
                "scan": ("LaserScan", LaserScan, "/scan"), "grid": ("OccupancyGrid", OccupancyGrid, "/map"),
            }[case]
            got: Collector[Any] = Collector()
            node.create_subscription(cls, topic, got)
            peer = procs.start(str(HERE / "rclpy_peer.py"), "pub", kind, topic)
            res["received"] = wait_for(lambda: len(got) >= 3, 30)
            if got.items:
                m = got.items[-1]
                if isinstance(m, String):
                    res["data"] = m.data
                elif isinstance(m, Twist):
                    res["x"], res["z"] = m.linear.x, m.angular.z
                elif isinstance(m, LaserScan):
                    res["n"] = len(m.ranges)
                    res["r5"] = float(m.ranges[5])
                elif isinstance(m, OccupancyGrid):
                    res["n"] = len(m.data)
                    res["w"] = m.info.width
                    res["d123"] = int(m.data[123])
            res["node_listed"] = wait_for(lambda: "/peer_pub" in graph.node_names(), 10)
            res["publisher"] = [p.node for p in graph.publishers(topic)]
            procs.stop(peer)
            res["node_left"] = wait_for(lambda: "/peer_pub" not in graph.node_names(), 20)
            res["route_left"] = wait_for(lambda: not graph.publishers(topic), 20)
        elif case in ("listener", "twist_out", "latched"):
            kind, topic = {"listener": ("String", "/chatter2"), "twist_out": ("Twist", "/cmd_vel2"),
                           "latched": ("String", "/latched")}[case]
            if case == "latched":
                pub = node.create_publisher(String, topic, QOS_LATCHED)
                pub.publish(String(data="the one latched"))
                # the bridge has made its DDS writer (its zenros subscription is in the graph)
                res["bridged"] = wait_for(lambda: graph.subscribers(topic), 20)
                # the late joiner starts now: the bridge's DDS writer keeps the sample for it
                # (transient local), whether it wrote it before or after the join
                peer = procs.start(str(HERE / "rclpy_peer.py"), "sub", kind, topic, "--tl")
                res["got"] = lines_of(peer, 1, 30)
            else:
                pub2: Any = node.create_publisher(String if kind == "String" else Twist, topic)
                peer = procs.start(str(HERE / "rclpy_peer.py"), "sub", kind, topic)
                import threading
                stop = threading.Event()

                def spam() -> None:
                    i = 0
                    while not stop.is_set():
                        i += 1
                        pub2.publish(String(data=f"zen {i}") if kind == "String"
                                     else Twist(linear=Vector3(x=0.25), angular=Vector3(z=float(i))))
                        stop.wait(0.05)
                t = threading.Thread(target=spam, daemon=True)
                t.start()
                res["got"] = lines_of(peer, 3, 30)
                stop.set()
                t.join()
        elif case == "srv_out":
            from zenros.msgs.std_srvs import SetBool
            peer = procs.start(str(HERE / "rclpy_peer.py"), "srv", "SetBool", "/set_flag")
            client = node.create_client(SetBool, "/set_flag")
            res["available"] = client.wait_for_service(60)
            res["servers"] = [t.node for t in graph.servers("/set_flag")]
            replies = []
            for flag in (True, False, True):
                r = client.call(SetBool.Request(data=flag), timeout=20)
                replies.append([r.success, r.message])
            res["replies"] = replies
            res["served"] = [d["served"] for d in lines_of(peer, 3, 10)]
            procs.stop(peer)
            res["route_left"] = wait_for(lambda: not graph.servers("/set_flag"), 30)
        elif case == "act_out":
            res.update(action_out(procs, node))
        elif case == "act_in":
            res.update(action_in(procs, node))
        elif case == "bad":
            from cyclonedds._clayer import ddspy_write
            from cyclonedds.domain import DomainParticipant
            from cyclonedds.pub import DataWriter
            from cyclonedds.topic import Topic
            from zenros.services.gateway.ros2.ddstypes import dds_type
            got2: Collector[Any] = Collector()
            node.create_subscription(String, "/bad", got2)
            dp = DomainParticipant(0)
            w = DataWriter(dp, Topic(dp, "rt/bad", dds_type("std_msgs/msg/String")))
            assert wait_for(lambda: w.get_matched_subscriptions(), 20)
            # what DDS accepts (a well-formed string) but is not UTF-8: zenros cannot decode it
            bad = b"\x00\x01\x00\x00\x03\x00\x00\x00\xff\xfe\x00\x00"
            res["bad_written"] = [ddspy_write(w._ref, bad) for _ in range(5)]
            ok = b"\x00\x01\x00\x00\x03\x00\x00\x00ok\x00\x00"
            res["good_after"] = wait_for(lambda: (ddspy_write(w._ref, ok), len(got2) > 0)[1], 20,
                                         interval=0.1)
            res["items"] = [m.data for m in got2.items[:1]]
    except Exception:  # noqa: BLE001 the JSON line carries the failure and the bridge's log
        res["error"] = traceback.format_exc()[-3000:]
        res["failed_at_s"] = round(time.monotonic() - started, 2)
    finally:
        node.close()
        ctx.close()
        errs = procs.stop_all()
        res["bridge_log"] = errs["0"]
    return res


def _plain(value: object) -> object:
    """A wait's result as the bool it stands for (``res["received"] = wait_for(...)``)."""
    if isinstance(value, Waited):
        return value.ok
    raise TypeError(f"{type(value).__name__} is not JSON serializable")


if __name__ == "__main__":
    print(json.dumps(main(sys.argv[1]), default=_plain), flush=True)
