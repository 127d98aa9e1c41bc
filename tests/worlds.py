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
