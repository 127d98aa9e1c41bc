"""Services over Zenoh queryables: calls, handler styles, errors, timeouts, bad requests."""

from __future__ import annotations

import asyncio
import json
import math
import threading
import time
from typing import Any

import pytest
from zenros import ServiceError, ServiceUnavailableError, ZenrosTimeout
from zenros.errors import EncodeError
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse
from zenros.msgs.std_srvs import Trigger, TriggerRequest, TriggerResponse
from zenros.msgs.test_msgs import BasicTypesRequest, BasicTypesService
from zenros.reach import REACH_GRACE
from zenros.testing import wait_for


@pytest.fixture
def nodes(make_node: Any) -> tuple[Any, Any]:
    return make_node("server", 1), make_node("caller", 0)


def test_call_returns_the_response(nodes: Any) -> None:
    server, caller = nodes
    server.create_service(AddTwoInts, "add_two_ints", lambda r: AddTwoIntsResponse(sum=r.a + r.b))
    client = caller.create_client(AddTwoInts, "add_two_ints")
    assert client.wait_for_service(5)
    assert client.call(AddTwoIntsRequest(a=2, b=40)).sum == 42


def test_rclpy_style_handler_fills_the_response(nodes: Any) -> None:
    server, caller = nodes

    def handle(req: TriggerRequest, res: TriggerResponse) -> TriggerResponse:
        res.success, res.message = True, "done"
        return res

    server.create_service(Trigger, "trigger", handle)
    client = caller.create_client(Trigger, "trigger")
    assert client.wait_for_service(5)
    assert client.call(TriggerRequest()) == TriggerResponse(success=True, message="done")


def test_async_handler_and_async_call(nodes: Any) -> None:
    server, caller = nodes

    async def handle(req: AddTwoIntsRequest) -> AddTwoIntsResponse:
        await asyncio.sleep(0)
        return AddTwoIntsResponse(sum=req.a * req.b)

    server.create_service(AddTwoInts, "mul", handle)
    client = caller.create_client(AddTwoInts, "mul")
    assert client.wait_for_service(5)

    async def go() -> list[int]:
        res = await asyncio.gather(*(client.call_async(AddTwoIntsRequest(a=i, b=3)) for i in range(5)))
        return [r.sum for r in res]

    assert asyncio.run(go()) == [0, 3, 6, 9, 12]


