"""navigate_across: legs, map switches and relocalisation along a route, on a Robot double."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
from zenros.building import load_building
from zenros.maps.maproute import Link, PointEnd
from zenros.msgs.zenros_msgs import ElevatorState
from zenros.msgs.zenros_msgs.task_actions import NavAction
from zenros.services.tasks.crossmap import carry_over, navigate_across
from zenros.services.tasks.robot import Outcome

TOWER = Path(__file__).parents[3] / "deploy" / "buildings" / "tower" / "tower.yaml"
POINTS = {("a", "p", 0): (1.0, 0.0, 0.0), ("b", "p", 0): (5.0, 5.0, math.pi / 2),
          ("b", "p", 1): (6.0, 5.0, 0.0), ("c", "p", 0): (0.0, 0.0, 0.0),
          ("c", "p", 2): (2.0, 1.0, 0.5)}


class MapRobot:
    """Maps a..c, every call recorded in ``log``."""

    def __init__(self, links: list[Link]) -> None:
        self.links = links
        self.map = "a"
        self.log: list[Any] = []
        self.here: tuple[float, float, float] | None = None

    def now(self) -> float:
        return 0.0

    def nav_point(self, index: int, map_name: str, path_name: str) -> tuple[float, ...]:
        try:
            return POINTS[(map_name, path_name, index)]
        except KeyError:
            raise LookupError(f"no nav point {index} on {map_name}/{path_name}") from None

    def point_connections(self) -> list[Link]:
        return self.links

    def pose(self) -> tuple[float, float, float] | None:
        return self.here

    def switch_map(self, name: str, path: str, start_index: int) -> Outcome:
        self.log.append(("switch", name))
        self.map = name
        return Outcome("complete")

    def relocalise(self, x: float, y: float, theta: float) -> Outcome:
        self.log.append(("relocalise", round(x, 3), round(y, 3), round(theta, 3)))
        return Outcome("complete")

    def relocalise_landmarks(self) -> Outcome:
        self.log.append(("landmarks",))
        return Outcome("complete", "relocalised on 3 reflector(s)")


def leg_of(robot: MapRobot) -> Any:
    def leg(p: NavAction) -> Outcome:
        robot.log.append(("nav", robot.map, p.index if isinstance(p.index, int) else (p.x, p.y)))
        if isinstance(p.x, float) and isinstance(p.y, float):
            # it stops 0.1 m past the point, along the point's heading
            th = p.theta
            robot.here = (p.x + 0.1 * math.cos(th), p.y + 0.1 * math.sin(th), th)
        return Outcome("complete", "arrived")
    return leg


def link(ident: str, a: tuple[str, int], b: tuple[str, int], kind: str = "direct") -> Link:
    return Link(ident, kind, True, PointEnd(a[0], "p", a[1]), PointEnd(b[0], "p", b[1]))


def test_two_hops_then_the_goal() -> None:
    robot = MapRobot([link("1", ("a", 0), ("b", 0)), link("2", ("b", 1), ("c", 0))])
    notes: list[str] = []
    out = navigate_across(robot, NavAction(map="c", path="p", index=2), "a",
                          leg_of(robot), notes.append)
    assert out == Outcome("complete", "arrived")
    assert robot.log == [
        ("nav", "a", (1.0, 0.0)), ("switch", "b"), ("relocalise", 5.0, 5.1, 1.571),
        ("nav", "b", (6.0, 5.0)), ("switch", "c"), ("relocalise", 0.1, 0.0, 0.0),
        ("nav", "c", 2)]
    assert notes[-1].startswith("on map c via direct connection 2")


def test_an_elevator_or_no_route_fails_before_moving() -> None:
    robot = MapRobot([link("lift", ("a", 0), ("b", 0), "elevator")])
    out = navigate_across(robot, NavAction(map="b", x=1.0, y=1.0), "a",
                          leg_of(robot), print)
    assert out.name == "error" and "elevator connection lift" in out.reason
    assert "knows no building" in out.reason and robot.log == []
    out = navigate_across(robot, NavAction(map="c", x=1.0, y=1.0), "a",
                          leg_of(robot), print)
    assert out.name == "error" and "no route from map 'a' to map 'c'" in out.reason


def test_a_missing_goal_point_fails_before_moving() -> None:
    robot = MapRobot([link("1", ("a", 0), ("b", 0))])
    out = navigate_across(robot, NavAction(map="b", path="p", index=9), "a",
                          leg_of(robot), print)
    assert out.name == "error" and "no nav point 9" in out.reason and robot.log == []


@pytest.mark.parametrize(("robot", "expected"), [
    (None, (5.0, 5.0, math.pi / 2)),
    ((1.0, 0.0, 0.0), (5.0, 5.0, math.pi / 2)),
    ((1.2, 0.1, 0.1), (4.9, 5.2, math.pi / 2 + 0.1)),
])
def test_carry_over_keeps_the_offset(robot: Any, expected: tuple[float, ...]) -> None:
    got = carry_over((1.0, 0.0, 0.0), (5.0, 5.0, math.pi / 2), robot)
    assert got == pytest.approx(expected)


def test_a_pause_preempts_and_a_resume_starts_from_the_map_it_is_on() -> None:
    robot = MapRobot([link("1", ("a", 0), ("b", 0)), link("2", ("b", 1), ("c", 0))])
    calls: list[str] = []

    def paused_on_b(p: NavAction) -> Outcome:
        calls.append(robot.map)
        return Outcome("preempted") if robot.map == "b" else Outcome("complete")

    out = navigate_across(robot, NavAction(map="c", x=1.0, y=1.0), "a",
                          paused_on_b, print)
    assert out.name == "preempted" and "direct connection 2" in out.reason
    assert calls == ["a", "b"] and robot.map == "b"
    robot.log.clear()
    out = navigate_across(robot, NavAction(map="c", x=1.0, y=1.0), "b",
                          leg_of(robot), print)
    assert out.name == "complete"
    assert [e[0] for e in robot.log] == ["nav", "switch", "relocalise", "nav"]


class FakeLift:
    """The demo tower's elevator as `ElevatorLink` shows it: the car answers at once."""

    def __init__(self) -> None:
        self.building = load_building(TOWER)
        self.me = "/"
        self.log: list[Any] = []
        self.refuse = ""
        self.held: ElevatorState | None = None  # the car's state (None: not heard)

    def state(self, name: str) -> ElevatorState | None:
        return self.held

    def command(self, name: str, command: str, level: int = 0) -> Outcome:
        self.log.append((command, level))
        if command == self.refuse:
            return Outcome("error", f"elevator {name}: {command}: refused")
        return Outcome("complete")

    def wait(self, name: str, until: Any, what: str, deadline: Any, cancelled: Any) -> Outcome:
        self.log.append(("wait", what))
        return Outcome("preempted", "cancelled") if cancelled() else Outcome("complete")


