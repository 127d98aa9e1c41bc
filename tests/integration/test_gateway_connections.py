"""Point connections (docs/robot-api.md §6.7) through the gateway's REST API, and a robot (chassis
at 10x, nav, tasks) that drives to a nav point on a second map through a direct connection.

The second map ``office2`` is the demo office saved under another name, so a direct
connection joins two points at the same physical spot.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from typing import Any

import httpx
import pytest
from sim_robot import GatewayRobot, gateway_robot
from zenros.msgs.geometry_msgs import Pose2D
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs import Teleport, TeleportRequest
from zenros.services.nav.params import DEMO_MAP
from zenros.testing import wait_for

OFFICE = "2 0 0 0 0.1 0.1 0 a\n4 0 0 0 0.1 0.1 0 door\n"
OFFICE2 = "4 0 0 0 0.1 0.1 0 door\n2 1.5 0 1.57 0.1 0.1 0 desk\n"


class Rig:
    def __init__(self, robot: GatewayRobot) -> None:
        self.gw, self.nav, self.http = robot.gw, robot.nav, robot.http
        user = robot.user
        self.truth: tuple[float, float] | None = None
        user.create_subscription(Odometry, "sim/ground_truth", self._on_truth)
        self.teleport = user.create_client(Teleport, "sim/teleport")

    def _on_truth(self, msg: Odometry) -> None:
        p = msg.pose.pose.position
        self.truth = (p.x, p.y)

    def near(self, x: float, y: float, tol: float = 0.3) -> bool:
        return self.truth is not None and math.hypot(self.truth[0] - x,
                                                     self.truth[1] - y) <= tol

    def connect(self, a: tuple[str, int], b: tuple[str, int], kind: str = "direct",
                available: bool = True) -> httpx.Response:
        return self.http.post("/navigation/point_connections", json={
            "points": [{"map": a[0], "path": "p1", "index": a[1]},
                       {"map": b[0], "path": "p1", "index": b[1]}],
            "type": kind, "is_available": available})

    def clear(self) -> None:
        for c in self.http.get("/navigation/point_connections").json()["connections"]:
            assert self.http.delete("/navigation/point_connections",
                                    params={"id": c["id"]}).status_code == 200


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    tmp = tmp_path_factory.mktemp("rig")  # removed by pytest (it keeps the last 3 runs)
    with gateway_robot(tmp) as robot:
        robot.nav.core.maps.store.import_map(DEMO_MAP, "office2")
        for name, text in (("office", OFFICE), ("office2", OFFICE2)):
            robot.add_nav_points(name, "p1", text)
        yield Rig(robot)


def error(r: httpx.Response, code: int, text: str) -> None:
    assert r.status_code == code, r.text
    body = r.json()
    assert body["status"] == "error" and text in body["description"], body


def test_crud(rig: Rig) -> None:
    rig.clear()
    listing = rig.http.get("/navigation/point_connections").json()
    assert listing["connections"] == []
    desk = next(p for p in listing["points"] if p["map"] == "office2" and p["index"] == 1)
    assert desk == {"x": 2.0, "y": 1.5, "theta": 1.57, "name": "desk", "map": "office2",
                    "path": "p1", "index": 1, "type": "floor", "levels": []}
    assert {(p["map"], p["index"]) for p in listing["points"]} == {
        ("office", 0), ("office", 1), ("office2", 0), ("office2", 1)}
    r = rig.connect(("office", 1), ("office2", 0))
    assert r.status_code == 200, r.text
    conn = r.json()
    assert re.fullmatch(r"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}",
                        conn["id"])
    assert re.fullmatch(r"[0-9a-f]{24}", conn["_id"]["$oid"])
    assert conn["type"] == "direct" and conn["is_available"] is True
    assert [(p["map"], p["path"], p["index"]) for p in conn["points"]] == [
        ("office", "p1", 1), ("office2", "p1", 0)]
    assert rig.http.get("/navigation/point_connections").json()["connections"] == [conn]
    error(rig.connect(("office2", 0), ("office", 1)), 400, "already connected")
    r = rig.http.delete("/navigation/point_connections", params={"id": conn["id"]})
    assert r.status_code == 200 and r.json() == {"status": "ok"}
    assert rig.http.get("/navigation/point_connections").json()["connections"] == []
    error(rig.http.delete("/navigation/point_connections", params={"id": conn["id"]}),
          404, "unknown connection id")


@pytest.mark.parametrize(("body", "code", "text"), [
    ({"a": ("nowhere", 0)}, 404, "unknown map 'nowhere'"),
    ({"a": ("office", 5)}, 404, "unknown nav point 5"),
    ({"path": "p9"}, 404, "unknown path 'p9'"),
    ({"b": ("office", 1)}, 400, "two different points"),
    ({"type": "teleport"}, 400, "type"),
    ({"index": -1}, 400, "index"),
    ({"one": True}, 400, "points"),
    ({"is_available": "yes"}, 400, "is_available"),
    ({"map": "../etc"}, 400, "map"),
])
def test_bad_connections(rig: Rig, body: dict[str, Any], code: int, text: str) -> None:
    a, b = body.get("a", ("office", 1)), body.get("b", ("office2", 0))
    points = [{"map": body.get("map", a[0]), "path": "p1", "index": body.get("index", a[1])},
              {"map": b[0], "path": body.get("path", "p1"), "index": b[1]}]
    doc = {"points": points[:1] if body.get("one") else points,
           "type": body.get("type", "direct"), "is_available": body.get("is_available", True)}
    error(rig.http.post("/navigation/point_connections", json=doc), code, text)
    error(rig.http.delete("/navigation/point_connections"), 400, "id")


def test_no_route_or_an_elevator_is_refused(rig: Rig) -> None:
    rig.clear()
    go = {"index": 1, "map": "office2", "path": "p1"}
    error(rig.http.get("/navigation/move_to_index", params=go), 409,
          "no route from map 'office' to map 'office2'")
    assert rig.connect(("office", 0), ("office2", 1), available=False).status_code == 200
    error(rig.http.post("/navigation/start_nav_task", json={"x": 1, "y": 1, "map": "office2"}),
          409, "1 unavailable connection(s) skipped")
    assert rig.connect(("office", 1), ("office2", 0), "elevator").status_code == 200
    error(rig.http.get("/navigation/move_to_index", params=go), 409,
          "needs the elevator connection")
    error(rig.http.get("/navigation/move_to_index", params={**go, "index": 7}), 404,
          "nav point 7 does not exist")
    error(rig.http.post("/navigation/start_nav_task", json={"x": 1, "y": 1, "map": "nope"}),
          404, "unknown map 'nope'; known maps: office, office2")
    error(rig.http.get("/navigation/move_to_index", params={**go, "map": "nope"}), 404,
          "unknown map 'nope'")
    # a nav_action made directly fails the same way when it runs, before the robot moves
    task = rig.http.post("/action", json={"type": "nav_action", "x": 1.0, "y": 1.0,
                                          "map": "office2"}).json()
    assert rig.http.get("/task/start", params={"id": task["id"]}).status_code == 200
    assert wait_for(lambda: rig.http.get("/task", params={"id": task["id"]}).json()["state"]
                    == "ERROR", 20)
    sub = rig.http.get("/task", params={"id": task["id"]}).json()["sub_tasks"][0]
    assert "elevator connection" in sub["result"] and "knows no building" in sub["result"]
    assert rig.http.get("/navigation/current_map").json()["name"] == "office"
    rig.clear()


def test_goes_to_a_point_on_another_map(rig: Rig) -> None:
    rig.clear()
    assert rig.teleport.call(TeleportRequest(pose=Pose2D()), timeout=10).success
    assert wait_for(lambda: rig.near(0, 0, 0.05), 10)
    assert rig.connect(("office", 1), ("office2", 0)).status_code == 200
    r = rig.http.get("/navigation/move_to_index",
                     params={"index": 1, "map": "office2", "path": "p1"})
    assert r.status_code == 200, r.text
    task = r.json()
    assert task["sub_tasks"][0]["map"] == "office2"

    def state() -> str:
        return str(rig.http.get("/task", params={"id": task["id"]}).json()["state"])

    assert wait_for(lambda: state() in ("COMPLETE", "ERROR"), 50)
    doc = rig.http.get("/task", params={"id": task["id"]}).json()
    assert doc["state"] == "COMPLETE", [(t.get("type"), t.get("state"), t.get("result"))
                                        for t in doc["sub_tasks"]]
    assert rig.http.get("/navigation/current_map").json()["name"] == "office2"
    assert rig.near(2.0, 1.5)
    pose = rig.http.get("/navigation/pose").json()
    assert math.hypot(pose["x"] - 2.0, pose["y"] - 1.5) < 0.3
    assert rig.http.get("/navigation/current_path").json() == {"map": "office2",
                                                               "path": "p1"}
    # and back with start_nav_task to a pose on the first map
    r = rig.http.post("/navigation/start_nav_task",
                      json={"x": 1.0, "y": -0.5, "theta": 0.0, "map": "office"})
    assert r.status_code == 200, r.text
    back = r.json()["id"]
    assert wait_for(lambda: rig.http.get("/task", params={"id": back}).json()["state"]
                    in ("COMPLETE", "ERROR"), 50)
    assert rig.http.get("/task", params={"id": back}).json()["state"] == "COMPLETE"
    assert rig.http.get("/navigation/current_map").json()["name"] == "office"
    assert rig.near(1.0, -0.5)


def test_multi_map_task_goes_from_one_point_to_another_on_another_map(rig: Rig) -> None:
    rig.clear()
    assert rig.connect(("office", 1), ("office2", 0)).status_code == 200
    if rig.http.get("/navigation/current_map").json()["name"] != "office":
        back = rig.http.post("/action", json={"type": "switch_map_action", "map": "office",
                                              "path": "p1", "start_index": -1}).json()
        rig.http.get("/task/start", params={"id": back["id"]})
        assert wait_for(lambda: rig.http.get("/navigation/current_map").json()["name"]
                        == "office", 20)
    body = {"from": {"map": "office", "path": "p1", "index": 0},
            "to": {"map": "office2", "path": "p1", "index": 1, "level": 1}}
    error(rig.http.post("/navigation/multi_map_task", json={**body, "to": {
        "map": "nope", "index": 0}}), 404, "unknown map 'nope'")
    error(rig.http.post("/navigation/multi_map_task", json={**body, "to": {
        "map": "office2", "path": "p1", "index": 5}}), 404, "nav point 5 does not exist")
    error(rig.http.post("/navigation/multi_map_task", json={"from": body["from"]}), 400, "to")
    error(rig.http.post("/navigation/multi_map_task", json={**body, "via": 1}), 400, "via")
    r = rig.http.post("/navigation/multi_map_task", json=body)
    assert r.status_code == 200, r.text
    task = r.json()
    assert [(t["map"], t["index"]) for t in task["sub_tasks"]] == [("office", 0),
                                                                   ("office2", 1)]
    assert wait_for(lambda: rig.http.get("/task", params={"id": task["id"]}).json()["state"]
                    in ("COMPLETE", "ERROR"), 60)
    doc = rig.http.get("/task", params={"id": task["id"]}).json()
    assert doc["state"] == "COMPLETE", [t.get("result") for t in doc["sub_tasks"]]
    assert rig.http.get("/navigation/current_map").json()["name"] == "office2"
    assert wait_for(lambda: rig.near(2.0, 1.5), 5), (rig.truth, [
        (t.get("state"), t.get("result")) for t in doc["sub_tasks"]])
    rig.clear()


def test_switch_map_action_relocalises_at_start_index(rig: Rig) -> None:
    """Runs last: it leaves the robot's estimate at office2's desk wherever the robot is."""
    task = rig.http.post("/action", json={"type": "switch_map_action", "map": "office2",
                                          "path": "p1", "start_index": 1}).json()
    assert rig.http.get("/task/start", params={"id": task["id"]}).status_code == 200
    assert wait_for(lambda: rig.http.get("/task", params={"id": task["id"]}).json()["state"]
                    in ("COMPLETE", "ERROR"), 20)
    assert rig.http.get("/task", params={"id": task["id"]}).json()["state"] == "COMPLETE"
    assert rig.http.get("/navigation/current_map").json()["name"] == "office2"
    pose = rig.nav.core.localizer.pose()
    assert pose is not None and math.hypot(pose.x - 2.0, pose.y - 1.5) < 0.05
    assert abs(pose.theta - 1.57) < 0.05
    bad = rig.http.post("/action", json={"type": "switch_map_action", "map": "office",
                                         "path": "p1", "start_index": 9}).json()
    rig.http.get("/task/start", params={"id": bad["id"]})
    assert wait_for(lambda: rig.http.get("/task", params={"id": bad["id"]}).json()["state"]
                    == "ERROR", 20)
    sub = rig.http.get("/task", params={"id": bad["id"]}).json()["sub_tasks"][0]
    assert "no nav point 9" in sub["result"]
    assert rig.http.get("/navigation/current_map").json()["name"] == "office2"
