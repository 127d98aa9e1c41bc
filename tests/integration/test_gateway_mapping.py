"""Map building through the gateway over real Zenoh (docs/robot-api.md §5, §6.3): the gateway's
`SlamLink` against a mapping node that follows the ``zenros_msgs.slam`` contract (the stand-in
of `slam_stand_in`, until the real one is on main), the real nav node's maps store, and a
real HTTP client on the gateway's socket."""

from __future__ import annotations

import io
import math
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from PIL import Image
from slam_stand_in import SlamStandIn
from zenros.action import ActionClient
from zenros.action.types import GoalStatus
from zenros.msgs.geometry_msgs import Point, Quaternion
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs.slam import Explore, ExploreGoal
from zenros.node import Node
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.services.nav.node import NavNode
from zenros.testing import linked_contexts, wait_for

TIMEOUT = 20.0


class Rig:
    def __init__(self, ctxs: list[Any], tmp: Path) -> None:
        self.ctxs, self.tmp = ctxs, tmp
        self.nodes: list[Node] = []
        self.nav = self._add(NavNode("nav", context=ctxs[0], parameter_overrides={
            "maps_dir": str(tmp / "maps")}))
        self.chassis = self._add(Node("chassis", context=ctxs[0]))
        self.odom = self.chassis.create_publisher(Odometry, "odom", 10)
        self.slam: SlamStandIn | None = None
        self.gw: GatewayNode | None = None
        self.http: httpx.Client | None = None

    def _add(self, node: Any) -> Any:
        self.nodes.append(node)
        return node

    def start_slam(self) -> None:
        self.slam = self._add(SlamStandIn(context=self.ctxs[0]))
        assert self.gw is not None
        assert self.gw.graph.wait_for_service("/slam/start", TIMEOUT)
        assert self.gw.graph.wait_for_service("/map_server/import_map", TIMEOUT)

    def drive_to(self, x: float, y: float, theta: float = 0.0) -> None:
        msg = Odometry()
        msg.pose.pose.position = Point(x=x, y=y)
        msg.pose.pose.orientation = Quaternion(z=math.sin(theta / 2), w=math.cos(theta / 2))
        self.odom.publish(msg)

    def get(self, path: str, **params: Any) -> httpx.Response:
        assert self.http is not None
        return self.http.get(path, params=params)

    def status(self) -> str:
        return str(self.get("/system/status").json()["status"])


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    tmp = tmp_path_factory.mktemp("mapping")
    with linked_contexts(2) as ctxs:
        r = Rig(ctxs, tmp)
        try:
            with running_gateway(ctxs[1], tmp, no_token_check=True, startup_grace=0.0) as gw:
                r.gw = gw
                assert gw.graph.wait_for_service("/map_server/list_maps", TIMEOUT)
                with httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1",
                                  timeout=TIMEOUT) as http:
                    r.http = http
                    yield r
        finally:
            for n in reversed(r.nodes):
                n.close()


def test_without_a_mapping_node_every_map_call_is_a_503(rig: Rig) -> None:
    assert rig.slam is None  # the module's first test: no mapping node yet
    for path in ("/map/start", "/map/stop", "/map/pose", "/map/current_map_png", "/map/track"):
        r = rig.get(path)
        assert r.status_code == 503, (path, r.text)
        assert "the slam service is not running" in r.json()["description"]
    rig.start_slam()


def test_map_drive_save_stop_then_navigate_on_it(rig: Rig) -> None:
    rig.drive_to(2.0, 1.0, math.pi / 2)  # odometry's frame is not the new map's
    assert wait_for(lambda: rig.slam is not None and rig.slam.odom is not None, TIMEOUT)
    r = rig.get("/map/start")
    assert r.json() == {"result": True, "description": "mapping started (laser)"}, r.text
    assert wait_for(lambda: rig.status() == "Mapping", TIMEOUT)  # at the next status tick
    assert rig.get("/system/galileo_status").json()["mapStatus"] == 1
    assert wait_for(lambda: rig.get("/map/current_map_image").status_code == 200, TIMEOUT)
    pose = rig.get("/map/pose").json()
    assert abs(pose["x"]) < 1e-6 and abs(pose["y"]) < 1e-6  # the map starts where it stands
    first = rig.get("/system/info").json()["mapping"]["area_m2"]
    rig.drive_to(2.0, 2.5, math.pi / 2)  # 1.5 m ahead: the map's +x
    assert wait_for(lambda: rig.get("/map/pose").json()["x"] > 1.4, TIMEOUT)
    assert wait_for(lambda: rig.get("/system/info").json()["mapping"]["area_m2"] > first,
                    TIMEOUT)
    png = Image.open(io.BytesIO(rig.get("/map/current_map_png").content))
    meta = rig.get("/map/current_map_image").json()
    assert png.size == (meta["map_params"]["width"], meta["map_params"]["height"])
    track = rig.get("/map/track", keyframes="true").json()["trajectory"]
    assert len(track) >= 2 and track[-1]["x"] > 1.0
    assert len(rig.get("/map/track").json()["trajectory"]) >= 2
    # a bad name is a 400; a good one lands in nav's maps store
    assert rig.http is not None
    bad = rig.http.post("/map/current_map_image", json={"name": "../site2"})
    assert bad.status_code == 400 and bad.json()["result"] is False
    saved = rig.http.post("/map/current_map_image", json={"name": "site2"})
    assert saved.json() == {"result": True, "name": "site2"}, saved.text
    maps = {m["name"]: m for m in rig.get("/navigation/saved_maps").json()}
    assert maps["site2"]["resolution"] == pytest.approx(0.05)
    # navigating while mapping is refused with the §1.2 body
    nav = rig.get("/navigation/start", map="site2")
    assert nav.status_code == 409 and "mapping" in nav.json()["description"]
    assert rig.get("/map/stop").json()["result"] is True
    assert wait_for(lambda: rig.status() == "Free", TIMEOUT)
    r = rig.get("/navigation/start", map="site2")
    assert r.json()["result"] is True, r.text
    assert rig.get("/navigation/current_map").json()["name"] == "site2"
    png = rig.get("/navigation/map_png", name="site2")
    assert Image.open(io.BytesIO(png.content)).size == (200, 200)
    assert rig.get("/navigation/map_pgm", name="site2").content.startswith(b"P5\n200 200\n")