def tower_robot() -> MapRobot:
    b = load_building(TOWER)
    e = b.elevator()
    for lv in (1, 3):
        h = e.hall_pose(lv)
        POINTS[(f"floor{lv}", "elevator_lift1", 0)] = (h.x, h.y, h.theta)
    POINTS[("floor3", "p", 0)] = (2.0, 1.0, 0.0)
    robot = MapRobot([Link("l13", "elevator", True, PointEnd("floor1", "elevator_lift1", 0),
                           PointEnd("floor3", "elevator_lift1", 0))])
    robot.map = "floor1"
    return robot


def test_a_goal_two_floors_up_rides_the_elevator() -> None:
    robot, lift = tower_robot(), FakeLift()
    notes: list[str] = []
    out = navigate_across(robot, NavAction(map="floor3", path="p", index=0), "floor1",
                          leg_of(robot), notes.append, lift)  # type: ignore[arg-type]
    assert out == Outcome("complete", "arrived")
    car = lift.building.elevator().car_pose(1)
    assert [entry[0] for entry in robot.log] == ["nav", "nav", "switch", "relocalise", "nav",
                                                 "landmarks", "nav"]
    assert robot.log[1] == ("nav", "floor1", (car.x, car.y))  # into the car
    assert robot.log[2] == ("switch", "floor3")
    # relocalised where it stood in the car (0.1 m past the car's centre): the tower's car
    # has the same stop on every floor
    c, s = math.cos(car.theta), math.sin(car.theta)
    assert robot.log[3] == ("relocalise", round(car.x + 0.1 * c, 3),
                            round(car.y + 0.1 * s, 3), round(car.theta, 3))
    assert [c for c in lift.log if c[0] != "wait"] == [("call", 1), ("go", 3), ("release", 0)]
    assert any("riding elevator lift1 to level 3" in n for n in notes)
    assert notes[-1].startswith("on map floor3 via elevator connection l13")


def test_a_car_already_called_here_is_not_called_again() -> None:
    """An ``elevator_req_action`` before the goal left the car open here for this robot."""
    robot, lift = tower_robot(), FakeLift()
    lift.held = ElevatorState(name="lift1", holder="/", state="WAITING_IN", level=1,
                              position=1.0, door=1.0)
    out = navigate_across(robot, NavAction(map="floor3", path="p", index=0), "floor1",
                          leg_of(robot), print, lift)  # type: ignore[arg-type]
    assert out == Outcome("complete", "arrived")
    assert [c for c in lift.log if c[0] != "wait"] == [("go", 3), ("release", 0)]


def test_a_refused_or_cancelled_ride_releases_the_car() -> None:
    robot, lift = tower_robot(), FakeLift()
    lift.refuse = "go"
    out = navigate_across(robot, NavAction(map="floor3", path="p", index=0), "floor1",
                          leg_of(robot), print, lift)  # type: ignore[arg-type]
    assert out.name == "error" and "go: refused" in out.reason
    assert lift.log[-1] == ("release", 0)
    robot, lift = tower_robot(), FakeLift()
    out = navigate_across(robot, NavAction(map="floor3", path="p", index=0), "floor1",
                          leg_of(robot), print, lift, lambda: True)  # type: ignore[arg-type]
    assert out.name == "preempted" and lift.log[-1] == ("release", 0)
    assert ("go", 3) not in lift.log


def test_a_cancel_during_the_ride_still_puts_nav_on_the_floor_the_car_reaches() -> None:
    robot, lift = tower_robot(), FakeLift()
    out = navigate_across(robot, NavAction(map="floor3", path="p", index=0), "floor1",
                          leg_of(robot), print, lift,  # type: ignore[arg-type]
                          lambda: ("go", 3) in lift.log)
    assert out.name == "preempted" and "in elevator lift1 at level 3, on map floor3" in \
        out.reason
    assert ("switch", "floor3") in robot.log and robot.log[-1][0] == "relocalise"
    assert lift.log[-1] == ("release", 0)
