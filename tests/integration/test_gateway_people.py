"""People in the simulated world through REST (docs/robot-api.md §3.5): a person walks a route
(``sim/set_people``), ``PUT /system/tracking_mode`` makes the robot follow them on the laser's
leg detector at about 1 m, ``PUT /system/uwb_track`` on their UWB tag; ``PUT /system/greeting``
speaks once when a person comes near; nav's costmap has a person standing in its way, and a
goal past them is reached round them. Distances are measured on the simulation's ground
truth (the robot's body and the person's), never on what the robot believes."""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterator

import httpx
import pytest
from sim_robot import GatewayRobot, gateway_robot
from zenros.msgs.geometry_msgs import Point, Pose2D
from zenros.msgs.std_msgs import String
from zenros.msgs.zenros_msgs import (
    PersonRoute,
    SetPeople,
    SetPeopleRequest,
    Teleport,
    TeleportRequest,
)
from zenros.se2 import Pose2
from zenros.services.chassis.devices import PeopleDevice
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for

SPEED = 5.0  # the chassis's real-time factor
pytestmark = pytest.mark.timeout(300)  # a walk of 15 sim s: a minute of a loaded 2-core box


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[GatewayRobot]:
    with gateway_robot(tmp_path_factory.mktemp("people"), chassis={
            "speed": SPEED, "camera_rate": 0.0, "range_noise": 0.01}) as robot:
        yield robot


def set_people(rig: GatewayRobot, *routes: PersonRoute) -> None:
    client = rig.user.create_client(SetPeople, "sim/set_people")
    res = client.call(SetPeopleRequest(op="replace", people=list(routes)), 10)
    assert res.success, res.message


def reset(rig: GatewayRobot) -> None:
    """Nobody in the world, following and greeting off, the robot at the origin."""
    for path, body in (("/system/tracking_mode", {"enable": False}),
                       ("/system/uwb_track", {"enable": False}),
                       ("/system/greeting", {"greeting": False})):
        assert rig.http.put(path, json=body).status_code == 200
    set_people(rig)
    client = rig.user.create_client(Teleport, "sim/teleport")
    assert client.call(TeleportRequest(pose=Pose2D(x=0.0, y=0.0, theta=0.0)), 10).success


def walker(pid: str, *xy: tuple[float, float], speed: float = 0.3,
           uwb: bool = False) -> PersonRoute:
    return PersonRoute(id=pid, waypoints=[Point(x=x, y=y) for x, y in xy], speed=speed,
                       uwb=uwb)


def gap(rig: GatewayRobot, pid: str) -> float:
    """Ground truth: from the robot's centre to the person's (m)."""
    people = rig.chassis.device(PeopleDevice)
    assert people is not None
    w, t = people.walkers[pid], rig.chassis.sim.truth
    return math.hypot(w.x - t.x, w.y - t.y)


def follow_along_the_corridor(rig: GatewayRobot, pid: str) -> list[float]:
    """The gaps seen while the person walks from x = 2.5 to 5.5 (the robot following)."""
    people = rig.chassis.device(PeopleDevice)
    assert people is not None
    w = people.walkers[pid]
    assert wait_for(lambda: w.x > 2.5, 120), "the person never walked"
    gaps: list[float] = []

    def walked() -> bool:
        gaps.append(gap(rig, pid))
        return w.x > 5.5

    assert wait_for(walked, 180, interval=0.02), f"the person stopped at x={w.x:.2f}"
    return gaps


def test_without_nav_the_rows_are_503(gw: GatewayNode, http: httpx.Client) -> None:
    for method, path, body in (("GET", "/system/tracking_mode", None),
                               ("PUT", "/system/uwb_track", {"enable": True}),
                               ("PUT", "/system/greeting", {"greeting": True})):
        r = http.request(method, path, json=body)
        assert r.status_code == 503 and "follow/set is not in the graph" in r.json()[
            "description"], r.text


