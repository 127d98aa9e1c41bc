"""A tiny building for the elevator tests: three 4 m x 4 m floors (walls round the edge, an
empty map each) and one elevator ``lift1`` serving them, its car at (2, 2) on every floor with
its door facing -y (door line y = 1.2, hall point y = 0.3).

``tests/`` is on ``sys.path`` (its conftest.py), so a test imports this as ``tiny_building``."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import yaml
from zenros.maps import GridMap, save_map

CAR = (2.0, 2.0)       # the car's centre on every floor
DOORWAY = (2.0, 1.2)   # on the door's line
HALL = (2.0, 0.3)      # the hall point, outside


def write_building(folder: Path, **elevator: object) -> Path:
    """``folder/tower.yaml`` and its floors' maps; ``elevator`` overrides lift1's fields
    (``travel_s``, ``door_s``, ...). Returns the building file."""
    grid = np.zeros((80, 80), dtype=np.int8)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = 100
    floors = []
    for level in (1, 2, 3):
        (folder / f"floor{level}").mkdir(parents=True, exist_ok=True)
        save_map(GridMap(grid, 0.05, (0.0, 0.0, 0.0)),
                 folder / f"floor{level}" / f"floor{level}.yaml")
        floors.append({"level": level, "map": f"floor{level}/floor{level}.yaml"})
    lift = {"name": "lift1", "levels": [1, 2, 3], "start_level": 1, "travel_s": 1.0,
            "door_s": 0.5, "dwell_s": 1.0, "hold_s": 30.0, "capacity": 1,
            "car": {"depth": 1.6, "width": 1.4},
            "stops": {lv: {"x": CAR[0], "y": CAR[1], "theta": -math.pi / 2}
                      for lv in (1, 2, 3)}}
    lift.update(elevator)
    path = folder / "tower.yaml"
    path.write_text(yaml.safe_dump({"name": "tower", "floors": floors, "elevators": [lift]}))
    return path
