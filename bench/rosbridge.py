"""rosbridge benchmark: a Twist topic delivered to 1 and 10 roslibpy clients, zenros's rosbridge
vs a bare ``websockets`` relay, in the same run. Prints one JSON line.

Three processes per case: the server (the rosbridge server on its own Zenoh session, or a
relay that forwards every ``publish`` frame it gets to every client that subscribed), the
roslibpy clients (all in one process, on roslibpy's default Twisted transport), and this
parent, which publishes: through a zenros publisher on another session (rosbridge), or as
ready-made rosbridge ``publish`` frames over one WebSocket (relay: no decoding, no encoding).
Each message carries its send time (``angular.z``, monotonic clock) so clients measure the
one-way latency; msgs/s is what each client received per second of publishing flat out
(averaged over the clients); p50/p99 come from a second run paced at ``--latency-rate``, below
saturation (flat out, latency only measures how deep the queues are). ``relay_ratio`` is
rosbridge msgs/s / relay msgs/s (the lower of the 1- and 10-client ratios).
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import os
import statistics
import sys
import threading
import time
from typing import Any

from _fairness import child_clients as child_fair_clients
from _fairness import child_gateway, child_map, measure_fairness, start_gateway
from _harness import Child, bench_parser, emit, free_port, percentile, unique_prefix

TOPIC = "/bench_twist"
WARMUP, MEASURE, END = 0.0, 1.0, 2.0  # linear.y: the phase a message belongs to


def frame(phase: float) -> str:
    return json.dumps({"op": "publish", "topic": TOPIC, "msg": {
        "linear": {"x": 0.5, "y": phase, "z": 0.0},
        "angular": {"x": 0.0, "y": 0.0, "z": time.monotonic()}}}, separators=(",", ":"))


# ------------------------------------------------------------------ children


def child_relay(port: int) -> None:
    """A bare websockets relay: publish frames in, the same text out to every subscriber."""
    from websockets.asyncio.server import broadcast, serve

    subs: set[Any] = set()

    async def handler(ws: Any) -> None:
        try:
            async for msg in ws:
                if msg.startswith('{"op":"publish"'):
                    broadcast(subs, msg)
                elif json.loads(msg).get("op") == "subscribe":
                    subs.add(ws)
        finally:
            subs.discard(ws)

    async def main() -> None:
        async with serve(handler, "127.0.0.1", port, compression=None):
            print("ready", flush=True)
            await asyncio.get_running_loop().run_in_executor(None, sys.stdin.readline)

    asyncio.run(main())


def child_rosbridge(port: int, zport: int, prefix: str) -> None:
    from zenros.context import Context
    from zenros.node import Node
    from zenros.services.gateway.rosbridge import RosbridgeServer
    from zenros.testing import loopback_options

    ctx = Context(loopback_options(zport), prefix=prefix)
    node = Node("rosbridge", context=ctx)
    server = RosbridgeServer(node, port=port)
    server.start_in_thread()
    print("ready", flush=True)
    sys.stdin.readline()
    server.stop_in_thread()
    node.close()
    ctx.close()


def child_clients(port: int, n: int) -> None:
    """``n`` roslibpy clients; "ready" once each got a message, a JSON line once each got END."""
    import roslibpy

    lat: list[list[float]] = [[] for _ in range(n)]
    span: list[list[float]] = [[] for _ in range(n)]  # first and last MEASURE arrival
    warm = [threading.Event() for _ in range(n)]
    ended = [threading.Event() for _ in range(n)]

    def on_message(i: int) -> Any:
        def cb(msg: dict[str, Any]) -> None:
            now = time.monotonic()
            phase = msg["linear"]["y"]
            if phase == MEASURE:
                lat[i].append(now - msg["angular"]["z"])
                span[i][1:] = [now]
                if len(span[i]) == 1:
                    span[i].insert(0, now)
            elif phase == WARMUP:
                warm[i].set()
            else:
                ended[i].set()
        return cb

    clients = []
    for i in range(n):
        ros = roslibpy.Ros("127.0.0.1", port)
        ros.run(20)
        roslibpy.Topic(ros, TOPIC, "geometry_msgs/Twist").subscribe(on_message(i))
        clients.append(ros)
    for e in warm:
        e.wait(30)
    print("ready", flush=True)
    for e in ended:
        e.wait(60)
    counts = [len(x) for x in lat]
    rates = [len(x) / (s[-1] - s[0]) for x, s in zip(lat, span, strict=True) if len(x) > 1]
    flat = [v for x in lat for v in x]
    print(json.dumps({"counts": counts, "rates": rates,
                      "p50_us": percentile(flat, 50) * 1e6 if flat else None,
                      "p99_us": percentile(flat, 99) * 1e6 if flat else None}), flush=True)
    os._exit(0)  # Twisted's reactor thread would keep the process alive


# ------------------------------------------------------------------ parent


class Publisher:
    """Sends Twist messages to the server under test from a thread."""

    def __init__(self, impl: str, port: int, zport: int, prefix: str) -> None:
        self.impl = impl
        if impl == "rosbridge":
            from zenros.context import Context
            from zenros.msgs.geometry_msgs import Twist
            from zenros.node import Node
            from zenros.testing import loopback_options

            self._ctx = Context(loopback_options(connect=[zport]), prefix=prefix)
            self._node = Node("bench_pub", context=self._ctx)
            self._pub = self._node.create_publisher(Twist, TOPIC)
            self._twist = Twist
        else:
            from websockets.sync.client import connect

            self._stack = contextlib.ExitStack()
            self._ws = self._stack.enter_context(
                connect(f"ws://127.0.0.1:{port}/", compression=None))

    def send(self, phase: float) -> None:
        if self.impl == "rosbridge":
            msg = self._twist()
            msg.linear.x, msg.linear.y, msg.angular.z = 0.5, phase, time.monotonic()
            self._pub.publish(msg)
        else:
            self._ws.send(frame(phase))

    def run(self, phase: float, stop: threading.Event, rate: float = 0.0) -> int:
        """Send until ``stop``: flat out, or paced to ``rate`` messages/s; returns the count."""
        sent = 0
        start = time.monotonic()
        while not stop.is_set():
            if rate:
                due = int((time.monotonic() - start) * rate) + 1
                if sent >= due:
                    stop.wait(min(0.001, 1.0 / rate))
                    continue
            self.send(phase)
            sent += 1
        return sent

    def close(self) -> None:
        if self.impl == "rosbridge":
            self._node.close()
            self._ctx.close()
        else:
            self._stack.close()


def measure(impl: str, n: int, duration: float, rate: float) -> dict[str, float]:
    port, zport, prefix = free_port(), free_port(), unique_prefix()
    script = os.path.abspath(__file__)
    if impl == "rosbridge":
        server = Child(script, "--role", "rosbridge", "--port", str(port), "--zport", str(zport),
                       "--prefix", prefix)
    else:
        server = Child(script, "--role", "relay", "--port", str(port))
    pub = Publisher(impl, port, zport, prefix)
    try:
        warm = threading.Event()
        t = threading.Thread(target=pub.run, args=(WARMUP, warm, 50.0), daemon=True)
        t.start()
        clients = Child(script, "--role", "clients", "--port", str(port), "--n", str(n))
        warm.set()
        t.join()
        stop = threading.Event()
        timer = threading.Timer(duration, stop.set)
        start = time.monotonic()
        timer.start()
        sent = pub.run(MEASURE, stop, rate)
        elapsed = time.monotonic() - start
        ending = threading.Event()
        t = threading.Thread(target=pub.run, args=(END, ending, 50.0), daemon=True)
        t.start()
        result = clients.result(120)
        ending.set()
        t.join()
    finally:
        pub.close()
        server.stop()
    counts = result["counts"]
    return {"msgs_s": statistics.mean(result["rates"]), "sent_s": sent / elapsed,
            "delivered": statistics.mean(counts) / sent,
            "p50_us": result["p50_us"], "p99_us": result["p99_us"]}


def map_message(side: int) -> Any:
    """A ``side`` x ``side`` OccupancyGrid as maps are: free space, walls and unknown cells."""
    import numpy as np
    from zenros.message import Int8Array, to_array
    from zenros.msgs.nav_msgs import OccupancyGrid

    rng = np.random.default_rng(7)
    cells = np.full((side, side), -1, dtype=np.int8)
    inner = slice(side // 8, side - side // 8)
    cells[inner, inner] = 0
    walls = rng.random((side, side)) < 0.05
    cells[walls & (cells == 0)] = 100
    msg = OccupancyGrid(data=to_array(Int8Array, cells.reshape(-1)))
    msg.header.frame_id = "map"
    msg.info.width = msg.info.height = side
    msg.info.resolution = 0.05
    return msg


def measure_cbor(side: int = 1448) -> dict[str, Any]:
    """Bytes of one ~2 MB map (``side``² cells) as rosbridge sends it as JSON and as CBOR,
    to two WebSocket clients of one server in the same run."""
    from websockets.sync.client import connect
    from zenros.context import Context
    from zenros.msgs.nav_msgs import OccupancyGrid
    from zenros.node import Node
    from zenros.testing import loopback_options

    port, zport, prefix = free_port(), free_port(), unique_prefix()
    server = Child(os.path.abspath(__file__), "--role", "rosbridge", "--port", str(port),
                   "--zport", str(zport), "--prefix", prefix)
    ctx = Context(loopback_options(connect=[zport]), prefix=prefix)
    node = Node("bench_map", context=ctx)
    sizes: dict[str, int] = {}
    try:
        pub = node.create_publisher(OccupancyGrid, "/bench_map")
        msg = map_message(side)
        url = f"ws://127.0.0.1:{port}/"
        with connect(url, max_size=None) as js, connect(url, max_size=None) as cb:
            for ws, compression in ((js, "none"), (cb, "cbor")):
                ws.send(json.dumps({"op": "subscribe", "topic": "/bench_map",
                                    "type": "nav_msgs/OccupancyGrid",
                                    "compression": compression}))
            deadline = time.monotonic() + 30
            while len(sizes) < 2 and time.monotonic() < deadline:
                pub.publish(msg)
                for ws, key in ((js, "json"), (cb, "cbor")):
                    with contextlib.suppress(TimeoutError):
                        while True:
                            sizes[key] = len(ws.recv(timeout=0.5 if key not in sizes else 0.05,
                                                     decode=False))
    finally:
        node.close()
        ctx.close()
        server.stop()
    return {"map_cells": side * side, "map_json_bytes": sizes.get("json"),
            "map_cbor_bytes": sizes.get("cbor"),
            "cbor_bytes_ratio": round(sizes["json"] / sizes["cbor"], 3)
            if len(sizes) == 2 else None}


FRAGMENTS = 262_144
"""The ``fragment_size`` of the ``rosbridge-fragments`` door's clients (characters)."""


