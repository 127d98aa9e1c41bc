"""Simulated people: routes as the parameter writes them, walking back and forth and round,
the legs' gait, waiting for the robot, the device's service and the UWB anchor's noise."""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np
import pytest
from zenros.msgs.geometry_msgs import Point
from zenros.msgs.zenros_msgs import PersonRoute, SetPeopleRequest
from zenros.params import Parameters
from zenros.se2 import Pose2
from zenros.services.chassis.camera import PERSON, Camera, CameraConfig
from zenros.services.chassis.config import declare_chassis
from zenros.services.chassis.devices import PeopleDevice, UwbDevice
from zenros.services.chassis.devices.uwb import uwb_reading
from zenros.services.chassis.laser import Laser, LaserConfig
from zenros.services.chassis.people import (
    CLEARANCE,
    HIP,
    LEG_RADIUS,
    MAX_ASIDE,
    Route,
    RouteError,
    Walker,
    blocked_by,
    parse_route,
)
from zenros.services.chassis.world import World


def never(*_: float) -> bool:
    return False


def test_a_route_is_parsed_and_bad_ones_say_why() -> None:
    r = parse_route("alice=1,0;4,0.5 speed=0.8 loop uwb")
    assert r == Route("alice", ((1.0, 0.0), (4.0, 0.5)), 0.8, True, True)
    assert parse_route("bob=2,2") == Route("bob", ((2.0, 2.0),))
    for bad, why in (("alice", "expected id=x,y"), ("a=1;2", "x,y pairs"),
                     ("a=1,0 fly", "unknown word"), ("a=1,0 speed=9", "speed must be"),
                     ("=1,0", "person id"), ("a=", "1 to 100 waypoints"),
                     ("a=" + ";".join(["1,1"] * 101), "got 101")):
        with pytest.raises(RouteError, match=why):
            parse_route(bad)


def test_a_person_walks_back_and_forth_at_their_speed() -> None:
    w = Walker(Route("p", ((0.0, 0.0), (2.0, 0.0)), speed=1.0))
    xs = []
    for i in range(400):  # 4 s at 100 Hz: there and back
        w.step(0.01, never)
        xs.append(w.x)
        if i == 300:
            assert w.theta == pytest.approx(math.pi)  # on the way back
    assert max(xs) == pytest.approx(2.0, abs=0.011)
    assert xs[-1] == pytest.approx(0.0, abs=0.011)
    assert w.walked == pytest.approx(4.0, abs=0.02)


def test_a_looping_person_goes_round() -> None:
    w = Walker(Route("p", ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0)), speed=0.5, loop=True))
    seen = set()
    for _ in range(int((2 + math.sqrt(2)) / 0.5 / 0.01)):
        w.step(0.01, never)
        seen.add((round(w.x, 1), round(w.y, 1)))
    assert (1.0, 0.5) in seen and (0.5, 0.5) in seen  # up the side, back along the diagonal
    assert math.hypot(w.x, w.y) < 0.02


def test_the_legs_swing_with_the_gait_and_stand_side_by_side_at_rest() -> None:
    w = Walker(Route("p", ((0.0, 0.0), (5.0, 0.0))))
    left, right = w.legs()
    assert left.id == "person:p:l" and right.id == "person:p:r"
    assert (left.x, left.y, right.y) == pytest.approx((0.0, HIP, -HIP))
    assert left.radius == LEG_RADIUS
    spreads = []
    for _ in range(100):
        w.step(0.01, never)
        a, b = w.legs()
        spreads.append(a.x - b.x)
    assert max(spreads) > 0.25 and min(spreads) < -0.25  # a stride each way


def test_a_person_waits_for_the_robot_in_their_way_and_walks_away_from_it() -> None:
    w = Walker(Route("p", ((0.0, 0.0), (3.0, 0.0)), speed=1.0))
    robot = blocked_by(1.0, 0.0, 0.2)
    for _ in range(100):
        w.step(0.01, robot)
    assert w.waiting and w.speed == 0.0 and 0.45 < w.x < 0.5 + 1e-9
    w.step(0.01, blocked_by(5.0, 0.0, 0.2))  # the robot moved off
    assert not w.waiting and w.x > 0.5
    behind = Walker(Route("q", ((0.5, 0.0), (3.0, 0.0))))
    behind.step(0.1, blocked_by(0.3, 0.0, 0.2))  # close behind: walking away is free
    assert not behind.waiting and behind.x == pytest.approx(0.6)


def build(values: dict[str, object]) -> tuple[Any, Any]:
    from test_chassis_devices import StandInNode  # the devices' stand-in node
    chassis = declare_chassis(Parameters("/chassis", {"camera_rate": 0.0, **values})).build(
        logging.getLogger("test"))
    node = StandInNode()
    for d in chassis.devices:
        d.open(node)
    return chassis, node


def route(pid: str, *xy: tuple[float, float], uwb: bool = False) -> PersonRoute:
    return PersonRoute(id=pid, waypoints=[Point(x=x, y=y) for x, y in xy], speed=0.5, uwb=uwb)


def test_the_device_puts_legs_in_the_world_and_the_laser_sees_them() -> None:
    chassis, node = build({"people": ["alice=2,0;5,0 speed=0.5"]})
    people = chassis.device(PeopleDevice)
    assert set(people.walkers) == {"alice"}
    assert {"person:alice:l", "person:alice:r"} <= set(chassis.sim.world.obstacles)
    for _ in range(50):
        chassis.step(0.02)
    assert people.walkers["alice"].x == pytest.approx(2.5, abs=0.01)
    left = chassis.sim.world.obstacles["person:alice:l"]
    assert left.x == pytest.approx(2.5, abs=0.2)
    people.publish(node.stamp())
    [msg] = node.publishers["sim/people"].sent
    assert msg.people[0].id == "alice" and msg.people[0].speed == 0.5


