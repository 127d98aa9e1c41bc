"""Bag benchmark: recording throughput against the runtime's own one-way throughput, and
playback timing error at 1x.

record_ratio: a recorder process (`zenros.bag.Recorder`, Twist to MCAP with zstd) receiving
N numbered Twists from a zenros publisher process, lossless (every number in the bag, in
order, checked by reading it back), in msgs/s, divided by a zenros subscription process
receiving (and decoding) the same N Twists from the same publisher, back to back in each
repeat (as bench/pubsub.py measures one-way throughput).
play_error_p99_ms: a `zenros bag play` process (a real CLI process) plays a recorded bag of
Twists at 1x into a subscriber in this process; the error of a message is its arrival time
minus the recorded schedule (first message aligned by the median offset); p99 of |error|.
Prints one JSON line.
"""

from __future__ import annotations

import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from _harness import Child, bench_parser, emit, free_port, paired_ratio, percentile, unique_prefix
from zenros import Node
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.testing import loopback_options


def _wait_count(get: Any, count: int) -> None:
    """Until ``get()`` reaches ``count``, or it stops growing for 10 s (messages were lost)."""
    deadline = time.monotonic() + 120
    last_n, last_change = -1, time.monotonic()
    while time.monotonic() < deadline:
        n = get()
        if n >= count:
            return
        if n != last_n:
            last_n, last_change = n, time.monotonic()
        elif n and time.monotonic() - last_change > 10.0:
            return
        time.sleep(0.01)


def child_sink(port: int, prefix: str, count: int) -> None:
    """The runtime's own one-way receiver: a zenros subscription decoding every Twist."""
    ctx = Context(loopback_options(connect=[port]), prefix=prefix)
    node = Node("sink", context=ctx)
    times: list[float] = []
    xs: list[float] = []

    def on_msg(m: Twist) -> None:
        times.append(time.perf_counter())
        xs.append(m.linear.x)

    node.create_subscription(Twist, "/data", on_msg)
    print("ready", flush=True)
    _wait_count(lambda: len(xs), count)
    node.close()
    ctx.close()
    print(json.dumps({"received": len(xs), "lossless": xs == [float(i) for i in range(count)],
                      "seconds": times[-1] - times[0] if times else -1.0}), flush=True)


def child_recorder(port: int, prefix: str, count: int, directory: str) -> None:
    from mcap.reader import make_reader
    from zenros.bag import Recorder, RecordOptions, bag_files

    ctx = Context(loopback_options(connect=[port]), prefix=prefix)
    rec = Recorder(ctx, RecordOptions(Path(directory), topics=["/data"]))
    print("ready", flush=True)
    _wait_count(lambda: rec.sink.message_count, count)
    rec.close()
    ctx.close()
    times, xs = [], []
    for f in bag_files(Path(directory)):
        with open(f, "rb") as fh:
            for _, _, m in make_reader(fh).iter_messages():
                times.append(m.log_time)
                xs.append(json.loads(m.data)["linear"]["x"])
    lossless = xs == [float(i) for i in range(count)]
    print(json.dumps({"received": len(xs), "lossless": lossless,
                      "seconds": (max(times) - min(times)) / 1e9 if times else -1.0}), flush=True)


def throughput(role: str, count: int, workdir: Path) -> tuple[float, int]:
    """msgs/s into a ``role`` child (recorder or sink) and how many were lost; the parent
    publishes the same numbered Twists either way."""
    port, prefix = free_port(), unique_prefix()
    directory = workdir / f"rec_{prefix}"
    ctx = Context(loopback_options(port), prefix=prefix)
    node = Node("bench", context=ctx)
    pub = node.create_publisher(Twist, "/data")
    child = Child(__file__, "--role", role, "--port", str(port), "--prefix", prefix,
                  "--count", str(count), "--dir", str(directory))
    try:
        assert pub.wait_for_subscribers(1, 10)
        for i in range(count):
            pub.publish(Twist(linear=Vector3(x=float(i))))
        res = child.result(120)
    finally:
        child.stop()
        node.close()
        ctx.close()
        shutil.rmtree(directory, ignore_errors=True)
    lost = count - int(res["received"]) if res["lossless"] else max(1, count - res["received"])
    return (res["received"] / res["seconds"] if res["seconds"] > 0 else 0.0), lost


