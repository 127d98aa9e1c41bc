"""State machines across real processes: `zenros smach` on the patrol example, and a
SimpleActionState whose action server is killed mid-goal."""

from __future__ import annotations

import signal
import subprocess
import sys
from collections.abc import Callable, Iterator

import pytest
from zenros import Node
from zenros.context import Context
from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal
from zenros.msgs.std_msgs import String
from zenros.qos import QOS_LATCHED
from zenros.smach import ContainerStatus, SimpleActionState, StateMachine
from zenros.testing import Collector, Proc

pytestmark = pytest.mark.system

SERVER = "/smach_patrol/smach"


@pytest.fixture
def tester(observer: Context) -> Iterator[Node]:
    node = Node("smach_tester", context=observer)
    try:
        yield node
    finally:
        node.close()


@pytest.fixture
def patrol(router: str, prefix: str) -> Iterator[Proc]:
    proc = Proc([sys.executable, "-m", "zenros.examples.smach_patrol", "-e", router,
                 "--prefix", prefix])
    try:
        assert proc.wait_line("started", 15), proc.output
        yield proc
    finally:
        proc.stop()


def smach(router: str, prefix: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "zenros.cli", "smach", *args, "-e", router, "--prefix", prefix],
        capture_output=True, text=True, timeout=30, check=False,
    )


def active(statuses: Collector[ContainerStatus]) -> list[str]:
    return statuses.items[-1].active_paths if statuses.items else []


def send_until(send: Callable[[], None], statuses: Collector[ContainerStatus],
               paths: list[str]) -> None:
    """Publish until the machine shows ``paths`` active: a command sent before the monitoring
    state's fresh subscription is routed is lost, and repeating it is harmless here."""
    cond = statuses._cond
    for _ in range(20):
        send()
        with cond:
            if cond.wait_for(lambda: active(statuses) == paths, 1.0):
                return
    pytest.fail(f"the machine never reached {paths}; active: {active(statuses)}")


def test_show_list_and_set_initial_follow_the_running_patrol(
    router: str, prefix: str, patrol: Proc, tester: Node,
) -> None:
    r = smach(router, prefix, "list")
    assert r.returncode == 0 and f"{SERVER}  (node /smach_patrol)" in r.stdout, r.stderr

    r = smach(router, prefix, "show", "--once")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith(f"{SERVER}  StateMachine  running")
    assert "    userdata: laps=0" in lines
    assert any(ln.startswith("|-- * IDLE (MonitorState) [initial]") and "invalid -> PATROL" in ln
               for ln in lines), r.stdout
    assert any("  ARRIVE (MonitorState)" in ln and "*" not in ln for ln in lines)

    statuses: Collector[ContainerStatus] = Collector()
    tester.create_subscription(ContainerStatus, f"{SERVER}/status", statuses, QOS_LATCHED)
    command = tester.create_publisher(String, "/smach_patrol/command")
    assert command.wait_for_subscribers(1, 10)
    patrolling = ["/PATROL/TOUR/VISIT/ARRIVE", "/PATROL/STOP"]
    send_until(lambda: command.publish(String(data="start")), statuses, patrolling)

    r = smach(router, prefix, "show", SERVER, "--once")
    assert r.returncode == 0, r.stderr
    marked = [ln.split("(")[0].split("*")[1].strip() for ln in r.stdout.splitlines()
              if "-- * " in ln]
    assert marked == ["PATROL", "TOUR", "VISIT", "ARRIVE", "STOP"], r.stdout
    assert "(item 0)" in r.stdout and "waypoint=[1.0,0.0]" in r.stdout

    r = smach(router, prefix, "set_initial", SERVER, "--path", "/PATROL/TOUR/VISIT",
              "--state", "NOPE")
    assert r.returncode == 1 and "unknown initial state 'NOPE'" in r.stderr
    assert "available states: ARRIVE, SEND" in r.stderr
    r = smach(router, prefix, "set_initial", SERVER, "--state", "IDLE", "--userdata",
              "{laps: 7}")
    assert r.returncode == 0 and "applies when / next starts" in r.stdout, r.stderr

    send_until(lambda: command.publish(String(data="stop")), statuses, ["/IDLE"])
    assert patrol.wait_line("PATROL -> IDLE (stopped)", 10), patrol.output
    r = smach(router, prefix, "show", "--once", "--json")
    assert r.returncode == 0 and '"active_paths": ["/IDLE"]' in r.stdout, r.stdout

    assert patrol.stop() == 0, patrol.output
    assert "machine ended: preempted" in patrol.output


def test_show_without_a_machine_says_so(router: str, prefix: str) -> None:
    r = smach(router, prefix, "show", "--once")
    assert r.returncode == 1 and "no smach introspection server found" in r.stderr
    r = smach(router, prefix, "show", "/nobody/smach", "--once", "--timeout", "0.5")
    assert r.returncode == 1 and "no structure and status from /nobody/smach" in r.stderr


def test_simple_action_state_aborts_when_its_server_is_killed(
    router: str, prefix: str, tester: Node,
) -> None:
    server = Proc([sys.executable, "-m", "zenros.examples.fibonacci_server", "-e", router,
                   "--prefix", prefix, "-p", "period:=0.05"])
    try:
        feedback: Collector[object] = Collector()
        state = SimpleActionState(tester, Fibonacci, "/fibonacci", FibonacciGoal(order=5000),
                                  feedback_cb=lambda ud, fb: feedback(fb),
                                  server_wait_timeout=15)
        sm = StateMachine(outcomes=["succeeded", "aborted", "preempted"])
        sm.add("FIB", state)
        run = sm.execute_in_thread()
        assert feedback.wait(3, 15), server.output
        server.signal(signal.SIGKILL)
        assert run.result(10) == "aborted"
    finally:
        server.stop()
