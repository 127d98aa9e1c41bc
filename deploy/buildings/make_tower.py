"""Generate the demo building: three floors of the demo office joined by one elevator.

    python deploy/buildings/make_tower.py [OUT_DIR]     # default: deploy/buildings/tower

Writes OUT_DIR/tower.yaml (the building, `zenros.building`) and one map folder a floor,
floor1/ .. floor3/ (map_server YAML + PGM, 0.05 m cells, the office's map frame; poses.yaml;
landmarks.yaml: the office's reflector strips, which nav relocalises on after a ride). Each floor
is the office of deploy/maps/make_office.py with the elevator's shaft in the north-east
office: a 1.6 m deep, 1.4 m wide car whose doors open south onto the main corridor at
x = 23.6 m in map. Floor 1 keeps the office's dock and start pose; floors 2 and 3 have
other furniture (so that a robot can tell them apart) and no dock.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import yaml

from zenros.maps import GridMap, MapPose, MapPoses, save_landmarks, save_map, save_poses

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "maps"))
from make_office import ORIGIN, RES, WALL, Floor, draw, reflectors  # noqa: E402

# the car in building-local metres (make_office's drawing frame)
CAR_X, CAR_Y = 26.6, 11.8
DEPTH, WIDTH = 1.6, 1.4
CORRIDOR_NORTH = 11.0  # the main corridor's north wall, where the doors are


def add_shaft(f: Floor) -> None:
    """The shaft's walls around the car, and the door's opening in the corridor wall."""
    x0, x1 = CAR_X - WIDTH / 2, CAR_X + WIDTH / 2
    back = CORRIDOR_NORTH + DEPTH
    f.block(x0 - WALL, CORRIDOR_NORTH - WALL / 2, x0, back + WALL)
    f.block(x1, CORRIDOR_NORTH - WALL / 2, x1 + WALL, back + WALL)
    f.block(x0, back, x1, back + WALL)
    f.free(x0, CORRIDOR_NORTH, x1, back)
    f.free(x0, CORRIDOR_NORTH - WALL, x1, CORRIDOR_NORTH + WALL)  # the doorway


FURNITURE = {
    2: [(3.0, 12.5, 5.0, 13.5), (15.5, 3.0, 18.0, 4.0), (8.0, 14.0, 9.5, 15.5)],
    3: [(20.5, 12.0, 22.5, 13.0), (2.0, 2.0, 4.0, 6.0), (11.0, 16.0, 12.0, 19.0)],
}


def floor(level: int) -> Floor:
    f = draw()
    if level != 1:
        f.free(24.5, 0.75, 25.5, 1.0)  # no dock on the upper floors
        for box in FURNITURE[level]:
            f.block(*box)
    add_shaft(f)
    return f


def main(out: Path) -> None:
    ox, oy, _ = ORIGIN
    stop = {"x": round(CAR_X + ox, 3), "y": round(CAR_Y + oy, 3), "theta": -math.pi / 2}
    floors = []
    for level in (1, 2, 3):
        folder = out / f"floor{level}"
        folder.mkdir(parents=True, exist_ok=True)
        f = floor(level)
        save_map(GridMap(f.grid, RES, ORIGIN), folder / f"floor{level}.yaml")
        save_landmarks(reflectors(f), folder / f"floor{level}.yaml")  # the office's strips
        start = MapPose(0.0, 0.0, 0.0)
        dock = MapPose(25.0 + ox, 0.75 + 0.22 + oy, -math.pi / 2) if level == 1 else None
        save_poses(MapPoses(start=start, dock=dock), folder / f"floor{level}.yaml")
        floors.append({"level": level, "map": f"floor{level}/floor{level}.yaml"})
    building = {
        "name": "tower",
        "floors": floors,
        "elevators": [{
            "name": "lift1", "levels": [1, 2, 3], "start_level": 1,
            "travel_s": 4.0, "door_s": 2.0, "dwell_s": 6.0, "hold_s": 60.0, "capacity": 1,
            "car": {"depth": DEPTH, "width": WIDTH},
            "stops": {level: dict(stop) for level in (1, 2, 3)},
        }],
    }
    text = ("# The demo building (deploy/buildings/make_tower.py writes it): three floors of the\n"
            "# demo office, one elevator. docs/building.md.\n"
            + yaml.safe_dump(building, sort_keys=False))
    (out / "tower.yaml").write_text(text)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent / "tower")
