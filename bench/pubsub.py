"""Pub/sub benchmark: Twist round trip (p50/p99) and one-way throughput, zenros vs raw zenoh.

Two processes on loopback, multicast off. "raw" is zenoh-python doing what an application
must do without zenros: encode the Twist (msgspec JSON), put it, and decode it on arrival,
with the same congestion control as the zenros profile (reliable = BLOCK). "raw_bytes" also
skips encoding and decoding (pre-encoded bytes, payload untouched): the transport's ceiling.
Prints one JSON line.
"""

from __future__ import annotations

import statistics
import sys
import threading
import time
from typing import Any

import msgspec
import zenoh
from _harness import (
    Child,
    bench_parser,
    emit,
    free_port,
    paired_ratio,
    percentile,
    raw_config,
    serve_node,
    unique_prefix,
)
from zenros import Node
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.testing import loopback_options

MSG = Twist(linear=Vector3(x=0.5, y=0.1), angular=Vector3(z=-0.3))
ENC = msgspec.json.Encoder()
DEC = msgspec.json.Decoder(Twist)


# ------------------------------------------------------------------ children


def child_echo(impl: str, port: int, prefix: str) -> None:
    if impl == "zenros":
        def setup(node: Node) -> None:
            pong = node.create_publisher(Twist, "pong")
            node.create_subscription(Twist, "ping", pong.publish)

        serve_node(port, prefix, "echo", setup)
        return
    s = zenoh.open(raw_config(connect=port))
    pub = s.declare_publisher(f"{prefix}/pong", congestion_control=zenoh.CongestionControl.BLOCK)
    if impl in ("raw", "raw_default"):
        sub = s.declare_subscriber(f"{prefix}/ping",
                                   lambda smp: pub.put(ENC.encode(DEC.decode(smp.payload.to_bytes()))))
    else:
        sub = s.declare_subscriber(f"{prefix}/ping", lambda smp: pub.put(smp.payload))
    print("ready", flush=True)
    sys.stdin.readline()
    sub.undeclare()
    s.close()


def child_sink(impl: str, port: int, prefix: str, count: int) -> None:
    done = threading.Event()
    n = 0
    first = last = 0.0

    latest = [0.0]

    def on_msg(_: Any) -> None:
        nonlocal n, first, last
        latest[0] = time.perf_counter()
        if n == 0:
            first = latest[0]
        n += 1
        if n == count:
            last = latest[0]
            done.set()

    if impl == "zenros":
        ctx = Context(loopback_options(connect=[port]), prefix=prefix)
        node = Node("sink", context=ctx)
        node.create_subscription(Twist, "data", on_msg)
        closer: Any = lambda: (node.close(), ctx.close())
    else:
        s = zenoh.open(raw_config(connect=port))
        if impl in ("raw", "raw_default"):
            sub = s.declare_subscriber(f"{prefix}/data",
                                       lambda smp: on_msg(DEC.decode(smp.payload.to_bytes())))
        else:
            sub = s.declare_subscriber(f"{prefix}/data", on_msg)
        closer = lambda: (sub.undeclare(), s.close())
    print("ready", flush=True)
    deadline = time.monotonic() + 60
    while not done.wait(0.5) and time.monotonic() < deadline:
        if n and time.perf_counter() - latest[0] > 2.0:  # samples were dropped: stop waiting
            last = latest[0]
            break
    closer()
    import json

    print(json.dumps({"received": n, "seconds": (last - first) if last else -1.0}), flush=True)


# ------------------------------------------------------------------ parent


class Side:
    """The parent's endpoints for one implementation."""

    def __init__(self, impl: str, port: int, prefix: str) -> None:
        self.impl = impl
        self.pong = threading.Event()
        if impl == "zenros":
            self.ctx = Context(loopback_options(port), prefix=prefix)
            self.node = Node("bench", context=self.ctx)
            self.ping_pub = self.node.create_publisher(Twist, "ping")
            self.data_pub = self.node.create_publisher(Twist, "data")
            self.node.create_subscription(Twist, "pong", lambda m: self.pong.set())
            self.send_ping = self.ping_pub.publish
            self.send_data = self.data_pub.publish
        else:
            self.s = zenoh.open(raw_config(listen=port))
            # raw_default: zenoh's default congestion control (DROP), to show what it loses
            cc = {} if impl == "raw_default" else {"congestion_control": zenoh.CongestionControl.BLOCK}
            ping = self.s.declare_publisher(f"{prefix}/ping", **cc)
            data = self.s.declare_publisher(f"{prefix}/data", **cc)
            self._pubs = (ping, data)
            if impl in ("raw", "raw_default"):
                self.sub = self.s.declare_subscriber(
                    f"{prefix}/pong", lambda smp: (DEC.decode(smp.payload.to_bytes()), self.pong.set()))
                self.send_ping = lambda m: ping.put(ENC.encode(m))
                self.send_data = lambda m: data.put(ENC.encode(m))
            else:
                payload = ENC.encode(MSG)
                self.sub = self.s.declare_subscriber(f"{prefix}/pong", lambda smp: self.pong.set())
                self.send_ping = lambda m: ping.put(payload)
                self.send_data = lambda m: data.put(payload)

    def wait_matching(self, which: str) -> None:
        deadline = time.monotonic() + 10
        if self.impl == "zenros":
            pub = self.ping_pub if which == "ping" else self.data_pub
            assert pub.wait_for_subscribers(1, 10)
            return
        pub = self._pubs[0 if which == "ping" else 1]
        while not pub.matching_status.matching:
            assert time.monotonic() < deadline
            time.sleep(0.001)

    def close(self) -> None:
        if self.impl == "zenros":
            self.node.close()
            self.ctx.close()
        else:
            self.sub.undeclare()
            for p in self._pubs:
                p.undeclare()
            self.s.close()


