"""The `zenros` command line against real node processes through a real router."""

from __future__ import annotations

import json
import shlex
import subprocess
import sys
from collections.abc import Iterator
from typing import Any

import pytest
from zenros.testing import Proc, unique_prefix, wait_for

# A test here runs up to three CLI processes, each bounded at 30 s: past the suite's 60 s
# default a loaded box's slow start would fire pytest-timeout's alarm inside the failure
# report, which ends the whole run (an xdist INTERNALERROR) instead of failing one test.
pytestmark = [pytest.mark.system, pytest.mark.timeout(150)]


def zenros(router: str, prefix: str, *args: str, timeout: float = 30) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "zenros.cli", *args, "-e", router, "--prefix", prefix],
        capture_output=True, text=True, timeout=timeout, check=False,
    )


@pytest.fixture(scope="module")
def system(_shared_router: Any) -> Iterator[tuple[str, str]]:
    """A talker (20 Hz) and an add_two_ints server on the shared router, under a prefix of the
    module's own: shared by the module's tests, which only read from them."""
    router, prefix = _shared_router.get(), unique_prefix()
    procs = [
        Proc([sys.executable, "-m", mod, "-e", router, "--prefix", prefix, *extra])
        for mod, extra in [
            ("zenros.examples.talker", ["-p", "rate:=20.0"]),
            ("zenros.examples.add_two_ints_server", []),
        ]
    ]
    try:
        for p in procs:
            assert p.wait_line("started", 15), p.output
        yield router, prefix
    finally:
        for p in procs:
            p.stop()


def test_topic_list_info_type(system: tuple[str, str]) -> None:
    r = zenros(*system, "topic", "list", "-t")
    assert r.returncode == 0, r.stderr
    assert "/chatter [std_msgs/String]" in r.stdout
    r = zenros(*system, "topic", "info", "/chatter", "-v")
    assert r.returncode == 0 and "Publisher count: 1" in r.stdout and "/talker" in r.stdout
    r = zenros(*system, "topic", "type", "/chatter")
    assert r.stdout.strip() == "std_msgs/String"


def test_topic_echo_once_yaml_and_json(system: tuple[str, str]) -> None:
    r = zenros(*system, "topic", "echo", "/chatter", "--once", "--timeout", "10")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("data: hello world") and r.stdout.rstrip().endswith("---")
    r = zenros(*system, "topic", "echo", "/chatter", "-n", "2", "--json", "--timeout", "10")
    lines = r.stdout.splitlines()
    assert len(lines) == 2 and json.loads(lines[0])["data"].startswith("hello world")


def test_topic_pub_once_reaches_echo(system: tuple[str, str]) -> None:
    echo = Proc([sys.executable, "-m", "zenros.cli", "topic", "echo", "/cmd_vel", "--once",
                 "--json", "--timeout", "20", "-e", system[0], "--prefix", system[1]])
    try:
        # the echo says it waits once its subscriber is declared (a loaded box can take
        # seconds to start it: a publish before that was lost, 2 runs in 5 beside CPU hogs)
        assert echo.wait_line("waiting for one", 30), echo.output
        r = zenros(*system, "topic", "pub", "/cmd_vel", "geometry_msgs/Twist",
                   "{linear: {x: 0.5}, angular: {z: 0.1}}", "--once")
        assert r.returncode == 0, r.stderr
        assert echo.wait(20) == 0
        body = json.loads(echo.lines[-1])
        assert body["linear"]["x"] == 0.5 and body["angular"]["z"] == 0.1
    finally:
        echo.stop()


def test_topic_hz_and_bw(system: tuple[str, str]) -> None:
    r = zenros(*system, "topic", "hz", "/chatter", "--count", "1")
    assert r.returncode == 0, r.stderr
    rate = float(r.stdout.split("average rate:")[1].split()[0])
    assert 10 < rate < 30
    assert "std dev" in r.stdout and "min:" in r.stdout
    r = zenros(*system, "topic", "bw", "/chatter", "--count", "1")
    assert r.returncode == 0 and "B/s from" in r.stdout


