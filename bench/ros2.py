"""ROS 2 DDS bridge benchmark: rclpy -> zenros through the bridge against rclpy -> rclpy.

One unmodified rclpy publisher (rmw_fastrtps) sends geometry_msgs/Twist on /bench_twist; an
rclpy subscriber (the reference) and a zenros subscriber behind ``python -m
zenros.services.gateway.ros2`` receive the same samples in the same run, so load on the machine
hits both. Each Twist carries its send time (CLOCK_MONOTONIC, the same in every process).

- latency: 300 samples at 100 Hz; ``ros2_latency_ratio`` = bridged p50 / rclpy p50
  (target <= 1.5);
- throughput: the publisher sends as fast as it can for 2 s (reliable, keep-last 10);
  ``ros2_throughput_ratio`` = samples/s reaching zenros / samples/s reaching the rclpy
  subscriber (target >= 0.5).

DDS discovery is multicast: the bench re-runs itself inside a network namespace it creates
(``unshare -n``, loopback with multicast; needs root and the extra ``ros2``), so no DDS packet
leaves loopback. Prints one JSON line.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from _harness import emit, free_port, percentile, unique_prefix

HERE = Path(__file__).resolve()
TOPIC = "/bench_twist"
NETNS = ("ip link set lo up && ip link set lo multicast on && "
         "ip route add 224.0.0.0/4 dev lo && exec \"$@\"")
WARMUP, PHASE_LATENCY, PHASE_BURST, PHASE_END = 0.0, 1.0, 2.0, 3.0
LATENCY_N, LATENCY_HZ, BURST_S = 300, 100.0, 2.0


class Tally:
    """What one receiver saw: latencies of the latency phase, burst arrivals, the end."""

    def __init__(self) -> None:
        self.lat: list[float] = []
        self.burst: list[float] = []  # receive times
        self.done = False

    def add(self, sent: float, phase: float) -> None:
        now = time.monotonic()
        if phase == PHASE_LATENCY:
            self.lat.append(now - sent)
        elif phase == PHASE_BURST:
            self.burst.append(now)
        elif phase == PHASE_END:
            self.done = True

    def summary(self) -> dict[str, Any]:
        rate = 0.0
        if len(self.burst) > 1:
            rate = (len(self.burst) - 1) / (self.burst[-1] - self.burst[0])
        return {"n_lat": len(self.lat),
                "p50_us": percentile(self.lat, 50) * 1e6 if self.lat else 0.0,
                "p90_us": percentile(self.lat, 90) * 1e6 if self.lat else 0.0,
                "n_burst": len(self.burst), "rate": rate}


def rclpy_role(role: str) -> None:
    """``pub``: the phases above; ``sub``: the reference receiver (prints its tally)."""
    import rclpy
    from geometry_msgs.msg import Twist
    from rclpy.node import Node

    rclpy.init()
    node = Node(f"bench_{role}")
    if role == "sub":
        tally = Tally()
        node.create_subscription(Twist, TOPIC, lambda m: tally.add(m.linear.x, m.linear.y), 10)
        print("ready", flush=True)
        deadline = time.monotonic() + 120
        while not tally.done and time.monotonic() < deadline:
            rclpy.spin_once(node, timeout_sec=0.1)
        print(json.dumps(tally.summary()), flush=True)
        return
    pub = node.create_publisher(Twist, TOPIC, 10)

    def send(phase: float) -> None:
        m = Twist()
        m.linear.x, m.linear.y = time.monotonic(), phase
        pub.publish(m)

    print("ready", flush=True)
    while pub.get_subscription_count() < 2:  # the rclpy subscriber and the bridge's reader
        send(WARMUP)
        time.sleep(0.05)
    t_end = time.monotonic() + 2.0  # the bridge's zenros route and subscriber settle
    while time.monotonic() < t_end:
        send(WARMUP)
        time.sleep(0.05)
    period = 1.0 / LATENCY_HZ
    t_next = time.monotonic()
    for _ in range(LATENCY_N):
        send(PHASE_LATENCY)
        t_next += period
        time.sleep(max(0.0, t_next - time.monotonic()))
    time.sleep(0.5)
    t_end = time.monotonic() + BURST_S
    while time.monotonic() < t_end:
        send(PHASE_BURST)
    time.sleep(1.0)
    for _ in range(20):
        send(PHASE_END)
        time.sleep(0.05)


def start(*args: str, **kw: Any) -> subprocess.Popen[str]:
    env = {**os.environ, "AMENT_PREFIX_PATH": sys.prefix, "ROS_DOMAIN_ID": "0",
           "PYTHONUNBUFFERED": "1"}
    return subprocess.Popen([sys.executable, *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True, **kw)


def stop(p: subprocess.Popen[str]) -> None:
    if p.poll() is None:
        os.killpg(p.pid, signal.SIGINT)
        try:
            p.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(5)


def in_namespace() -> dict[str, Any]:
    from zenros.context import Context
    from zenros.msgs.geometry_msgs import Twist
    from zenros.node import Node
    from zenros.session import SessionOptions
    from zenros.testing import wait_for

    port, prefix = free_port(), unique_prefix()
    procs = [start("-m", "zenros.services.gateway.ros2", "-l", f"tcp/127.0.0.1:{port}",
                   "--prefix", prefix, "-p", "domain_id:=0", "-p", f"allow:={TOPIC}")]
    ctx = Context(SessionOptions(connect=[f"tcp/127.0.0.1:{port}"]), prefix=prefix)
    node = Node("bench_zenros_sub", context=ctx)
    tally = Tally()
    node.create_subscription(Twist, TOPIC, lambda m: tally.add(m.linear.x, m.linear.y))
    try:
        sub = start(str(HERE), "--role", "sub")
        procs.append(sub)
        assert sub.stdout is not None and sub.stdout.readline().startswith("ready")
        pub = start(str(HERE), "--role", "pub")
        procs.append(pub)
        wait_for(lambda: tally.done, 150, interval=0.1)
        out, _ = sub.communicate(timeout=30)
        ref = json.loads([ln for ln in out.splitlines() if ln.startswith("{")][-1])
    finally:
        node.close()
        ctx.close()
        for p in procs:
            stop(p)
    return {"bridged": tally.summary(), "rclpy": ref}


def main() -> None:
    if len(sys.argv) > 2 and sys.argv[1] == "--role":
        rclpy_role(sys.argv[2])
        return
    if os.environ.get("ZENROS_BENCH_NETNS") != "1":
        if os.geteuid() != 0:
            emit("ros2", {}, error="needs root for a network namespace (unshare -n)")
            return
        env = {**os.environ, "ZENROS_BENCH_NETNS": "1"}
        p = subprocess.run(["unshare", "-n", "sh", "-c", NETNS, "sh", sys.executable,
                            str(HERE)], env=env, check=False)
        sys.exit(p.returncode)
    res = in_namespace()
    b, r = res["bridged"], res["rclpy"]
    emit("ros2", {
        "ros2_latency_p50_us_bridged": round(b["p50_us"], 1),
        "ros2_latency_p50_us_rclpy": round(r["p50_us"], 1),
        "ros2_latency_p90_us_bridged": round(b["p90_us"], 1),
        "ros2_latency_p90_us_rclpy": round(r["p90_us"], 1),
        "ros2_latency_ratio": round(b["p50_us"] / r["p50_us"], 3) if r["p50_us"] else 0.0,
        "ros2_throughput_bridged": round(b["rate"], 1),
        "ros2_throughput_rclpy": round(r["rate"], 1),
        "ros2_throughput_ratio": round(b["rate"] / r["rate"], 3) if r["rate"] else 0.0,
    }, samples={"latency": [b["n_lat"], r["n_lat"], LATENCY_N],
                "burst": [b["n_burst"], r["n_burst"]]},
        targets={"ros2_latency_ratio": "<= 1.5", "ros2_throughput_ratio": ">= 0.5"})


if __name__ == "__main__":
    main()
