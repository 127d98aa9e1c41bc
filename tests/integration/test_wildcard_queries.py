"""A wildcard get never calls a service or an action: each answers only its own key, and
refuses others with a clear error. Parameter reads by wildcard still work."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import zenoh
from zenros.action import ActionClient, ServerGoalHandle
from zenros.context import Context
from zenros.msgs.example_interfaces import AddTwoInts, Fibonacci, FibonacciGoal, FibonacciResult
from zenros.param_client import ParameterClient
from zenros.rpc import Client
from zenros.services.master.node import MasterNode


@pytest.fixture
def master(ctx_pair: list[Context], tmp_path: Path) -> Iterator[MasterNode]:
    m = MasterNode(context=ctx_pair[1], parameter_overrides={"data_dir": str(tmp_path)})
    yield m
    m.close()


def _get_all(ctx: Context, key: str, body: bytes) -> list[zenoh.Reply]:
    return list(ctx.session.get(key, payload=body, encoding="application/json", timeout=3.0))


def _refusals(replies: list[zenoh.Reply]) -> list[str]:
    out = []
    for r in replies:
        assert r.err is not None, f"a wildcard query was answered: {r.ok}"
        body = json.loads(r.err.payload.to_bytes())
        assert body["error"] == "BadRequest"
        out.append(body["message"])
    return out


def test_a_wildcard_get_calls_no_service(make_node: Any, ctx_pair: list[Context]) -> None:
    calls: list[Any] = []

    def add(req: Any) -> Any:
        calls.append(req)
        return AddTwoInts.Response(sum=req.a + req.b)

    server = make_node("server", 1)
    server.create_service(AddTwoInts, "add_two_ints", add)
    server.create_service(AddTwoInts, "robot/add", add)
    client = Client(ctx_pair[0], AddTwoInts, "/add_two_ints")
    assert client.wait_for_service(10)
    keys = ctx_pair[0].keys
    for pattern in (f"{keys.prefix}/service/**", f"{keys.prefix}/service/*",
                    f"{keys.prefix}/service/robot/a$*"):
        messages = _refusals(_get_all(ctx_pair[0], pattern, b'{"a": 1, "b": 2}'))
        assert messages and all("answers only queries on its own key" in m for m in messages)
    assert calls == []
    assert client.call(AddTwoInts.Request(a=1, b=2)).sum == 3
    assert len(calls) == 1


def test_a_wildcard_get_sends_no_goal(make_node: Any, ctx_pair: list[Context]) -> None:
    goals: list[Any] = []

    def execute(h: ServerGoalHandle[FibonacciGoal]) -> FibonacciResult:
        goals.append(h.request)
        h.succeed()
        return FibonacciResult()

    make_node("server", 1).create_action_server(Fibonacci, "fib", execute)
    client: ActionClient = make_node("client", 0).create_action_client(Fibonacci, "fib")
    assert client.wait_for_server(10)
    keys = ctx_pair[0].keys
    body = json.dumps({"goal_id": {"uuid": list(range(1, 17))}, "goal": {"order": 3}}).encode()
    for pattern in (f"{keys.prefix}/action/**", f"{keys.prefix}/action/fib/*",
                    f"{keys.prefix}/action/*/send_goal"):
        messages = _refusals(_get_all(ctx_pair[0], pattern, body))
        assert messages and all("action /fib answers only" in m for m in messages)
    assert goals == []
    client.send_goal(FibonacciGoal(order=1), timeout=10)
    assert len(goals) == 1


def test_a_wildcard_get_deletes_no_parameter_and_reads_still_work(
    ctx_pair: list[Context], master: MasterNode
) -> None:
    params = ParameterClient(ctx_pair[0], timeout=5.0)
    assert params.wait_for_master(10)
    params.set("/nav/max_speed", 0.5)
    params.set("/nav/name", "r1")
    keys = ctx_pair[0].keys
    for pattern in (f"{keys.prefix}/service/**", f"{keys.prefix}/service/master/*"):
        _refusals(_get_all(ctx_pair[0], pattern, b'{"name": "/", "namespace": true}'))
    assert params.list() == ["/nav/max_speed", "/nav/name"]
    replies = list(ctx_pair[0].session.get(f"{keys.prefix}/param/**", timeout=3.0))
    assert sorted(str(r.ok.key_expr) for r in replies if r.ok is not None) == [
        keys.param("/nav/max_speed"), keys.param("/nav/name")]
