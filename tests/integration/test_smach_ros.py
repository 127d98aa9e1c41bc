"""ROS-aware smach states and the introspection server, across two real Zenoh sessions."""

from __future__ import annotations

import asyncio
import concurrent.futures
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from zenros.action import ActionServer, ServerGoalHandle
from zenros.errors import InvalidStateError, InvalidUserCodeError
from zenros.msgs.example_interfaces import (
    AddTwoInts,
    AddTwoIntsRequest,
    AddTwoIntsResponse,
    Fibonacci,
    FibonacciFeedback,
    FibonacciGoal,
    FibonacciResult,
)
from zenros.msgs.std_msgs import Int32
from zenros.node import Node
from zenros.smach import (
    ContainerEvent,
    ContainerStatus,
    IntrospectionServer,
    MonitorState,
    ServiceState,
    SetInitialState,
    SetInitialStateRequest,
    SimpleActionState,
    State,
    StateMachine,
    StateStructure,
    UserData,
    UserDataAccess,
    cb_interface,
)
from zenros.smach.doubles import SucceedState, WaitForPreempt
from zenros.testing import Collector, wait_for

Nodes = Callable[..., Node]


def machine(state: State, **remap: str) -> StateMachine:
    """A one-state machine whose outcomes are the state's own."""
    sm = StateMachine(outcomes=list(state.outcomes), input_keys=list(state.input_keys),
                      output_keys=list(state.output_keys))
    sm.add("S", state, remapping=remap or None)
    return sm


# ---------------------------------------------------------------- MonitorState


@pytest.fixture
def numbers(make_node: Nodes) -> Iterator[tuple[Node, Any]]:
    """The machine's node on side 0, a publisher of /numbers on side 1."""
    sm_node, other = make_node("sm", 0), make_node("source", 1)
    yield sm_node, other.create_publisher(Int32, "/numbers")


def test_monitor_state_valid_after_max_checks_and_invalid_on_first_false(
    numbers: tuple[Node, Any],
) -> None:
    node, pub = numbers
    seen: list[int] = []

    @cb_interface(output_keys=["last"])
    def small(ud: UserDataAccess, msg: Int32) -> bool:
        seen.append(msg.data)
        ud.last = msg.data
        return msg.data < 10

    state = MonitorState(node, "/numbers", Int32, small, max_checks=3)
    assert state.outcomes == ("valid", "invalid", "preempted")
    assert state.output_keys == ("last",)
    sm = machine(state)
    for values, outcome, checks in (([1, 2, 3], "valid", 3), ([4, 50, 6], "invalid", 2)):
        run = sm.execute_in_thread()
        assert pub.wait_for_subscribers(1, 10)
        for v in values:
            pub.publish(Int32(data=v))
        assert run.result(10) == outcome
        assert state.checks == checks and sm.userdata.last == values[checks - 1]
        assert node.graph.wait_for(lambda: not node.graph.subscribers("/numbers"), 10)
        # and gone on the publisher's side too: else the next run's wait_for_subscribers may
        # count this run's subscription and publish before the new one is matched (a run
        # beside a CPU hog lost its three samples so)
        assert wait_for(lambda: pub.subscription_count == 0, 10)
    assert seen == [1, 2, 3, 4, 50]  # the 6 came after the verdict: nobody listened


def test_monitor_state_preempt_timeout_and_a_failing_condition(
    numbers: tuple[Node, Any],
) -> None:
    node, pub = numbers
    state = MonitorState(node, "/numbers", Int32, lambda ud, msg: True)
    sm = machine(state)
    run = sm.execute_in_thread()
    assert node.graph.wait_for(lambda: bool(node.graph.subscribers("/numbers")), 10)
    run.request_preempt()
    assert run.result(10) == "preempted"
    state.request_preempt()  # a request before the run: no subscription at all
    assert state.execute(UserData()) == "preempted" and state.checks == 0

    quiet = MonitorState(node, "/numbers", Int32, lambda ud, msg: True, timeout=0.2)
    assert machine(quiet).execute() == "invalid"

    def broken(ud: UserDataAccess, msg: Int32) -> bool:
        raise ValueError("bad reading")

    assert node.graph.wait_for(lambda: not node.graph.subscribers("/numbers"), 10)
    run = machine(MonitorState(node, "/numbers", Int32, broken)).execute_in_thread()
    assert pub.wait_for_subscribers(1, 10)
    # Published until the run ends: right after the last subscriber left, the publisher's
    # match may still be the old one's (Zenoh's matching status lags the graph), and a first
    # message can go nowhere.
    assert wait_for(lambda: pub.publish(Int32(data=1)) or run.future.done(), 10, interval=0.1)
    with pytest.raises(InvalidUserCodeError, match="cond_cb of /S .*ValueError: bad reading"):
        run.result(10)


