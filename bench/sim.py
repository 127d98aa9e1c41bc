"""Simulator benchmark: the chassis process's real-time factor against ir-sim's, and one scan.

Prints one JSON line with:

- ``rtf``: sim seconds per wall second the chassis process reaches at ``speed:=0`` (as fast
  as it can) on the demo office map, driving in circles, with odom and TF at 50 Hz and a
  360-beam scan at 10 Hz all published over Zenoh to a subscriber in this process (which
  receives every one); measured from the odom stamps that arrive.
- ``rtf_irsim``: ir-sim (the Python simulator, a bench-only dependency) stepping a
  diff-drive robot with a 360-beam, 12 m lidar among geometric obstacles (a 30 x 20 m
  walled room with circles and boxes), its default 0.1 s step, in its fastest setup: the
  better of ``display=False`` and ``headless=True``.
- ``rtf_ratio``: the median over repeats of rtf / rtf_irsim, each repeat measuring both
  back to back (load on a shared machine hits both).
- ``scan_ms``: one 360-beam scan on the office map (ray-cast, 0.05-12 m), the minimum
  over 40 repeats of the mean over 50 random free poses (of 200).

Run: ``python bench/sim.py [--seconds S] [--repeats N]`` (needs the ``bench`` extra).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import logging
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from zenros.context import Context
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.tf2_msgs import TFMessage
from zenros.node import Node
from zenros.testing import free_port, loopback_options, unique_prefix, wait_for

sys.path.insert(0, str(Path(__file__).parent))
from _harness import emit, missing_extra

ROOT = Path(__file__).resolve().parents[1]
OFFICE = ROOT / "deploy" / "maps" / "office" / "office.yaml"
IRSIM_STEP = 0.1

IRSIM_WORLD = """\
world: {height: 20, width: 30, step_time: 0.1, sample_time: 0.1, collision_mode: stop}
robot:
  - kinematics: {name: diff}
    shape: {name: circle, radius: 0.2}
    state: [5, 10, 0]
    sensors:
      - {type: lidar2d, range_min: 0.05, range_max: 12, angle_range: 6.2657, number: 360}
obstacle:
  - {shape: {name: rectangle, length: 30, width: 0.2}, state: [15, 0.1, 0]}
  - {shape: {name: rectangle, length: 30, width: 0.2}, state: [15, 19.9, 0]}
  - {shape: {name: rectangle, length: 0.2, width: 20}, state: [0.1, 10, 0]}
  - {shape: {name: rectangle, length: 0.2, width: 20}, state: [29.9, 10, 0]}
  - {shape: {name: rectangle, length: 12, width: 0.2}, state: [12, 12.5, 0]}
  - {shape: {name: rectangle, length: 12, width: 0.2}, state: [12, 7.5, 0]}
  - {shape: {name: circle, radius: 0.5}, state: [20, 12, 0]}
  - {shape: {name: circle, radius: 0.4}, state: [22, 6, 0]}
  - {shape: {name: rectangle, length: 2, width: 1}, state: [15, 16, 0]}
  - {shape: {name: rectangle, length: 1.5, width: 3}, state: [6, 3, 0.3]}
