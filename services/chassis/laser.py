"""Laser: a 2-D scan ray-cast against the world, in C where built, else in numpy (reference).

The numpy reference is vectorised over beams (float32 ray marching). Each beam first
marches a fixed number of steps along the map's distance field (a step is the distance to
the nearest solid cell, less a cell's diagonal so it never jumps over one, and at least
half a cell); the few beams still going, those grazing a wall, are then sampled every half
cell in one array operation. A beam that lands in a solid cell ranges to the ray's exact
entry into the first solid cell it crosses after its last free sample (a cell-by-cell walk
over that half cell). A ray clipping only the corner of a lone cell by less than half a
cell may miss it.
Obstacles are intersected exactly (circles and boxes); the nearer hit wins.

The map part runs compiled when ``_march.c`` is built (``pip install`` builds it where a C
compiler is present): an exact cell-by-cell traversal of each beam (Amanatides & Woo), which
never misses a corner. The numpy march here is the reference and the fallback; set
``ZENROS_CHASSIS_PURE=1`` to use it anyway.
"""

from __future__ import annotations

import importlib
import math
import os
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np
from scipy.ndimage import distance_transform_edt

from .obstacles import Obstacle, ray_hits
from .world import World

__all__ = ["Laser", "LaserConfig"]

_COARSE_STEPS = 20
_MARGIN = np.float32(math.sqrt(2))  # a cell's diagonal: a step never jumps over a solid cell
_MIN_STEP = np.float32(0.5)  # cells
_ENTRY_CROSSINGS = 2  # cell boundaries a ray crosses in half a cell, at most


def _load_compiled() -> ModuleType | None:
    """The compiled march (``_march``), or None: not built, or ``ZENROS_CHASSIS_PURE`` set."""
    if os.environ.get("ZENROS_CHASSIS_PURE", "") not in ("", "0"):
        return None
    try:
        return importlib.import_module(f"{__package__}._march")
    except ImportError:
        return None


compiled = _load_compiled()
"""The compiled march module, or None (the numpy reference runs)."""


@dataclass(frozen=True)
class LaserConfig:
    """Beams spread over ``[angle_min, angle_min + (beams - 1) * increment]``, full circle
    by default; ranges outside ``[range_min, range_max]`` are reported as ``inf``."""

    beams: int = 360
    range_min: float = 0.05
    range_max: float = 12.0
    fov: float = 2 * math.pi
    noise: float = 0.0

    def __post_init__(self) -> None:
        if self.beams < 1:
            raise ValueError(f"scan_beams must be >= 1, got {self.beams}")
        if not 0 <= self.range_min < self.range_max:
            raise ValueError(f"need 0 <= range_min < range_max, got {self.range_min}, "
                             f"{self.range_max}")
        if not 0 < self.fov <= 2 * math.pi:
            raise ValueError(f"scan_fov must be in (0, 2 pi], got {self.fov}")
        if self.noise < 0:
            raise ValueError(f"range_noise must be >= 0, got {self.noise}")

    @property
    def angle_increment(self) -> float:
        full = abs(self.fov - 2 * math.pi) < 1e-9
        return self.fov / (self.beams if full else max(self.beams - 1, 1))

    @property
    def angle_min(self) -> float:
        return -self.fov / 2 if abs(self.fov - 2 * math.pi) > 1e-9 else -math.pi

    @property
    def angle_max(self) -> float:
        return self.angle_min + (self.beams - 1) * self.angle_increment