def test_explore_runs_to_done_and_stop_cancels_it(rig: Rig) -> None:
    rig.get("/navigation/stop")
    r = rig.get("/map/start", mode="explore")
    assert r.json()["result"] is True, r.text
    assert wait_for(lambda: rig.get("/system/info").json()["mapping"]["explore"]["state"]
                    == "done", TIMEOUT)
    explore = rig.get("/system/info").json()["mapping"]["explore"]
    assert explore["goals_reached"] == 3 and explore["frontiers_left"] == 0
    assert rig.get("/map/stop").json()["result"] is True
    assert wait_for(lambda: rig.status() == "Free", TIMEOUT)


def test_stop_cancels_exploring_whoever_started_it(rig: Rig) -> None:
    assert rig.get("/map/start").json()["result"] is True
    client = ActionClient(rig.chassis, Explore, "explore")  # a ROS client's goal
    assert client.wait_for_server(TIMEOUT)
    handle = client.send_goal_async(ExploreGoal())
    assert handle.wait_accepted(TIMEOUT)
    assert rig.get("/map/stop").json()["result"] is True
    assert handle.result(TIMEOUT).status is GoalStatus.CANCELED
    assert wait_for(lambda: rig.status() == "Free", TIMEOUT)


def test_the_map_goes_out_as_an_archive_and_back_in(rig: Rig) -> None:
    assert rig.http is not None
    rig.http.post("/navigation/nav_points", json={
        "map_name": "site2", "path_name": "p1", "path_data": "1 0 0 0 0.1 0.1 0\n"})
    out = rig.get("/navigation/download_map_from_robot", map_name="site2")
    assert out.status_code == 200, out.text
    names = sorted(zipfile.ZipFile(io.BytesIO(out.content)).namelist())
    assert names == ["site2/map.json", "site2/nav.json", "site2/site2.pgm", "site2/site2.yaml"]
    r = rig.http.post("/navigation/upload_map_to_robot", data={"map_name": "site3"},
                      files=[("map_files", ("site2.zip", out.content))])
    assert r.status_code == 200, r.text
    assert r.json()["paths"] == 1
    listed = {m["name"] for m in rig.get("/navigation/saved_maps").json()}
    assert {"site2", "site3"} <= listed
    points = rig.get("/navigation/nav_points", map_name="site3", path_name="p1")
    assert points.status_code == 200 and "1 0 0 0" in points.text, points.text
    # a zip-slip archive is refused and the store is as it was
    before = sorted(p.name for p in (rig.tmp / "maps").iterdir())
    evil = io.BytesIO()
    with zipfile.ZipFile(evil, "w") as z:
        z.writestr("../../evil.yaml", b"image: x.pgm\n")
    r = rig.http.post("/navigation/upload_map_to_robot", data={"map_name": "site4"},
                      files=[("map_files", ("evil.zip", evil.getvalue()))])
    assert r.status_code == 400 and "leaves" in r.json()["description"]
    assert sorted(p.name for p in (rig.tmp / "maps").iterdir()) == before
    assert not (rig.tmp / "evil.yaml").exists()


def test_hostile_input_to_the_mapping_rows_gets_no_500(rig: Rig) -> None:
    """The fuzz of test_gateway_rest (every implemented row, hostile queries and bodies),
    here with a mapping node that maps, so the inputs reach past the 503."""
    from test_gateway_rest import assert_no_500
    assert rig.http is not None
    assert rig.get("/map/start").json()["result"] is True
    try:
        assert wait_for(lambda: rig.get("/map/current_map_image").status_code == 200, TIMEOUT)
        index = rig.get("/").json()
        rows = [e for e in index["implemented"]
                if "/map/" in e or "update_map" in e or "_map_" in e]
        assert len(rows) == 13, rows  # the §5 rows, the map transfers, multi_map_task
        for entry in rows:
            # start, stop and update change what the others read: their inputs are checked
            # in test_gateway_mapping_routes
            if entry.split(" ", 1)[0] == "GET" and entry.endswith(("/start", "/stop", "/update")):
                continue
            assert_no_500(rig.http, entry, {})
    finally:
        assert rig.get("/map/stop").json()["result"] is True