def test_bad_bodies_are_400(rig: GatewayRobot) -> None:
    for path, body in (("/system/tracking_mode", {"enable": "yes"}),
                       ("/system/uwb_track", {}),
                       ("/system/greeting", {"greeting": True, "text": ""}),
                       ("/system/tracking_mode", {"enable": True, "speed": 2})):
        r = rig.http.put(path, json=body)
        assert r.status_code == 400, (path, body, r.text)


def test_greeting_speaks_once_when_a_person_comes_near(rig: GatewayRobot) -> None:
    reset(rig)
    said: list[String] = []
    rig.user.create_subscription(String, "tts", said.append)
    r = rig.http.put("/system/greeting", json={"greeting": True, "text": "Hello there!"})
    assert r.status_code == 200 and r.json() == {"greeting": True, "text": "Hello there!"}
    n = len(said)  # the latched tts may bring an earlier text
    set_people(rig, walker("guest", (4.0, 0.0), (0.6, 0.0), speed=0.5))  # up to the robot
    people = rig.chassis.device(PeopleDevice)
    assert people is not None
    assert wait_for(lambda: any(m.data == "Hello there!" for m in said[n:]), 120), \
        f"no greeting; the guest is {gap(rig, 'guest'):.2f} m away"
    assert gap(rig, "guest") < 1.9  # greeted as they came near, not before
    assert wait_for(lambda: gap(rig, "guest") < 1.0, 60)
    w = people.walkers["guest"]
    set_people(rig, walker("guest", (w.x, w.y)))  # then stands by the robot
    stamp = rig.chassis.sim.time
    assert wait_for(lambda: rig.chassis.sim.time > stamp + 5.0, 60)  # 5 s standing there
    assert [m.data for m in said[n:]] == ["Hello there!"]  # once per approach
    assert rig.http.put("/system/greeting", json={"greeting": False}).json()["greeting"] is False