def latency(impl: str, n: int) -> list[float]:
    port, prefix = free_port(), unique_prefix()
    side = Side(impl, port, prefix)
    child = Child(__file__, "--role", "echo", "--impl", impl, "--port", str(port), "--prefix", prefix)
    try:
        side.wait_matching("ping")
        # wait until the echo path works end to end
        for _ in range(50):
            side.pong.clear()
            side.send_ping(MSG)
            if side.pong.wait(0.2):
                break
        rtts = []
        for i in range(n + 200):
            side.pong.clear()
            t0 = time.perf_counter()
            side.send_ping(MSG)
            if not side.pong.wait(2):
                raise RuntimeError("pong lost")
            if i >= 200:
                rtts.append(time.perf_counter() - t0)
        return rtts
    finally:
        child.stop()
        side.close()


def throughput(impl: str, count: int) -> tuple[float, int]:
    port, prefix = free_port(), unique_prefix()
    side = Side(impl, port, prefix)
    child = Child(__file__, "--role", "sink", "--impl", impl, "--port", str(port), "--prefix",
                  prefix, "--count", str(count))
    try:
        side.wait_matching("data")
        send = side.send_data
        for _ in range(count):
            send(MSG)
        res = child.result(90)
    finally:
        child.stop()
        side.close()
    received = int(res["received"])
    return (received / res["seconds"] if res["seconds"] > 0 else 0.0), count - received


def main() -> None:
    ap = bench_parser(__doc__, ["echo", "sink"], repeats=5)
    ap.add_argument("--count", type=int, default=50_000)
    ap.add_argument("--pings", type=int, default=2000)
    a = ap.parse_args()
    if a.role == "echo":
        child_echo(a.impl, a.port, a.prefix)
        return
    if a.role == "sink":
        child_sink(a.impl, a.port, a.prefix, a.count)
        return
    impls = ("raw", "zenros", "raw_bytes")
    p50: dict[str, list[float]] = {i: [] for i in impls}
    p99: dict[str, list[float]] = {i: [] for i in impls}
    thr: dict[str, list[float]] = {i: [] for i in impls}
    lost: dict[str, int] = {i: 0 for i in impls}
    for _ in range(a.repeats):  # interleaved, so drift on a noisy machine hits both
        for impl in impls:
            rtts = latency(impl, a.pings)
            p50[impl].append(percentile(rtts, 50) * 1e6)
            p99[impl].append(percentile(rtts, 99) * 1e6)
            rate, missing = throughput(impl, a.count)
            thr[impl].append(rate)
            lost[impl] += missing
    med = {i: (statistics.median(p50[i]), statistics.median(p99[i]), statistics.median(thr[i]))
           for i in impls}
    z, r, rb = med["zenros"], med["raw"], med["raw_bytes"]
    _, drop_lost = throughput("raw_default", a.count)
    emit(
        "pubsub",
        {
            "latency_p50_us_zenros": round(z[0], 1), "latency_p50_us_raw": round(r[0], 1),
            "latency_p50_ratio": round(paired_ratio(p50), 3),
            "latency_p99_us_zenros": round(z[1], 1), "latency_p99_us_raw": round(r[1], 1),
            "latency_p99_ratio": round(paired_ratio(p99), 3),
            "throughput_msgs_zenros": round(z[2]), "throughput_msgs_raw": round(r[2]),
            "throughput_ratio": round(paired_ratio(thr), 3),
            "lost_zenros": lost["zenros"], "lost_raw": lost["raw"],
            "lost_raw_default_drop": drop_lost,
            "latency_p50_us_raw_bytes": round(rb[0], 1),
            "throughput_msgs_raw_bytes": round(rb[2]),
            "throughput_ratio_vs_raw_bytes": round(z[2] / rb[2], 3),
        },
        message="geometry_msgs/Twist", qos="reliable (BLOCK)", count=a.count, pings=a.pings,
        repeats=a.repeats, stat="medians; ratios are medians of per-repeat ratios",
    )


if __name__ == "__main__":
    main()
