"""REST /map/... (docs/robot-api.md §5) and the §6.3 map transfer rows, in process on stand-in
ports: the mapping node's (`SlamPort`) and nav's calls, every row and every bad input."""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path
from typing import Any, cast

import numpy as np
import pytest
from PIL import Image
from zenros.maps import GridMap, save_map
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.geometry_msgs import Point, Pose2D
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.slam import MappingState
from zenros.services.gateway.errors import PortError, Unavailable, port_error
from zenros.services.gateway.http.app import build_api
from zenros.services.gateway.http.context import Context
from zenros.maps.archive import MAX_ARCHIVE
from zenros.services.gateway.ports.nav_services import SERVICES, NavServices
from zenros.services.gateway.ports.slam_link import (
    ExploreProgress,
    MappingSummary,
    TrackPoint,
)
from zenros.services.gateway.state.config import GatewayConfig
from zenros.services.gateway.state.core import Core, make_identity
from zenros.services.gateway.state.settings import Settings
from zenros.services.gateway.state.status import system_status_name
from zenros.services.gateway.testing import AsgiClient


def small_grid(w: int = 40, h: int = 30) -> OccupancyGrid:
    cells = np.full((h, w), -1, dtype=np.int8)
    cells[5:25, 5:35] = 0
    cells[5, 5:35] = 100
    return GridMap(cells, 0.05, (-1.0, -0.5, 0.0)).to_msg()


class FakeSlam:
    """The mapping node as the routes see it: records calls, answers from its fields."""

    def __init__(self, core: Core) -> None:
        self.core = core
        self.up = True
        self.explore_up = True
        self.update_map = False
        self.calls: list[tuple[Any, ...]] = []
        self.errors: dict[str, PortError] = {}
        self._state = MappingState()
        self._grid: OccupancyGrid | None = None
        self._pose: Pose2D | None = None
        self.seen_status: list[str] = []
        self._explore = ExploreProgress()

    def _do(self, name: str, *args: Any) -> None:
        self.calls.append((name, *args))
        self.seen_status.append(system_status_name(self.core.refresh()))
        if name in self.errors:
            raise self.errors[name]

    def available(self) -> bool:
        return self.up

    def explore_available(self) -> bool:
        return self.explore_up

    def state(self) -> MappingState:
        return self._state

    def mapping(self) -> bool:
        return self._state.state in ("starting", "mapping")

    def grid(self) -> OccupancyGrid | None:
        return self._grid

    def pose(self) -> Pose2D | None:
        return self._pose

    def track(self, keyframes: bool) -> list[TrackPoint]:
        return [TrackPoint(1.0, 2.0)] if keyframes else [TrackPoint(0.0, 0.0),
                                                         TrackPoint(0.5, 0.0)]

    def explore(self) -> ExploreProgress:
        return self._explore

    def summary(self) -> MappingSummary:
        st = self._state
        return MappingSummary(state=st.state, mode=st.mode, map_name=st.map_name,
                              scans=st.scans, nodes=st.nodes, loop_closures=st.loop_closures,
                              width=st.width, height=st.height, resolution=st.resolution,
                              area_m2=st.area_m2, message=st.message,
                              update_map=self.update_map, explore=self._explore)

    async def start(self, mode: str, map_name: str = "",
                    initial_pose: Pose2D | None = None) -> None:
        self._do("start", mode, map_name, initial_pose)
        self._state = MappingState(state="mapping", mode=mode, map_name=map_name)
        self._grid, self._pose = small_grid(), Pose2D(x=0.25, y=-0.5, theta=0.1)

    async def stop(self) -> None:
        self._do("stop")
        self._state = MappingState(state="idle")
        self._grid = self._pose = None

    async def save(self, name: str, type: str, levels: list[int]) -> str:
        self._do("save", name, type, levels)
        return name

    async def start_explore(self) -> None:
        self._do("start_explore")
        self._explore = ExploreProgress(state="exploring")

    async def cancel_explore(self) -> None:
        self._do("cancel_explore")


