"""`PtzView`: what a PTZ camera fixed in the world sees at a pan, tilt and zoom: its video
frame and its thermal image, drawn by level `Camera` s (one per zoom and tilt, a few kept).

The mount is at (``x``, ``y``) in ``map``, ``z`` above the floor, facing ``yaw`` at pan 0;
pan turns it right (the view's yaw is ``yaw - pan``). Zoom narrows the field of view to
``hfov / zoom``; tilt moves the horizon (`camera` module: ``cy = height/2 + f tan(tilt)``).
The thermal channel is a quarter of the video's size a side, the same field of view.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .camera import Camera, CameraConfig, Columns
from .laser import Laser, LaserConfig
from .obstacles import Obstacle
from .thermal import ThermalModel
from .world import World

__all__ = ["THERMAL_SCALE", "Mount", "PtzView"]

THERMAL_SCALE = 4  # the thermal image is the video's size / 4 a side
_KEPT = 8  # lenses kept per channel


@dataclass(frozen=True)
class Mount:
    """Where the camera is fixed, its lens and its image size."""

    x: float
    y: float
    z: float
    yaw: float
    hfov: float
    width: int
    height: int


class PtzView:
    """The camera's channels over ``world``; thread-safe (the video on a worker thread, the
    thermal in a service call)."""

    def __init__(self, world: World, mount: Mount) -> None:
        self.world = world
        self.mount = mount
        self.caster = Laser(world, LaserConfig(beams=1, range_max=CameraConfig().range_max))
        self._lenses: OrderedDict[tuple[int, int, float, float], Camera] = OrderedDict()
        self._lock = threading.Lock()

    def config(self, zoom: float, tilt: float, scale: int = 1) -> CameraConfig:
        """The level camera that draws the view at ``zoom`` and ``tilt``, ``scale`` times
        smaller a side than the video."""
        m = self.mount
        w, h = m.width // scale, m.height // scale
        hfov = m.hfov / zoom
        f = w / 2 / math.tan(hfov / 2)
        return CameraConfig(width=w, height=h, hfov=hfov, z=m.z,
                            cy=round(h / 2 + f * math.tan(tilt), 2))

    def lens(self, zoom: float, tilt: float, scale: int = 1) -> Camera:
        """The `Camera` of `config` (made once, the last few kept)."""
        c = self.config(zoom, tilt, scale)
        key = (c.width, c.height, c.hfov, c.horizon)
        with self._lock:
            cam = self._lenses.get(key)
            if cam is not None:
                self._lenses.move_to_end(key)
                return cam
        cam = Camera(self.world, c, self.caster)
        with self._lock:
            self._lenses[key] = cam
            while len(self._lenses) > 2 * _KEPT:
                self._lenses.popitem(last=False)
        return cam

    def frame(self, pan: float, tilt: float, zoom: float,
              things: Iterable[Obstacle]) -> np.ndarray:
        """The RGB video frame (``height x width x 3``, uint8; the lens's own array)."""
        m = self.mount
        return self.lens(zoom, tilt).render(m.x, m.y, m.yaw - pan, things)

    def columns(self, pan: float, tilt: float, zoom: float, things: Iterable[Obstacle],
                scale: int = THERMAL_SCALE) -> tuple[Columns, CameraConfig]:
        """What the thermal image's columns see, and its camera."""
        m = self.mount
        cam = self.lens(zoom, tilt, scale)
        return cam.cast(m.x, m.y, m.yaw - pan, things), cam.config

    def thermal(self, pan: float, tilt: float, zoom: float, things: Iterable[Obstacle],
                model: ThermalModel) -> np.ndarray:
        """The thermal image (C per pixel, the video's size / `THERMAL_SCALE`)."""
        cols, config = self.columns(pan, tilt, zoom, things)
        return model.image(cols, config)
