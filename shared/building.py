"""A building: its floors (a map each) and the elevators joining them, from a YAML file
(docs/building.md).

Format (paths relative to the file)::

    name: tower
    floors:
      - {level: 1, map: floor1/floor1.yaml}     # map_server YAML; the map's name is its stem
      - {level: 2, map: floor2/floor2.yaml}
    elevators:
      - name: lift1
        levels: [1, 2]
        start_level: 1
        travel_s: 4.0        # seconds a floor
        door_s: 2.0          # seconds to open (and to close) the doors
        dwell_s: 6.0         # doors stay open this long once nobody holds or blocks them
        hold_s: 60.0         # a claim the holder does not use (enter, ride) lapses after this
        capacity: 1          # robots in the car at once
        car: {depth: 1.6, width: 1.4}
        stops:               # per level: the car's centre on that floor's map, heading out
          1: {x: 10.0, y: 5.0, theta: -1.5708}
          2: {x: 10.0, y: 5.0, theta: -1.5708}

A car is a ``depth`` x ``width`` rectangle centred at its stop, its door on the side the
stop's heading points to; the hall point (where a robot waits for the car) is
``HALL_GAP`` metres beyond the door along that heading. The floor's map draws the shaft's
walls and leaves the door's opening free; the simulator closes it while the doors are shut.
"""

from __future__ import annotations

import math
from pathlib import Path

import msgspec
import yaml

from .errors import ConfigError
from .se2 import Pose2, wrap_angle

__all__ = ["ELEVATOR_PATH", "HALL_GAP", "Building", "Car", "Elevator", "Floor", "Stop",
           "elevator_of_path", "load_building"]

HALL_GAP = 0.9  # m from the car's door to its hall point
ELEVATOR_PATH = "elevator_"  # nav's path of an elevator's hall points: elevator_<name>


def elevator_of_path(path_name: str) -> str | None:
    """The elevator whose hall points nav's path ``path_name`` holds, or None."""
    return path_name[len(ELEVATOR_PATH):] if path_name.startswith(ELEVATOR_PATH) else None