def fairness(duration: float, doors: list[str], map_compression: str = "none",
             map_fragment_size: int = 0) -> dict[str, Any]:
    """/odom's p99 delivery age (ms) to 5 clients without and with a 2 MB map at 1 Hz, on
    rosbridge (no prefix), the topic WebSocket (``topicws_``) and Foxglove (``foxglove_``);
    rosbridge's clients take the map with ``map_compression`` (in ``fragment`` ops of
    ``map_fragment_size`` characters when given). ``rosbridge-fragments`` (``fragments_``)
    is rosbridge with clients that take the map in `FRAGMENTS`-character fragments, the
    protocol's own way for small frames to pass a large one (a whole message holds up
    everything behind it on its WebSocket)."""
    try:
        import foxglove  # noqa: F401
        has_foxglove = True
    except ImportError:
        has_foxglove = False
    script = os.path.abspath(__file__)
    gw, ports, zport, prefix = start_gateway(script, has_foxglove)
    out: dict[str, Any] = {}
    try:
        for door in doors:
            real = "rosbridge" if door == "rosbridge-fragments" else door
            if not ports.get(real):
                continue
            r = measure_fairness(script, real, ports[real], zport, prefix, duration=duration,
                                 map_compression=map_compression,
                                 map_fragment_size=FRAGMENTS if real != door
                                 else map_fragment_size)
            key = {"rosbridge": "", "rosbridge-fragments": "fragments_"}.get(door, f"{door}_")
            for phase in ("without_map", "with_map"):
                for stat in ("p99", "p50", "max"):
                    value = r[phase][f"{stat}_ms"]
                    out[f"{key}odom_{stat}_ms_{phase}"] = None if value is None else round(value, 2)
            out[f"{key}odom_samples"] = r["with_map"]["n"]
        out["map_compression"] = map_compression
        out["map_fragment_size"] = map_fragment_size
    finally:
        gw.stop()
    return out


