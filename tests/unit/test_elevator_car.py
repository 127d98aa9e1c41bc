"""The elevator car's state machine (services/elevator/car.py) driven with explicit times:
calls, doors, travel time, the light curtain, hold_s lapsing, a queue of two robots, lost
holders, riders, and the commands it refuses; the body table's lease on two clocks."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import msgspec
import pytest
from zenros.building import Elevator, Stop
from zenros.msgs.zenros_msgs.elevator import BuildingBody, ElevatorCommandRequest
from zenros.services.elevator.bodies import Body, BodyTable, body_of
from zenros.services.elevator.car import Car, CarError
from zenros.services.elevator.commands import execute

DT = 0.05
# Door faces -y: the door line is at y = 5 - 0.8 = 4.2, the hall point at y = 3.3.
SPEC = Elevator(name="lift1", levels=[1, 2, 3],
                stops={lv: Stop(10.0, 5.0, -math.pi / 2) for lv in (1, 2, 3)},
                travel_s=4.0, door_s=2.0, dwell_s=6.0, hold_s=30.0, capacity=1)
INSIDE = (10.0, 5.0)
DOORWAY = (10.0, 4.2)
HALL = (10.0, 3.3)


class Sim:
    """A car and a clock: ``run(seconds)`` steps it every DT with the bodies set, checking
    on every step that it never moves with doors that are not fully closed."""

    def __init__(self, spec: Elevator = SPEC) -> None:
        self.t = 0.0
        self.car = Car(spec, 0.0)
        self.bodies: list[Body] = []
        self.lost: dict[str, Body] = {}

    def run(self, seconds: float, bodies: Sequence[Body] | None = None,
            lost: Mapping[str, Body] | None = None) -> None:
        if bodies is not None:
            self.bodies = list(bodies)
        if lost is not None:
            self.lost = dict(lost)
        end = self.t + seconds
        while self.t < end - 1e-9:
            self.t = round(self.t + DT, 9)
            before = self.car.position
            self.car.step(self.t, self.bodies, self.lost)
            if self.car.position != before or self.car.moving:
                assert self.car.door == 0.0, (self.t, self.car.door)

    def until(self, pred: object, limit: float = 120.0) -> float:
        """Step until ``pred()`` holds; the time it took."""
        start = self.t
        assert callable(pred)
        while not pred():
            assert self.t - start < limit, f"not within {limit} s"
            self.run(DT)
        return self.t - start


def body(robot: str, level: int, at: tuple[float, float], radius: float = 0.25) -> Body:
    return Body(robot, level, at[0], at[1], radius)


def test_a_call_at_the_cars_floor_opens_it_for_the_robot() -> None:
    s = Sim()
    assert "called" in s.car.call("robot1", 1, s.t)
    s.run(DT)
    snap = s.car.snapshot()
    assert (snap.state, snap.holder, snap.level, snap.direction) == ("WAITING_IN", "robot1", 1,
                                                                     "STOP")
    s.run(1.0 - DT)
    assert s.car.door == pytest.approx(0.5, abs=0.03)
    assert not s.car.snapshot().front_door_open
    s.run(1.0)
    assert s.car.snapshot().front_door_open


def test_a_call_two_floors_up_takes_two_travel_times_then_opens() -> None:
    s = Sim()
    s.car.call("robot1", 3, s.t)
    s.run(DT)
    assert s.car.snapshot().calls == [3]
    s.run(3.0)  # 3.05 s: three quarters of a floor
    snap = s.car.snapshot()
    assert (snap.direction, snap.level, snap.door) == ("UP", 1, 0.0)
    assert snap.position == pytest.approx(1.75, abs=0.02)
    s.run(2.0)  # 5.05 s: past level 2
    assert s.car.level == 2
    s.until(lambda: s.car.state == "WAITING_IN")
    assert s.t == pytest.approx(2 * SPEC.travel_s, abs=2 * DT)
    snap = s.car.snapshot()
    assert (snap.level, snap.position, snap.direction, snap.calls) == (3, 3.0, "STOP", [])
    assert s.until(lambda: s.car.snapshot().front_door_open) == pytest.approx(2.0, abs=2 * DT)


def test_go_closes_rides_opens_and_release_frees_the_car() -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.run(2.5)
    rider = body("robot1", 1, INSIDE)
    s.run(0.5, [rider])
    assert s.car.riders == ["robot1"]
    assert "takes robot1 to level 2" in s.car.go("robot1", 2, s.t)
    assert s.car.snapshot().calls == [2]
    closing = s.until(lambda: s.car.moving)
    assert closing == pytest.approx(SPEC.door_s, abs=2 * DT)
    riding = s.until(lambda: s.car.state == "WAITING_OUT")
    assert riding == pytest.approx(SPEC.travel_s, abs=2 * DT)
    # the chassis has not moved the body to level 2 yet: still a rider (carried)
    s.run(DT)
    assert s.car.riders == ["robot1"]
    s.run(DT, [body("robot1", 2, INSIDE)])
    assert s.car.riders == ["robot1"]
    s.until(lambda: s.car.snapshot().front_door_open)
    s.run(1.0, [body("robot1", 2, HALL)])
    assert s.car.riders == []
    s.car.release("robot1", s.t)
    snap = s.car.snapshot()
    assert (snap.state, snap.holder, snap.queue) == ("NONE", "", [])
    assert s.until(lambda: s.car.door == 0.0) == pytest.approx(SPEC.door_s, abs=2 * DT)


def test_the_doors_never_close_on_a_body_in_the_doorway() -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.run(2.5)
    s.car.go("robot1", 2, s.t)
    s.run(1.0)  # half closed
    assert s.car.door == pytest.approx(0.5, abs=0.03)
    s.run(0.5, [body("robot2", 1, DOORWAY)])  # somebody steps in: the doors open again
    s.run(10.0)
    assert s.car.door == 1.0 and not s.car.moving and s.car.position == 1.0
    # a body on another floor's doorway does not count
    s.run(DT, [body("robot2", 2, DOORWAY)])
    assert not s.car.blocked
    s.until(lambda: s.car.moving)
    s.until(lambda: s.car.state == "WAITING_OUT")
    assert s.car.level == 2


def test_close_and_an_idle_car_wait_for_a_clear_doorway() -> None:
    s = Sim()
    s.car.open(s.t)
    s.run(3.0, [body("person", 1, DOORWAY)])
    assert "once the doorway is clear" in s.car.close(s.t)
    s.run(20.0)
    assert s.car.door == 1.0
    s.run(DT, [])
    assert s.until(lambda: s.car.door == 0.0) == pytest.approx(SPEC.door_s, abs=2 * DT)


def test_a_holder_that_does_nothing_loses_its_claim_after_hold_s() -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.car.call("robot2", 3, s.t)
    s.run(DT)
    assert s.car.holder == "robot1" and s.car.queue == ["robot2"]
    waited = s.until(lambda: s.car.holder != "robot1")
    assert waited == pytest.approx(SPEC.hold_s, abs=2 * DT)
    assert any("robot1's claim on lift1 lapsed" in e for e in s.car.events)
    snap = s.car.snapshot()
    assert (snap.holder, snap.queue, snap.calls) == ("robot2", [], [3])
    s.until(lambda: s.car.state == "WAITING_IN")
    assert s.car.level == 3


def test_two_robots_share_the_car_in_turn() -> None:
    s = Sim()
    s.car.call("robot1", 2, s.t)
    s.car.call("robot2", 1, s.t)
    assert s.car.snapshot().calls == [2, 1]
    s.until(lambda: s.car.state == "WAITING_IN")
    assert (s.car.level, s.car.holder) == (2, "robot1")
    s.until(lambda: s.car.snapshot().front_door_open)
    s.car.go("robot1", 3, s.t)
    s.until(lambda: s.car.state == "WAITING_OUT")
    assert s.car.level == 3 and s.car.queue == ["robot2"]
    s.car.release("robot1", s.t)
    s.until(lambda: s.car.state == "WAITING_IN")
    assert (s.car.level, s.car.holder, s.car.queue) == (1, "robot2", [])
    s.car.go("robot2", 2, s.t)
    s.until(lambda: s.car.state == "WAITING_OUT")
    s.car.release("robot2", s.t)
    assert s.car.snapshot().holder == ""


def test_a_queued_robot_gives_up_its_place() -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.car.call("robot2", 2, s.t)
    assert "left the queue" in s.car.release("robot2", s.t)
    assert s.car.queue == [] and s.car.holder == "robot1"


def test_a_lost_holder_outside_the_car_loses_its_claim_inside_it_keeps_it() -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.car.call("robot2", 1, s.t)
    s.run(1.0, lost={"robot1": body("robot1", 1, INSIDE)})
    assert s.car.holder == "robot1"
    s.run(DT, lost={"robot1": body("robot1", 1, HALL)})
    assert s.car.holder == "robot2"
    assert any("robot1 lost its claim" in e for e in s.car.events)


def test_release_while_riding_still_ends_the_ride_at_its_floor() -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.run(2.5)
    s.car.go("robot1", 3, s.t)
    s.until(lambda: s.car.moving)
    s.run(1.0)
    s.car.release("robot1", s.t)
    assert s.car.holder == "" and s.car.snapshot().calls == [3]
    s.until(lambda: not s.car.moving)
    assert s.car.position == 3.0
    assert s.until(lambda: s.car.door == 1.0) == pytest.approx(SPEC.door_s, abs=2 * DT)


def test_to_level_comes_opens_dwells_and_closes() -> None:
    s = Sim()
    assert "called to level 2" in s.car.to_level(2, s.t)
    assert "already called" in s.car.to_level(2, s.t)
    s.until(lambda: s.car.snapshot().front_door_open)
    assert s.car.state == "NONE" and s.car.level == 2
    open_for = s.until(lambda: s.car.door < 1.0)
    assert open_for == pytest.approx(SPEC.dwell_s, abs=2 * DT)
    s.until(lambda: s.car.door == 0.0)
    assert s.car.jobs == []


def test_open_holds_the_doors_dwell_s_and_is_refused_while_moving() -> None:
    s = Sim()
    s.car.open(s.t)
    s.until(lambda: s.car.door == 1.0)
    assert s.until(lambda: s.car.door < 1.0) == pytest.approx(SPEC.dwell_s, abs=2 * DT)
    s.car.to_level(3, s.t)
    s.until(lambda: s.car.moving)
    with pytest.raises(CarError, match="is moving"):
        s.car.open(s.t)


@pytest.mark.parametrize(("command", "robot", "level", "why"), [
    ("call", "robot1", 7, "does not serve level 7 (levels 1, 2, 3)"),
    ("to_level", "", 0, "does not serve level 0"),
    ("call", "", 2, "call needs a robot"),
    ("call", "robot1", 2, "already holds lift1"),
    ("call", "robot2", 2, "already queued"),
    ("go", "robot2", 2, "robot2 does not hold lift1 (holder: robot1)"),
    ("go", "robot1", 9, "does not serve level 9"),
    ("go", "", 2, "a robot with no name does not hold"),
    ("release", "robot3", 0, "robot3 neither holds nor waits for lift1"),
    ("close", "", 0, "held by robot1 (WAITING_IN)"),
])
def test_bad_commands_are_refused_with_a_reason(command: str, robot: str, level: int,
                                                why: str) -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.car.call("robot2", 2, s.t)
    s.run(DT)
    before = s.car.snapshot()
    req = msgspec.convert({"command": command, "robot": robot, "level": level},
                          ElevatorCommandRequest)
    res = execute(s.car, req, s.t)
    assert not res.success
    assert why in res.message
    assert s.car.snapshot() == before


def test_go_is_refused_while_riding_and_at_the_same_floor() -> None:
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.run(DT)
    with pytest.raises(CarError, match="already at level 1"):
        s.car.go("robot1", 1, s.t)
    s.car.go("robot1", 2, s.t)
    with pytest.raises(CarError, match="go is for a car waiting"):
        s.car.go("robot1", 3, s.t)


def test_a_call_is_refused_while_robots_without_a_claim_fill_the_car() -> None:
    s = Sim()
    s.run(DT, [body("stowaway", 1, INSIDE)])
    assert s.car.riders == ["stowaway"]
    with pytest.raises(CarError, match="lift1 is full: stowaway inside"):
        s.car.call("robot1", 2, s.t)
    s.run(DT, [body("stowaway", 1, HALL)])
    s.car.call("robot1", 2, s.t)


def test_the_body_table_loses_a_body_only_after_the_lease_on_both_clocks() -> None:
    table = BodyTable(lease=5.0, forget=20.0)
    b = body("robot1", 1, HALL)
    table.heard(b, sim=100.0, wall=1000.0)
    # 10x sim time: 50 sim s but only 5 wall s -> not yet lost
    assert table.live(150.0, 1004.9) == [b] and table.lost(150.0, 1004.9) == {}
    assert table.lost(150.0, 1005.1) == {"robot1": b} and table.live(150.0, 1005.1) == []
    # a stalled sim: sim time standing still never loses it
    assert table.lost(100.0, 2000.0) == {}
    # forgotten past `forget`
    assert table.lost(200.0, 1100.0) == {}
    assert table.live(100.0, 1000.0) == []


def test_malformed_bodies_are_not_bodies() -> None:
    assert body_of(BuildingBody(robot="", level=1)) is None
    assert body_of(BuildingBody(robot="r", x=math.nan)) is None
    assert body_of(BuildingBody(robot="r", radius=-1.0)) is None
    assert body_of(BuildingBody(robot="r", level=2, x=1.0, y=2.0, radius=0.3)) == Body(
        "r", 2, 1.0, 2.0, 0.3)


def test_a_robot_aboard_without_a_claim_keeps_the_car_open_at_its_floor() -> None:
    """A robot paused in the car, or one that released it still inside, is never carried
    off to another floor: the car stands open until it is out, then serves its calls."""
    s = Sim()
    s.car.call("robot1", 1, s.t)
    s.run(2.5, [body("robot1", 1, INSIDE)])
    s.car.call("robot2", 3, s.t)
    s.car.release("robot1", s.t)  # paused inside: robot2's call waits
    s.run(15.0)
    assert (s.car.position, s.car.door, s.car.moving) == (1.0, 1.0, False)
    assert "called to level 2" in s.car.to_level(2, s.t)  # a person's call waits as well
    s.run(10.0)
    assert (s.car.position, s.car.door) == (1.0, 1.0)
    s.run(DT, [body("robot1", 1, HALL)])  # out
    s.until(lambda: s.car.state == "WAITING_IN" and s.car.level == 3)
    assert s.car.holder == "robot2"