def test_monitor_state_rejects_bad_arguments(make_node: Nodes) -> None:
    node = make_node("sm", 0)
    with pytest.raises(InvalidStateError, match="max_checks"):
        MonitorState(node, "x", Int32, lambda ud, m: True, max_checks=0)
    with pytest.raises(InvalidStateError, match="callable"):
        MonitorState(node, "x", Int32, "nope")  # type: ignore[arg-type]


# ---------------------------------------------------------------- ServiceState


@pytest.fixture
def adder(make_node: Nodes) -> Iterator[concurrent.futures.Future[None]]:
    """/add_two_ints on side 1; a request with a == -1 waits until the future is set."""
    gate: concurrent.futures.Future[None] = concurrent.futures.Future()

    async def handle(req: AddTwoIntsRequest) -> AddTwoIntsResponse:
        if req.a == -1:
            await asyncio.wrap_future(gate)
        if req.a == -2:
            raise ValueError("no negative numbers")
        return AddTwoIntsResponse(sum=req.a + req.b)

    make_node("adder", 1).create_service(AddTwoInts, "/add_two_ints", handle)
    yield gate
    if not gate.done():
        gate.set_result(None)


def test_service_state_builds_the_request_and_stores_the_response(
    make_node: Nodes, adder: Any,
) -> None:
    node = make_node("sm", 0)

    @cb_interface(outcomes=["big"])
    def judge(ud: UserDataAccess, res: AddTwoIntsResponse) -> str | None:
        return "big" if res.sum > 100 else None

    state = ServiceState(node, AddTwoInts, "/add_two_ints", AddTwoIntsRequest(b=1),
                         request_slots=["a"], response_slots=["sum"], response_key="response",
                         response_cb=judge)
    assert set(state.outcomes) == {"succeeded", "aborted", "preempted", "big"}
    assert (state.input_keys, state.output_keys) == (("a",), ("sum", "response"))
    sm = StateMachine(outcomes=["succeeded", "aborted", "preempted", "big"])
    sm.add("ADD", state)
    sm.userdata.a = 41
    assert sm.execute() == "succeeded"
    assert sm.userdata.sum == 42 and sm.userdata.response == AddTwoIntsResponse(sum=42)
    sm.userdata.a = 200
    assert sm.execute() == "big"

    def build(ud: UserDataAccess, req: AddTwoIntsRequest) -> AddTwoIntsRequest:
        return AddTwoIntsRequest(a=ud.x, b=ud.x)

    twice = ServiceState(node, AddTwoInts, "/add_two_ints", request_cb=build,
                         input_keys=["x"], response_slots=["sum"])
    sm2 = machine(twice)
    sm2.userdata.x = 5
    assert sm2.execute() == "succeeded" and sm2.userdata.sum == 10


def test_service_state_aborts_on_failures_and_is_preemptible_mid_call(
    make_node: Nodes, adder: concurrent.futures.Future[None],
) -> None:
    node = make_node("sm", 0)
    missing = ServiceState(node, AddTwoInts, "/nobody_home", server_wait_timeout=0.2)
    assert machine(missing).execute() == "aborted"
    failing = ServiceState(node, AddTwoInts, "/add_two_ints", AddTwoIntsRequest(a=-2))
    assert machine(failing).execute() == "aborted"
    slow = ServiceState(node, AddTwoInts, "/add_two_ints", AddTwoIntsRequest(a=-1),
                        response_slots=["sum"])
    sm = machine(slow)
    run = sm.execute_in_thread()
    assert not run.future.done()
    run.request_preempt()
    assert run.result(10) == "preempted" and "sum" not in sm.userdata
    with pytest.raises(InvalidStateError, match="not fields of AddTwoIntsRequest"):
        ServiceState(node, AddTwoInts, "/add_two_ints", request_slots=["c"])


# ---------------------------------------------------------------- SimpleActionState