def test_handler_exception_reaches_the_caller_as_service_error(nodes: Any) -> None:
    server, caller = nodes

    def handle(req: AddTwoIntsRequest) -> AddTwoIntsResponse:
        if req.b == 0:
            raise ZeroDivisionError("division by zero")
        return AddTwoIntsResponse(sum=req.a // req.b)

    server.create_service(AddTwoInts, "div", handle)
    client = caller.create_client(AddTwoInts, "div")
    assert client.wait_for_service(5)
    with pytest.raises(ServiceError) as info:
        client.call(AddTwoIntsRequest(a=1, b=0))
    assert info.value.service == "/div"
    assert "ZeroDivisionError: division by zero" in info.value.reason
    assert client.call(AddTwoIntsRequest(a=9, b=3)).sum == 3  # still serving


def test_async_call_raises_service_error(nodes: Any) -> None:
    server, caller = nodes

    def boom(req: Any) -> Any:
        raise RuntimeError("nope")

    server.create_service(AddTwoInts, "boom", boom)
    client = caller.create_client(AddTwoInts, "boom")
    assert client.wait_for_service(5)
    with pytest.raises(ServiceError, match="nope"):
        asyncio.run(client.call_async(AddTwoIntsRequest()))


def test_malformed_request_gets_a_clear_error_and_service_keeps_serving(
    nodes: Any, ctx_pair: Any
) -> None:
    server, caller = nodes
    srv = server.create_service(AddTwoInts, "add", lambda r: AddTwoIntsResponse(sum=r.a + r.b))
    client = caller.create_client(AddTwoInts, "add")
    assert client.wait_for_service(5)
    replies = list(ctx_pair[0].session.get(srv.key, payload=b'{"a": "one"}', timeout=5))
    assert len(replies) == 1 and replies[0].err is not None
    body = json.loads(replies[0].err.payload.to_bytes())
    assert body["error"] == "BadRequest" and "$.a" in body["message"]
    assert client.call(AddTwoIntsRequest(a=1, b=1)).sum == 2


def test_handler_returning_the_wrong_type_is_reported(nodes: Any) -> None:
    server, caller = nodes
    server.create_service(AddTwoInts, "bad", lambda r: "not a response")
    client = caller.create_client(AddTwoInts, "bad")
    assert client.wait_for_service(5)
    with pytest.raises(ServiceError, match="BadResponse"):
        client.call(AddTwoIntsRequest())


def test_a_raw_servers_responses_unreadable_and_null_floats(nodes: Any) -> None:
    # a server outside zenros: another shape is a ServiceError naming the path; NaN written
    # as null (msgspec's and rosbridge's way) arrives as NaN
    server, caller = nodes
    client = caller.create_client(BasicTypesService, "raw_basic")
    answers = iter([b'{"int64_value": "many"}', b'{"float64_value": null, "int64_value": 3}'])
    qbl = server.context.session.declare_queryable(
        client.key, lambda q: q.reply(q.key_expr, next(answers)))
    try:
        def refused() -> bool:
            try:
                client.call(BasicTypesRequest(), timeout=1)
            except ServiceUnavailableError:  # the queryable not routable yet
                return False
            except ServiceError as exc:
                assert "bad response" in str(exc) and "$.int64_value" in str(exc)
                return True
            raise AssertionError("an unreadable response was taken")

        assert wait_for(refused, 5)
        res = client.call(BasicTypesRequest())
        assert math.isnan(res.float64_value) and res.int64_value == 3
    finally:
        qbl.undeclare()


def test_no_server_is_unavailable(nodes: Any) -> None:
    _, caller = nodes
    client = caller.create_client(AddTwoInts, "nobody")
    assert not client.service_is_ready()
    assert not client.wait_for_service(0.2)
    with pytest.raises(ServiceUnavailableError, match="/nobody"):
        client.call(AddTwoIntsRequest(), timeout=3)


def test_slow_server_times_out(nodes: Any) -> None:
    server, caller = nodes
    release = threading.Event()

    def slow(req: AddTwoIntsRequest) -> AddTwoIntsResponse:
        release.wait(10)
        return AddTwoIntsResponse()

    server.create_service(AddTwoInts, "slow", slow)
    client = caller.create_client(AddTwoInts, "slow")
    assert client.wait_for_service(5)
    try:
        with pytest.raises(ZenrosTimeout, match="did not answer within 0.3"):
            client.call(AddTwoIntsRequest(), timeout=0.3)
    finally:
        release.set()


def test_request_of_the_wrong_type_is_refused_locally(nodes: Any) -> None:
    _, caller = nodes
    client = caller.create_client(AddTwoInts, "add")
    with pytest.raises(EncodeError, match="example_interfaces/AddTwoIntsRequest"):
        client.call(TriggerRequest())


def test_a_caller_beside_a_server_runs_one_request_on_one_server(make_node: Any) -> None:
    """Zenoh 1.10 delivers a BEST_MATCHING query both to the caller's own session and to a
    remote server; a call must run once (a delete done twice answers "not set"). The caller's
    own server answers; without one, exactly one remote server does."""
    hits: list[str] = []

    def serve(who: str) -> Any:
        return lambda r: (hits.append(who), AddTwoIntsResponse(sum=r.a + r.b))[1]

    remote = make_node("remote", 1)
    local = make_node("local", 0)
    remote.create_service(AddTwoInts, "/add", serve("remote"))
    caller = make_node("caller", 0)
    client = caller.create_client(AddTwoInts, "/add")
    assert client.wait_for_service(5)
    assert client.call(AddTwoIntsRequest(a=1, b=2)).sum == 3
    assert hits == ["remote"]
    srv = local.create_service(AddTwoInts, "/add", serve("local"))
    hits.clear()
    for i in range(20):
        assert client.call(AddTwoIntsRequest(a=i, b=1)).sum == i + 1
    assert asyncio.run(client.call_async(AddTwoIntsRequest(a=1, b=1))).sum == 2
    assert hits == ["local"] * 21
    srv.close()
    hits.clear()
    assert client.call(AddTwoIntsRequest(a=1, b=2)).sum == 3
    assert hits == ["remote"]


def test_a_listed_server_not_yet_routable_is_asked_again(nodes: Any) -> None:
    # the graph lists the server (its token) before its queryable is there, as a fresh
    # session can see a server's token a moment before it has a route to it
    server, caller = nodes
    ctx = server.context
    token = ctx.session.liveliness().declare_token(ctx.keys.entity_token(
        "srv", server.fqn, "/late_add", AddTwoInts.name, "", ctx.zid,
        ctx.next_eid()))
    client = caller.create_client(AddTwoInts, "/late_add")
    try:
        assert client.wait_for_service(5)
        t0 = time.monotonic()
        with pytest.raises(ServiceUnavailableError, match="/late_add"):  # never served
            client.call(AddTwoIntsRequest(a=1, b=2), timeout=5)
        assert time.monotonic() - t0 >= REACH_GRACE / 2  # asked again meanwhile, not given up
        asked = threading.Event()
        results: list[int] = []

        def call() -> None:
            asked.set()
            results.append(client.call(AddTwoIntsRequest(a=1, b=2), timeout=5).sum)

        t = threading.Thread(target=call)
        t.start()
        assert asked.wait(5)
        server.create_service(AddTwoInts, "/late_add",
                              lambda r: AddTwoIntsResponse(sum=r.a + r.b))
        t.join(10)
        assert results == [3]
    finally:
        token.undeclare()
