"""Every client asks a server the graph lists again until a query reaches it (`zenros.reach`).

The servers here declare their liveliness token first and their queryables only once the
client has found its first query unanswered: the state a fresh session can be in for a moment
(it lists a server before it has a route to it; docs/wire.md), made deterministic. The client
asks the graph whether a server is listed only after a query went unanswered, so a spy on that
question says when the server may appear.
"""

from __future__ import annotations

import asyncio
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from zenros import Node, ServiceUnavailableError
from zenros.action import ActionClient, ActionServer, GoalStatus, ServerGoalHandle
from zenros.errors import ActionServerUnavailableError
from zenros.msgs.example_interfaces import (
    AddTwoInts,
    AddTwoIntsRequest,
    AddTwoIntsResponse,
    Fibonacci,
    FibonacciGoal,
    FibonacciResult,
)
from zenros.reach import REACH_GRACE

MakeNode = Callable[..., Node]


def listed_token(node: Node, kind: str, name: str, type_name: str) -> Any:
    """A server's liveliness token alone (no queryable yet): the graph lists the server."""
    ctx = node.context
    return ctx.session.liveliness().declare_token(ctx.keys.entity_token(
        kind, node.fqn, name, type_name, "", ctx.zid, ctx.next_eid()))


class AskedAgain:
    """Wraps a client's "is a server listed?" question; ``event`` is set once it was asked,
    which a client does only after a query ended with no reply."""

    def __init__(self, client: Any, attr: str) -> None:
        self.event = threading.Event()
        listed = getattr(client, attr)

        def spy() -> bool:
            self.event.set()
            return bool(listed())

        setattr(client, attr, spy)


@pytest.fixture
def tokens() -> Iterator[list[Any]]:
    held: list[Any] = []
    yield held
    for t in held:
        t.undeclare()


def add(req: AddTwoIntsRequest) -> AddTwoIntsResponse:
    return AddTwoIntsResponse(sum=req.a + req.b)


def fib(h: ServerGoalHandle[FibonacciGoal]) -> FibonacciResult:
    h.succeed()
    return FibonacciResult(sequence=[0, 1][: h.request.order])


# ------------------------------------------------------------------ services


def test_call_async_asks_a_listed_server_again(make_node: MakeNode, tokens: list[Any]) -> None:
    server, caller = make_node("server", 1), make_node("caller", 0)
    tokens.append(listed_token(server, "srv", "/late_add", AddTwoInts.name))
    client = caller.create_client(AddTwoInts, "/late_add")
    assert client.wait_for_service(5)
    asked = AskedAgain(client, "service_is_ready")

    async def go() -> int:
        call = asyncio.ensure_future(client.call_async(AddTwoIntsRequest(a=1, b=2), 10))
        seen = await asyncio.get_running_loop().run_in_executor(None, asked.event.wait, 5)
        assert seen, "call_async never asked again after its first query went unanswered"
        server.create_service(AddTwoInts, "/late_add", add)
        return int((await call).sum)

    assert asyncio.run(go()) == 3


def test_call_async_gives_up_within_its_grace(make_node: MakeNode, tokens: list[Any]) -> None:
    server, caller = make_node("server", 1), make_node("caller", 0)
    tokens.append(listed_token(server, "srv", "/never_add", AddTwoInts.name))
    client = caller.create_client(AddTwoInts, "/never_add")
    assert client.wait_for_service(5)
    t0 = time.monotonic()
    with pytest.raises(ServiceUnavailableError, match="/never_add"):
        asyncio.run(client.call_async(AddTwoIntsRequest(a=1, b=2), 10))
    took = time.monotonic() - t0
    assert REACH_GRACE / 2 <= took < 10 * 0.9, took  # asked again, then gave up


def test_call_async_does_not_wait_for_an_unlisted_server(make_node: MakeNode) -> None:
    client = make_node("caller", 0).create_client(AddTwoInts, "/nobody_adds")
    t0 = time.monotonic()
    with pytest.raises(ServiceUnavailableError, match="/nobody_adds"):
        asyncio.run(client.call_async(AddTwoIntsRequest(a=1, b=2), 10))
    assert time.monotonic() - t0 < REACH_GRACE, "waited for a server the graph does not list"


# ------------------------------------------------------------------ actions


@pytest.fixture
def late_action(make_node: MakeNode, tokens: list[Any]
                ) -> tuple[ActionClient, AskedAgain, Callable[[], ActionServer]]:
    """A client of /late_fib, listed (its token) but not served until ``serve()``."""
    server_node, client_node = make_node("server", 1), make_node("client", 0)
    tokens.append(listed_token(server_node, "act", "/late_fib", Fibonacci.name))
    client = ActionClient(client_node, Fibonacci, "/late_fib")
    assert client.wait_for_server(5)
    asked = AskedAgain(client, "server_is_ready")
    return client, asked, lambda: ActionServer(server_node, Fibonacci, "/late_fib", fib)


def in_thread(fn: Callable[[], Any]) -> tuple[threading.Thread, list[Any]]:
    out: list[Any] = []

    def run() -> None:
        try:
            out.append(fn())
        except Exception as exc:  # noqa: BLE001 (handed to the test)
            out.append(exc)

    t = threading.Thread(target=run, daemon=True)
    t.start()
    return t, out


def test_send_goal_asks_a_listed_server_again(late_action: Any) -> None:
    client, asked, serve = late_action
    t, out = in_thread(lambda: client.send_goal(FibonacciGoal(order=2), timeout=10))
    assert asked.event.wait(5), "send_goal never asked again after its first query"
    serve()
    t.join(15)
    assert len(out) == 1 and not isinstance(out[0], Exception), out
    assert out[0].status is GoalStatus.SUCCEEDED


def test_send_goal_async_asks_a_listed_server_again(late_action: Any) -> None:
    client, asked, serve = late_action
    handle = client.send_goal_async(FibonacciGoal(order=2))
    assert asked.event.wait(5), "send_goal_async never asked again after its first query"
    serve()
    assert handle.result(15).status is GoalStatus.SUCCEEDED


def test_cancel_asks_a_listed_server_again(late_action: Any) -> None:
    client, asked, serve = late_action
    t, out = in_thread(lambda: client.cancel_goal(uuid.uuid4(), timeout=10))
    assert asked.event.wait(5), "cancel never asked again after its first query"
    serve()
    t.join(15)
    assert out == [[]]  # answered: no such goal, nothing canceling


def test_a_goal_to_a_listed_server_never_served_fails_within_the_grace(
        make_node: MakeNode, tokens: list[Any]) -> None:
    server_node, client_node = make_node("server", 1), make_node("client", 0)
    tokens.append(listed_token(server_node, "act", "/never_fib", Fibonacci.name))
    client = ActionClient(client_node, Fibonacci, "/never_fib", reach_grace=0.5)
    assert client.wait_for_server(5)
    t0 = time.monotonic()
    with pytest.raises(ActionServerUnavailableError, match="no action server answered"):
        client.send_goal(FibonacciGoal(order=1), timeout=10)
    assert 0.25 <= time.monotonic() - t0 < 5