class FakeNavServices:
    """Nav's services: ``answers[name](request)`` answers (``name``: the service's, as
    `SERVICES` says for its type), ``calls`` records them."""

    current_map = NavServices.current_map

    def __init__(self) -> None:
        self.calls: list[tuple[str, Any]] = []
        self.answers: dict[str, Any] = {}

    async def call(self, srv: Any, request: Any) -> Any:
        name = SERVICES[srv]
        self.calls.append((name, request))
        if name not in self.answers:
            raise port_error(ResultCode.UNAVAILABLE, f"no stand-in for {name}")
        answer = self.answers[name]
        return answer(request) if callable(answer) else answer

    def names(self) -> list[str]:
        return [n for n, _ in self.calls]

    def publish_initialpose(self, x: float, y: float, theta: float) -> None:
        self.calls.append(("initialpose", (x, y, theta)))


class FakeNav:
    def __init__(self) -> None:
        self.stopped = False
        self.path_name = ""
        self.opened = 0

    def available(self) -> bool:
        return True

    def open(self) -> None:
        self.opened += 1

    async def point(self, index: int) -> tuple[float, float, float]:
        raise AssertionError("no nav point is read here")


class Rig:
    def __init__(self, tmp: Path) -> None:
        self.tmp = tmp
        self.core = Core(GatewayConfig(no_token_check=True), Settings(tmp / "settings.json"),
                         make_identity("/r", "6.6.8", 0), startup_grace=0.0)
        self.slam = FakeSlam(self.core)
        self.link = FakeNavServices()
        self.nav = FakeNav()
        self.link.answers["map_server/current_map"] = zm.GetCurrentMapResponse(name="office")
        none = cast(Any, None)
        self.ctx = Context(core=self.core, tasks=none, nav_actions=cast(Any, self.nav),
                           nav_services=cast(Any, self.link), io=none, topics=none, hub=none,
                           params=none, files=none, speech=none, audio=none, coverage=none,
                           slam=self.slam)
        self.http = AsgiClient(build_api(self.ctx), "/api/v1")

    def status(self) -> str:
        return str(system_status_name(self.core.refresh()))


@pytest.fixture
def rig(tmp_path: Path) -> Rig:
    return Rig(tmp_path)


def error(r: Any, code: int, *words: str) -> None:
    assert r.status_code == code, r.text
    body = r.json()
    assert body.get("status") == "error" or body.get("result") is False, body
    for w in words:
        assert w in body["description"], body


MAP_OPS = [("GET", "/map/start"), ("GET", "/map/stop"), ("GET", "/map/update"),
           ("GET", "/map/pose"), ("GET", "/map/current_map_image"),
           ("POST", "/map/current_map_image"), ("GET", "/map/current_map_png"),
           ("GET", "/map/track")]


def test_every_map_row_answers_and_none_is_501(rig: Rig) -> None:
    index = rig.http.get("/").json()
    for method, path in MAP_OPS + [("GET", "/navigation/update_map"),
                                   ("PUT", "/navigation/update_map"),
                                   ("GET", "/navigation/download_map_from_robot"),
                                   ("POST", "/navigation/upload_map_to_robot"),
                                   ("GET", "/navigation/upload_map"),
                                   ("GET", "/navigation/download_map")]:
        assert f"{method} /api/v1{path}" in index["implemented"]


@pytest.mark.parametrize(("method", "path"), MAP_OPS)
def test_no_mapping_node_is_a_503_naming_it(rig: Rig, method: str, path: str) -> None:
    rig.slam.up = False
    body = {"name": "site2"} if method == "POST" else None
    r = rig.http.request(method, path, json=body)
    error(r, 503, "slam", "not running")
    assert rig.slam.calls == []