"""


def scan_ms(repeats: int) -> float:
    """Milliseconds per 360-beam scan on the office map (min over repeats of the mean)."""
    from zenros.maps import load_map
    from zenros.services.chassis.laser import Laser, LaserConfig
    from zenros.services.chassis.world import World

    world = World(load_map(OFFICE))
    laser = Laser(world, LaserConfig())
    rng = np.random.default_rng(7)
    poses: list[tuple[float, float, float]] = []
    while len(poses) < 200:
        x, y = rng.uniform(-3, 27), rng.uniform(-9.7, 9.7)
        if world.body_free(x, y, 0.2):
            poses.append((x, y, rng.uniform(-math.pi, math.pi)))
    for p in poses[:20]:
        laser.ranges(*p)
    best = math.inf
    for i in range(repeats):  # short repeats: the minimum finds the unloaded moments
        batch = poses[(i * 50) % len(poses):][:50]
        t0 = time.perf_counter()
        for p in batch:
            laser.ranges(*p)
        best = min(best, (time.perf_counter() - t0) / len(batch))
    return best * 1e3


class Counter:
    """Counts messages; keeps (wall time, stamp) of the odometry."""

    def __init__(self) -> None:
        self.odom: list[tuple[float, float]] = []
        self.tf = 0
        self.scans = 0

    def on_odom(self, m: Odometry) -> None:
        self.odom.append((time.perf_counter(), m.header.stamp.to_sec()))

    def on_tf(self, m: TFMessage) -> None:
        self.tf += 1

    def on_scan(self, m: LaserScan) -> None:
        self.scans += 1


def chassis_rtf(seconds: float) -> dict[str, float]:
    """Run the chassis process as fast as it can; its RTF from the odom stamps received."""
    port = free_port()
    prefix = unique_prefix()
    ctx = Context(loopback_options(port), prefix=prefix)
    node = Node("bench_sim", context=ctx)
    got = Counter()
    node.create_subscription(Odometry, "odom", got.on_odom)
    node.create_subscription(TFMessage, "/tf", got.on_tf, 100)
    node.create_subscription(LaserScan, "scan", got.on_scan)
    cmd = node.create_publisher(Twist, "cmd_vel")
    env = {**os.environ, "ZENROS_PREFIX": prefix, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(
        [sys.executable, "-m", "zenros.services.chassis", "--no-multicast-scouting",
         "-e", f"tcp/127.0.0.1:{port}", "-l", f"tcp/127.0.0.1:{free_port()}",
         "--log-level", "error", "-p", "speed:=0", "-p", "cmd_timeout:=1000000.0",
         "-p", "battery_initial:=1.0", "-p", f"map:={OFFICE}"],
        env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        if not wait_for(lambda: (len(got.odom) > 10 and got.scans > 0)
                        or proc.poll() is not None, 30) or proc.poll() is not None:
            raise RuntimeError("the chassis published nothing: "
                               + (proc.stderr.read().decode() if proc.poll() is not None
                                  and proc.stderr else "still running"))
        cmd.wait_for_subscribers(1, 10)
        cmd.publish(Twist(linear=Vector3(x=0.2), angular=Vector3(z=0.5)))  # circles
        time.sleep(1.0)  # warm-up
        n0, tf0, s0 = len(got.odom), got.tf, got.scans
        time.sleep(seconds)
        n1, tf1, s1 = len(got.odom), got.tf, got.scans
        (w0, t0), (w1, t1) = got.odom[n0], got.odom[n1 - 1]
        sim_s = t1 - t0
        return {"rtf": sim_s / (w1 - w0), "odom_hz": (n1 - n0) / sim_s,
                "tf_hz": (tf1 - tf0) / sim_s, "scan_hz": (s1 - s0) / sim_s}
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        node.close()
        ctx.close()


def irsim_rtf(seconds: float, world: str) -> dict[str, float]:
    """ir-sim's RTF in its fastest setup (the better of display=False and headless=True)."""
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # it prints backend warnings on import
            import irsim
    except ModuleNotFoundError as err:
        raise SystemExit(missing_extra(err, "bench")) from None
    logging.getLogger().setLevel(logging.ERROR)
    best: dict[str, float] = {"rtf_irsim": 0.0}
    for setup in ({"display": False}, {"headless": True}):
        with contextlib.redirect_stdout(io.StringIO()):
            env = irsim.make(world, log_level="ERROR", **setup)
            try:
                for _ in range(5):
                    env.step([0.2, 0.5])
                n = 0
                t0 = time.perf_counter()
                while time.perf_counter() - t0 < seconds / 2:
                    env.step([0.2, 0.5])
                    n += 1
                rtf = n * IRSIM_STEP / (time.perf_counter() - t0)
                beams = len(env.robot.get_lidar_scan()["ranges"])
            finally:
                env.end(0)
        if rtf > best["rtf_irsim"]:
            best = {"rtf_irsim": rtf, "irsim_beams": beams,
                    "irsim_setup": "headless" if "headless" in setup else "display=False"}
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=5.0, help="wall seconds per measurement")
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        world = os.path.join(tmp, "world.yaml")
        Path(world).write_text(IRSIM_WORLD)
        ours: list[dict[str, float]] = []
        theirs: list[dict[str, Any]] = []
        for _ in range(a.repeats):
            ours.append(chassis_rtf(a.seconds))
            theirs.append(irsim_rtf(a.seconds, world))
    ms = scan_ms(40)
    rtf = statistics.median(r["rtf"] for r in ours)
    rtf_ir = statistics.median(r["rtf_irsim"] for r in theirs)
    ratio = statistics.median(o["rtf"] / t["rtf_irsim"] for o, t in zip(ours, theirs,
                                                                        strict=True))
    emit("sim", {"rtf": round(rtf, 1), "rtf_irsim": round(rtf_ir, 1),
                 "rtf_ratio": round(ratio, 2), "scan_ms": round(ms, 3)},
         odom_hz=round(statistics.median(r["odom_hz"] for r in ours), 1),
         tf_hz=round(statistics.median(r["tf_hz"] for r in ours), 1),
         scan_hz=round(statistics.median(r["scan_hz"] for r in ours), 1),
         irsim_setup=theirs[-1]["irsim_setup"], repeats=a.repeats, seconds=a.seconds)


if __name__ == "__main__":
    main()