class Laser:
    """Casts scans from a pose in a `World`.

    The map part is fixed at construction: a padded grid (one ring of "outside" cells) with,
    per cell, the safe marching step in cells (0 on solid and outside cells) and its kind
    (0 free, 1 solid, 2 outside).
    """

    def __init__(self, world: World, config: LaserConfig,
                 rng: np.random.Generator | None = None) -> None:
        self.world = world
        self.config = config
        self.rng = rng or np.random.default_rng()
        self._angles = config.angle_min + np.arange(config.beams) * config.angle_increment
        self._cast: tuple[tuple[Any, ...], np.ndarray] | None = None  # (pose, obstacles), ranges
        self._bind()

    def _bind(self) -> None:
        """Derive the marching grids from the world's map (again after a floor change)."""
        world, config = self.world, self.config
        self._generation = world.generation
        self._cast = None
        h, w = world.height, world.width
        blocked = np.ones((h + 2, w + 2), dtype=bool)
        blocked[1:-1, 1:-1] = world.solid
        edt = distance_transform_edt(~blocked).astype(np.float32)
        step = np.where(edt > 0, np.maximum(edt - _MARGIN, _MIN_STEP), 0)
        self._step = np.ascontiguousarray(step, dtype=np.float32).reshape(-1)
        kind = np.full((h + 2, w + 2), 2, dtype=np.uint8)
        kind[1:-1, 1:-1] = world.solid
        self._kind = kind.reshape(-1)
        self._stride = w + 2
        self._limit = np.float32(config.range_max / world.res + 1.0)
        self._fine = np.arange(0, 2 * int(self._limit) + 4, dtype=np.float32) * _MIN_STEP

    def ranges(self, x: float, y: float, theta: float) -> np.ndarray:
        """Float32 ranges of one scan from the laser at (x, y) facing ``theta`` in ``map``.

        The rays are cast again only when the pose or the obstacles changed since the last
        scan (a robot at rest sees the same world; the noise is drawn anew for each scan).
        """
        cfg = self.config
        key = (x, y, theta, self.world.generation, tuple(self.world.obstacles.values()))
        if self._cast is not None and self._cast[0] == key:
            out = self._cast[1].copy()
        else:
            out = self._trace(x, y, theta, key[4])
            self._cast = (key, out.copy())
        if cfg.noise > 0:
            finite = np.isfinite(out)
            out[finite] += self.rng.normal(0.0, cfg.noise, int(finite.sum())).astype(np.float32)
        out[(out < cfg.range_min) | (out > cfg.range_max)] = np.inf
        return out

    def cast_map(self, x: float, y: float, angles: np.ndarray) -> np.ndarray:
        """Noise-free float32 ranges to the map's walls from (x, y) along the absolute
        ``angles`` (radians in ``map``); inf where no wall is within ``range_max``. The
        cameras cast their columns with it."""
        return self._march_map(x, y, np.cos(angles), np.sin(angles))

    def _march_map(self, x: float, y: float, dx64: np.ndarray, dy64: np.ndarray) -> np.ndarray:
        if self.world.generation != self._generation:
            self._bind()
        march = compiled
        if march is not None:
            return self._march_compiled(march, x, y, dx64, dy64)
        return self._march(x, y, dx64.astype(np.float32), dy64.astype(np.float32))

    def _trace(self, x: float, y: float, theta: float,
               obstacles: tuple[Obstacle, ...]) -> np.ndarray:
        """Noise-free ranges: the map's walls, then the obstacles."""
        ang = self._angles + theta
        dx64, dy64 = np.cos(ang), np.sin(ang)
        out = self._march_map(x, y, dx64, dy64)
        if obstacles:
            hits = ray_hits(list(obstacles), x, y, dx64, dy64)
            np.minimum(out, hits.astype(np.float32), out=out)
        return out

    def _march_compiled(self, march: ModuleType, x: float, y: float, dx: np.ndarray,
                        dy: np.ndarray) -> np.ndarray:
        """`_march` by the compiled exact traversal (float64 unit directions)."""
        w = self.world
        out = np.empty(dx.size, dtype=np.float32)
        march.march(self._kind, self._stride, self._kind.size // self._stride,
                       (x - w.ox) / w.res + 1.0, (y - w.oy) / w.res + 1.0,
                       np.ascontiguousarray(dx, dtype=np.float64),
                       np.ascontiguousarray(dy, dtype=np.float64),
                       float(self._limit), w.res, out)
        return out

    def _free_at(self, px: float, py: float) -> bool:
        """True when (px, py), in cells of the padded grid, is in a free cell of the map."""
        if not (0 <= px < self._stride and 0 <= py < self._kind.size // self._stride):
            return False  # also false for nan
        return bool(self._kind[int(py) * self._stride + int(px)] == 0)

    def _cells(self, t: np.ndarray, dx: np.ndarray, dy: np.ndarray, px: np.float32,
               py: np.float32) -> np.ndarray:
        fy = t * dy
        fy += py
        fx = t * dx
        fx += px
        iy: np.ndarray = fy.astype(np.int32)
        iy *= self._stride
        iy += fx.astype(np.int32)
        return iy

    def _march(self, x: float, y: float, dx: np.ndarray, dy: np.ndarray) -> np.ndarray:
        """Map ranges in metres (inf: no solid cell within range)."""
        w = self.world
        px = np.float32((x - w.ox) / w.res + 1.0)
        py = np.float32((y - w.oy) / w.res + 1.0)
        if not self._free_at(float(px), float(py)):
            return np.full(dx.size, np.inf, dtype=np.float32)  # inside a wall or off the map
        # phase 1: every beam marches a fixed number of safe steps along the distance field
        t = np.zeros(dx.size, dtype=np.float32)
        step = self._step
        for _ in range(_COARSE_STEPS):
            s = step[self._cells(t, dx, dy, px, py)]
            t += s
        # phase 2: the few beams still going (grazing a wall) are sampled every half cell
        active = np.nonzero((s > 0) & (t < self._limit))[0]
        if active.size:
            t0 = t[active]
            n = math.ceil((float(self._limit) - float(t0.min())) / _MIN_STEP) + 1
            tt = self._fine[:n] + t0[:, None]
            fx = tt * dx[active, None]
            fx += px
            fy = tt * dy[active, None]
            fy += py
            iy = fy.astype(np.int32)
            iy *= self._stride
            iy += fx.astype(np.int32)
            # a beam meets the outside ring before it can leave the grid; past that point
            # the indices are not used, "clip" only keeps them in bounds
            first = (np.take(self._kind, iy, mode="clip") != 0).argmax(axis=1)
            t[active] = tt[np.arange(active.size), first]
        hit = np.take(self._kind, self._cells(t, dx, dy, px, py), mode="clip") == 1
        out = np.full(dx.size, np.inf, dtype=np.float32)
        if hit.any():
            out[hit] = _entry(self._kind, self._stride, px, py, dx[hit], dy[hit],
                              t[hit]) * np.float32(w.res)
        return out


def _entry(kind: np.ndarray, stride: int, px: np.float32, py: np.float32, dx: np.ndarray,
           dy: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Where each ray first enters a solid cell (cell units), walking cell by cell (as a DDA
    does) from the last free sample, half a cell before ``t`` where it landed in one."""
    tiny = np.float32(1e-30)  # an axis-parallel ray: that slab never limits
    dx = np.where(dx == 0, tiny, dx)
    dy = np.where(dy == 0, tiny, dy)
    tb = np.maximum(t - _MIN_STEP, np.float32(0))
    x = px + tb * dx
    y = py + tb * dy
    fx = np.floor(x)
    fy = np.floor(y)
    pos_x, pos_y = dx > 0, dy > 0
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        next_x = tb + (fx + pos_x - x) / dx
        next_y = tb + (fy + pos_y - y) / dy
    cell = fy.astype(np.int32) * stride + fx.astype(np.int32)
    step_x = np.where(pos_x, 1, -1).astype(np.int32)
    step_y = np.where(pos_y, stride, -stride).astype(np.int32)
    out = t.copy()
    found = np.take(kind, cell, mode="clip") == 1
    out[found] = tb[found]
    for _ in range(_ENTRY_CROSSINGS):
        along_x = next_x < next_y
        cross = np.where(along_x, next_x, next_y)
        cell += np.where(along_x, step_x, step_y)
        new = (np.take(kind, cell, mode="clip") == 1) & ~found & (cross <= t)
        out[new] = cross[new]
        found |= new
        if _ == 0:
            next_x = np.where(along_x, np.inf, next_x)  # each axis crosses once in half a cell
            next_y = np.where(along_x, next_y, np.inf)
    return out
