"""The building (`zenros.building`) and the robot in it (`Floors`): the demo tower's floors,
landing doors shut unless the car stands open at the floor, and a ride to another floor."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from zenros.building import load_building
from zenros.errors import ConfigError
from zenros.maps import load_map
from zenros.msgs.zenros_msgs import ElevatorState, SetObstaclesRequest
from zenros.se2 import Pose2
from zenros.services.chassis.drive import Drive, DriveLimits
from zenros.services.chassis.floors import DOOR_PREFIX, Floors
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.obstacle_requests import apply_request
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.sim import Simulation
from zenros.services.chassis.world import World

TOWER = Path(__file__).parents[3] / "deploy" / "buildings" / "tower" / "tower.yaml"
R = 0.2


def car(level: int, position: float | None = None, door: float = 0.0) -> ElevatorState:
    return ElevatorState(name="lift1", level=level,
                         position=float(level) if position is None else position, door=door)


@pytest.fixture
def tower() -> Floors:
    b = load_building(TOWER)
    return Floors(b, World(load_map(b.floor(1).map)), 1)


def test_the_demo_tower() -> None:
    b = load_building(TOWER)
    assert [f.level for f in b.floors] == [1, 2, 3]
    assert b.level_of_map("floor2") == 2
    e = b.elevator()
    assert e.name == "lift1" and b.elevator("lift1") is e
    for lv in e.levels:
        w = World(load_map(b.floor(lv).map))
        car_at, hall = e.car_pose(lv), e.hall_pose(lv)
        assert w.body_free(car_at.x, car_at.y, R) and w.body_free(hall.x, hall.y, R)
        assert e.inside(lv, car_at.x, car_at.y) and not e.inside(lv, hall.x, hall.y)
        # the hall point faces the door, 0.9 m from it
        door = e.door_pose(lv)
        assert math.isclose(math.hypot(door.x - hall.x, door.y - hall.y), 0.9)
        assert math.isclose(math.atan2(door.y - hall.y, door.x - hall.x), hall.theta)
    with pytest.raises(LookupError, match="no level 7"):
        b.floor(7)
    with pytest.raises(LookupError, match="unknown elevator 'lift9'"):
        b.elevator("lift9")


@pytest.mark.parametrize(("change", "says"), [
    (lambda d: d["floors"].pop(), "serves level 3, which has no floor"),
    (lambda d: d["elevators"][0]["stops"].pop(2), "no stop on level 2"),
    (lambda d: d["floors"][1].update(map="nowhere.yaml"), "no map file"),
    (lambda d: d["floors"][1].update(level=1), "two floors on one level"),
    (lambda d: d["elevators"][0].update(travel_s=0), "times must be > 0"),
    (lambda d: d["elevators"][0].update(start_level=5), "start_level 5"),
    (lambda d: d["elevators"][0].update(lift="x"), "unknown field"),
    (lambda d: d.update(floors="many"), "Expected `array`"),
])
def test_a_bad_building_file_says_what_is_wrong(tmp_path: Path, change, says: str) -> None:
    raw = yaml.safe_load(TOWER.read_text())
    for f in raw["floors"]:
        f["map"] = str(TOWER.parent / f["map"])
    change(raw)
    path = tmp_path / "b.yaml"
    path.write_text(yaml.safe_dump(raw))
    with pytest.raises(ConfigError, match=says):
        load_building(path)
    path.write_text("floors: [unclosed")
    with pytest.raises(ConfigError, match="b.yaml"):
        load_building(path)


def test_landing_doors_are_shut_unless_the_car_stands_open_there(tower: Floors) -> None:
    e = tower.building.elevator()
    w = tower.world
    door = e.door_pose(1)
    assert not w.body_free(door.x, door.y, R)  # no state heard yet: shut
    assert tower.on_state(car(1, door=0.5))
    assert not w.body_free(door.x, door.y, R)  # opening is not open
    assert tower.on_state(car(1, door=1.0))
    assert w.body_free(door.x, door.y, R)
    assert not tower.on_state(ElevatorState(name="lift9"))
    # a request's clear keeps the doors (the world's own obstacles)
    assert tower.on_state(car(1, position=1.2, door=0.0))  # the car left
    assert not w.body_free(door.x, door.y, R)
    assert apply_request(Simulation(world=w, drive=Drive(DriveLimits()), truth=Pose2(0, 0, 0)),
                         SetObstaclesRequest(op="clear")) == ""
    assert any(i.startswith(DOOR_PREFIX) for i in w.obstacles)


def test_a_ride_carries_the_robot_to_the_floor_the_car_stops_at(tower: Floors) -> None:
    e = tower.building.elevator()
    w = tower.world
    laser = Laser(w, LaserConfig(beams=360, range_max=30.0))
    before = laser.ranges(1.0, 5.0, 0.0).copy()  # in the first north office
    c1 = e.car_pose(1)
    inside = Pose2(c1.x + 0.1, c1.y - 0.2, math.pi / 2)  # in the car, facing its back wall
    tower.on_state(car(1, door=1.0))
    assert tower.ride(inside) is None  # aboard, at its own floor
    tower.on_state(car(1, position=1.5))
    assert tower.ride(inside) is None  # riding
    gen = w.generation
    tower.on_state(car(2, door=0.0))
    pose = tower.ride(inside)
    assert pose is not None and tower.level == 2 and w.generation == gen + 1
    assert math.isclose(pose.x, inside.x) and math.isclose(pose.y, inside.y)
    assert e.inside(2, pose.x, pose.y)
    floor2 = World(load_map(tower.building.floor(2).map))
    assert np.array_equal(w.solid, floor2.solid)
    assert not np.array_equal(laser.ranges(1.0, 5.0, 0.0), before)  # floor 2's furniture
    door2 = e.door_pose(2)
    assert not w.body_free(door2.x, door2.y, R)  # still opening
    tower.on_state(car(2, door=1.0))
    assert w.body_free(door2.x, door2.y, R)
    assert tower.ride(pose) is None  # aboard on floor 2 now: no second ride


def test_a_robot_outside_the_car_stays_on_its_floor(tower: Floors) -> None:
    e = tower.building.elevator()
    hall = e.hall_pose(1)
    tower.on_state(car(1, door=1.0))
    assert tower.ride(hall) is None
    tower.on_state(car(3))
    assert tower.ride(hall) is None and tower.level == 1
    tower.move_to(3)
    assert tower.level == 3
    with pytest.raises(LookupError):
        tower.move_to(4)


def test_another_robot_is_on_its_own_floor(tower: Floors) -> None:
    body = Obstacle("robot:/robot2", "circle", 5.0, 0.0, radius=0.2)
    tower.place_body(body.id, 2, body)
    assert tower.world.body_free(5.0, 0.0, R)  # on floor 2, not here
    tower.move_to(2)
    assert not tower.world.body_free(5.0, 0.0, R)
    tower.place_body(body.id, 1, body)  # it rode down
    assert tower.world.body_free(5.0, 0.0, R)
    tower.move_to(1)
    assert not tower.world.body_free(5.0, 0.0, R)
    tower.place_body(body.id, 1, None)  # gone
    assert tower.world.body_free(5.0, 0.0, R)