class Stop(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """The car's centre on one floor's map; ``theta`` faces out of the door."""

    x: float
    y: float
    theta: float = 0.0


class Car(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    depth: float = 1.6
    width: float = 1.4


class Elevator(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    name: str
    levels: list[int]
    stops: dict[int, Stop]
    start_level: int | None = None
    travel_s: float = 4.0
    door_s: float = 2.0
    dwell_s: float = 6.0
    hold_s: float = 60.0
    capacity: int = 1
    car: Car = Car()

    @property
    def first_level(self) -> int:
        return self.start_level if self.start_level is not None else self.levels[0]

    def car_pose(self, level: int) -> Pose2:
        s = self.stops[level]
        return Pose2(s.x, s.y, s.theta)

    def door_pose(self, level: int) -> Pose2:
        """The middle of the door's opening (heading out)."""
        return _ahead(self.car_pose(level), self.car.depth / 2)

    def hall_pose(self, level: int) -> Pose2:
        """Where a robot waits for the car on ``level``, facing the door."""
        p = _ahead(self.car_pose(level), self.car.depth / 2 + HALL_GAP)
        return Pose2(p.x, p.y, wrap_angle(p.theta + math.pi))

    def inside(self, level: int, x: float, y: float, margin: float = 0.0) -> bool:
        """(x, y) on ``level``'s map is within the car, ``margin`` m in from its walls."""
        lx, ly = _local(self.car_pose(level), x, y)
        return (abs(lx) <= self.car.depth / 2 - margin
                and abs(ly) <= self.car.width / 2 - margin)

    def in_doorway(self, level: int, x: float, y: float, radius: float) -> bool:
        """A disc of ``radius`` at (x, y) overlaps the door's line (it would be caught by
        closing doors)."""
        lx, ly = _local(self.car_pose(level), x, y)
        return abs(lx - self.car.depth / 2) < radius and abs(ly) < self.car.width / 2 + radius


class Floor(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    level: int
    map: str  # the map_server YAML (absolute once loaded)

    @property
    def map_name(self) -> str:
        return Path(self.map).stem


class Building(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    name: str
    floors: list[Floor]
    elevators: list[Elevator] = msgspec.field(default_factory=list)

    def floor(self, level: int) -> Floor:
        for f in self.floors:
            if f.level == level:
                return f
        raise LookupError(f"building {self.name!r} has no level {level} "
                          f"(levels {', '.join(str(f.level) for f in self.floors)})")

    def level_of_map(self, map_name: str) -> int:
        for f in self.floors:
            if f.map_name == map_name:
                return f.level
        raise LookupError(f"map {map_name!r} is not a floor of building {self.name!r}")

    def elevator(self, name: str = "") -> Elevator:
        """The elevator called ``name`` ("": the first, the building's default)."""
        if not self.elevators:
            raise LookupError(f"building {self.name!r} has no elevator")
        if not name:
            return self.elevators[0]
        for e in self.elevators:
            if e.name == name:
                return e
        raise LookupError(f"unknown elevator {name!r} (building {self.name!r} has "
                          f"{', '.join(e.name for e in self.elevators)})")


def load_building(path: str | Path) -> Building:
    """Read and check a building file; map paths come back absolute.

    Raises:
        ConfigError: unreadable, malformed, or inconsistent (a stop for a level the building
            lacks, a missing map file, two floors on one level, ...), saying what and where.
    """
    path = Path(path)
    try:
        raw = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as exc:
        raise ConfigError(f"building file {path}: {exc}") from exc
    try:
        b = msgspec.convert(raw, Building, strict=False)
    except msgspec.ValidationError as exc:
        raise ConfigError(f"building file {path}: {exc}") from exc
    floors = [Floor(f.level, str((path.parent / f.map).resolve())) for f in b.floors]
    b = Building(b.name, floors, b.elevators)
    _check(b, path)
    return b


def _check(b: Building, path: Path) -> None:
    def bad(why: str) -> ConfigError:
        return ConfigError(f"building file {path}: {why}")

    if not b.floors:
        raise bad("no floors")
    levels = [f.level for f in b.floors]
    if len(set(levels)) != len(levels):
        raise bad(f"two floors on one level ({levels})")
    names = [f.map_name for f in b.floors]
    if len(set(names)) != len(names):
        raise bad(f"two floors with one map name ({names}): a map is named by its file's stem")
    for f in b.floors:
        if not Path(f.map).is_file():
            raise bad(f"level {f.level}: no map file {f.map}")
    seen: set[str] = set()
    for e in b.elevators:
        if not e.name or e.name in seen:
            raise bad(f"elevator names must be given and distinct ({e.name!r})")
        seen.add(e.name)
        if len(e.levels) < 2 or len(set(e.levels)) != len(e.levels):
            raise bad(f"elevator {e.name!r}: levels must be two or more distinct floors")
        for lv in e.levels:
            if lv not in levels:
                raise bad(f"elevator {e.name!r} serves level {lv}, which has no floor")
            if lv not in e.stops:
                raise bad(f"elevator {e.name!r} has no stop on level {lv}")
        if e.first_level not in e.levels:
            raise bad(f"elevator {e.name!r}: start_level {e.first_level} is not one it serves")
        if min(e.travel_s, e.door_s, e.dwell_s, e.hold_s) <= 0 or e.capacity < 1:
            raise bad(f"elevator {e.name!r}: times must be > 0 and capacity >= 1")
        if e.car.depth <= 0 or e.car.width <= 0:
            raise bad(f"elevator {e.name!r}: the car's depth and width must be > 0")


def _ahead(p: Pose2, d: float) -> Pose2:
    return Pose2(p.x + d * math.cos(p.theta), p.y + d * math.sin(p.theta), p.theta)


def _local(p: Pose2, x: float, y: float) -> tuple[float, float]:
    dx, dy = x - p.x, y - p.y
    c, s = math.cos(p.theta), math.sin(p.theta)
    return c * dx + s * dy, -s * dx + c * dy

