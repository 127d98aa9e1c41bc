"""Camera: a pinhole view of the 2-D world, rendered by casting one ray per image column (as
Wolfenstein 3D drew its levels).

The map's solid cells are walls ``wall_height`` high, the obstacles ``obstacle_height``, the
other robots' bodies ``robot_height``, people's legs (``person:...``) ``person_height`` in
their own colour, the dock a block behind its pose; the floor is a 1 m
checkerboard seen in perspective and the ceiling is plain. Each column casts one ray into the
map (`Laser.cast_map`) and one into each obstacle; the nearest wall is drawn, then the
nearest obstacle in front of it. Walls are shaded by distance, their faces along x and y
apart and a seam every metre, so a moving robot's view moves as a camera's would.

The horizon is on row ``cy`` (the image's middle by default): a camera tilted up or down is
drawn as a level one whose principal point moved (``cy = height/2 + f tan(tilt)``), what a
taller level image cropped would show; verticals stay vertical. `Camera.cast` gives what each
column's ray met (`Columns`), which the thermal view reads.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .laser import Laser
from .obstacles import Obstacle, ray_hits
from .people import PERSON_PREFIX
from .shared_world import BODY_PREFIX
from .world import World

__all__ = ["DOCK", "DOCK_ID", "NOTHING", "OBSTACLE", "OBSTACLE_RGB", "PERSON", "PERSON_PREFIX",
           "PERSON_RGB", "ROBOT", "ROBOT_PREFIX",
           "Camera", "CameraConfig", "Columns"]

ROBOT_PREFIX = BODY_PREFIX  # obstacle ids of the other robots' bodies
DOCK_ID = "dock:"  # the dock block's id (never an obstacle of the world)

_CEILING = np.array([214, 220, 228], dtype=np.float32)
_FLOOR = (np.array([132, 138, 150], dtype=np.float32), np.array([100, 105, 116], dtype=np.float32))
_WALL = np.array([236, 226, 200], dtype=np.float32)
OBSTACLE_RGB = (200, 90, 40)  # an obstacle's colour, lit (a camera calibration's board)
_OBSTACLE = np.array(OBSTACLE_RGB, dtype=np.float32)
_ROBOT = np.array([50, 110, 200], dtype=np.float32)
_DOCK = np.array([40, 160, 80], dtype=np.float32)
PERSON_RGB = (150, 60, 160)  # a person's colour, lit
_PERSON = np.array(PERSON_RGB, dtype=np.float32)
NOTHING, OBSTACLE, ROBOT, DOCK, PERSON = 0, 1, 2, 3, 4  # what a ray met besides the walls
_THINGS = np.stack([np.zeros(3, dtype=np.float32), _OBSTACLE, _ROBOT, _DOCK, _PERSON])


@dataclass(frozen=True)
class CameraConfig:
    """A ``width`` x ``height`` pinhole camera with horizontal field of view ``hfov`` (rad),
    square pixels, its lens ``z`` metres above the floor, looking level; the horizon on row
    ``cy`` (None: ``height / 2``; any value, also off the image)."""

    width: int = 640
    height: int = 480
    hfov: float = 1.2
    z: float = 0.5
    wall_height: float = 2.5
    obstacle_height: float = 1.0
    robot_height: float = 0.5
    person_height: float = 1.7
    dock_height: float = 0.4
    range_max: float = 30.0
    cy: float | None = None

    def __post_init__(self) -> None:
        if not (8 <= self.width <= 4096 and 8 <= self.height <= 4096):
            raise ValueError(f"camera size must be 8..4096 pixels a side, got "
                             f"{self.width}x{self.height}")
        if not 0.05 <= self.hfov <= 3.0:
            raise ValueError(f"camera hfov must be 0.05..3.0 rad, got {self.hfov}")
        if not 0 < self.z < self.wall_height:
            raise ValueError(f"camera z must be above the floor and below the walls "
                             f"({self.wall_height} m), got {self.z}")
        if self.cy is not None and not math.isfinite(self.cy):
            raise ValueError(f"camera cy must be finite, got {self.cy}")

    @property
    def horizon(self) -> float:
        """The horizon's row (the principal point's), from the top."""
        return self.height / 2 if self.cy is None else self.cy

    @property
    def f(self) -> float:
        """Focal length in pixels (fx = fy)."""
        return self.width / 2 / math.tan(self.hfov / 2)

    @property
    def k(self) -> list[float]:
        """The intrinsic matrix, row-major (CameraInfo.k)."""
        f, cx, cy = self.f, self.width / 2, self.horizon
        return [f, 0.0, cx, 0.0, f, cy, 0.0, 0.0, 1.0]


class Camera:
    """Renders RGB frames (``height x width x 3``, uint8) of a `World` from a pose.

    ``caster`` casts the map rays (a `Laser` on the same world; the cameras of a robot share
    one). A frame is rendered again only when the pose or the things in view changed.
    """

    def __init__(self, world: World, config: CameraConfig, caster: Laser) -> None:
        self.world = world
        self.config = config
        self.caster = caster
        c = config
        u = np.arange(c.width, dtype=np.float64) + 0.5
        self._offsets = np.arctan((c.width / 2 - u) / c.f)  # left of the axis is positive
        self._cos = np.cos(self._offsets)
        rows = np.arange(c.height, dtype=np.float64) + 0.5 - c.horizon
        self._rows = rows[:, None]  # pixel rows below the horizon are positive
        below = rows[rows > 0]
        self._floor_rows = int(c.height - below.size)
        floor_depth = c.f * c.z / below  # metres ahead, per floor row
        self._floor_along = (floor_depth[:, None] / self._cos[None, :]).astype(np.float32)
        shades = _shade(floor_depth)[:, None, None]  # (rows, light/dark, rgb)
        self._floor_lut = (np.stack(_FLOOR)[None, :, :] * shades).astype(np.uint8).reshape(-1, 3)
        self._floor_index = (2 * np.arange(below.size, dtype=np.int32))[:, None]
        ceiling = np.linspace(1.0, 0.8, c.height - below.size, dtype=np.float32)[:, None]
        self._ceiling = (ceiling * _CEILING).astype(np.uint8)[:, None, :].repeat(c.width, 1)
        self._last: tuple[tuple[object, ...], np.ndarray, Columns] | None = None

    def render(self, x: float, y: float, yaw: float,
               things: Iterable[Obstacle] = ()) -> np.ndarray:
        """The frame seen from (x, y) facing ``yaw`` in ``map`` with ``things`` (obstacles,
        robots ``robot:...``, the dock ``dock:``) in the world. The array is the camera's
        own: copy it to keep it past the next call."""
        shown = tuple(things)
        key = (x, y, yaw, shown)
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        columns = self._cast(x, y, yaw, shown)
        frame = self._render(x, y, columns)
        self._last = (key, frame, columns)
        return frame

    def cast(self, x: float, y: float, yaw: float,
             things: Iterable[Obstacle] = ()) -> Columns:
        """What each column's ray meets from (x, y) facing ``yaw`` (`render`'s view, not
        drawn; the last rendered view's own when it is that one)."""
        shown = tuple(things)
        if self._last is not None and self._last[0] == (x, y, yaw, shown):
            return self._last[2]
        return self._cast(x, y, yaw, shown)

    def _cast(self, x: float, y: float, yaw: float, things: tuple[Obstacle, ...]) -> Columns:
        c = self.config
        angles = yaw + self._offsets
        dx, dy = np.cos(angles), np.sin(angles)
        walls = self.caster.cast_map(x, y, angles).astype(np.float64)
        walls[walls > c.range_max] = np.inf
        near = np.full(c.width, np.inf)
        kind = np.zeros(c.width, dtype=np.int8)
        height = np.zeros(c.width)
        for thing in things:
            hit = ray_hits([thing], x, y, dx, dy)
            closer = (hit < near) & (hit < walls)
            near[closer] = hit[closer]
            k, h = self._look(thing)
            kind[closer] = k
            height[closer] = h
        return Columns(dx, dy, walls * self._cos, near * self._cos, kind, height)

    def _render(self, x: float, y: float, cols: Columns) -> np.ndarray:
        c = self.config
        image = np.empty((c.height, c.width, 3), dtype=np.uint8)
        image[: self._floor_rows] = self._ceiling
        self._floor(image, x, y, cols.dx, cols.dy)
        walls = cols.wall / self._cos
        hx, hy = x + walls * cols.dx, y + walls * cols.dy
        self._columns(image, walls, c.wall_height, self._wall_colour(walls, hx, hy))
        if cols.kind.any():
            near = cols.thing / self._cos
            colour = _THINGS[cols.kind]
            self._columns(image, near, cols.height, colour * _shade(cols.thing)[:, None])
        return image

    def _look(self, thing: Obstacle) -> tuple[int, float]:
        c = self.config
        if thing.id.startswith(ROBOT_PREFIX):
            return ROBOT, c.robot_height
        if thing.id == DOCK_ID:
            return DOCK, c.dock_height
        if thing.id.startswith(PERSON_PREFIX):
            return PERSON, c.person_height
        return OBSTACLE, c.obstacle_height

    def _floor(self, image: np.ndarray, x: float, y: float, dx: np.ndarray,
               dy: np.ndarray) -> None:
        """A 1 m checkerboard, darker with distance."""
        along = self._floor_along  # metres along each column's ray, per floor row
        px = np.floor(along * dx.astype(np.float32)[None, :] + np.float32(x)).astype(np.int32)
        py = np.floor(along * dy.astype(np.float32)[None, :] + np.float32(y)).astype(np.int32)
        px += py
        px &= 1  # 1: a dark tile
        px += self._floor_index  # 2 * row: the row's light tile in the flat table
        image[self._floor_rows:] = self._floor_lut[px]

    def _wall_colour(self, walls: np.ndarray, hx: np.ndarray, hy: np.ndarray) -> np.ndarray:
        """Each column's wall colour: faces along y darker than faces along x, a seam every
        metre, dimmer with distance."""
        w = self.world
        with np.errstate(invalid="ignore"):
            fx = (hx - w.ox) / w.res
            fy = (hy - w.oy) / w.res
            on_x_face = np.abs(fx - np.round(fx)) < np.abs(fy - np.round(fy))
            along = np.where(on_x_face, hy, hx)
            seam = np.abs(along - np.round(along)) < 0.02
        face = np.where(on_x_face, 0.82, 1.0) * np.where(seam, 0.6, 1.0)
        colour: np.ndarray = _WALL[None, :] * (face * _shade(walls * self._cos))[:, None]
        return colour.astype(np.float32)

    def _columns(self, image: np.ndarray, ranges: np.ndarray, height: float | np.ndarray,
                 colour: np.ndarray) -> None:
        """Draw, in each column with a finite range, a block from the floor up to ``height``
        metres at that range's depth."""
        c = self.config
        depth = ranges * self._cos
        cols = np.nonzero(np.isfinite(depth) & (depth > 1e-3))[0]
        if not cols.size:
            return
        d = depth[cols]
        h = np.broadcast_to(np.asarray(height, dtype=np.float64), depth.shape)[cols]
        half = c.horizon
        top = np.clip(np.ceil(half - c.f * (h - c.z) / d - 0.5), 0, c.height).astype(np.int64)
        bottom = np.clip(np.floor(half + c.f * c.z / d - 0.5) + 1, 0, c.height).astype(np.int64)
        pixels = colour[cols].astype(np.uint8)
        for col, t, b, px in zip(cols.tolist(), top.tolist(), bottom.tolist(), pixels,
                                 strict=True):
            image[t:b, col] = px


@dataclass(frozen=True)
class Columns:
    """What each image column's ray met: its direction (``dx``, ``dy`` in ``map``), the
    depth (along the optical axis, m; ``inf``: none in range) of the wall and of the nearest
    thing in front of it, that thing's kind (`NOTHING`, `OBSTACLE`, `ROBOT`, `DOCK`,
    `PERSON`) and
    height (m)."""

    dx: np.ndarray
    dy: np.ndarray
    wall: np.ndarray
    thing: np.ndarray
    kind: np.ndarray
    height: np.ndarray


def _shade(depth: np.ndarray) -> np.ndarray:
    """Brightness at ``depth`` metres: 1 near, fading to 0.35 far."""
    with np.errstate(invalid="ignore"):
        out = 0.35 + 0.65 / (1.0 + 0.08 * np.nan_to_num(depth, posinf=1e6))
    return np.asarray(out, dtype=np.float32)
