"""Worlds the tests generate: small sites a robot has never seen, for mapping and exploring.

``tests/`` is on ``sys.path`` (its conftest.py), so any test imports these as ``worlds``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from zenros.maps import GridMap, save_map

RES = 0.05


def small_world(folder: Path) -> Path:
    """14 m x 8 m: a corridor along the south (the robot at (0, 0) in it, facing east along
    it), two rooms north of it behind 0.9 m doors (walls the laser does not see through), a
    box in the east room; the rooms can only be mapped from inside. About 100 m2 of floor.

    Returns the map_server YAML written into ``folder`` (``small.yaml``)."""
    g = np.zeros((160, 280), dtype=np.int8)

    def wall(x0: float, y0: float, x1: float, y1: float, v: int = 100) -> None:
        g[round((y0 + 1) / RES):round((y1 + 1) / RES),
          round((x0 + 1) / RES):round((x1 + 1) / RES)] = v

    wall(-1, -1, 13, -0.9)
    wall(-1, 6.9, 13, 7)
    wall(-1, -1, -0.9, 7)
    wall(12.9, -1, 13, 7)
    wall(-1, 1.5, 13, 1.6)          # corridor | rooms
    wall(1.5, 1.5, 2.4, 1.6, 0)      # west door
    wall(8.0, 1.5, 8.9, 1.6, 0)      # east door
    wall(5.5, 1.5, 5.6, 7)           # west room | east room
    wall(10.0, 4.0, 10.6, 4.6)       # a box
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "small.yaml"
    save_map(GridMap(g, RES, (-1.0, -1.0, 0.0)), path)
    return path


def crossing_world(folder: Path, lanes: int = 1, *, width: float = 0.8, length: float = 3.0,
                   hall: float = 3.0) -> Path:
    """Two halls, ``hall`` metres deep (x), joined by ``lanes`` corridors ``width`` wide and
    ``length`` long, one every 2 m from y = 1.5 (`lane_y`); the halls are 2 * lanes + 1 m
    tall. The west hall spans x in [0, hall], the east one [hall + length, 2 * hall + length].
    A 0.8 m corridor is one robot wide for nav (two 0.22 m inscribed radii and their
    margins do not fit), and narrow for the schedule manager at its default passing width
    (1.3 m). Returns the map_server YAML written into ``folder`` (``crossing.yaml``)."""
    height = 2.0 * lanes + 1.0
    x_max, y_max = 2 * hall + length, height
    rows, cols = round((y_max + 0.4) / RES), round((x_max + 0.4) / RES)
    g = np.full((rows, cols), 100, dtype=np.int8)

    def free(x0: float, y0: float, x1: float, y1: float) -> None:
        g[round((y0 + 0.2) / RES):round((y1 + 0.2) / RES),
          round((x0 + 0.2) / RES):round((x1 + 0.2) / RES)] = 0

    free(0.0, 0.0, hall, height)
    free(hall + length, 0.0, x_max, height)
    for k in range(lanes):
        y = lane_y(k)
        free(hall, y - width / 2, hall + length, y + width / 2)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "crossing.yaml"
    save_map(GridMap(g, RES, (-0.2, -0.2, 0.0)), path)
    return path


def lane_y(k: int) -> float:
    """The centre line (y) of `crossing_world`'s corridor ``k``."""
    return 1.5 + 2.0 * k
