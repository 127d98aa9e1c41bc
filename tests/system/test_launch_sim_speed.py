"""`zenros launch deploy/launch/sim.yaml speed:=10`, as a user types it: the chassis stays up
and publishes /clock at about ten sim seconds per wall second, and the terminal is quiet.

The sim runs on a free router port with its own key prefix and ZENROS_HOME; the gateway's
fixed ports are moved to free ones by storing them on master first (as the docs check does).
"""

from __future__ import annotations

import re
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from zenros.context import Context
from zenros.msgs.rosgraph_msgs import Clock
from zenros.node import Node
from zenros.qos import QOS_SENSOR
from zenros.session import SessionOptions
from zenros.testing import Proc, free_port, store_on_master, unique_prefix, wait_for

pytestmark = pytest.mark.system

ROOT = Path(__file__).resolve().parents[2]
GATEWAY_PORTS = ("rest_port", "ws_port", "modbus_port", "rosbridge_port")


@pytest.fixture
def sim_at_10x(tmp_path: Path) -> Iterator[tuple[Proc, str, str]]:
    home, prefix = tmp_path / "home", unique_prefix()
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    store_on_master(home, prefix, {f"/gateway/{k}": free_port() for k in GATEWAY_PORTS}
                     | {"/gateway/discovery_port": -1})
    proc = Proc([sys.executable, "-m", "zenros.cli", "launch",
                 str(ROOT / "deploy" / "launch" / "sim.yaml"), "speed:=10"],
                env={"ZENROS_HOME": str(home), "ZENROS_PREFIX": prefix,
                     "ZENROS_CONNECT": endpoint})
    try:
        yield proc, endpoint, prefix
    finally:
        proc.stop(timeout=30)


@pytest.mark.timeout(300)
def test_speed_10_alone_runs_the_chassis_on_sim_time(sim_at_10x: tuple[Proc, str, str]) -> None:
    proc, endpoint, prefix = sim_at_10x
    assert proc.wait_line("[launch] chassis is ready", 180), proc.output
    stamps: list[tuple[float, float]] = []  # (wall, sim) seconds
    lock = threading.Lock()

    def on_clock(msg: Clock) -> None:
        with lock:
            stamps.append((time.monotonic(), msg.clock.sec + msg.clock.nanosec * 1e-9))

    with Context(SessionOptions(connect=[endpoint]), prefix=prefix) as ctx:
        node = Node("clock_probe", context=ctx)
        try:
            node.create_subscription(Clock, "/clock", on_clock, QOS_SENSOR)
            assert wait_for(lambda: len(stamps) > 0, 20), proc.output
            with lock:
                first = stamps[-1]
            assert wait_for(lambda: stamps[-1][0] - first[0] >= 3.0, 20), proc.output
            with lock:
                last = stamps[-1]
        finally:
            node.close()
    ratio = (last[1] - first[1]) / (last[0] - first[0])
    assert 5.0 < ratio < 12.0, ratio  # ~10 sim s per wall s (less on a loaded box)
    assert proc.wait_line("[launch] gateway is ready", 120), proc.output
    out = proc.output
    assert len(re.findall(r"\[launch\] started chassis \(pid", out)) == 1, out  # no respawn
    assert "could not start" not in out and "not restarting it" not in out, out
    assert "I heard" not in out, out  # the listener's INFO chatter stays in its log
    assert proc.popen.poll() is None, out