def test_service_list_and_call(system: tuple[str, str]) -> None:
    r = zenros(*system, "service", "list", "-t")
    assert "/add_two_ints [example_interfaces/AddTwoInts]" in r.stdout
    r = zenros(*system, "service", "call", "/add_two_ints", "example_interfaces/AddTwoInts",
               "{a: 1, b: 2}")
    assert r.returncode == 0, r.stderr
    assert "sum: 3" in r.stdout


def test_node_list_and_info(system: tuple[str, str]) -> None:
    # (the rig is the module's: a node an earlier test started may take a moment to leave)
    listed: list[str] = []

    def only_the_rig() -> bool:
        listed[:] = zenros(*system, "node", "list").stdout.split()
        return listed == ["/add_two_ints_server", "/talker"]

    assert wait_for(only_the_rig, 20, interval=0.5), listed
    r = zenros(*system, "node", "info", "/talker")
    assert "/chatter: std_msgs/String" in r.stdout


@pytest.mark.parametrize(
    "args, needle",
    [
        (["topic", "pub", "/x", "geometry_msgs/Twst", "{}"], "unknown message type"),
        (["topic", "pub", "/x", "geometry_msgs/Twist", "{linear: {x: fast}}"], "$.linear.x"),
        (["topic", "pub", "/x", "geometry_msgs/Twist", "{linar: {x: 1}}"],
         "unknown field 'linar' at $ (geometry_msgs/Twist has: linear, angular)"),
        (["topic", "pub", "/x", "geometry_msgs/Twist", "{linear: ["], "invalid YAML"),
        (["topic", "pub", "/bad name", "std_msgs/String", "{}"], "invalid topic name"),
        (["service", "call", "/nothing", "std_srvs/Trigger"], "not available"),
        (["node", "info", "/ghost"], "unknown node /ghost"),
    ],
)
def test_bad_input_gives_one_clear_line_and_exit_1(
    router: str, prefix: str, args: list[str], needle: str
) -> None:
    r = zenros(router, prefix, *args)
    assert r.returncode == 1, (r.stdout, r.stderr)
    assert needle in r.stderr
    assert "Traceback" not in r.stderr


def test_graph_as_dot(system: tuple[str, str]) -> None:
    r = zenros(*system, "graph")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("digraph zenros {")
    assert '"n:/talker" -> "t:/chatter";' in r.stdout
    assert "/rosout" not in r.stdout
    r = zenros(*system, "graph", "--all")
    assert '"s:/add_two_ints"' in r.stdout


def test_echo_gets_a_latched_message_published_before_it_started(router: str, prefix: str) -> None:
    from zenros import QOS_LATCHED, Node
    from zenros.context import Context
    from zenros.msgs.std_msgs import String
    from zenros.session import SessionOptions

    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    node = Node("map_server", context=ctx)
    try:
        node.create_publisher(String, "map_name", QOS_LATCHED).publish(String(data="floor1"))
        r = zenros(router, prefix, "topic", "echo", "/map_name", "--once", "--timeout", "10")
        assert r.returncode == 0, r.stderr
        assert r.stdout.startswith("data: floor1")
    finally:
        node.close()
        ctx.close()


