"""Service benchmark: a trivial call's round trip, zenros Service/Client vs raw get/queryable.

Two processes on loopback, multicast off. The raw server decodes the request and encodes the
response with msgspec, as an application must. Prints one JSON line.
"""

from __future__ import annotations

import statistics
import sys
import time

import msgspec
import zenoh
from _harness import (
    Child,
    bench_parser,
    emit,
    free_port,
    latency_repeats,
    paired_ratio,
    raw_config,
    serve_node,
    unique_prefix,
)
from zenros import Node
from zenros.context import Context
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsRequest, AddTwoIntsResponse
from zenros.testing import loopback_options

REQ_DEC = msgspec.json.Decoder(AddTwoIntsRequest)
RES_DEC = msgspec.json.Decoder(AddTwoIntsResponse)
ENC = msgspec.json.Encoder()


def child_server(impl: str, port: int, prefix: str) -> None:
    if impl == "zenros":
        serve_node(port, prefix, "server", lambda node: node.create_service(
            AddTwoInts, "add", lambda r: AddTwoIntsResponse(sum=r.a + r.b)))
        return
    s = zenoh.open(raw_config(connect=port))

    def on_query(q: zenoh.Query) -> None:
        req = REQ_DEC.decode(q.payload.to_bytes() if q.payload else b"{}")
        q.reply(q.key_expr, ENC.encode(AddTwoIntsResponse(sum=req.a + req.b)))

    qbl = s.declare_queryable(f"{prefix}/add", on_query)
    print("ready", flush=True)
    sys.stdin.readline()
    qbl.undeclare()
    s.close()


def measure(impl: str, n: int) -> list[float]:
    port, prefix = free_port(), unique_prefix()
    req = AddTwoIntsRequest(a=1, b=2)
    if impl == "zenros":
        ctx = Context(loopback_options(port), prefix=prefix)
        node = Node("client", context=ctx)
        client = node.create_client(AddTwoInts, "add")
        child = Child(__file__, "--role", "server", "--impl", impl, "--port", str(port),
                      "--prefix", prefix)

        def call() -> None:
            assert client.call(req).sum == 3

        assert client.wait_for_service(10)
        closer = lambda: (node.close(), ctx.close())
    else:
        s = zenoh.open(raw_config(listen=port))
        child = Child(__file__, "--role", "server", "--impl", impl, "--port", str(port),
                      "--prefix", prefix)
        key = f"{prefix}/add"

        def call() -> None:
            for reply in s.get(key, payload=ENC.encode(req), timeout=5):
                assert RES_DEC.decode(reply.ok.payload.to_bytes()).sum == 3  # type: ignore[union-attr]
                return
            raise RuntimeError("no reply")

        closer = s.close
    try:
        deadline = time.monotonic() + 10
        while True:  # until the path works end to end
            try:
                call()
                break
            except Exception:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.01)
        out = []
        for i in range(n + 200):
            t0 = time.perf_counter()
            call()
            if i >= 200:
                out.append(time.perf_counter() - t0)
        return out
    finally:
        child.stop()
        closer()


def main() -> None:
    ap = bench_parser(__doc__, ["server"], repeats=5)
    ap.add_argument("--calls", type=int, default=2000)
    a = ap.parse_args()
    if a.role == "server":
        child_server(a.impl, a.port, a.prefix)
        return
    p50, p99 = latency_repeats(lambda impl: measure(impl, a.calls), a.repeats)
    med = {k: {i: statistics.median(v[i]) for i in v} for k, v in (("p50", p50), ("p99", p99))}
    emit("service", {
        "call_p50_us_zenros": round(med["p50"]["zenros"], 1),
        "call_p50_us_raw": round(med["p50"]["raw"], 1),
        "call_p50_ratio": round(paired_ratio(p50), 3),
        "call_p99_us_zenros": round(med["p99"]["zenros"], 1),
        "call_p99_us_raw": round(med["p99"]["raw"], 1),
        "call_p99_ratio": round(paired_ratio(p99), 3),
    }, service="example_interfaces/AddTwoInts", calls=a.calls, repeats=a.repeats,
        stat="medians; ratios are medians of per-repeat ratios")


if __name__ == "__main__":
    main()
