"""`Floors`: the simulated robot in a building (docs/building.md): one map a floor, the floor
it is on, the elevator doors as obstacles, and the ride that carries it to another floor.

The chassis's one `World` holds the map of the robot's floor: changing floors makes it take
the new floor's map (`World.take_map`) and that floor's obstacles, so every device keeps its
world. A landing door is a thin box across the car's doorway on its floor, there unless the
car stands at that floor with its doors fully open (as the elevator controller reports).
A robot is aboard a car when its centre is inside the car while the car stands at its floor;
when the car then stands at another floor, the robot is on that floor, at the same place in
the car.
"""

from __future__ import annotations

from zenros.building import Building, Elevator
from zenros.maps import load_map
from zenros.msgs.zenros_msgs import ElevatorState
from zenros.se2 import Pose2

from .obstacles import Obstacle
from .world import World

__all__ = ["DOOR_PREFIX", "Floors"]

DOOR_PREFIX = "door:"
DOOR_THICKNESS = 0.1  # m
OPEN = 0.999  # a door at least this open lets a body through
AT_FLOOR = 0.01  # floors: a car this close to a floor stands at it


class Floors:
    """``world`` (the chassis's, holding the map of ``level``) in ``building``."""

    def __init__(self, building: Building, world: World, level: int) -> None:
        self.building = building
        self.world = world
        self.level = level
        self._maps = {f.level: World(load_map(f.map)) for f in building.floors}
        self._obstacles: dict[int, dict[str, Obstacle]] = {
            f.level: {} for f in building.floors}
        self._obstacles[level] = world.obstacles
        self._cars: dict[str, ElevatorState] = {}
        self._aboard: str | None = None  # the car the robot rides, if any
        for e in building.elevators:
            for lv in e.levels:
                self._obstacles[lv][_door_id(e, lv)] = _door(e, lv)

    def car(self, name: str) -> ElevatorState | None:
        return self._cars.get(name)

    def on_state(self, msg: ElevatorState) -> bool:
        """Take a car's state (its doors open or close on each floor); False for a car the
        building does not have."""
        try:
            e = self.building.elevator(msg.name) if msg.name else None
        except LookupError:
            return False
        if e is None:
            return False
        self._cars[e.name] = msg
        for lv in e.levels:
            obstacles = self._obstacles[lv]
            if _stands_at(msg, lv) and msg.door >= OPEN:
                obstacles.pop(_door_id(e, lv), None)
            else:
                obstacles[_door_id(e, lv)] = _door(e, lv)
        return True

    def ride(self, truth: Pose2) -> Pose2 | None:
        """After a step: the robot's new pose when the car it rides stands at another floor
        now (it is on that floor then), else None."""
        if self._aboard is None:
            for e in self.building.elevators:
                car = self._cars.get(e.name)
                if (car is not None and _stands_at(car, self.level)
                        and e.inside(self.level, truth.x, truth.y)):
                    self._aboard = e.name
            return None
        e = self.building.elevator(self._aboard)
        car = self._cars.get(e.name)
        if not e.inside(self.level, truth.x, truth.y):
            self._aboard = None
            return None
        if car is None or car.level == self.level or not _stands_at(car, car.level):
            return None
        new = car.level
        if new not in self._maps:
            return None
        pose = _carry(e.car_pose(self.level), e.car_pose(new), truth)
        self.world.take_map(self._maps[new])
        self.world.obstacles = self._obstacles[new]
        self.level = new
        return pose

    def place_body(self, ident: str, level: int, body: Obstacle | None) -> None:
        """Put another robot's ``body`` (obstacle id ``ident``) on ``level``, off every other
        floor; None takes it out of the building."""
        for lv, obstacles in self._obstacles.items():
            if lv == level and body is not None:
                obstacles[ident] = body
            else:
                obstacles.pop(ident, None)

    def move_to(self, level: int) -> None:
        """Put the robot on ``level`` (a teleport to another floor).

        Raises:
            LookupError: the building has no such floor.
        """
        self.building.floor(level)
        if level != self.level:
            self.world.take_map(self._maps[level])
            self.world.obstacles = self._obstacles[level]
            self.level = level
        self._aboard = None


def _stands_at(car: ElevatorState, level: int) -> bool:
    return car.level == level and abs(car.position - level) < AT_FLOOR


def _door_id(e: Elevator, level: int) -> str:
    return f"{DOOR_PREFIX}{e.name}:{level}"


def _door(e: Elevator, level: int) -> Obstacle:
    d = e.door_pose(level)
    return Obstacle(_door_id(e, level), "box", d.x, d.y, d.theta,
                    size_x=DOOR_THICKNESS, size_y=e.car.width + 2 * DOOR_THICKNESS)


def _carry(old: Pose2, new: Pose2, truth: Pose2) -> Pose2:
    """``truth`` relative to the car at ``old``, put in the car at ``new``."""
    return new * (old.inverse() * truth)