def test_tracking_mode_follows_the_nearest_person_at_about_a_metre(rig: GatewayRobot) -> None:
    reset(rig)
    r = rig.http.get("/system/tracking_mode")
    assert r.status_code == 200 and r.json()["tracking_flag"] is False, r.text
    set_people(rig, walker("alice", (1.6, 0.0), (6.5, 0.0)))
    r = rig.http.put("/system/tracking_mode", json={"enable": True})
    assert r.status_code == 200 and r.json()["tracking_flag"] is True, r.text
    gaps = follow_along_the_corridor(rig, "alice")
    assert rig.chassis.sim.truth.x > 3.5  # the robot came along
    steady = gaps[len(gaps) // 3:]
    mean = statistics.fmean(steady)
    print(f"tracking: gap mean {mean:.3f} m, min {min(steady):.3f}, max {max(steady):.3f}")
    assert 0.8 < mean < 1.4 and min(steady) > 0.6 and max(steady) < 2.0
    status = rig.http.get("/system/tracking_mode").json()
    assert status["tracking_flag"] is True and status["state"] in ("following", "lost")
    r = rig.http.put("/system/uwb_track", json={"enable": True})  # one mode at a time
    assert r.status_code == 200 and r.json()["enable"] is True
    assert rig.http.get("/system/tracking_mode").json()["tracking_flag"] is False
    r = rig.http.put("/system/uwb_track", json={"enable": False})
    assert r.json()["enable"] is False


def test_uwb_track_follows_the_tagged_person(rig: GatewayRobot) -> None:
    reset(rig)
    set_people(rig, walker("bob", (1.6, 0.0), (6.5, 0.0), uwb=True))
    r = rig.http.put("/system/uwb_track", json={"enable": True})
    assert r.status_code == 200 and r.json()["enable"] is True, r.text
    gaps = follow_along_the_corridor(rig, "bob")
    steady = gaps[len(gaps) // 3:]
    mean = statistics.fmean(steady)
    print(f"uwb: gap mean {mean:.3f} m, min {min(steady):.3f}, max {max(steady):.3f}")
    assert 0.8 < mean < 1.4 and min(steady) > 0.6 and max(steady) < 2.0
    status = rig.http.get("/system/uwb_track").json()
    assert status["enable"] is True and status["distance"] > 0, status
    assert rig.http.put("/system/uwb_track", json={"enable": False}).json()["enable"] is False


def test_following_is_refused_while_a_goal_runs(rig: GatewayRobot) -> None:
    reset(rig)
    goal = rig.nav.core.make_nav(Pose2(6.0, 0.0, 0.0))
    rig.nav.core.start(goal)  # as a navigation goal does
    try:
        r = rig.http.put("/system/tracking_mode", json={"enable": True})
        assert r.status_code == 409 and "cancel it before following" in r.json()[
            "description"], r.text
        assert rig.nav.core.motion.active is goal
    finally:
        rig.nav.core.motion.halt(goal)


def test_nav_s_costmap_has_a_person_standing_in_the_corridor(rig: GatewayRobot) -> None:
    reset(rig)
    costs = rig.nav.core.costmaps
    assert costs.cost_at(2.0, 0.1) < 253  # free before anyone stands there
    set_people(rig, walker("carl", (2.0, 0.0)))  # one waypoint: standing
    assert wait_for(lambda: costs.cost_at(2.0, 0.1) >= 253, 60), costs.cost_at(2.0, 0.1)
    set_people(rig)


def drive_past(rig: GatewayRobot, pid: str, goal_x: float) -> tuple[float, bool]:
    """Send a REST goal at (goal_x, 0) and wait for the robot there; how close (ground truth,
    centre to centre) it came to person ``pid`` and whether it ever touched anything."""
    r = rig.http.post("/navigation/start_nav_task", json={"x": goal_x, "y": 0.0, "theta": 0.0})
    assert r.status_code == 200, r.text
    closest, bumped = math.inf, False

    def arrived() -> bool:
        nonlocal closest, bumped
        closest = min(closest, gap(rig, pid))
        bumped = bumped or rig.chassis.sim.bumper
        t = rig.chassis.sim.truth
        return math.hypot(t.x - goal_x, t.y) < 0.3 and not rig.nav.core.motion.active
    assert wait_for(arrived, 180, interval=0.05), (rig.chassis.sim.truth, closest)
    return closest, bumped


def test_a_goal_past_a_person_drives_round_them(rig: GatewayRobot) -> None:
    """A person stands in the corridor between the robot and its goal: nav's costmaps mark
    their legs and the robot passes round them (ground truth: never closer than its body and
    their legs, no contact) and reaches the goal."""
    reset(rig)
    set_people(rig, walker("dana", (2.0, 0.0)))  # one waypoint: standing, mid-corridor
    costs = rig.nav.core.costmaps
    assert wait_for(lambda: costs.cost_at(2.0, 0.1) >= 253, 60), costs.cost_at(2.0, 0.1)  # a leg
    closest, bumped = drive_past(rig, "dana", 4.5)
    print(f"passed a standing person at {closest:.2f} m (centre to centre)")
    assert closest > 0.45 and not bumped, (closest, bumped)
    set_people(rig)


def test_a_goal_past_a_person_walking_towards_the_robot(rig: GatewayRobot) -> None:
    """A person walks down the corridor towards the robot while it drives to a goal behind
    them: they step aside, the robot passes them (ground truth: clear of their legs, which
    touch its 0.2 m body at 0.36 m centre to centre; no contact) and reaches the goal."""
    reset(rig)
    set_people(rig, walker("eve", (4.5, 0.0), (-1.0, 0.0), speed=0.3))
    closest, bumped = drive_past(rig, "eve", 5.0)
    print(f"passed a walking person at {closest:.2f} m (centre to centre)")
    assert closest > 0.4 and not bumped, (closest, bumped)
    set_people(rig)