def test_start_goes_busy_then_mapping_then_stop_busy_then_free(rig: Rig) -> None:
    assert rig.status() == "Free"
    assert rig.http.get("/map/start").json() == {"result": True,
                                                 "description": "mapping started (laser)"}
    assert rig.slam.calls == [("start", "laser", "", None)]
    assert rig.slam.seen_status == ["Busy"]
    assert rig.status() == "Mapping" and rig.core.status.mapStatus == 1
    assert rig.nav.stopped and rig.core.status.navStatus == 0
    info = rig.http.get("/system/info").json()
    assert info["mapping"]["state"] == "mapping" and info["mapping"]["mode"] == "laser"
    assert rig.http.get("/map/stop").json()["result"] is True
    assert [c[0] for c in rig.slam.calls[1:]] == ["cancel_explore", "stop"]
    assert rig.slam.seen_status[1:] == ["Busy", "Busy"]
    assert rig.status() == "Free" and rig.core.status.mapStatus == 0


def test_explore_mode_sends_the_explore_goal(rig: Rig) -> None:
    assert rig.http.get("/map/start", params={"mode": "explore"}).json()["result"] is True
    assert [c[0] for c in rig.slam.calls] == ["start", "start_explore"]
    assert rig.slam.calls[0][1] == "explore"
    info = rig.http.get("/system/info").json()["mapping"]
    assert info["explore"]["state"] == "exploring"


def test_explore_without_an_explore_node_is_a_503_before_mapping_starts(rig: Rig) -> None:
    rig.slam.explore_up = False
    error(rig.http.get("/map/start", params={"mode": "explore"}), 503, "explore")
    assert rig.slam.calls == []


def test_explore_refused_stops_the_mapping_it_started(rig: Rig) -> None:
    rig.slam.errors["start_explore"] = port_error(ResultCode.CONFLICT, "no scan yet")
    error(rig.http.get("/map/start", params={"mode": "explore"}), 409, "no scan yet")
    assert [c[0] for c in rig.slam.calls] == ["start", "start_explore", "stop"]
    assert rig.status() == "Free"


@pytest.mark.parametrize("query", [{"mode": "camera"}, {"mode": ""}, {"speed": "1"}])
def test_start_bad_queries_are_400(rig: Rig, query: dict[str, str]) -> None:
    error(rig.http.get("/map/start", params=query), 400)
    assert rig.slam.calls == []


def test_mapping_while_navigating_is_refused_and_says_why(rig: Rig) -> None:
    rig.core.state.goal.status = 1
    rig.core.state.goal.num_id = 3
    rig.core.refresh()
    r = rig.http.get("/map/start")
    error(r, 409, "navigating to a goal", "targetStatus 1", "/navigation/stop")
    assert r.json()["result"] is False
    rig.core.state.goal.status = 0
    rig.core.state.looping = True
    rig.core.refresh()
    error(rig.http.get("/map/update", params={"map": "office"}), 409, "loop task")
    assert rig.slam.calls == []


def test_navigating_while_mapping_is_refused_and_says_why(rig: Rig) -> None:
    rig.http.get("/map/start")
    r = rig.http.get("/navigation/start")
    error(r, 409, "mapping", "mapStatus 1", "/map/stop")
    assert r.json()["result"] is False and rig.nav.opened == 0
    error(rig.http.get("/map/start"), 409, "mapping already")


def test_what_needs_the_saved_map_is_refused_while_mapping(rig: Rig) -> None:
    # nav points, patrols and the charge pose belong to the saved map, not the one being built
    rig.http.get("/map/start")
    for r, what in (
            (rig.http.get("/navigation/move_to_index", params={"index": 0}), "nav point"),
            (rig.http.post("/navigation/loop_task", json={"wait_time": 0}), "loop task"),
            (rig.http.get("/navigation/go_charge"), "go to charge"),
            (rig.http.post("/navigation/charge_pose"), "charge pose")):
        error(r, 409, what, "mapStatus 1", "/map/stop")


