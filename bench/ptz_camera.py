"""PTZ camera benchmark: the simulated PTZ camera's frames and thermal readings in the demo
office (docs/chassis.md, PTZ camera).

Prints one JSON line with, per preset (``home``, ``corridor``, ``room``), ``<preset>_frame_ms``
(one 640x480 frame rendered, the p50 over ``--frames`` pans a hair apart: nothing cached, the
lens made) and ``<preset>_thermal_ms`` (one 160x120 thermal reading, the same way), and
``moving_frame_ms``: the p50 while tilt and zoom change every frame (a new lens each time).

Run: ``python bench/ptz_camera.py [--frames N]``.
"""

from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

from zenros.params import Parameters
from zenros.services.chassis.config import declare_chassis
from zenros.services.chassis.devices import PtzDevice
from zenros.services.chassis.thermal import ThermalModel, read_rule

sys.path.insert(0, str(Path(__file__).parent))
from _harness import emit, percentile

PRESETS = {"home": (0.0, -0.17, 1.0), "corridor": (0.48, -0.089, 4.0),
           "room": (-0.463, -0.32, 1.5)}


def main(frames: int) -> None:
    chassis = declare_chassis(Parameters("/chassis", {"camera_rate": 0.0})).build(
        logging.getLogger("bench"))
    device = chassis.device(PtzDevice)
    assert device is not None and device.view is not None
    view, things = device.view, device.things()
    metrics: dict[str, float] = {}
    for name, (pan, tilt, zoom) in PRESETS.items():
        view.frame(pan, tilt, zoom, things)  # the lens made
        video, thermal = [], []
        for i in range(1, frames + 1):
            t0 = time.perf_counter()
            view.frame(pan + 1e-6 * i, tilt, zoom, things)
            t1 = time.perf_counter()
            read_rule(view.thermal(pan + 1e-6 * i, tilt, zoom, things, ThermalModel()))
            video.append(t1 - t0)
            thermal.append(time.perf_counter() - t1)
        metrics[f"{name}_frame_ms"] = round(percentile(video, 50) * 1e3, 2)
        metrics[f"{name}_thermal_ms"] = round(percentile(thermal, 50) * 1e3, 2)
    moving = []
    for i in range(frames):
        t0 = time.perf_counter()
        view.frame(0.0, -0.3 + 0.5 * i / frames, 2.0 + 4.0 * i / frames, things)
        moving.append(time.perf_counter() - t0)
    metrics["moving_frame_ms"] = round(percentile(moving, 50) * 1e3, 2)
    emit("ptz_camera", metrics, frames=frames)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="the simulated PTZ camera's frame times")
    parser.add_argument("--frames", type=int, default=30, help="frames timed per case")
    main(parser.parse_args().frames)
