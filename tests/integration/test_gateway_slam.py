"""The gateway's /map/... rows (docs/robot-api.md §5) on the real mapping node
(`zenros.services.slam`), with the simulated chassis at 10x and nav: the map grows as the
robot drives, the pose, the tracks, /system/info and the §7 states follow the node.
(Saving needs nav's ``map_server/save_grid``: tests/system/test_mapping_flow.py.)"""

from __future__ import annotations

import io
from collections.abc import Iterator

import pytest
from PIL import Image
from sim_robot import GatewayRobot, gateway_robot
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.services.slam.node import SlamNode
from zenros.testing import wait_for

TIMEOUT = 30.0


@pytest.fixture(scope="module")
def robot(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[GatewayRobot, SlamNode]]:
    home = tmp_path_factory.mktemp("gwslam")
    with gateway_robot(home) as robot:
        slam = SlamNode("slam", context=robot.contexts[1], parameter_overrides={
            "use_sim_time": True, "graph_dir": str(home / "slam"),
            "maps_dir": str(home / "maps")})
        try:
            assert robot.gw.graph.wait_for_service("/slam/start", TIMEOUT)
            yield robot, slam
        finally:
            slam.close()


def info(robot: GatewayRobot) -> dict[str, float]:
    mapping: dict[str, float] = robot.http.get("/system/info").json()["mapping"]
    return mapping


def test_the_map_grows_as_the_robot_drives(robot: tuple[GatewayRobot, SlamNode]) -> None:
    r, _ = robot
    http = r.http
    started = http.get("/map/start").json()
    assert started["result"] is True, started
    assert wait_for(lambda: http.get("/system/status").json()["status"] == "Mapping", TIMEOUT)
    assert wait_for(lambda: http.get("/map/current_map_image").status_code == 200, TIMEOUT)
    first = info(r)["area_m2"]
    pub = r.user.create_publisher(Twist, "cmd_vel", 10)
    start = http.get("/map/pose").json()
    assert abs(start["x"]) < 0.2 and abs(start["y"]) < 0.2  # the map's frame: where it started

    def ahead() -> bool:
        pub.publish(Twist(linear=Vector3(x=0.4)))
        return bool(http.get("/map/pose").json()["x"] > 1.5)

    assert wait_for(ahead, TIMEOUT, interval=0.1)
    pub.publish(Twist())
    assert wait_for(lambda: info(r)["area_m2"] > first, TIMEOUT)
    meta = http.get("/map/current_map_image").json()["map_params"]
    png = Image.open(io.BytesIO(http.get("/map/current_map_png").content))
    assert png.size == (meta["width"], meta["height"])
    assert wait_for(lambda: len(http.get("/map/track", params={"keyframes": "true"})
                                .json()["trajectory"]) >= 2, TIMEOUT)
    assert len(http.get("/map/track").json()["trajectory"]) >= 10  # a point every 5 cm
    assert info(r)["state"] == "mapping" and info(r)["nodes"] >= 2
    stopped = http.get("/map/stop").json()
    assert stopped["result"] is True, stopped
    assert wait_for(lambda: http.get("/system/status").json()["status"] == "Free", TIMEOUT)
    assert http.get("/map/current_map_png").status_code == 409


def test_save_with_a_bad_name_never_reaches_the_node(
        robot: tuple[GatewayRobot, SlamNode]) -> None:
    r, _ = robot
    assert r.http.get("/map/start").json()["result"] is True
    try:
        for name in ("", "../x", "a/b"):
            res = r.http.post("/map/current_map_image", json={"name": name})
            assert res.status_code == 400 and res.json()["result"] is False
    finally:
        assert r.http.get("/map/stop").json()["result"] is True