class Fib:
    """A Fibonacci action server on its own context; ``order < 0`` waits for a cancel."""

    def __init__(self, node: Node) -> None:
        self.cancels = 0
        self.started = threading.Event()
        self.release = threading.Event()
        self.server = ActionServer(node, Fibonacci, "/fibonacci", self.execute)

    def execute(self, gh: ServerGoalHandle[FibonacciGoal]) -> FibonacciResult:
        self.started.set()
        order = gh.request.order
        if order == -1:  # stream feedback until a cancel comes (or for 30 s)
            deadline = time.monotonic() + 30
            while not gh.wait_for_cancel(0.01) and time.monotonic() < deadline:
                gh.publish_feedback(FibonacciFeedback(sequence=[-1]))
            if gh.is_cancel_requested:
                self.cancels += 1
                gh.canceled()
                return FibonacciResult(sequence=[-1])
            gh.abort()
            return FibonacciResult()
        if order == -3:  # wait until released, never honouring a cancel
            self.release.wait(30)
            gh.abort()
            return FibonacciResult()
        if order == -2:
            gh.abort()
            return FibonacciResult(sequence=[-2])
        seq = [0, 1]
        for _ in range(order - 1):
            seq.append(seq[-1] + seq[-2])
            gh.publish_feedback(FibonacciFeedback(sequence=list(seq)))
        gh.succeed()
        return FibonacciResult(sequence=seq[: order + 1])


@pytest.fixture
def fib(make_node: Nodes) -> Iterator[Fib]:
    server = Fib(make_node("fib_server", 1))
    yield server
    server.release.set()


def test_simple_action_state_succeeds_with_slots_feedback_and_result_cb(
    make_node: Nodes, fib: Fib,
) -> None:
    node = make_node("sm", 0)
    feedback: list[list[int]] = []
    ends: list[Any] = []

    def on_result(ud: UserDataAccess, status: Any, result: FibonacciResult) -> str | None:
        ends.append(status.name)
        return None

    state = SimpleActionState(
        node, Fibonacci, "/fibonacci", goal_slots=["order"], result_slots=["sequence"],
        result_key="result", result_cb=on_result,
        feedback_cb=lambda ud, fb: feedback.append(list(fb.sequence)))
    sm = machine(state)
    sm.userdata.order = 5
    assert sm.execute() == "succeeded"
    assert sm.userdata.sequence == [0, 1, 1, 2, 3, 5]
    assert sm.userdata.result == FibonacciResult(sequence=[0, 1, 1, 2, 3, 5])
    assert ends == ["SUCCEEDED"]
    # feedback sent before Zenoh routes it to the new client, or after the result, is not
    # seen; what arrives is in order
    full = [0, 1, 1, 2, 3, 5]
    assert all(fb == full[: len(fb)] for fb in feedback)
    sm.userdata.order = -2
    assert sm.execute() == "aborted" and sm.userdata.sequence == [-2]


def test_simple_action_state_preempt_cancels_the_goal(make_node: Nodes, fib: Fib) -> None:
    node = make_node("sm", 0)
    feedback: Collector[Any] = Collector()
    state = SimpleActionState(node, Fibonacci, "/fibonacci", FibonacciGoal(order=-1),
                              result_slots=["sequence"], feedback_cb=lambda ud, fb: feedback(fb))
    sm = machine(state)
    run = sm.execute_in_thread()
    assert feedback.wait(1, 10)  # the goal runs, and its feedback reaches the callback
    run.request_preempt()
    assert run.result(10) == "preempted"
    assert fib.cancels == 1 and sm.userdata.sequence == [-1]
    assert not state.preempt_requested()


def test_simple_action_state_exec_timeout_and_missing_server(make_node: Nodes, fib: Fib) -> None:
    node = make_node("sm", 0)
    timed = SimpleActionState(node, Fibonacci, "/fibonacci", FibonacciGoal(order=-1),
                              exec_timeout=0.3)
    assert machine(timed).execute() == "aborted" and fib.cancels == 1
    nobody = SimpleActionState(node, Fibonacci, "/no_such_action", server_wait_timeout=0.2)
    assert machine(nobody).execute() == "aborted"


def test_simple_action_state_aborts_when_the_server_shuts_down(
    make_node: Nodes, fib: Fib,
) -> None:
    node = make_node("sm", 0)
    state = SimpleActionState(node, Fibonacci, "/fibonacci", FibonacciGoal(order=-1))
    run = machine(state).execute_in_thread()
    assert fib.started.wait(10)
    fib.server.close()  # cancels the running goal: CANCELED, but nobody here asked for it
    assert run.result(10) == "aborted"


# ---------------------------------------------------------------- IntrospectionServer