def make_bag(directory: Path, n: int, hz: float) -> None:
    """A bag of ``n`` Twists with uneven gaps (1x, 0.5x, 1.5x the period in turn)."""
    from zenros.bag.schema import schema_for
    from zenros.bag.sink import BagSink

    sink = BagSink(directory, directory.name)
    enc, schema = schema_for("geometry_msgs/Twist")
    cid = sink.add_channel("/play", "json", "geometry_msgs/Twist", enc, schema,
                           {"zenoh_encoding": "application/json;geometry_msgs/Twist",
                            "qos": "rel+10"})
    t = time.time_ns()
    for i in range(n):
        t += int(1e9 / hz * (1.0, 0.5, 1.5)[i % 3])
        sink.add(cid, t, t, json.dumps({"linear": {"x": float(i), "y": 0.0, "z": 0.0},
                                        "angular": {"x": 0.0, "y": 0.0, "z": 0.0}}).encode())
    sink.close()


def play_errors(workdir: Path, n: int, hz: float) -> list[float]:
    from mcap.reader import make_reader
    from zenros.bag import bag_files

    port, prefix = free_port(), unique_prefix()
    directory = workdir / f"play_{prefix}"
    make_bag(directory, n, hz)
    recorded: list[int] = []
    for f in bag_files(directory):
        with open(f, "rb") as fh:
            recorded += [m.log_time for _, _, m in make_reader(fh).iter_messages()]
    ctx = Context(loopback_options(port), prefix=prefix)
    node = Node("bench_sink", context=ctx)
    arrivals: dict[int, float] = {}
    done = threading.Event()

    def on_msg(m: Twist) -> None:
        arrivals[int(m.linear.x)] = time.perf_counter()
        if len(arrivals) == n:
            done.set()

    node.create_subscription(Twist, "/play", on_msg)
    proc = subprocess.Popen(
        [sys.executable, "-m", "zenros.cli", "bag", "play", str(directory), "-e",
         f"tcp/127.0.0.1:{port}", "--prefix", prefix],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, stdin=subprocess.DEVNULL)
    try:
        done.wait(n / hz + 30)
        proc.wait(30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        node.close()
        ctx.close()
        shutil.rmtree(directory, ignore_errors=True)
    if len(arrivals) != n:
        out = proc.stdout.read() if proc.stdout else ""
        raise RuntimeError(f"playback delivered {len(arrivals)}/{n}: {out}")
    offsets = [arrivals[i] - recorded[i] / 1e9 for i in range(n)]
    med = statistics.median(offsets)
    return [abs(o - med) for o in offsets]


def main() -> None:
    ap = bench_parser(__doc__, ["recorder", "sink"], repeats=3)
    ap.add_argument("--count", type=int, default=50_000)
    ap.add_argument("--dir", default="")
    ap.add_argument("--play-count", type=int, default=2000)
    ap.add_argument("--play-hz", type=float, default=500.0)
    a = ap.parse_args()
    if a.role == "recorder":
        child_recorder(a.port, a.prefix, a.count, a.dir)
        return
    if a.role == "sink":
        child_sink(a.port, a.prefix, a.count)
        return
    workdir = Path(tempfile.mkdtemp(prefix="zenros_bag_bench_"))
    thr: dict[str, list[float]] = {"zenros": [], "raw": []}  # "raw" = the runtime's own sink
    lost: dict[str, int] = {"record": 0, "runtime": 0}
    p99s: list[float] = []
    p50s: list[float] = []
    worst = 0.0
    try:
        for _ in range(a.repeats):
            rate, missing = throughput("recorder", a.count, workdir)
            thr["zenros"].append(rate)
            lost["record"] += missing
            rate, missing = throughput("sink", a.count, workdir)
            thr["raw"].append(rate)
            lost["runtime"] += missing
            errors = play_errors(workdir, a.play_count, a.play_hz)
            p99s.append(percentile(errors, 99) * 1e3)
            p50s.append(percentile(errors, 50) * 1e3)
            worst = max(worst, max(errors) * 1e3)
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    emit("bag", {
        "record_ratio": round(paired_ratio(thr), 3),
        "record_msgs_per_s": round(statistics.median(thr["zenros"])),
        "runtime_msgs_per_s": round(statistics.median(thr["raw"])),
        "record_lost": lost["record"], "runtime_lost": lost["runtime"],
        "play_error_p99_ms": round(statistics.median(p99s), 3),
        "play_error_p50_ms": round(statistics.median(p50s), 3),
        "play_error_max_ms": round(worst, 3),
    }, message="geometry_msgs/Twist", compression="zstd", count=a.count, repeats=a.repeats,
        play_count=a.play_count, play_hz=a.play_hz, loadavg=os.getloadavg()[0],
        stat="medians over repeats (record_ratio: of per-repeat ratios; play errors: of "
             "per-repeat percentiles of |arrival - recorded schedule|)")


if __name__ == "__main__":
    main()
