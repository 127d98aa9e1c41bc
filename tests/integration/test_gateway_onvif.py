"""docs/robot-api.md §17 through a real server and the simulated PTZ camera of a real chassis:
the camera listed and its profile, moves reaching their targets, a continuous move and its
stop, presets, the thermal reading hot on the robot, a snapshot in saved_images, the MJPEG
stream a browser shows; bad values 400, an unknown preset 404, no camera 503, credentials 401;
a move as a task of the real tasks service (onvif_camera_move_action)."""

from __future__ import annotations

import io
import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from PIL import Image
from zenros.context import Context
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.services.gateway.testing import running_gateway
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for

PAN, TILT, ZOOM = 2.967, 0.5236, 10.0  # the default ranges: ±pan, ±tilt, 1..zoom


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_rate": 0.0, "speed": 5.0, "ptz_width": 160, "ptz_height": 120})
    yield node
    node.close()


def _refused(r: httpx.Response, status: int, words: str) -> None:
    assert r.status_code == status, r.text
    assert r.json()["status"] == "error" and words in r.json()["description"], r.text


def test_no_camera_is_a_503_and_an_empty_list(gw: GatewayNode, http: httpx.Client) -> None:
    assert http.get("/system/onvif_cameras").json() == {"cameras": []}
    for path, params in (("pose", {}), ("move", {"x": "0"}), ("temperature", {}),
                         ("stream", {}), ("snapshot", {}), ("goto_preset", {"preset": "home"})):
        _refused(http.get(f"/system/onvif_camera/{path}", params=params), 503, "no PTZ camera")


def _pose(http: httpx.Client) -> dict[str, float]:
    r = http.get("/system/onvif_camera/pose")
    assert r.status_code == 200, r.text
    got: dict[str, float] = r.json()
    return got


def _reaches(http: httpx.Client, x: float, y: float, zoom: float) -> bool:
    p = _pose(http)
    return all(abs(p[k] - v) < 1e-3 for k, v in (("x", x), ("y", y), ("zoom", zoom)))


def _ok(r: httpx.Response) -> dict[str, Any]:
    assert r.status_code == 200 and r.json()["status"] == "ok", r.text
    got: dict[str, Any] = r.json()
    return got


def test_the_camera_moves_reads_and_streams(chassis: ChassisNode, gw: GatewayNode,
                                            http: httpx.Client) -> None:
    listed: list[Any] = []

    def found() -> bool:
        listed.append(http.get("/system/onvif_cameras").json())
        return bool(listed[-1]["cameras"])

    assert wait_for(found, 20), listed[-1]
    assert listed[-1] == {"cameras": [{"ip": "127.0.0.1", "port": gw.rest_port}]}
    profile = http.get("/system/onvif_cameras", params={
        "ip": "127.0.0.1", "port": gw.rest_port, "username": "", "password": ""}).json()
    [main] = profile["profiles"]
    assert main["video_encoder"]["encoding"] == "JPEG"
    assert main["video_encoder"]["resolution"] == {"width": 160, "height": 120}
    assert main["video_source"]["framerate"] == 5.0
    assert [p["name"] for p in main["ptz"]["presets"]] == ["home", "corridor", "dock", "room"]
    _refused(http.get("/system/onvif_cameras", params={"ip": "10.0.0.9"}), 404, "10.0.0.9")

    # an absolute move reaches its target over sim time
    assert _pose(http) == {"x": 0.0, "y": 0.0, "zoom": 0.0}
    assert "moving to" in _ok(http.get("/system/onvif_camera/move",
                                       params={"x": 0.5, "y": -0.5, "zoom": 0.25}))["description"]
    assert wait_for(lambda: _reaches(http, 0.5, -0.5, 0.25), 20), _pose(http)
    for params, words in (({"x": 2}, "x (pan) must be a number in [-1, 1], got 2"),
                          ({"zoom": -0.1}, "zoom must be"), ({"y": "nan"}, "got nan"),
                          ({"x": "left"}, "x"), ({"tilt": 1}, "tilt")):
        _refused(http.get("/system/onvif_camera/move", params=params), 400, words)
    # a continuous move, then its stop: the camera stands still where the stop found it
    _ok(http.get("/system/onvif_camera/move_speed", params={"speed_x": -1}))
    assert wait_for(lambda: _pose(http)["x"] < 0.3, 20), _pose(http)
    assert _ok(http.get("/system/onvif_camera/move_speed"))["description"] == "stopped"
    link = gw.robot.context.ptz
    assert link is not None
    assert wait_for(lambda: link.state is not None and not link.state.moving, 20)
    assert link.state is not None
    still, since = _pose(http), link.state.header.stamp
    assert wait_for(lambda: link.state is not None and link.state.header.stamp > since, 20)
    assert _pose(http) == still
    _refused(http.get("/system/onvif_camera/move_speed", params={"speed_y": 3}), 400,
             "speed_y")

    # presets by name and token; an unknown one is a 404 naming them
    _ok(http.get("/system/onvif_camera/goto_preset", params={"preset": "dock"}))
    assert wait_for(lambda: _reaches(http, round(-0.846 / PAN, 4), round(-0.216 / TILT, 4),
                                     round(2 / 9, 4)), 20), _pose(http)
    _refused(http.get("/system/onvif_camera/goto_preset", params={"preset": "attic"}), 404,
             "home (1), corridor (2), dock (3), room (4)")
    _ok(http.get("/system/onvif_camera/goto_preset", params={"preset": "2"}))  # corridor
    assert wait_for(lambda: _reaches(http, round(0.48 / PAN, 4), round(-0.089 / TILT, 4),
                                     round(3 / 9, 4)), 20), _pose(http)

    # the corridor preset looks at the robot's start pose: the thermal reading is hot there
    t = http.get("/system/onvif_camera/temperature").json()["temperature"]
    [rule] = t["ThermometryRulesTemperatureInfoList"]["ThermometryRulesTemperatureInfo"]
    assert set(rule) == {"id", "maxTemperature", "minTemperature", "averageTemperature",
                         "MaxTemperaturePoint", "MinTemperaturePoint", "isFreezedata"}
    assert 35.0 <= rule["maxTemperature"] <= 40.0 and rule["minTemperature"] < 23.0
    assert rule["minTemperature"] <= rule["averageTemperature"] <= rule["maxTemperature"]
    assert 0.4 < rule["MaxTemperaturePoint"]["positionX"] < 0.6
    assert rule["id"] == 1 and rule["isFreezedata"] is False

    # a snapshot is a PNG in Pictures, listed by saved_images
    shot = http.get("/system/onvif_camera/snapshot", params={"channel": 1}, timeout=30).json()
    assert shot["snapshot"].endswith(".png"), shot
    assert shot["snapshot"] in {e["filename"] for e in http.get("/system/saved_images/").json()}
    png = http.get(f"/system/saved_images/{shot['file_timestamp']}")
    assert Image.open(io.BytesIO(png.content)).size == (160, 120)
    assert shot["url"] == f"/api/v1/system/saved_images/{shot['file_timestamp']}"
    _refused(http.get("/system/onvif_camera/snapshot", params={"channel": 2}), 404,
             "channel 1")

    # the stream: an MJPEG URL on this server, at least two JPEG parts Pillow decodes
    url = http.get("/system/onvif_camera/stream").json()["stream"]
    assert url == f"http://127.0.0.1:{gw.rest_port}/api/v1/system/onvif_camera/mjpeg"
    with httpx.stream("GET", url, timeout=30) as r:
        assert r.status_code == 200
        kind = r.headers["content-type"]
        assert kind.startswith("multipart/x-mixed-replace; boundary=")
        boundary = ("--" + kind.split("boundary=")[1]).encode()
        images = _parts(r.iter_bytes(), boundary, 2)
    for jpeg in images:
        im = Image.open(io.BytesIO(jpeg))
        assert im.format == "JPEG" and im.size == (160, 120)


