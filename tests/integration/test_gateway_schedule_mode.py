"""Schedule mode end to end (docs/fleet.md, "Traffic schedule"): the robot API turns it on,
a goal through a door that another robot holds waits before the door (at the passing
place) until the door is free, then reaches; stopping the mode releases the robot's
reservations."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from sim_robot import GatewayRobot, gateway_robot
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs.traffic import ReleaseRouteRequest
from zenros.services.schedule.node import ScheduleServerNode
from zenros.services.schedule.traffic import RoutePoint
from zenros.testing import wait_for

pytestmark = pytest.mark.xdist_group("schedule_mode")

DOOR_X = 4.7  # the second north office's door (1 m wide) in the corridor's north wall


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[GatewayRobot, Any, list]]:
    tmp: Path = tmp_path_factory.mktemp("schedule_mode")
    with gateway_robot(tmp) as robot:
        server = ScheduleServerNode(context=robot.contexts[-1], parameter_overrides={
            "data_dir": str(tmp / "shelf")})
        truth: list[tuple[float, float]] = []
        robot.user.create_subscription(
            Odometry, "sim/ground_truth",
            lambda m: truth.append((m.pose.pose.position.x, m.pose.pose.position.y)))
        try:
            assert robot.gw.graph.wait_for_service("/schedule/local/request_route", 10)
            yield robot, server, truth
        finally:
            server.close()


def test_a_goal_through_a_held_door_waits_before_it_then_reaches(rig: Any) -> None:
    robot, server, truth = rig
    http = robot.http
    assert http.get("/system/schedule_manager").json()["schedule_mode"] is False
    r = http.get("/navigation/start_schedule_mode").json()
    assert r["result"] is True and "schedule server 'local'" in r["description"], r
    info = http.get("/system/schedule_manager").json()
    assert info["schedule_mode"] is True and info["id"] == "local", info
    # another robot is coming out of the office through the door, and holds it
    ghost = [RoutePoint(DOOR_X, 3.0 - k * 0.25, k * 0.5) for k in range(15)]
    g = server.traffic.table.request("ghost", ghost, server.now().nanoseconds * 1e-9, 30.0)
    assert g.granted and g.holds
    r = http.post("/navigation/start_nav_task", json={"x": DOOR_X, "y": 3.0, "theta": 1.57})
    assert r.status_code == 200, r.text

    def waiting() -> bool:
        st = http.get("/system/schedule_manager").json()
        return st["state"] == "waiting" and st["wait_for"] == "ghost"

    assert wait_for(waiting, 60)
    assert wait_for(lambda: bool(truth), 5)
    _, y = truth[-1]
    assert y < 1.25 - 0.3, truth[-1]  # in the corridor, out of the door's mouth
    server.traffic.release(ReleaseRouteRequest(robot="ghost"))
    assert wait_for(lambda: math.hypot(truth[-1][0] - DOOR_X, truth[-1][1] - 3.0) < 0.25, 90)
    r = http.get("/navigation/stop_schedule_mode").json()
    assert r["result"] is True, r
    assert http.get("/system/schedule_manager").json()["schedule_mode"] is False
    assert wait_for(lambda: server.traffic.table.robots == {}, 10)