def main() -> None:
    ap = bench_parser(__doc__, ["relay", "rosbridge", "clients", "gateway", "fair_clients", "map"],
                      repeats=1)
    ap.add_argument("--zport", type=int, default=0)
    ap.add_argument("--door", choices=["rosbridge", "topicws", "foxglove"], default="rosbridge")
    ap.add_argument("--foxglove", type=int, default=1)
    ap.add_argument("--doors", default="rosbridge,rosbridge-fragments,topicws,foxglove",
                    help="the doors whose fairness is measured (comma-separated)")
    ap.add_argument("--fair-duration", type=float, default=10.0,
                    help="seconds of /odom without, then with, the map (fairness)")
    ap.add_argument("--map-compression", choices=["none", "png", "cbor", "cbor-raw"],
                    default="none",
                    help="how rosbridge's fairness clients subscribe to the map")
    ap.add_argument("--map-fragment-size", type=int, default=0,
                    help="rosbridge's fairness clients take the map in fragment ops of this "
                         "many characters (0: whole)")
    ap.add_argument("--side", type=int, default=1448, help="the map's side in cells (fairness)")
    ap.add_argument("--n", type=int, default=1)
    ap.add_argument("--duration", type=float, default=3.0)
    ap.add_argument("--latency-rate", type=float, default=500.0,
                    help="messages/s for the latency runs (throughput runs publish flat out)")
    ap.add_argument("--only", choices=["cbor", "throughput", "fairness"], default=None,
                    help="run one part: the map's CBOR size, the Twist throughput, or /odom's "
                         "delivery age beside a 2 MB map")
    args = ap.parse_args()
    if args.role == "relay":
        child_relay(args.port)
        return
    if args.role == "rosbridge":
        child_rosbridge(args.port, args.zport, args.prefix)
        return
    if args.role == "clients":
        child_clients(args.port, args.n)
        return
    if args.role == "gateway":
        child_gateway(args.zport, args.prefix, bool(args.foxglove))
        return
    if args.role == "map":
        child_map(args.zport, args.prefix, args.side)
        return
    if args.role == "fair_clients":
        child_fair_clients(args.door, args.port, args.n, args.map_compression,
                           args.map_fragment_size)
        return
    metrics: dict[str, Any] = measure_cbor() if args.only in (None, "cbor") else {}
    if args.only in (None, "fairness"):
        metrics.update(fairness(args.fair_duration, args.doors.split(","), args.map_compression,
                                args.map_fragment_size))
    for n in (1, 10) if args.only in (None, "throughput") else ():
        # The relay's publisher is held back by TCP when the relay falls behind, so flat out
        # it offers what the relay path sustains; rosbridge (which never holds a publisher
        # back) is offered that same rate.
        relay = max((measure("relay", n, args.duration, 0.0) for _ in range(args.repeats)),
                    key=lambda r: r["msgs_s"])
        offered = relay["sent_s"]
        bridge = max((measure("rosbridge", n, args.duration, offered)
                      for _ in range(args.repeats)), key=lambda r: r["msgs_s"])
        for impl, top in (("relay", relay), ("rosbridge", bridge)):
            paced = [measure(impl, n, args.duration, args.latency_rate)
                     for _ in range(args.repeats)]
            metrics[f"{impl}_{n}_msgs_s"] = round(top["msgs_s"])
            metrics[f"{impl}_{n}_delivered"] = round(top["delivered"], 3)
            for key in ("p50_us", "p99_us"):
                metrics[f"{impl}_{n}_{key}"] = round(min(r[key] for r in paced))
        metrics[f"offered_{n}_msgs_s"] = round(offered)
        metrics[f"relay_ratio_{n}"] = round(
            metrics[f"rosbridge_{n}_msgs_s"] / metrics[f"relay_{n}_msgs_s"], 3)
    if args.only in (None, "throughput"):
        metrics["relay_ratio"] = min(metrics["relay_ratio_1"], metrics["relay_ratio_10"])
    emit("rosbridge", metrics, duration_s=args.duration, latency_rate=args.latency_rate)

if __name__ == "__main__":
    main()