class Watch:
    """A tool's view of an introspection server: structure, statuses and events."""

    def __init__(self, node: Node, name: str) -> None:
        from zenros.qos import QOS_LATCHED

        self.structures: Collector[StateStructure] = Collector()
        self.statuses: Collector[ContainerStatus] = Collector()
        self.events: Collector[ContainerEvent] = Collector()
        node.create_subscription(StateStructure, f"{name}/structure", self.structures,
                                 QOS_LATCHED)
        node.create_subscription(ContainerStatus, f"{name}/status", self.statuses, QOS_LATCHED)
        node.create_subscription(ContainerEvent, f"{name}/events", self.events, 100)

    def until(self, pred: Callable[[ContainerStatus], bool], timeout: float = 10) -> bool:
        cond = self.statuses._cond
        with cond:
            return cond.wait_for(lambda: bool(self.statuses.items)
                                 and pred(self.statuses.items[-1]), timeout)


def patrol() -> tuple[StateMachine, WaitForPreempt]:
    inner = StateMachine(outcomes=["succeeded", "preempted"])
    wait = WaitForPreempt(outcomes=["succeeded"])
    inner.add("WAIT", wait)
    inner.add("OTHER", SucceedState())
    root = StateMachine(outcomes=["done", "preempted"])
    root.add("FIRST", SucceedState(), transitions={"succeeded": "INNER"})
    root.add("INNER", inner, transitions={"succeeded": "done"})
    root.userdata.laps = 0
    return root, wait


def test_introspection_server_publishes_structure_status_and_events(make_node: Nodes) -> None:
    robot, tool = make_node("robot", 0), make_node("tool", 1)
    root, wait = patrol()
    server = IntrospectionServer(robot, root, period=0.2)
    assert server.name == "/robot/smach"
    watch = Watch(tool, "/robot/smach")
    assert watch.structures.wait(1, 10)
    structure = watch.structures.items[-1]
    assert [c.label for c in structure.children] == ["FIRST", "INNER"]
    assert structure.children[1].initial_states == ["WAIT"]
    assert watch.until(lambda s: not s.running and s.userdata == {"laps": 0})
    assert server._events.wait_for_subscribers(1, 10)  # events are not latched: be routed first

    run = root.execute_in_thread()
    assert wait.entered.wait(10)
    assert watch.until(lambda s: s.running and s.active_paths == ["/INNER/WAIT"])
    assert watch.events.wait(3, 10)  # events travel on their own topic: no order with status
    kinds = [(e.kind, e.path) for e in watch.events.items]
    assert kinds[:3] == [("start", "/"), ("transition", "/"), ("start", "/INNER")]
    # heartbeats keep coming while nothing happens
    n = len(watch.statuses)
    assert watch.statuses.wait(n + 2, 10)
    run.request_preempt()
    assert run.result(10) == "preempted"
    assert watch.until(lambda s: not s.running and s.last_outcome == "preempted")
    assert watch.events.wait(len(kinds) + 3)
    server.close()
    server.close()


def test_set_initial_state_service_now_later_and_refused(make_node: Nodes) -> None:
    robot, tool = make_node("robot", 0), make_node("tool", 1)
    root, wait = patrol()
    IntrospectionServer(robot, root, "/patrol/smach")
    client = tool.create_client(SetInitialState, "/patrol/smach/set_initial_state")
    assert client.wait_for_service(10)

    res = client.call(SetInitialStateRequest(path="/INNER", initial_states=["NOPE"]))
    assert not res.success and "unknown initial state 'NOPE'" in res.message
    assert "available states: OTHER, WAIT" in res.message
    res = client.call(SetInitialStateRequest(path="/MISSING"))
    assert not res.success and "no state 'MISSING'" in res.message
    res = client.call(SetInitialStateRequest(path="/FIRST", initial_states=["X"]))
    assert not res.success and "not a container" in res.message

    res = client.call(SetInitialStateRequest(path="/", initial_states=["INNER"],
                                             userdata={"laps": 3}))
    assert res.success and res.applied
    assert root.get_initial_states() == ["INNER"] and root.userdata.laps == 3

    run = root.execute_in_thread()
    assert wait.entered.wait(10)
    res = client.call(SetInitialStateRequest(path="/", initial_states=["FIRST"],
                                             userdata={"laps": 4}))
    assert res.success and not res.applied and "next starts" in res.message
    assert root.userdata.laps == 3  # not while it runs
    run.request_preempt()
    assert run.result(10) == "preempted"
    wait.entered.clear()
    run = root.execute_in_thread()
    assert wait.entered.wait(10) and root.userdata.laps == 4
    run.request_preempt()
    assert run.result(10) == "preempted"
