"""The PTZ camera's thermal channel: a temperature per pixel from what each pixel's ray meets
(`camera.Columns`), and a thermometry rule's reading over a frame. No Zenoh here.

The room is still air at `AMBIENT`: the floor a little cooler, the walls warmer towards the
ceiling (warm air rises), the obstacles (furniture, boxes in the light) a little warmer, a
robot's body hot near its motors at the bottom and cooler at its top, the dock warm while it
charges. A pixel's ray meets the nearest of the thing in its column (up to that thing's
height), the wall (up to the walls' height), else the floor (looking down) or the ceiling.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .camera import DOCK, OBSTACLE, PERSON, ROBOT, CameraConfig, Columns

__all__ = ["AMBIENT", "Reading", "ThermalModel", "read_rule"]

AMBIENT = 22.0  # C


@dataclass(frozen=True)
class ThermalModel:
    """Surface temperatures (C); ``dock_charging``: the dock is charging the robot."""

    floor: float = AMBIENT - 1.0
    ceiling: float = AMBIENT + 1.5
    wall_low: float = AMBIENT - 0.5  # at the floor
    wall_high: float = AMBIENT + 1.0  # at the walls' top
    obstacle: float = AMBIENT + 2.0
    person: float = 33.0  # clothed legs
    robot_motors: float = 40.0  # a robot's body at the floor (its motors, its wheels)
    robot_top: float = 35.0
    dock_charging: float = 30.0
    dock_idle: float = AMBIENT + 0.5
    charging: bool = False

    def image(self, cols: Columns, config: CameraConfig) -> np.ndarray:
        """The temperature of each pixel (``height x width``, float32) of the view whose
        rays met ``cols``, seen by a camera of ``config``."""
        with np.errstate(invalid="ignore", over="ignore"):  # rays meeting nothing: inf
            return self._image(cols, config)

    def _image(self, cols: Columns, config: CameraConfig) -> np.ndarray:
        c = config
        rows = np.arange(c.height, dtype=np.float64)[:, None] + 0.5
        slope = (c.horizon - rows) / c.f  # the ray's rise per metre of depth, per row
        wall_h = c.z + slope * cols.wall[None, :]  # where each ray is at the wall
        thing_h = c.z + slope * cols.thing[None, :]
        out = np.where(slope < 0, np.float32(self.floor), np.float32(self.ceiling))
        out = np.broadcast_to(out, (c.height, c.width)).astype(np.float32)
        on_wall = np.isfinite(wall_h) & (wall_h >= 0) & (wall_h <= c.wall_height)
        wall_t = self.wall_low + (self.wall_high - self.wall_low) * wall_h / c.wall_height
        out[on_wall] = wall_t[on_wall]
        on_thing = np.isfinite(thing_h) & (thing_h >= 0) & (thing_h <= cols.height[None, :])
        if on_thing.any():
            kind = np.broadcast_to(cols.kind[None, :], out.shape)
            top = np.maximum(np.broadcast_to(cols.height[None, :], out.shape), 1e-6)
            robot = self.robot_motors + (self.robot_top - self.robot_motors) * thing_h / top
            dock = self.dock_charging if self.charging else self.dock_idle
            thing_t = np.select([kind == ROBOT, kind == DOCK, kind == OBSTACLE, kind == PERSON],
                                [robot, np.full(out.shape, dock),
                                 np.full(out.shape, self.obstacle),
                                 np.full(out.shape, self.person)], default=AMBIENT)
            out[on_thing] = thing_t[on_thing]
        return out


@dataclass(frozen=True)
class Reading:
    """A rule's temperatures (C) and where its hottest and coldest pixels are (normalised:
    0..1 from the left and the top, the pixel's centre; the first such pixel in row order)."""

    max: float
    min: float
    average: float
    max_at: tuple[float, float]
    min_at: tuple[float, float]


def read_rule(temps: np.ndarray) -> Reading:
    """The reading of the whole frame ``temps`` (one thermometry rule)."""
    h, w = temps.shape
    hot = int(np.argmax(temps))
    cold = int(np.argmin(temps))

    def at(i: int) -> tuple[float, float]:
        row, col = divmod(i, w)
        return (col + 0.5) / w, (row + 0.5) / h

    return Reading(float(temps.flat[hot]), float(temps.flat[cold]), float(temps.mean()),
                   at(hot), at(cold))
