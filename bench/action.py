"""Action benchmark: goal round trip (send, accept, trivial execute, result) vs a raw Zenoh
get/queryable round trip, in the same run.

Two processes on loopback, multicast off. The parent is the client; the child serves.
"zenros": `ActionClient.send_goal` against an `ActionServer` whose execute callback returns at
once (example_interfaces/Fibonacci, order 2), measured from the call to the `GoalResult`.
"raw": zenoh-python doing one request/response: the parent encodes the goal (msgspec JSON)
and gets; the child's queryable decodes it, encodes a result and replies; the parent decodes.
Prints one JSON line.
"""

from __future__ import annotations

import sys
import time
from typing import Any

import msgspec
import zenoh
from _harness import (
    Child,
    bench_parser,
    emit,
    free_port,
    latency_repeats,
    median,
    paired_ratio,
    raw_config,
    unique_prefix,
)
from zenros import Node
from zenros.action import ActionClient, ActionServer
from zenros.context import Context
from zenros.msgs.example_interfaces import Fibonacci, FibonacciGoal, FibonacciResult
from zenros.testing import loopback_options

GOAL = FibonacciGoal(order=2)
ENC = msgspec.json.Encoder()
GOAL_DEC = msgspec.json.Decoder(FibonacciGoal)
RESULT_DEC = msgspec.json.Decoder(FibonacciResult)
WARMUP = 200


def child_server(impl: str, port: int, prefix: str) -> None:
    if impl == "zenros":
        ctx = Context(loopback_options(connect=[port]), prefix=prefix)
        node = Node("bench_server", context=ctx)

        def execute(handle: Any) -> FibonacciResult:
            handle.succeed()
            return FibonacciResult(sequence=[0, 1, 1])

        ActionServer(node, Fibonacci, "bench", execute, policy="parallel", result_timeout=5.0)
        print("ready", flush=True)
        sys.stdin.readline()
        node.close()
        ctx.close()
        return
    s = zenoh.open(raw_config(connect=port))

    def on_query(q: zenoh.Query) -> None:
        with q:
            assert q.payload is not None
            GOAL_DEC.decode(q.payload.to_bytes())
            q.reply(q.key_expr, ENC.encode(FibonacciResult(sequence=[0, 1, 1])))

    qbl = s.declare_queryable(f"{prefix}/bench", on_query, complete=True)
    print("ready", flush=True)
    sys.stdin.readline()
    qbl.undeclare()  # type: ignore[no-untyped-call]
    s.close()  # type: ignore[no-untyped-call]


def _measure(call: Any, n: int) -> list[float]:
    out = []
    for i in range(n + WARMUP):
        t0 = time.perf_counter()
        call()
        if i >= WARMUP:
            out.append(time.perf_counter() - t0)
    return out


def roundtrips(impl: str, n: int) -> list[float]:
    port, prefix = free_port(), unique_prefix()
    if impl == "zenros":
        ctx = Context(loopback_options(port), prefix=prefix)
        node = Node("bench_client", context=ctx)
        client = ActionClient(node, Fibonacci, "bench")
        child = Child(__file__, "--role", "server", "--impl", impl, "--port", str(port),
                      "--prefix", prefix)
        try:
            if not client.wait_for_server(10):
                raise RuntimeError("no action server")

            def call() -> None:
                res = client.send_goal(GOAL, timeout=5)
                if not res.succeeded:
                    raise RuntimeError(f"goal failed: {res}")

            return _measure(call, n)
        finally:
            child.stop()
            node.close()
            ctx.close()
    s = zenoh.open(raw_config(listen=port))
    child = Child(__file__, "--role", "server", "--impl", impl, "--port", str(port),
                  "--prefix", prefix)
    key = f"{prefix}/bench"
    try:
        deadline = time.monotonic() + 10
        while not list(s.get(key, payload=ENC.encode(GOAL), timeout=1)):
            if time.monotonic() > deadline:
                raise RuntimeError("no raw queryable")

        def raw_call() -> None:
            for reply in s.get(key, payload=ENC.encode(GOAL), timeout=5,
                               target=zenoh.QueryTarget.BEST_MATCHING):
                assert reply.ok is not None
                RESULT_DEC.decode(reply.ok.payload.to_bytes())

        return _measure(raw_call, n)
    finally:
        child.stop()
        s.close()  # type: ignore[no-untyped-call]


def main() -> None:
    ap = bench_parser(__doc__, ["server"], repeats=5)
    ap.add_argument("--goals", type=int, default=1000)
    a = ap.parse_args()
    if a.role == "server":
        child_server(a.impl, a.port, a.prefix)
        return
    p50, p99 = latency_repeats(lambda impl: roundtrips(impl, a.goals), a.repeats)
    emit(
        "action",
        {
            "goal_roundtrip_p50_us_zenros": round(median(p50["zenros"]), 1),
            "goal_roundtrip_p50_us_raw": round(median(p50["raw"]), 1),
            "goal_roundtrip_p50_ratio": round(paired_ratio(p50), 3),
            "goal_roundtrip_p99_us_zenros": round(median(p99["zenros"]), 1),
            "goal_roundtrip_p99_us_raw": round(median(p99["raw"]), 1),
        },
        action="example_interfaces/Fibonacci", policy="parallel", goals=a.goals,
        repeats=a.repeats, ratio="median of per-repeat ratios",
    )


if __name__ == "__main__":
    main()
