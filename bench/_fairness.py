"""Large-message fairness, for bench/rosbridge.py: /odom's delivery age beside a 2 MB map.

One gateway child serves the three doors (rosbridge 9090-style, the topic WebSocket 3547-style,
Foxglove when foxglove-sdk is installed). The parent publishes nav_msgs/Odometry on /odom at
50 Hz (its send time, monotonic clock, in ``pose.pose.position.z``; the phase in ``.x``) and,
in the second phase only, a 2 MB OccupancyGrid on /map at 1 Hz from a process of its own
(as a robot's map server is: the map's encoding, in the odometry's process, would hold up
/odom there, before the gateway has it). Five client processes
hold a WebSocket client each on one door, each subscribed to both topics (plain JSON, no
fragments, no compression: the case a browser asks for; ``--map-compression`` asks rosbridge
for the map as ``png``, ``cbor`` or ``cbor-raw`` instead); each reads every frame, parses
/odom's and records its age at arrival. The map frames are read whole but not parsed: a
Python parse of 5 MB of JSON takes 0.4 s and would measure the client, not the server. For
the same reason frames are received as bytes, text frames too (``recv(decode=False)``): the
UTF-8 decoding of a 4.6 MB text frame is the client's work, not the server's.
"""

from __future__ import annotations

import asyncio
import json
import os
import struct
import sys
import tempfile
import threading
import time
from typing import Any

from _harness import Child, free_port, percentile, unique_prefix

WARMUP, PLAIN, WITH_MAP, END = 0.0, 1.0, 2.0, 3.0
ODOM_HZ, MAP_HZ = 50.0, 1.0


# ------------------------------------------------------------------ children


def child_gateway(zport: int, prefix: str, foxglove: bool) -> None:
    """A gateway on free ports (rosbridge, topic WebSocket, Foxglove); prints them."""
    from zenros.context import Context
    from zenros.services.gateway.testing import running_gateway
    from zenros.testing import loopback_options

    ctx = Context(loopback_options(zport), prefix=prefix)
    with tempfile.TemporaryDirectory() as home, running_gateway(
            ctx, __import__("pathlib").Path(home), no_token_check=True,
            foxglove_port=0 if foxglove else -1) as gw:
        fox = gw.foxglove.port if gw.foxglove is not None else 0
        print("ready", json.dumps({"rosbridge": gw.rosbridge.port if gw.rosbridge else 0,
                                   "topicws": gw.ws_port, "foxglove": fox}), flush=True)
        sys.stdin.readline()
    ctx.close()


def _odom_of(door: str, data: bytes | str) -> dict[str, Any] | None:
    """The Odometry in a frame of ``door``, or None for any other frame."""
    if door == "foxglove":
        if isinstance(data, str) or not data or data[0] != 1:
            return None
        sub = struct.unpack_from("<I", data, 1)[0]
        if sub != 1:
            return None
        obj: dict[str, Any] = json.loads(data[13:])
        return obj
    raw = data.encode() if isinstance(data, str) else data
    if door == "rosbridge":
        if not raw.startswith(b'{"op":"publish","topic":"/odom"'):
            return None
        msg: dict[str, Any] = json.loads(raw)["msg"]
        return msg
    if len(raw) > 100_000:
        return None
    return json.loads(raw)  # type: ignore[no-any-return]


