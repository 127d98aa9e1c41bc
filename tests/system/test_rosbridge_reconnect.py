"""rosbridge clients across gateway restarts, on `zenros launch deploy/launch/sim.yaml`:

* 100 rosbridge connect/disconnect cycles (each subscribes, advertises a service and a topic,
  calls rosapi) leave the gateway's RSS within 5 MB and its thread count as it was;
* after a ``kill -9`` of the gateway (the launch respawns it), a roslibpy client with its
  reconnect on hears /odom again within 5 s, and the service it advertised is served again.

The sim runs on a free router port with its own key prefix and ZENROS_HOME; the gateway's
fixed ports are moved to free ones by storing them on master first.
"""

from __future__ import annotations

import json
import os
import re
import signal
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
import roslibpy
from roslibpy.comm.comm_autobahn import AutobahnRosBridgeClientFactory
from websockets.sync.client import connect
from zenros.context import Context
from zenros.msgs.example_interfaces import AddTwoInts, AddTwoIntsRequest
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import (
    Proc,
    free_port,
    roslibpy_connect,
    store_on_master,
    unique_prefix,
    wait_for,
)

pytestmark = pytest.mark.system

ROOT = Path(__file__).resolve().parents[2]
GATEWAY_PORTS = ("rest_port", "ws_port", "modbus_port", "rosbridge_port")
RECONNECT_S = 5.0  # from the gateway ready again to odom flowing and the service served
RESPAWN_S = 60.0  # from the kill to odom flowing, respawn and set-up included


@dataclass
class Sim:
    proc: Proc
    endpoint: str
    prefix: str
    rosbridge_port: int

    def gateway_pid(self) -> int:
        """The pid of the gateway the launch runs now (the last one it started)."""
        pids = re.findall(r"\[launch\] started gateway \(pid (\d+)", self.proc.output)
        assert pids, self.proc.output
        return int(pids[-1])


@pytest.fixture(scope="module")
def sim(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Sim]:
    home, prefix = tmp_path_factory.mktemp("home"), unique_prefix()
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    ports = {k: free_port() for k in GATEWAY_PORTS}
    store_on_master(home, prefix, {f"/gateway/{k}": v for k, v in ports.items()}
                    | {"/gateway/discovery_port": -1})
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch",
                 str(ROOT / "deploy" / "launch" / "sim.yaml")],
                env={"ZENROS_HOME": str(home), "ZENROS_PREFIX": prefix,
                     "ZENROS_CONNECT": endpoint})
    try:
        assert proc.wait_line("[launch] gateway is ready", 180), proc.output
        assert proc.wait_line("[launch] chassis is ready", 180), proc.output
        yield Sim(proc, endpoint, prefix, ports["rosbridge_port"])
    finally:
        proc.stop(timeout=30)


def _status(pid: int) -> tuple[int, int]:
    """RSS (bytes) and thread count of a process, from /proc."""
    text = Path(f"/proc/{pid}/status").read_text()
    rss = int(re.search(r"VmRSS:\s+(\d+) kB", text).group(1)) * 1024  # type: ignore[union-attr]
    threads = int(re.search(r"Threads:\s+(\d+)", text).group(1))  # type: ignore[union-attr]
    return rss, threads


def _cycle(port: int, n: int) -> None:
    """One client's life: connect, subscribe, advertise, call rosapi, go (half of them
    politely, half by dropping the connection with their subscriptions in place)."""
    with connect(f"ws://127.0.0.1:{port}/", open_timeout=10) as ws:
        ws.send(json.dumps({"op": "subscribe", "id": f"s{n}", "topic": "/odom",
                            "type": "nav_msgs/Odometry", "throttle_rate": 100}))
        ws.send(json.dumps({"op": "advertise", "topic": f"/cycle_{n % 3}",
                            "type": "std_msgs/String"}))
        ws.send(json.dumps({"op": "advertise_service", "service": f"/cycle_add_{n % 3}",
                            "type": "example_interfaces/AddTwoInts"}))
        ws.send(json.dumps({"op": "call_service", "id": f"c{n}", "service": "/rosapi/topics"}))
        while True:
            frame = json.loads(ws.recv(timeout=10))
            if frame.get("op") == "service_response" and frame.get("id") == f"c{n}":
                break
        if n % 2:
            ws.send(json.dumps({"op": "unsubscribe", "id": f"s{n}", "topic": "/odom"}))