def test_the_mapping_nodes_refusal_keeps_its_code_and_reason(rig: Rig) -> None:
    rig.slam.errors["start"] = port_error(ResultCode.CONFLICT,
                                          "nav refused mapping mode: a goal is being driven")
    error(rig.http.get("/map/start"), 409, "a goal is being driven")
    assert rig.status() == "Free" and not rig.nav.stopped
    rig.slam.errors["start"] = Unavailable("nav is not running")
    error(rig.http.get("/map/start"), 503, "nav is not running")


def test_save_names_and_types(rig: Rig) -> None:
    error(rig.http.post("/map/current_map_image", json={"name": "site2"}), 409, "not mapping")
    rig.http.get("/map/start")
    r = rig.http.post("/map/current_map_image", json={"name": "site2"})
    assert r.json() == {"result": True, "name": "site2"}
    r = rig.http.post("/map/current_map_image",
                      json={"name": "lift", "type": "elevator", "levels": [1, 2]})
    assert r.json()["name"] == "lift"
    assert rig.slam.calls[-2:] == [("save", "site2", "floor", []),
                                   ("save", "lift", "elevator", [1, 2])]


@pytest.mark.parametrize("body", [
    {"name": ""}, {"name": "../site2"}, {"name": "a/b"}, {"name": ".hidden"},
    {"name": "/etc/passwd"}, {"name": "x" * 65}, {}, {"name": 5},
    {"name": "ok", "type": "cellar"}, {"name": "ok", "levels": ["one"]},
    {"name": "ok", "extra": 1}])
def test_save_refuses_bad_bodies_with_400(rig: Rig, body: dict[str, Any]) -> None:
    rig.http.get("/map/start")
    r = rig.http.post("/map/current_map_image", json=body)
    error(r, 400)
    assert r.json()["result"] is False
    assert not any(c[0] == "save" for c in rig.slam.calls)


def test_a_refused_save_keeps_the_nodes_code(rig: Rig) -> None:
    rig.http.get("/map/start")
    rig.slam.errors["save"] = port_error(ResultCode.INVALID, "invalid map name 'con'")
    error(rig.http.post("/map/current_map_image", json={"name": "con"}), 400, "'con'")


def test_current_map_image_png_pose_and_track(rig: Rig) -> None:
    for path in ("/map/current_map_image", "/map/current_map_png", "/map/pose"):
        error(rig.http.get(path), 409, "not mapping")
    rig.http.get("/map/start")
    meta = rig.http.get("/map/current_map_image").json()
    assert meta == {"status": "OK", "map_params": {"origin": [-1.0, -0.5, 0.0], "width": 40,
                                                   "height": 30, "resolution": 0.05},
                    "map_image": "/api/v1/map/current_map_png"}
    png = rig.http.get("/map/current_map_png")
    assert png.headers["content-type"] == "image/png"
    img = Image.open(io.BytesIO(png.content))
    assert img.size == (40, 30)
    # the wall along row 5 of the grid (y up) is row 24 of the image (y down), black
    assert img.getpixel((10, 24)) == 0 and img.getpixel((10, 20)) == 254
    assert rig.http.get("/map/pose").json() == {"x": 0.25, "y": -0.5, "angle": 0.1}
    assert rig.http.get("/map/track").json() == {"trajectory": [
        {"x": 0.0, "y": 0.0, "z": 0.0}, {"x": 0.5, "y": 0.0, "z": 0.0}]}
    assert rig.http.get("/map/track", params={"keyframes": "true"}).json() == {
        "trajectory": [{"x": 1.0, "y": 2.0, "z": 0.0}]}
    error(rig.http.get("/map/track", params={"keyframes": "maybe"}), 400)


def test_no_grid_yet_is_a_409_not_a_blank_image(rig: Rig) -> None:
    rig.http.get("/map/start")
    rig.slam._grid = None
    error(rig.http.get("/map/current_map_png"), 409, "no map has come yet")


