"""Actions across real processes: a server killed mid-goal, and the `zenros action` CLI."""

from __future__ import annotations

import signal
import sys
import threading
import time
from collections.abc import Iterator

import pytest
from zenros import Node
from zenros.action import ActionClient, GoalStatus
from zenros.context import Context
from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal
from zenros.testing import Collector, Proc

pytestmark = pytest.mark.system


@pytest.fixture
def client_node(observer: Context) -> Iterator[Node]:
    node = Node("action_test_client", context=observer)
    try:
        yield node
    finally:
        node.close()


@pytest.fixture
def fib_server(router: str, prefix: str) -> Iterator[Proc]:
    p = Proc([sys.executable, "-m", "zenros.examples.fibonacci_server", "-e", router,
              "--prefix", prefix, "-p", "period:=0.05"])
    try:
        yield p
    finally:
        p.stop()


def test_server_killed_mid_goal_is_lost_after_lost_timeout(client_node: Node,
                                                           fib_server: Proc) -> None:
    client = ActionClient(client_node, Fibonacci, "/fibonacci", lost_timeout=1.0)
    assert client.wait_for_server(15), fib_server.output
    feedback: Collector[object] = Collector()
    handle = client.send_goal_async(FibonacciGoal(order=5000), feedback)
    assert feedback.wait(3, 10), fib_server.output  # executing, feedback flowing
    start = time.monotonic()
    fib_server.signal(signal.SIGKILL)
    out = handle.result(10)
    assert 1.0 <= time.monotonic() - start < 4.0  # the wait for its return, then LOST
    assert out.status is GoalStatus.LOST and handle.status is GoalStatus.LOST
    assert "went away while goal" in out.reason
    assert not client.server_is_ready()


def test_server_frozen_past_its_lease_still_delivers_the_result(client_node: Node,
                                                                fib_server: Proc) -> None:
    """A server whose session dropped (frozen past the 1 s lease, as on a starved box) and
    came back within `lost_timeout` keeps its goal: the client asks for the result again."""
    client = ActionClient(client_node, Fibonacci, "/fibonacci", lost_timeout=10.0)
    assert client.wait_for_server(15), fib_server.output
    feedback: Collector[object] = Collector()
    gone = threading.Event()
    unlisten = client_node.context.graph.add_listener(
        lambda ev, tok: gone.set() if ev == "delete" and tok.kind == "act" else None)
    handle = client.send_goal_async(FibonacciGoal(order=60), feedback)  # 3 s at 0.05 s/step
    assert feedback.wait(3, 10), fib_server.output
    fib_server.signal(signal.SIGSTOP)
    try:
        assert gone.wait(10)  # the lease ran out: the server left the graph
        time.sleep(1.0)  # the fault: the outage lasts a second more
    finally:
        fib_server.signal(signal.SIGCONT)
        unlisten()
    out = handle.result(30)
    assert out.status is GoalStatus.SUCCEEDED, out.reason
    assert len(out.result.sequence) == 61


def run_cli(router: str, prefix: str, *args: str, timeout: float = 30) -> tuple[int, str]:
    p = Proc([sys.executable, "-m", "zenros.cli", "action", *args, "-e", router,
              "--prefix", prefix])
    try:
        return p.wait(timeout), p.output
    finally:
        p.stop()


def test_cli_list_info_and_send_goal(router: str, prefix: str, client_node: Node,
                                     fib_server: Proc) -> None:
    assert client_node.graph.wait_for_action("/fibonacci", 15), fib_server.output
    rc, out = run_cli(router, prefix, "list", "-t")
    assert rc == 0 and out.strip() == "/fibonacci [example_interfaces/Fibonacci]", out
    rc, out = run_cli(router, prefix, "info", "fibonacci")
    assert rc == 0, out
    assert out.startswith("Action: /fibonacci\nType: example_interfaces/Fibonacci\n"
                          "Action clients: "), out
    assert "Action servers: 1\n    /fibonacci_server" in out
    rc, out = run_cli(router, prefix, "send_goal", "/fibonacci",
                      "example_interfaces/action/Fibonacci", "{order: 4}", "--feedback")
    assert rc == 0, out
    assert "Goal accepted with ID: " in out
    assert out.count("Feedback:") == 3
    assert "Result:\nsequence:\n- 0\n- 1\n- 1\n- 2\n- 3\n" in out
    assert out.rstrip().endswith("Goal finished with status: SUCCEEDED")
    rc, out = run_cli(router, prefix, "send_goal", "/fibonacci", "example_interfaces/Fibonacci",
                      "{order: -1}")
    assert rc == 1 and "Goal was rejected: order must be in [0, 10000], got -1" in out, out


def test_cli_send_goal_names_a_type_by_its_ros2_name(router: str, prefix: str,
                                                      client_node: Node) -> None:
    """test_msgs/action/Fibonacci, whose module `zenros.msgs` leaves out (its Fibonacci would
    make the short name ambiguous): the CLI loads it by name (issue 37.6)."""
    from zenros.action import ActionServer, ServerGoalHandle
    from zenros.msgs import test_msgs

    def execute(handle: ServerGoalHandle[test_msgs.FibonacciGoal]) -> test_msgs.FibonacciResult:
        seq = [0, 1]
        while len(seq) <= handle.request.order:
            seq.append(seq[-1] + seq[-2])
        handle.succeed()
        return test_msgs.FibonacciResult(sequence=seq)

    server = ActionServer(client_node, test_msgs.Fibonacci, "/acc_fib", execute)
    try:
        assert client_node.graph.wait_for_action("/acc_fib", 15)
        for spelled in ("test_msgs/action/Fibonacci", "test_msgs/Fibonacci"):
            rc, out = run_cli(router, prefix, "send_goal", "/acc_fib", spelled, "{order: 5}")
            assert rc == 0, out
            assert "Result:\nsequence:\n- 0\n- 1\n- 1\n- 2\n- 3\n- 5\n" in out, out
    finally:
        server.close()