def test_set_people_adds_replaces_removes_and_refuses_with_the_reason() -> None:
    chassis, node = build({})
    handle = node.services["sim/set_people"]
    assert "sim/people" not in node.publishers  # nobody yet: nothing declared
    res = handle(SetPeopleRequest(people=[route("a", (2, 0), (4, 0)),
                                          route("b", (3, 0), uwb=True)]))
    assert res.success and [p.id for p in res.people] == ["a", "b"]
    res = handle(SetPeopleRequest(people=[route("c", (5, 0), uwb=True)]))
    assert not res.success and "only one person can carry the UWB tag" in res.message
    res = handle(SetPeopleRequest(people=[route("c", (0.1, 0))]))
    assert not res.success and "cannot start on the robot" in res.message
    res = handle(SetPeopleRequest(people=[route("c", (1, 0), (math.nan, 0))]))
    assert not res.success and "finite" in res.message
    crowd = [route(f"p{i}", (5, 0)) for i in range(51)]
    res = handle(SetPeopleRequest(op="replace", people=crowd))
    assert not res.success and "at most 50 people" in res.message
    res = handle(SetPeopleRequest(op="remove", ids=["zed"]))
    assert not res.success and "unknown people ['zed']; known: a, b" in res.message
    res = handle(SetPeopleRequest(op="remove", ids=["a"]))
    assert res.success and [p.id for p in res.people] == ["b"]
    assert "person:a:l" not in chassis.sim.world.obstacles
    res = handle(SetPeopleRequest(op="replace", people=[route("d", (3, 0))]))
    assert [p.id for p in res.people] == ["d"] and "person:b:l" not in chassis.sim.world.obstacles
    assert handle(SetPeopleRequest(op="clear")).people == []
    assert not any(i.startswith("person:") for i in chassis.sim.world.obstacles)


def test_a_bad_people_parameter_is_refused_at_start() -> None:
    with pytest.raises(ValueError, match="parameter 'people': only one person can carry"):
        build({"people": ["a=1,0 uwb", "b=2,0 uwb"]})


def test_the_uwb_reading_is_range_and_bearing_with_the_noise_asked() -> None:
    rng = np.random.default_rng(3)
    robot = Pose2(1.0, 1.0, math.pi / 2)
    assert uwb_reading(robot, 1.0, 3.0, rng, 0.0, 0.0) == pytest.approx((2.0, 0.0))
    reads = np.array([uwb_reading(robot, 0.0, 1.0, rng, 0.05, 0.02) for _ in range(4000)])
    assert reads[:, 0].mean() == pytest.approx(1.0, abs=0.005)
    assert reads[:, 0].std() == pytest.approx(0.05, rel=0.1)
    assert reads[:, 1].mean() == pytest.approx(math.pi / 2, abs=0.002)
    assert reads[:, 1].std() == pytest.approx(0.02, rel=0.1)


def test_the_uwb_device_reads_only_while_someone_carries_the_tag() -> None:
    chassis, node = build({"uwb_range_noise": 0.0, "uwb_bearing_noise": 0.0})
    uwb = chassis.device(UwbDevice)
    uwb.publish(node.stamp())
    assert uwb.reading() is None and "uwb/target" not in node.publishers
    node.services["sim/set_people"](SetPeopleRequest(people=[route("t", (0, 2), uwb=True)]))
    uwb.publish(node.stamp())
    [msg] = node.publishers["uwb/target"].sent
    assert (msg.range, msg.bearing) == pytest.approx((2.0, math.pi / 2), abs=1e-4)


def test_the_cameras_draw_people_taller_than_obstacles_in_their_colour(room: World) -> None:
    w = Walker(Route("p", ((2.0, 1.5),)))
    cam = Camera(room, CameraConfig(width=64, height=48), Laser(room, LaserConfig()))
    cols = cam.cast(0.5, 1.5, 0.0, w.legs())
    assert PERSON in cols.kind and cols.height[cols.kind == PERSON].max() == 1.7


def test_a_person_steps_aside_for_the_robot_and_back_onto_their_route() -> None:
    w = Walker(Route("p", ((0.0, 0.0), (3.0, 0.0)), speed=1.0))
    robot = blocked_by(1.0, 0.1, 0.2)  # a little left of their line: they step right

    def walk(seconds: float, blocked: object, room: bool = True) -> None:
        for _ in range(round(seconds / 0.01)):
            w.step(0.01, blocked, (1.0, 0.1), lambda x, y: room)  # type: ignore[arg-type]

    walk(1.5, robot, room=False)  # no room either side: they wait
    assert w.waiting and w.offset == 0.0
    walk(1.0, robot)
    assert not w.waiting and -MAX_ASIDE <= w.offset < -0.4  # stepped right and walked on
    assert math.hypot(w.x - 1.0, w.y - 0.1) >= 0.2 + CLEARANCE - 1e-9
    walk(4.0, blocked_by(5.0, 5.0, 0.2))  # the robot gone: back onto the route
    assert w.offset == pytest.approx(0.0) and w.y == pytest.approx(0.0)