def _parts(chunks: Iterator[bytes], boundary: bytes, wanted: int) -> list[bytes]:
    """The first ``wanted`` parts' bodies of a multipart stream."""
    buf, out = b"", []
    for chunk in chunks:
        buf += chunk
        while True:
            start = buf.find(boundary)
            head_end = buf.find(b"\r\n\r\n", start)
            if start < 0 or head_end < 0:
                break
            head = buf[start:head_end].decode()
            length = int(head.lower().split("content-length:")[1].split()[0])
            body = buf[head_end + 4:head_end + 4 + length]
            if len(body) < length:
                break
            out.append(body)
            buf = buf[head_end + 4 + length:]
            if len(out) == wanted:
                return out
    raise AssertionError(f"the stream ended after {len(out)} parts")


def test_configured_credentials_are_checked(chassis: ChassisNode, ctx_pair: list[Context],
                                            tmp_path: Path) -> None:
    (tmp_path / "config.json").write_text(json.dumps({"onvif_username": "cam",
                                                      "onvif_password": "secret"}))
    with running_gateway(ctx_pair[0], tmp_path, no_token_check=True) as gw, \
            httpx.Client(base_url=f"http://127.0.0.1:{gw.rest_port}/api/v1",
                         timeout=15) as http:
        assert wait_for(lambda: http.get("/system/onvif_camera/pose", params={
            "username": "cam", "password": "secret"}).status_code == 200, 20)
        _refused(http.get("/system/onvif_camera/pose"), 401, "username or password")
        _refused(http.get("/system/onvif_camera/pose", params={
            "username": "cam", "password": "guess"}), 401, "refused")
        url = http.get("/system/onvif_camera/stream", params={
            "username": "cam", "password": "secret"}).json()["stream"]
        assert url.endswith("/mjpeg?username=cam&password=secret")


def test_a_camera_move_is_a_task_that_ends_where_asked(chassis: ChassisNode, tasks: TasksNode,
                                                       gw: GatewayNode,
                                                       http: httpx.Client) -> None:
    def run(action: dict[str, Any]) -> dict[str, Any]:
        r = http.post("/task", json={"name": "look", "sub_tasks": [
            {"type": "onvif_camera_move_action", **action}]})
        assert r.status_code == 200, r.text
        assert http.get("/task/start", params={"id": r.json()["id"]}).status_code == 200
        got: list[dict[str, Any]] = []

        def ended() -> bool:
            got.append(http.get("/task", params={"id": r.json()["id"]}).json())
            return got[-1]["state"] in ("COMPLETE", "ERROR")

        assert wait_for(ended, 30), got[-1:]
        return got[-1]

    done = run({"ip": "127.0.0.1", "x": -0.25, "y": 0.5, "zoom": 0.5})
    assert done["state"] == "COMPLETE", done
    assert done["sub_tasks"][0]["progress"] == 1.0
    assert _pose(http) == {"x": -0.25, "y": 0.5, "zoom": 0.5}
    r = http.post("/task", json={"name": "bad", "sub_tasks": [
        {"type": "onvif_camera_move_action", "x": 1.5}]})
    assert r.status_code == 400 and "x" in r.json()["description"], r.text