async def _client(door: str, port: int, ages: dict[float, list[float]],
                  warm: asyncio.Event, ended: asyncio.Event, map_compression: str,
                  map_fragment_size: int = 0) -> None:
    from websockets.asyncio.client import connect
    from websockets.exceptions import ConnectionClosed

    url = f"ws://127.0.0.1:{port}/"
    conns = []
    if door == "rosbridge":
        ws = await connect(url, max_size=None, compression=None)
        for topic, typ, compression in (("/odom", "nav_msgs/Odometry", "none"),
                                        ("/map", "nav_msgs/OccupancyGrid", map_compression)):
            op: dict[str, Any] = {"op": "subscribe", "topic": topic, "type": typ,
                                  "compression": compression}
            if topic == "/map" and map_fragment_size:
                op["fragment_size"] = map_fragment_size
            await ws.send(json.dumps(op))
        conns = [ws]
    elif door == "topicws":  # one connection per topic
        conns = [await connect(url + t, max_size=None, compression=None) for t in ("odom", "map")]
    else:
        ws = await connect(url, max_size=None, compression=None,
                           subprotocols=["foxglove.sdk.v1"])  # type: ignore[list-item]
        channels: dict[str, int] = {}
        while len(channels) < 2:
            frame = json.loads(await ws.recv())
            if frame.get("op") == "advertise":
                channels.update({c["topic"]: c["id"] for c in frame["channels"]
                                 if c["topic"] in ("/odom", "/map")})
        await ws.send(json.dumps({"op": "subscribe", "subscriptions": [
            {"id": 1, "channelId": channels["/odom"]}, {"id": 2, "channelId": channels["/map"]}]}))
        conns = [ws]

    async def read(ws: Any) -> None:
        while True:
            try:
                # bytes, text frames too: a 4.6 MB map's UTF-8 decoding (a few ms, in each of
                # the five clients of this one process) would delay the next /odom frame
                # here, in the client, and the bench measures the server
                data = await ws.recv(decode=False)
            except ConnectionClosed:
                return
            now = time.monotonic()
            msg = _odom_of(door, data)
            if msg is None:
                continue
            pos = msg["pose"]["pose"]["position"]
            ages.setdefault(pos["x"], []).append(now - pos["z"])
            if pos["x"] == WARMUP:
                warm.set()
            elif pos["x"] == END:
                ended.set()
                return

    readers = [asyncio.ensure_future(read(ws)) for ws in conns]
    await ended.wait()
    for r in readers:
        r.cancel()
    for ws in conns:
        await ws.close()


def child_clients(door: str, port: int, n: int, map_compression: str = "none",
                  map_fragment_size: int = 0) -> None:
    """``n`` clients of ``door``: "ready" once each heard /odom, then the ages (s) of each
    phase as JSON. On rosbridge the map may be asked for with ``map_compression`` (``png``:
    the JSON deflated in a PNG, base64; ``cbor``, ``cbor-raw``: binary frames; the reference
    server's answers to large messages)."""

    async def main() -> None:
        ages: list[dict[float, list[float]]] = [{} for _ in range(n)]
        warm = [asyncio.Event() for _ in range(n)]
        ended = [asyncio.Event() for _ in range(n)]
        tasks = [asyncio.ensure_future(_client(door, port, ages[i], warm[i], ended[i],
                                               map_compression, map_fragment_size))
                 for i in range(n)]
        await asyncio.wait_for(asyncio.gather(*(w.wait() for w in warm)), 60)
        print("ready", flush=True)
        await asyncio.wait(tasks, timeout=120)  # on a starved machine: report what came
        print(json.dumps({key: [a for c in ages for a in c.get(phase, [])]
                          for phase, key in ((PLAIN, "without_map"), (WITH_MAP, "with_map"))}),
              flush=True)

    asyncio.run(main())
    os._exit(0)


# ------------------------------------------------------------------ parent


