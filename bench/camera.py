"""Camera benchmark: one simulated camera frame, and what the cameras cost a robot at rest.

Prints one JSON line with:

- ``camera_frame_ms``: one 640x480 frame of the demo office rendered (walls, floor, three
  obstacles in view) and JPEG-encoded, the p50 over 60 random free poses (each a new view:
  nothing cached). ``render_ms`` and ``jpeg_ms`` are its two parts; ``jpeg_ms`` is Pillow's
  own encoder, the reference a camera driver pays too.
- ``robot_idle_cameras_ratio``: the simulated robot's CPU (``deploy/launch/sim.yaml``, every
  process of the launch) at rest over ``--seconds`` with both cameras at 10 Hz, a subscriber
  in this process on each camera's raw and JPEG topics, over the same robot with nobody
  watching them (then they render and send nothing); the median over ``--repeats`` pairs,
  each measured back to back.

Run: ``python bench/camera.py [--seconds S] [--repeats N]``.
"""

from __future__ import annotations

import argparse
import io
import math
import os
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from PIL import Image as PilImage
from zenros.context import Context
from zenros.maps import load_map
from zenros.msgs.sensor_msgs import CompressedImage, Image
from zenros.node import Node
from zenros.services.chassis.camera import Camera, CameraConfig
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.world import World
from zenros.testing import free_port, loopback_options, unique_prefix, wait_for

sys.path.insert(0, str(Path(__file__).parent))
from _harness import emit, percentile

ROOT = Path(__file__).resolve().parents[1]
OFFICE = ROOT / "deploy" / "maps" / "office" / "office.yaml"
TOPICS = [(Image, "multi/front/image_raw"), (Image, "multi/back/image_raw"),
          (CompressedImage, "multi/front/image_raw/compressed"),
          (CompressedImage, "multi/back/image_raw/compressed")]


def frame_times(n: int = 60) -> tuple[float, float, float]:
    """p50 of render, JPEG and both (ms) over ``n`` random free poses of the office."""
    world = World(load_map(OFFICE))
    config = CameraConfig()
    camera = Camera(world, config, Laser(world, LaserConfig(beams=1, range_max=30.0)))
    rng = np.random.default_rng(1)
    rows, cols = np.nonzero(world.edt > 0.5)
    render, jpeg, both = [], [], []
    for i in rng.choice(rows.size, n, replace=False):
        x, y = world.cell_centre(int(rows[i]), int(cols[i]))
        yaw = float(rng.uniform(-math.pi, math.pi))
        things = [Obstacle(f"o{k}", "circle", x + 2 * math.cos(yaw + d), y + 2 * math.sin(yaw + d),
                           radius=0.3) for k, d in enumerate((-0.3, 0.0, 0.3))]
        t0 = time.perf_counter()
        pixels = camera.render(x, y, yaw, things)
        t1 = time.perf_counter()
        PilImage.fromarray(pixels).save(io.BytesIO(), "JPEG", quality=80)
        t2 = time.perf_counter()
        render.append((t1 - t0) * 1e3)
        jpeg.append((t2 - t1) * 1e3)
        both.append((t2 - t0) * 1e3)
    return percentile(render, 50), percentile(jpeg, 50), percentile(both, 50)


def group_cpu(root: int) -> float:
    """CPU seconds of process ``root`` and all its descendants (a launch and its nodes,
    each in a process group of its own)."""
    stats: dict[int, tuple[int, float]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue  # gone meanwhile
        cpu = (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
        stats[int(stat.parent.name)] = (int(fields[1]), cpu)
    tree, total = {root}, 0.0
    grew = True
    while grew:
        grew = False
        for pid, (ppid, _) in stats.items():
            if ppid in tree and pid not in tree:
                tree.add(pid)
                grew = True
    for pid in tree:
        total += stats.get(pid, (0, 0.0))[1]
    return total


def robot_cpu(launch: subprocess.Popen[bytes], seconds: float) -> float:
    c0, t0 = group_cpu(launch.pid), time.monotonic()
    time.sleep(seconds)
    return (group_cpu(launch.pid) - c0) / (time.monotonic() - t0)


def idle_ratios(seconds: float, repeats: int) -> tuple[list[float], list[float], list[float],
                                                        list[float]]:
    """The simulated robot (deploy/launch/sim.yaml: every service) at rest: its CPU per wall
    second with nobody watching the cameras, then with a subscriber on both cameras' raw and
    JPEG topics, ``repeats`` pairs back to back; and the frames a second received."""
    router_port, prefix = free_port(), unique_prefix()
    env = {**os.environ, "ZENROS_PREFIX": prefix, "ZENROS_CONNECT": f"tcp/127.0.0.1:{router_port}"}
    free = [str(free_port()) for _ in range(4)]
    launch = subprocess.Popen(
        [sys.executable, "-m", "zenros.cli", "launch", str(ROOT / "deploy/launch/sim.yaml"),
         "talker:=false", f"rest_port:={free[0]}", f"ws_port:={free[1]}",
         f"modbus_port:={free[2]}", f"rosbridge_port:={free[3]}", "discovery_port:=-1"],
        env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL, start_new_session=True)
    ctx: Context | None = None
    try:
        time.sleep(1.0)
        ctx = Context(loopback_options(connect=[router_port]), prefix=prefix)
        graph = ctx.graph
        assert wait_for(lambda: {"/chassis", "/nav", "/gateway"} <= set(graph.node_names()),
                        90), "the robot did not come up"
        time.sleep(10.0)  # past the start-up: maps loaded, lifecycle up
        off, on, ratios, rates = [], [], [], []
        for k in range(repeats):
            idle = robot_cpu(launch, seconds)
            counts = {topic: 0 for _, topic in TOPICS}
            node = Node(f"camera_bench{k}", context=ctx)

            for kind, topic in TOPICS:
                node.create_subscription(kind, topic, counter(counts, topic))
            assert wait_for(lambda c=counts: all(c.values()), 30), counts
            n0 = sum(counts.values())
            watched = robot_cpu(launch, seconds)
            rates.append((sum(counts.values()) - n0) / seconds)
            node.close()
            off.append(idle)
            on.append(watched)
            ratios.append(watched / idle)
        return off, on, ratios, rates
    finally:
        if ctx is not None:
            ctx.close()
        os.killpg(launch.pid, signal.SIGINT)
        try:
            launch.wait(30)
        except subprocess.TimeoutExpired:
            os.killpg(launch.pid, signal.SIGKILL)
            launch.wait()


def counter(counts: dict[str, int], topic: str) -> Any:
    def on_frame(_: Any) -> None:
        counts[topic] += 1
    return on_frame


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=10.0, help="wall seconds per measurement")
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    render_ms, jpeg_ms, frame_ms = frame_times()
    without_cpu, with_cpu, ratios, frames = idle_ratios(a.seconds, a.repeats)
    emit("camera", {"camera_frame_ms": round(frame_ms, 2),
                    "robot_idle_cameras_ratio": round(statistics.median(ratios), 3)},
         render_ms=round(render_ms, 2), jpeg_ms=round(jpeg_ms, 2),
         idle_cpu_with_cameras=round(statistics.median(with_cpu), 4),
         idle_cpu_without=round(statistics.median(without_cpu), 4),
         frames_per_s=round(statistics.median(frames), 1), repeats=a.repeats,
         seconds=a.seconds)


if __name__ == "__main__":
    main()
