"""Intra-process delivery: publish → callback latency for a subscriber in the same process.

Three paths for the same Twist: zenros in one context (the message object is handed over,
no serialization); raw zenoh with publisher and subscriber on one session (Zenoh's local
delivery: encode, put, decode); and zenros across processes (one-way = round trip / 2).
`latency_p50_ratio` = zenros in-process ÷ raw zenoh in-process. Prints one JSON line.
"""

from __future__ import annotations

import argparse
import threading
import time

import msgspec
import zenoh
from _harness import emit, percentile, raw_config, unique_prefix
from pubsub import latency
from zenros import Node
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.testing import loopback_options

MSG = Twist(linear=Vector3(x=0.5), angular=Vector3(z=0.1))


def zenros_local(n: int) -> list[float]:
    ctx = Context(loopback_options(), prefix=unique_prefix())
    a, b = Node("a", context=ctx), Node("b", context=ctx)
    t_recv = [0.0]
    b.create_subscription(Twist, "cmd_vel", lambda m: t_recv.__setitem__(0, time.perf_counter()))
    pub = a.create_publisher(Twist, "cmd_vel")
    out = []
    try:
        for i in range(n + 500):
            t0 = time.perf_counter()
            pub.publish(MSG)
            if i >= 500:
                out.append(t_recv[0] - t0)
        return out
    finally:
        a.close()
        b.close()
        ctx.close()


def raw_local(n: int) -> list[float]:
    s = zenoh.open(raw_config())
    enc, dec = msgspec.json.Encoder(), msgspec.json.Decoder(Twist)
    got = threading.Event()
    t_recv = [0.0]

    def on_sample(smp: zenoh.Sample) -> None:
        dec.decode(smp.payload.to_bytes())
        t_recv[0] = time.perf_counter()
        got.set()

    sub = s.declare_subscriber("local/cmd_vel", on_sample)
    pub = s.declare_publisher("local/cmd_vel", congestion_control=zenoh.CongestionControl.BLOCK)
    out = []
    try:
        for i in range(n + 500):
            got.clear()
            t0 = time.perf_counter()
            pub.put(enc.encode(MSG))
            if not got.wait(2):
                raise RuntimeError("local sample lost")
            if i >= 500:
                out.append(t_recv[0] - t0)
        return out
    finally:
        sub.undeclare()
        pub.undeclare()
        s.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--samples", type=int, default=5000)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    z, r, x = [], [], []
    for _ in range(a.repeats):
        z.append(percentile(zenros_local(a.samples), 50) * 1e6)
        r.append(percentile(raw_local(a.samples), 50) * 1e6)
        x.append(percentile(latency("zenros", 1000), 50) / 2 * 1e6)
    emit("intraprocess", {
        "latency_p50_us_zenros": round(min(z), 2),
        "latency_p50_us_raw": round(min(r), 2),
        "latency_p50_ratio": round(min(z) / min(r), 4),
        "cross_process_oneway_p50_us_zenros": round(min(x), 1),
        "intra_vs_cross_process_ratio": round(min(z) / min(x), 4),
    }, samples=a.samples, repeats=a.repeats)


if __name__ == "__main__":
    main()