def _nav_points(rig: Rig) -> None:
    rig.link.answers["map_server/list_maps"] = lambda req: zm.ListMapsResponse(
        maps=[zm.MapInfo(name=req.name)] if req.name in ("office", "site2") else [])
    rig.link.answers["list_paths"] = zm.ListPathsResponse(paths=[
        zm.PathRef(map_name="office", path_name="tour")])
    rig.link.answers["get_nav_points"] = zm.GetNavPointsResponse(points=[
        zm.NavPoint(x=1.0, y=2.0, theta=0.5), zm.NavPoint(x=3.0, y=4.0, theta=-1.0)])


def test_update_relocalises_at_a_nav_point_or_the_last_pose(rig: Rig) -> None:
    _nav_points(rig)
    r = rig.http.get("/map/update", params={"map": "office", "start_index": "1"})
    assert r.json() == {"result": True,
                        "description": "extending map 'office' from nav point 1"}
    assert rig.slam.calls[-1] == ("start", "laser", "office", Pose2D(x=3.0, y=4.0, theta=-1.0))
    assert ("get_nav_points", zm.GetNavPointsRequest(map_name="office", path_name="tour")
            ) in rig.link.calls
    rig.http.get("/map/stop")
    r = rig.http.get("/map/update")  # the current map, at its graph's last pose
    assert "the saved map's last pose" in r.json()["description"]
    assert rig.slam.calls[-1] == ("start", "laser", "office", None)


@pytest.mark.parametrize(("query", "code", "words"), [
    ({"map": "attic"}, 404, ["unknown map", "attic"]),
    ({"map": "office", "start_index": "7"}, 404, ["nav point 7", "0..1"]),
    ({"map": "../office"}, 400, ["map"]),
    ({"map": "office", "start_index": "-3"}, 400, ["start_index"]),
    ({"map": "office", "path": "a/b"}, 400, ["path"]),
])
def test_update_bad_queries(rig: Rig, query: dict[str, str], code: int,
                            words: list[str]) -> None:
    _nav_points(rig)
    error(rig.http.get("/map/update", params=query), code, *words)
    assert rig.slam.calls == []


def test_update_map_updates_the_map_in_use_while_navigating(rig: Rig) -> None:
    _nav_points(rig)
    assert rig.http.get("/navigation/update_map").json() == {"enabled": False}
    error(rig.http.put("/navigation/update_map", json={"enabled": True}), 409,
          "/navigation/start")
    rig.core.state.nav_open = True
    rig.core.state.pose = (1.0, 2.0, 0.5)
    assert rig.http.put("/navigation/update_map", json={"enabled": True}).json() == {
        "enabled": True}
    assert rig.slam.calls[-1] == ("start", "laser", "office", Pose2D(x=1.0, y=2.0, theta=0.5))
    assert rig.http.get("/navigation/update_map").json() == {"enabled": True}
    assert rig.core.state.nav_open  # still navigating
    assert rig.http.put("/navigation/update_map", json={"enabled": False}).json() == {
        "enabled": False}
    assert rig.slam.calls[-2:] == [("save", "office", "floor", []), ("stop",)]
    for bad in ({"enabled": "yes"}, {}, {"enabled": True, "x": 1}):
        error(rig.http.put("/navigation/update_map", json=bad), 400)


# ------------------------------------------------------------------ map archives


def _stored_map(rig: Rig, name: str = "office") -> Path:
    folder = rig.tmp / "maps" / name
    folder.mkdir(parents=True)
    cells = np.zeros((20, 30), dtype=np.int8)
    cells[0, :] = 100
    save_map(GridMap(cells, 0.05, (1.0, 2.0, 0.0)), folder / f"{name}.yaml")
    return folder