@pytest.mark.parametrize(
    "verb, lines",
    [
        (["topic", "echo", "/chatter"], 4),
        (["topic", "echo", "/chatter", "--json"], 2),
        (["topic", "hz", "/chatter"], 1),
        (["topic", "bw", "/chatter"], 1),
        (["tf", "echo", "world", "pipe_frame", "-r", "20"], 3),
    ],
)
def test_streaming_verb_piped_into_head_exits_quietly(
    system: tuple[str, str], verb: list[str], lines: int
) -> None:
    """`zenros topic echo /chatter | head -4`: no BrokenPipeError, and the verb ends."""
    router, prefix = system
    static = Proc([sys.executable, "-m", "zenros.cli", "tf", "static", "1", "0", "0", "0", "0",
                   "0", "world", "pipe_frame", "-e", router, "--prefix", prefix])
    try:
        # a bound, not a speed: a CLI's start took over 15 s in a suite beside three launches
        assert static.wait_line("publishing static transform", 45), static.output
        cmd = " ".join([shlex.quote(sys.executable), "-m", "zenros.cli",
                        *map(shlex.quote, verb), "-e", router, "--prefix", prefix])
        r = subprocess.run(["bash", "-c", f"set -o pipefail; {cmd} | head -{lines}"],
                           capture_output=True, text=True, timeout=30, check=False)
        assert r.returncode == 0, (r.stdout, r.stderr)
        assert len(r.stdout.splitlines()) == lines
        assert "Traceback" not in r.stderr and "Broken pipe" not in r.stderr, r.stderr
    finally:
        static.stop()


def test_topic_delay_from_header_stamps(system: tuple[str, str]) -> None:
    """ros2 topic delay: now minus each message's header.stamp; a type without a header
    is one clear line."""
    import threading
    import time

    from zenros.context import Context
    from zenros.msgs.builtin_interfaces import Time
    from zenros.msgs.geometry_msgs import PointStamped
    from zenros.msgs.std_msgs import Header
    from zenros.node import Node
    from zenros.session import SessionOptions

    router, prefix = system
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    node = Node("stamper", context=ctx)
    pub = node.create_publisher(PointStamped, "/stamped")
    stop = threading.Event()

    def stamp_late() -> None:  # each message stamped 0.25 s before it is sent
        while not stop.wait(0.05):
            pub.publish(PointStamped(header=Header(stamp=Time.from_nanoseconds(
                time.time_ns() - 250_000_000))))

    t = threading.Thread(target=stamp_late, daemon=True)
    t.start()
    try:
        r = zenros(router, prefix, "topic", "delay", "/stamped", "--count", "2")
        assert r.returncode == 0, r.stderr
        first = r.stdout.split("average delay:")[1].split()[0]
        assert 0.2 < float(first) < 0.45, r.stdout
        assert "std dev" in r.stdout and "window:" in r.stdout
        r = zenros(router, prefix, "topic", "delay", "/chatter", "--count", "1")
        assert r.returncode == 1 and "no header.stamp" in r.stderr, r.stderr
    finally:
        stop.set()
        t.join(5)
        node.close()
        ctx.close()


def test_doctor_reports_a_healthy_system_then_what_is_wrong(system: tuple[str, str]) -> None:
    """`zenros doctor`: ok on the rig; then two nodes with one name, a topic with two types
    and a pair ROS 2 would not connect are each named, and the exit code is 1."""
    from zenros.context import Context
    from zenros.msgs.std_msgs import Int32, String
    from zenros.node import Node
    from zenros.qos import QoSProfile, Reliability
    from zenros.session import SessionOptions

    router, prefix = system
    r = zenros(router, prefix, "doctor", "--hear", "1")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "links" in r.stdout and "no problems found" in r.stdout
    checks = {ln.split()[0]: ln.split()[1] for ln in r.stdout.splitlines() if ln[:1] != " "
              and len(ln.split()) > 1}
    assert all(checks[c] == "ok:" for c in ("links", "nodes", "QoS", "clocks", "zenoh")), \
        r.stdout
    ctxs = [Context(SessionOptions(connect=[router]), prefix=prefix) for _ in range(2)]
    nodes = [Node("twin", context=c) for c in ctxs]
    try:
        nodes[0].create_publisher(String, "/mixed")
        nodes[1].create_publisher(Int32, "/mixed")
        nodes[0].create_publisher(String, "/fragile", QoSProfile(
            reliability=Reliability.BEST_EFFORT))
        nodes[1].create_subscription(String, "/fragile", lambda m: None)
        g = ctxs[0].graph
        assert g.wait_for(lambda: len(g.subscribers("/fragile")) == 1
                          and len(g.topics().get("/mixed", [])) == 2, 10)
        r = zenros(router, prefix, "doctor", "--hear", "0.5")
        assert r.returncode == 1, r.stdout + r.stderr
        out = r.stdout
        assert "/twin: 2 nodes share it" in out
        assert "/mixed: std_msgs/Int32, std_msgs/String" in out
        assert "/fragile: /twin offers be+10, /twin requests rel+10 (RELIABILITY)" in out
        assert "3 problem(s)" in out
    finally:
        for n in nodes:
            n.close()
        for c in ctxs:
            c.close()