@pytest.mark.timeout(600)
def test_connect_disconnect_cycles_leak_neither_memory_nor_threads(sim: Sim) -> None:
    """A leak grows with every client: two batches of 100 each grow RSS alike. The first
    batch after the warm-up also pays one-off growth (the allocator's arenas, buffers that a
    loaded box fills while the gateway is starved: 28 MB once in a suite beside other
    launches, under 5 MB alone), so the second batch is the measure."""
    pid = sim.gateway_pid()
    for n in range(20):  # warm up: caches, the /odom feed, the rosapi's graph
        _cycle(sim.rosbridge_port, n)
    rss0, threads0 = _status(pid)
    marks = []
    for batch in range(2):
        for n in range(100):
            _cycle(sim.rosbridge_port, 100 * batch + n)
        # The server notices each close on its own loop: wait for it to settle. Zenoh's
        # runtime starts and ends blocking-pool threads of its own accord, so the count may
        # also drop.
        assert wait_for(lambda: _status(pid)[1] <= threads0, 20), (threads0, _status(pid))
        marks.append(_status(pid))
    (rss1, _), (rss2, threads2) = marks
    print(f"gateway RSS {rss0 / 1e6:.1f} -> {rss1 / 1e6:.1f} -> {rss2 / 1e6:.1f} MB, threads "
          f"{threads0} -> {threads2} after 2 x 100 cycles")
    assert threads2 <= threads0
    assert rss2 - rss1 < 5 * 1024 * 1024, f"RSS grew {(rss2 - rss1) / 1e6:.1f} MB in batch 2"


@pytest.mark.timeout(600)
def test_roslibpy_gets_odom_and_serves_again_after_kill_9(sim: Sim) -> None:
    delay = AutobahnRosBridgeClientFactory.maxDelay
    AutobahnRosBridgeClientFactory.set_max_delay(0.5)  # the client's setting: retry often
    ros = roslibpy_connect("127.0.0.1", sim.rosbridge_port, 30)
    heard: list[float] = []
    lock = threading.Lock()

    def on_odom(msg: dict[str, object]) -> None:
        with lock:
            heard.append(time.monotonic())

    odom = roslibpy.Topic(ros, "/odom", "nav_msgs/Odometry")
    service = roslibpy.Service(ros, "/reconnect_add", "example_interfaces/AddTwoInts")

    def add(request: dict[str, int], response: dict[str, int]) -> bool:
        response["sum"] = request["a"] + request["b"]
        return True

    ctx = Context(SessionOptions(connect=[sim.endpoint]), prefix=sim.prefix)
    node = Node("reconnect_probe", context=ctx)
    try:
        odom.subscribe(on_odom)
        service.advertise(add)
        assert wait_for(lambda: bool(heard), 30)
        client = node.create_client(AddTwoInts, "/reconnect_add")
        assert client.wait_for_service(30)
        assert client.call(AddTwoIntsRequest(a=2, b=3), timeout=10).sum == 5

        old = sim.gateway_pid()
        readies = sim.proc.output.count("[launch] gateway is ready")
        os.kill(old, signal.SIGKILL)
        killed = time.monotonic()
        phases: dict[str, float] = {}  # seconds after the kill, for the failure message

        def mark(name: str, cond: bool) -> bool:
            if cond:
                phases.setdefault(name, round(time.monotonic() - killed, 2))
            return cond

        def back_again() -> bool:
            mark("respawned", sim.gateway_pid() != old)
            mark("ready", sim.proc.output.count("[launch] gateway is ready") > readies)
            mark("reconnected", "respawned" in phases and ros.is_connected)
            return mark("odom", heard[-1] > killed + 0.05 and "reconnected" in phases)

        assert wait_for(back_again, 60, 0.02), sim.proc.output[-3000:]
        back = heard[-1] - killed
        assert sim.gateway_pid() != old
        # the service is advertised again by roslibpy's replay, and served through the bridge
        got: list[int] = []

        def call() -> bool:
            try:
                got.append(client.call(AddTwoIntsRequest(a=4, b=5), timeout=2).sum)
            except Exception:  # noqa: BLE001 not yet advertised again
                return False
            return True

        assert wait_for(call, max(1.0, RECONNECT_S - (time.monotonic() - killed)) + 10)
        served = time.monotonic() - killed
        assert got == [9]
        print(f"/odom again {back:.2f} s after kill -9, service served {served:.2f} s after"
              f" ({phases})")
        # measured from the launch's "ready" (the gateway set up again): how long the gateway
        # takes to start is the launch's and the box's (1 s quiet, 11-32 s seen under a loaded
        # suite); what is roslibpy's and the bridge's is the reconnect after it
        # (the bridge may serve, and /odom flow, before the launch has printed "ready": then
        # the reconnect counts from it)
        up = min(phases.get("ready", phases["reconnected"]), phases["reconnected"])
        assert phases["odom"] - up <= RECONNECT_S, \
            f"/odom came back {phases['odom'] - up:.2f} s after the gateway was up ({phases})"
        assert served - up <= RECONNECT_S, \
            f"the service was served {served - up:.2f} s after the gateway was up ({phases})"
        assert phases["odom"] <= RESPAWN_S, f"/odom came back too late ({phases})"
    finally:
        AutobahnRosBridgeClientFactory.set_max_delay(delay)
        ros.close()
        node.close()
        ctx.close()