def _archive_nav(rig: Rig, folder: Path) -> None:
    yaml_path, image = folder / "office.yaml", folder / "office.pgm"
    import hashlib
    rig.link.answers["map_server/list_maps"] = lambda req: zm.ListMapsResponse(maps=[
        zm.MapInfo(name="office", resolution=0.05, origin=[1.0, 2.0, 0.0], width=30,
                   height=20, md5sum=hashlib.md5(image.read_bytes()).hexdigest(),
                   yaml_path=str(yaml_path), image_path=str(image))] if req.name == "office"
        else [])
    rig.link.answers["list_paths"] = zm.ListPathsResponse(paths=[
        zm.PathRef(map_name="office", path_name="tour"),
        zm.PathRef(map_name="lab", path_name="other")])
    rig.link.answers["get_path"] = zm.GetPathResponse(points=[Point(x=1.0, y=1.0)])
    rig.link.answers["get_nav_points"] = zm.GetNavPointsResponse(points=[
        zm.NavPoint(name="door", x=1.5, y=2.5, theta=0.2)])
    rig.link.answers["list_point_connections"] = zm.ListPointConnectionsResponse(
        connections=[zm.PointConnection(id="c1", points=[
            zm.PointRef(map_name="office", path_name="tour", index=0),
            zm.PointRef(map_name="lab", path_name="other", index=0)]),
            zm.PointConnection(id="c2", points=[zm.PointRef(map_name="lab")])])


def test_download_map_from_robot_is_an_archive_of_the_map_and_its_nav_data(rig: Rig) -> None:
    _archive_nav(rig, _stored_map(rig))
    r = rig.http.get("/navigation/download_map_from_robot", params={"map_name": "office"})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "application/zip"
    assert 'filename="office.zip"' in r.headers["content-disposition"]
    z = zipfile.ZipFile(io.BytesIO(r.content))
    assert sorted(z.namelist()) == ["office/map.json", "office/nav.json", "office/office.pgm",
                                    "office/office.yaml"]
    assert b"image: office.pgm" in z.read("office/office.yaml")
    nav = json.loads(z.read("office/nav.json"))
    assert [p["name"] for p in nav["paths"]] == ["tour"]  # not the lab map's path
    assert nav["paths"][0]["nav_points"][0]["name"] == "door"
    assert [c["id"] for c in nav["connections"]] == ["c1"]  # those touching office only
    assert json.loads(z.read("office/map.json"))["width"] == 30
    error(rig.http.get("/navigation/download_map_from_robot", params={"map_name": "attic"}),
          404, "attic")
    error(rig.http.get("/navigation/download_map_from_robot",
                       params={"map_name": "../etc"}), 400)
    error(rig.http.get("/navigation/download_map_from_robot"), 400, "map_name")


def _upload(rig: Rig, files: list[tuple[str, bytes]], name: str = "site3") -> Any:
    return rig.http.post("/navigation/upload_map_to_robot", data={"map_name": name},
                         files=[("map_files", (n, c)) for n, c in files])


def _importing(rig: Rig) -> list[zm.ImportMapRequest]:
    seen: list[zm.ImportMapRequest] = []

    def imported(req: zm.ImportMapRequest) -> zm.ImportMapResponse:
        from zenros.maps import load_map
        load_map(req.yaml_path)  # nav reads the checked copy while the call lasts
        seen.append(req)
        return zm.ImportMapResponse(info=zm.MapInfo(name=req.name))
    rig.link.answers["map_server/import_map"] = imported
    for name in ("set_path", "set_nav_points"):
        rig.link.answers[name] = None
    rig.link.answers["add_point_connection"] = lambda req: (
        zm.AddPointConnectionResponse() if all(p.map_name == "site3" for p in req.points)
        else (_ for _ in ()).throw(port_error(ResultCode.NOT_FOUND, "no map 'lab'")))
    return seen


def _downloaded(rig: Rig) -> bytes:
    _archive_nav(rig, _stored_map(rig))
    r = rig.http.get("/navigation/download_map_from_robot", params={"map_name": "office"})
    return bytes(r.content)