def test_service_echo_prints_a_services_events(system: tuple[str, str]) -> None:
    """`zenros service echo`: the requests and responses of a service whose server turned
    introspection on (ROS 2's configure_introspection, CONTENTS)."""
    from zenros.context import Context
    from zenros.msgs.std_srvs import SetBool, SetBoolRequest, SetBoolResponse
    from zenros.node import Node
    from zenros.service_events import ServiceIntrospectionState
    from zenros.session import SessionOptions

    router, prefix = system
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    node = Node("echoed", context=ctx)
    srv = node.create_service(SetBool, "/echoed_flag",
                              lambda req: SetBoolResponse(success=req.data, message="ok"))
    srv.configure_introspection(node.get_clock(), None, ServiceIntrospectionState.CONTENTS)
    client = node.create_client(SetBool, "/echoed_flag")
    echo = Proc([sys.executable, "-m", "zenros.cli", "service", "echo", "/echoed_flag",
                 "-n", "2", "--timeout", "30", "-e", router, "--prefix", prefix])
    try:
        assert srv.events.wait_for_subscribers(1, 45), echo.output  # the echo's
        assert client.call(SetBoolRequest(data=True), timeout=10).success
        assert echo.wait(30) == 0, echo.output
        out = echo.output
        assert out.count("event_type:") == 2 and "data: true" in out and "message: ok" in out
    finally:
        echo.stop(5)
        node.close()
        ctx.close()


def test_action_echo_prints_an_actions_services_feedback_and_status(
        system: tuple[str, str]) -> None:
    """`zenros action echo` (ros2 action echo, Kilted): the goal service's events of a server
    that turned introspection on, and the action's feedback and status, each named."""
    from zenros.action import ActionClient
    from zenros.context import Context
    from zenros.msgs.example_interfaces import (
        Fibonacci,
        FibonacciFeedback,
        FibonacciGoal,
        FibonacciResult,
    )
    from zenros.node import Node
    from zenros.service_events import ServiceIntrospectionState
    from zenros.session import SessionOptions

    def execute(handle: Any) -> FibonacciResult:
        for n in range(6):
            handle.publish_feedback(FibonacciFeedback(sequence=list(range(n + 1))))
        handle.succeed()
        return FibonacciResult(sequence=[0, 1, 1])

    router, prefix = system
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    node = Node("echoed_action", context=ctx)
    server = node.create_action_server(Fibonacci, "/echoed_fib", execute)
    server.configure_introspection(node.get_clock(), None, ServiceIntrospectionState.CONTENTS)
    echo = Proc([sys.executable, "-m", "zenros.cli", "action", "echo", "/echoed_fib",
                 "-n", "9", "--timeout", "30", "-e", router, "--prefix", prefix])
    try:
        assert server.events.send_goal.wait_for_subscribers(1, 20), echo.output
        assert wait_for(lambda: node.graph.subscribers("/echoed_fib/_action/get_result"
                                                       "/_service_event"), 20)
        client = ActionClient(node, Fibonacci, "/echoed_fib")
        assert client.send_goal(FibonacciGoal(order=3)).result.sequence == [0, 1, 1]
        assert echo.wait(60) == 0, echo.output  # 9 messages, or its own 30 s timeout
        out = echo.output
        assert "interface: GOAL_SERVICE" in out and "order: 3" in out, out
        assert "interface: FEEDBACK_TOPIC" in out or "interface: STATUS_TOPIC" in out, out
    finally:
        echo.stop(5)
        node.close()
        ctx.close()
