"""Large payloads: 1 MB and 8 MB numpy arrays, zenros bulk message vs raw zenoh bytes.

Two processes on loopback (shared memory on for both: Zenoh's default for raw, and for zenros
``ZENROS_SHM=1``, which a process that moves large payloads sets; zenros's default is off),
reliable (BLOCK). The zenros message is a bulk (MessagePack) type whose array field
travels as raw bytes and arrives as a zero-copy numpy view; ``image`` is the same bytes as a
``sensor_msgs/Image`` (mono8, 1024 wide) read at the receiver with `zenros.images.image_to_numpy`.
Throughput counted at the receiver in MB/s. Prints one JSON line.
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import threading
import time
from typing import Any

import numpy as np
import zenoh
from _harness import Child, bench_parser, emit, free_port, raw_config, unique_prefix
from zenros import Message, Node
from zenros.context import Context
from zenros.images import image_to_numpy
from zenros.message import UInt8Array, array_field
from zenros.msgs.sensor_msgs import Image
from zenros.session import SHM_ENV
from zenros.testing import loopback_options

os.environ[SHM_ENV] = "1"  # before any session; the child inherits it


class Blob(Message):
    """A bulk payload: bytes as a numpy uint8 array."""

    __msgtype__ = "zenros_bench/Blob"
    __bulk__ = True
    seq: int = 0
    data: UInt8Array = array_field(UInt8Array)


def child_sink(impl: str, port: int, prefix: str, count: int) -> None:
    done = threading.Event()
    n = 0
    nbytes = 0
    first = last = 0.0

    def on_data(size: int) -> None:
        nonlocal n, nbytes, first, last
        if n == 0:
            first = time.perf_counter()
        n += 1
        nbytes += size
        if n == count:
            last = time.perf_counter()
            done.set()

    if impl == "zenros":
        ctx = Context(loopback_options(connect=[port]), prefix=prefix)
        node = Node("sink", context=ctx)
        node.create_subscription(Blob, "blob", lambda m: on_data(int(m.data.nbytes)), 100)
        closer: Any = lambda: (node.close(), ctx.close())
    elif impl == "image":
        ctx = Context(loopback_options(connect=[port]), prefix=prefix)
        node = Node("sink", context=ctx)
        node.create_subscription(Image, "image", lambda m: on_data(int(image_to_numpy(m).nbytes)),
                                 100)
        closer = lambda: (node.close(), ctx.close())
    else:
        s = zenoh.open(raw_config(connect=port))
        sub = s.declare_subscriber(f"{prefix}/blob",
                                   lambda smp: on_data(len(np.frombuffer(smp.payload.to_bytes(), np.uint8))))
        closer = lambda: (sub.undeclare(), s.close())
    print("ready", flush=True)
    done.wait(120)
    closer()
    print(json.dumps({"received": n, "bytes": nbytes, "seconds": (last - first) if last else -1}),
          flush=True)


def measure(impl: str, size: int, count: int) -> float:
    port, prefix = free_port(), unique_prefix()
    arr = np.random.default_rng(1).integers(0, 255, size, dtype=np.uint8)
    if impl in ("zenros", "image"):
        ctx = Context(loopback_options(port), prefix=prefix)
        node = Node("src", context=ctx)
        # the same bytes as a bulk message's numpy field, or as a mono8 image 1024 wide
        pub: Any = (node.create_publisher(Blob, "blob", 100) if impl == "zenros"
                    else node.create_publisher(Image, "image", 100))
        make = ((lambda i: Blob(seq=i, data=arr)) if impl == "zenros" else
                (lambda i: Image(height=size // 1024, width=1024, encoding="mono8", step=1024,
                                 data=arr)))
        child = Child(__file__, "--role", "sink", "--impl", impl, "--port", str(port), "--prefix",
                      prefix, "--count", str(count))
        assert pub.wait_for_subscribers(1, 10)
        send = lambda i: pub.publish(make(i))
        closer: Any = lambda: (node.close(), ctx.close())
    else:
        s = zenoh.open(raw_config(listen=port))
        zpub = s.declare_publisher(f"{prefix}/blob", congestion_control=zenoh.CongestionControl.BLOCK)
        child = Child(__file__, "--role", "sink", "--impl", impl, "--port", str(port), "--prefix",
                      prefix, "--count", str(count))
        deadline = time.monotonic() + 10
        while not zpub.matching_status.matching:
            assert time.monotonic() < deadline
            time.sleep(0.001)
        send = lambda i: zpub.put(arr.tobytes())
        closer = lambda: (zpub.undeclare(), s.close())
    try:
        for i in range(count):
            send(i)
        res = child.result(180)
    finally:
        child.stop()
        closer()
    if res["received"] != count:
        raise RuntimeError(f"{impl}: received {res['received']}/{count}")
    return res["bytes"] / res["seconds"] / 1e6


def main() -> None:
    ap = bench_parser(__doc__, ["sink"], repeats=5)
    ap.add_argument("--count", type=int, default=0)
    a = ap.parse_args()
    if a.role == "sink":
        child_sink(a.impl, a.port, a.prefix, a.count)
        return
    metrics: dict[str, float] = {}
    for label, size, count in (("1mb", 1 << 20, 300), ("8mb", 8 << 20, 60)):
        runs: dict[str, list[float]] = {"raw": [], "zenros": [], "image": []}
        for _ in range(a.repeats):  # back to back, so a ratio compares like with like
            for impl in ("raw", "zenros", "image"):
                runs[impl].append(measure(impl, size, count))
        ratios = [z / r for z, r in zip(runs["zenros"], runs["raw"], strict=True)]
        image_ratios = [z / r for z, r in zip(runs["image"], runs["raw"], strict=True)]
        metrics[f"throughput_{label}_mbps_zenros"] = round(statistics.median(runs["zenros"]), 1)
        metrics[f"throughput_{label}_mbps_image"] = round(statistics.median(runs["image"]), 1)
        metrics[f"throughput_{label}_mbps_raw"] = round(statistics.median(runs["raw"]), 1)
        metrics[f"throughput_{label}_ratio"] = round(statistics.median(ratios), 3)
        metrics[f"throughput_{label}_image_ratio"] = round(statistics.median(image_ratios), 3)
    emit("large", metrics, repeats=a.repeats, qos="reliable (BLOCK)",
         stat="medians; ratios are medians of per-repeat ratios")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