def test_an_archive_goes_back_in_under_a_new_name(rig: Rig) -> None:
    data = _downloaded(rig)
    seen = _importing(rig)
    r = _upload(rig, [("office.zip", data)])
    assert r.status_code == 200, r.text
    assert r.json() == {"status": "ok", "name": "site3", "width": 30, "height": 20,
                        "paths": 1, "connections": 0,
                        "skipped": ["connection c1: no map 'lab'"]}
    assert seen[0].name == "site3" and seen[0].overwrite
    assert not Path(seen[0].yaml_path).exists()  # the checked copy is gone afterwards
    sets = [req for n, req in rig.link.calls if n in ("set_path", "set_nav_points")]
    assert [(s.map_name, s.path_name) for s in sets] == [("site3", "tour")] * 2
    assert sets[1].points[0].name == "door"


def test_loose_files_go_in_too(rig: Rig) -> None:
    folder = _stored_map(rig)
    seen = _importing(rig)
    r = _upload(rig, [("office.yaml", (folder / "office.yaml").read_bytes()),
                      ("office.pgm", (folder / "office.pgm").read_bytes())])
    assert r.status_code == 200, r.text
    assert r.json()["paths"] == 0 and len(seen) == 1


def _zip(members: dict[str, bytes]) -> bytes:
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as z:
        for name, content in members.items():
            z.writestr(name, content)
    return out.getvalue()


def _members(rig: Rig) -> dict[str, bytes]:
    z = zipfile.ZipFile(io.BytesIO(_downloaded(rig)))
    return {n: z.read(n) for n in z.namelist()}


def _bad_uploads(rig: Rig) -> dict[str, tuple[list[tuple[str, bytes]], int, str]]:
    m = _members(rig)
    pgm = m["office/office.pgm"]
    yaml_text = m["office/office.yaml"]
    small = Image.new("L", (10, 10), 254)
    out = io.BytesIO()
    small.save(out, format="PNG")
    wrong_size = {**m, "office/office.pgm": b"P5\n10 10\n255\n" + bytes(100)}
    return {
        "wrong image size": ([("a.zip", _zip(wrong_size))], 400, "30x20"),
        "bad yaml": ([("a.zip", _zip({**m, "office/office.yaml": b"image: [\n"}))], 400,
                     "not valid YAML"),
        "yaml without keys": ([("a.zip", _zip({**m, "office/office.yaml":
                                               b"image: office.pgm\n"}))], 400, "resolution"),
        "zip slip": ([("a.zip", _zip({**m, "../../evil.yaml": b"x"}))], 400,
                     "leaves the map's folder"),
        "absolute member": ([("a.zip", _zip({**m, "/etc/cron.d/x": b"x"}))], 400,
                            "leaves the map's folder"),
        "image outside": ([("a.zip", _zip({**m, "office/office.yaml": yaml_text.replace(
            b"office.pgm", b"/etc/passwd")}))], 400, "bare name"),
        "loose path name": ([("../office.yaml", yaml_text), ("office.pgm", pgm)], 400,
                            "leaves the map's folder"),
        "not a map": ([("notes.txt", b"hello")], 400, "map YAML"),
        "damaged image": ([("a.zip", _zip({**m, "office/office.pgm": b"P5\n30 20\n255\n"}))],
                          400, "office.pgm"),
        "bad nav data": ([("a.zip", _zip({**m, "office/nav.json": b'{"paths": 5}'}))], 400,
                         "nav.json"),
        "stray file": ([("a.zip", _zip({**m, "office/run.sh": b"rm -rf /"}))], 400,
                       "run.sh"),
        "not a zip": ([("a.zip", b"PK\x03\x04 garbage")], 400, "not a zip"),
        "bad name": ([("a.zip", _zip(m))], 400, "map_name"),
    }


@pytest.mark.parametrize("case", ["wrong image size", "bad yaml", "yaml without keys",
                                  "zip slip", "absolute member", "image outside",
                                  "loose path name", "not a map", "damaged image",
                                  "bad nav data", "stray file", "not a zip", "bad name"])
def test_a_bad_upload_is_a_4xx_and_imports_nothing(rig: Rig, case: str) -> None:
    files, code, words = _bad_uploads(rig)[case]
    seen = _importing(rig)
    r = _upload(rig, files, name="../x" if case == "bad name" else "site3")
    error(r, code, words)
    assert seen == [] and "map_server/import_map" not in rig.link.names()