class _Publisher:
    """/odom at 50 Hz from this process; the map from a child (`child_map`) told when."""

    def __init__(self, script: str, zport: int, prefix: str, side: int) -> None:
        from zenros.context import Context
        from zenros.msgs.nav_msgs import Odometry
        from zenros.node import Node
        from zenros.testing import loopback_options

        self._ctx = Context(loopback_options(connect=[zport]), prefix=prefix)
        self._node = Node("bench_fair", context=self._ctx)
        self._odom = self._node.create_publisher(Odometry, "/odom")
        self._odom_type = Odometry
        self._map = Child(script, "--role", "map", "--zport", str(zport), "--prefix", prefix,
                          "--side", str(side))
        self.phase = WARMUP
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._odom_loop, daemon=True)
        self._thread.start()

    def start_map(self) -> None:
        assert self._map.p.stdin is not None
        self._map.p.stdin.write("go\n")
        self._map.p.stdin.flush()

    def _odom_loop(self) -> None:
        def send() -> None:
            msg = self._odom_type()
            msg.header.frame_id = "odom"
            msg.pose.pose.position.x = self.phase
            msg.pose.pose.position.z = time.monotonic()
            self._odom.publish(msg)
        _paced(ODOM_HZ, send, self._stop)

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self._map.stop()
        self._node.close()
        self._ctx.close()


def _paced(hz: float, send: Any, stop: threading.Event) -> None:
    start, n = time.monotonic(), 0
    while not stop.is_set():
        n += 1
        stop.wait(max(0.0, start + n / hz - time.monotonic()))
        send()


def child_map(zport: int, prefix: str, side: int) -> None:
    """Publishes a ``side`` x ``side`` OccupancyGrid on /map at 1 Hz once told ("go" on
    stdin), until stdin closes."""
    from rosbridge import map_message  # the cbor bench's map
    from zenros.context import Context
    from zenros.msgs.nav_msgs import OccupancyGrid
    from zenros.node import Node
    from zenros.testing import loopback_options

    ctx = Context(loopback_options(connect=[zport]), prefix=prefix)
    node = Node("bench_fair_map", context=ctx)
    pub = node.create_publisher(OccupancyGrid, "/map")
    grid = map_message(side)
    print("ready", flush=True)
    stop = threading.Event()
    if sys.stdin.readline():  # "go"
        threading.Thread(target=lambda: (sys.stdin.read(), stop.set()), daemon=True).start()
        _paced(MAP_HZ, lambda: pub.publish(grid), stop)
    node.close()
    ctx.close()


def start_gateway(script: str, foxglove: bool) -> tuple[Child, dict[str, int], int, str]:
    zport, prefix = free_port(), unique_prefix()
    gw = Child(script, "--role", "gateway", "--zport", str(zport), "--prefix", prefix,
               "--foxglove", "1" if foxglove else "0")
    ports: dict[str, int] = json.loads(gw.ready_line.split(" ", 1)[1])
    return gw, ports, zport, prefix


def measure_fairness(script: str, door: str, port: int, zport: int, prefix: str,
                     n: int = 5, duration: float = 10.0, side: int = 1448,
                     map_compression: str = "none", map_fragment_size: int = 0
                     ) -> dict[str, Any]:
    """/odom's delivery age to ``n`` clients of ``door``, without then with the map."""
    pub = _Publisher(script, zport, prefix, side)
    clients: list[Child] = []
    try:
        for _ in range(n):  # a process each, as browsers are: one's reading holds up no other
            clients.append(Child(script, "--role", "fair_clients", "--door", door,
                                 "--port", str(port), "--n", "1",
                                 "--map-compression", map_compression,
                                 "--map-fragment-size", str(map_fragment_size)))
        pub.phase = PLAIN
        time.sleep(duration)  # a measuring phase, not a wait on a condition
        pub.phase = WITH_MAP
        pub.start_map()
        time.sleep(duration)
        pub.phase = END
        results = [c.result(120) for c in clients]
    finally:
        pub.close()
        for c in clients:
            c.stop()
    out: dict[str, Any] = {}
    for key in ("without_map", "with_map"):
        flat = [a for r in results for a in r[key]]
        out[key] = {"n": len(flat), "p50_ms": percentile(flat, 50) * 1e3 if flat else None,
                    "p99_ms": percentile(flat, 99) * 1e3 if flat else None,
                    "max_ms": max(flat) * 1e3 if flat else None}
    return out
