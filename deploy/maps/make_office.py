"""Generate the demo map: an office floor with rooms, a corridor, doors and a charging dock.

    python deploy/maps/make_office.py [OUT_DIR]     # default: deploy/maps/office

Writes office.yaml + office.pgm (map_server, trinary, 0.05 m cells), poses.yaml (start
and dock poses, see zenros.maps.poses) and landmarks.yaml (reflector strips on the walls
met from the corridor, see zenros.maps.landmarks). The floor is 30 m x 20 m; the map
frame's (0, 0) is in the main corridor, near its west end, where the robot starts. Outside the building
is unknown, as a SLAM map would leave it.

Layout (x east, y north, metres in map):
- main corridor, 2.5 m wide, along y = -1.25 .. 1.25, the whole length of the building;
- five offices north of it (6 m wide, 1 m doors onto the corridor), one with a desk;
- south of it: a meeting room (table), an open-plan office with desk rows, and a lobby
  open to the corridor with the charging dock against its south wall.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from zenros.maps import (
    FREE,
    OCCUPIED,
    UNKNOWN,
    GridMap,
    MapPose,
    MapPoses,
    Reflector,
    save_landmarks,
    save_map,
    save_poses,
)

RES = 0.05
WIDTH_M, HEIGHT_M = 30.0, 20.0
# map (0, 0) sits at building-local (3.0, 9.75): the west end of the main corridor
ORIGIN = (-3.0, -9.75, 0.0)
WALL = 0.15
REFLECTOR_RADIUS = 0.05
# reflector strips, in map x along the corridor's walls (clear of doors and pillars, spaced
# unevenly so that no two pairs are alike), one on each end wall at map y, and two in the
# lobby (the reception counter's north face, the lobby's west wall)
NORTH_REFLECTORS = (0.6, 3.1, 6.9, 8.6, 12.8, 14.3, 18.9, 21.0, 24.4)
SOUTH_REFLECTORS = (-1.3, 2.9, 5.9, 10.4, 12.1, 16.2)
WEST_REFLECTOR_Y, EAST_REFLECTOR_Y = 0.45, -0.5
COUNTER_REFLECTOR_X, LOBBY_REFLECTOR_Y = 25.0, -3.0


class Floor:
    """A grid drawn in building-local metres (0..30 x 0..20), row 0 at the bottom."""

    def __init__(self) -> None:
        self.grid = np.full((round(HEIGHT_M / RES), round(WIDTH_M / RES)), UNKNOWN, np.int8)

    def _fill(self, x0: float, y0: float, x1: float, y1: float, value: int) -> None:
        c0, c1 = round(min(x0, x1) / RES), round(max(x0, x1) / RES)
        r0, r1 = round(min(y0, y1) / RES), round(max(y0, y1) / RES)
        self.grid[r0:r1, c0:c1] = value

    def free(self, x0: float, y0: float, x1: float, y1: float) -> None:
        self._fill(x0, y0, x1, y1, FREE)

    def block(self, x0: float, y0: float, x1: float, y1: float) -> None:
        self._fill(x0, y0, x1, y1, OCCUPIED)

    def hwall(self, y: float, x0: float, x1: float) -> None:
        self.block(x0, y - WALL / 2, x1, y + WALL / 2)

    def vwall(self, x: float, y0: float, y1: float) -> None:
        self.block(x - WALL / 2, y0, x + WALL / 2, y1)

    def door_h(self, y: float, x: float, width: float = 1.0) -> None:
        self.free(x - width / 2, y - WALL, x + width / 2, y + WALL)

    def door_v(self, x: float, y: float, width: float = 1.0) -> None:
        self.free(x - WALL, y - width / 2, x + WALL, y + width / 2)


def draw() -> Floor:
    """The office floor, in building-local coordinates."""
    f = Floor()
    x0, y0, x1, y1 = 0.5, 0.5, 29.5, 19.5
    f.free(x0, y0, x1, y1)
    for y in (y0, y1):
        f.hwall(y, x0 - WALL / 2, x1 + WALL / 2)
    for x in (x0, x1):
        f.vwall(x, y0 - WALL / 2, y1 + WALL / 2)
    c_lo, c_hi = 8.5, 11.0  # main corridor
    # north offices: five rooms, doors onto the corridor
    f.hwall(c_hi, x0, x1)
    for x in (6.3, 12.1, 17.9, 23.7):
        f.vwall(x, c_hi, y1)
    for cx in (3.4, 9.2, 15.0, 20.8, 26.6):
        f.door_h(c_hi, cx - 1.5)
    f.block(7.5, 17.5, 10.5, 18.7)  # a desk in the second office
    f.block(13.0, 17.8, 14.6, 19.4)  # a cabinet in the third
    # south side: meeting room | open-plan office | lobby with the dock
    f.hwall(c_lo, x0, 20.0)
    f.vwall(9.0, y0, c_lo)
    f.vwall(20.0, y0, c_lo)
    f.door_h(c_lo, 4.5)  # meeting room
    f.door_h(c_lo, 11.0, 1.2)  # open-plan office, two doors
    f.door_h(c_lo, 17.5, 1.2)
    f.door_v(20.0, 3.0)  # open-plan office <-> lobby
    f.block(2.5, 3.0, 6.5, 5.0)  # meeting table
    for dx in (10.5, 13.5, 16.5):  # desk rows
        f.block(dx, 2.0, dx + 1.6, 3.2)
        f.block(dx, 5.0, dx + 1.6, 6.2)
    f.block(27.0, 6.5, 29.5, 8.0)  # lobby reception counter
    for px in (8.0, 16.0):  # pillars in the corridor's south wall
        f.block(px - 0.2, c_lo - 0.2, px + 0.2, c_lo + 0.2)
    f.block(24.6, y0, 25.4, y0 + 0.25)  # the charging dock against the lobby wall
    return f


def _face(grid: np.ndarray, x: float, y: float, dx: int, dy: int) -> tuple[float, float]:
    """The face of the first solid cell from (x, y) in map, walking cell by cell along
    (dx, dy): the point on that face in line with (x, y)."""
    ox, oy, _ = ORIGIN
    col, row = int((x - ox) / RES), int((y - oy) / RES)
    while grid[row, col] < OCCUPIED:
        col, row = col + dx, row + dy
    if dx:
        return round(ox + (col + (dx < 0)) * RES, 3), y
    return x, round(oy + (row + (dy < 0)) * RES, 3)


def reflectors(floor: Floor) -> list[Reflector]:
    """The reflector strips: their centres on the wall faces met from the corridor."""
    out = [Reflector("west", *_face(floor.grid, -1.0, WEST_REFLECTOR_Y, -1, 0),
                     REFLECTOR_RADIUS)]
    out += [Reflector(f"n{i + 1}", *_face(floor.grid, x, 0.0, 0, 1), REFLECTOR_RADIUS)
            for i, x in enumerate(NORTH_REFLECTORS)]
    out += [Reflector(f"s{i + 1}", *_face(floor.grid, x, 0.0, 0, -1), REFLECTOR_RADIUS)
            for i, x in enumerate(SOUTH_REFLECTORS)]
    out.append(Reflector("east", *_face(floor.grid, 20.0, EAST_REFLECTOR_Y, 1, 0),
                         REFLECTOR_RADIUS))
    out.append(Reflector("counter", *_face(floor.grid, COUNTER_REFLECTOR_X, 0.0, 0, -1),
                         REFLECTOR_RADIUS))
    out.append(Reflector("lobby", *_face(floor.grid, 18.0, LOBBY_REFLECTOR_Y, -1, 0),
                         REFLECTOR_RADIUS))
    return out


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    floor = draw()
    ox, oy, _ = ORIGIN
    save_map(GridMap(floor.grid, RES, ORIGIN), out / "office.yaml")
    # the dock block's face is at y = 0.75; docked, the body (radius 0.2) is 2 cm from it
    dock = MapPose(25.0 + ox, 0.75 + 0.22 + oy, -math.pi / 2)
    save_poses(MapPoses(start=MapPose(0.0, 0.0, 0.0), dock=dock), out / "office.yaml")
    save_landmarks(reflectors(floor), out / "office.yaml")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent / "office")