def test_a_100_mb_upload_is_a_413(rig: Rig) -> None:
    seen = _importing(rig)
    big = b"\0" * (100 * 1024 * 1024)
    error(_upload(rig, [("big.zip", big)]), 413, "too large")
    r = rig.http.post("/navigation/upload_map_to_robot", content=b"--x--",
                      headers={"content-type": "multipart/form-data; boundary=x",
                               "content-length": str(MAX_ARCHIVE * 2)})
    error(r, 413, "too large")
    assert seen == []


def test_a_zip_bomb_is_refused_by_its_unpacked_size(rig: Rig) -> None:
    m = _members(rig)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for n, c in m.items():
            z.writestr(n, c)
        z.writestr("office/pad.bin", b"\0" * (MAX_ARCHIVE + 1))
    seen = _importing(rig)
    error(_upload(rig, [("bomb.zip", out.getvalue())]), 413, "unpacks to over")
    assert seen == []


def test_upload_form_fields_are_checked(rig: Rig) -> None:
    _importing(rig)
    post = rig.http.post
    error(post("/navigation/upload_map_to_robot", data={"map_name": "site3"},
               files=[("map_files", ("", b""))]), 400, "map_files")
    error(post("/navigation/upload_map_to_robot", files=[("map_files", ("a.zip", b"1"))]),
          400, "map_name")
    error(post("/navigation/upload_map_to_robot", data={"map_name": "a", "x": "1"},
               files=[("map_files", ("a.zip", b"1"))]), 400, "unknown form field", "x")
    error(post("/navigation/upload_map_to_robot", json={"map_name": "x"}), 400, "multipart")
    assert "map_server/import_map" not in rig.link.names()


def test_native_v_commands_map_as_the_routes_do(rig: Rig,
                                                caplog: pytest.LogCaptureFixture) -> None:
    """§12.3's 'V' 0x00..0x03 from the serial port or galileo/cmds: start, save (named by
    the date and time, since the command carries no name), stop, and extend the current map;
    a command the state refuses is logged and changes nothing."""
    import asyncio
    import logging
    import re
    import threading

    from zenros.services.gateway.http.routes.mapping import NativeMapping
    from zenros.services.gateway.ports.native import NativeCommands
    from zenros.testing import wait_for

    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    native = NativeCommands(rig.core, logging.getLogger("native-test"), loop,
                            NativeMapping(rig.ctx))

    def calls() -> list[str]:
        return [c[0] for c in rig.slam.calls]

    try:
        assert native(b"V\x02")  # save while not mapping: started, then refused
        assert wait_for(lambda: "the robot is not mapping" in caplog.text, 5), caplog.text
        assert rig.slam.calls == []
        assert native(b"V\x00")
        # the SLAM call is recorded before its answer reaches the gateway's state
        assert wait_for(lambda: calls() == ["start"] and rig.core.state.mapping, 5)
        assert rig.slam.calls[0][1] == "laser"
        assert wait_for(lambda: rig.status() == "Mapping", 5), rig.status()
        assert native(b"V\x02")
        assert wait_for(lambda: calls() == ["start", "save"], 5)
        assert re.fullmatch(r"map_\d{8}_\d{6}", rig.slam.calls[1][1])
        assert native(b"V\x01")
        assert wait_for(lambda: calls()[-1] == "stop" and not rig.core.state.mapping, 5)
        rig.link.answers["map_server/list_maps"] = zm.ListMapsResponse(
            maps=[zm.MapInfo(name="office")])
        assert native(b"V\x03")  # extend the current map from its last pose
        assert wait_for(lambda: calls()[-1] == "start", 5)
        assert rig.slam.calls[-1][1:3] == ("laser", "office")
        assert not native(b"V\x07") and not native(b"V")  # unknown: refused at once
    finally:
        loop.call_soon_threadsafe(loop.stop)
        thread.join(5)
        loop.close()
