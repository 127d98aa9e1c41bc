"""The gateway's docs/robot-api.md §6.10 local moves and §3.8 IO against the simulated robot
(chassis at 10x, nav, tasks): the robot's ground truth moves as asked, IO set through REST reads
back, an io_action in a task sets the chassis's output, bad parameters are §1.2 4xx bodies."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest
from pymodbus.client import ModbusTcpClient
from sim_robot import GatewayRobot, gateway_robot
from zenros.msgs.geometry_msgs import Pose2D
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs import (
    Obstacle,
    SetObstacles,
    SetObstaclesRequest,
    Teleport,
    TeleportRequest,
)
from zenros.services.chassis.devices import IoDevice
from zenros.testing import wait_for
from zenros.tf.quaternion import yaw_from_quaternion

POINTS = "2 0 0 0 0.1 0.1 0 first\n1.5 0.5 0 1.57 0.1 0.1 0 second\n"
DONE = ("COMPLETE", "ERROR", "CANCELLED")


class Rig:
    def __init__(self, robot: GatewayRobot) -> None:
        self.gw, self.nav, self.chassis, self.http = robot.gw, robot.nav, robot.chassis, robot.http
        user = robot.user
        self.pose: tuple[float, float, float] | None = None
        user.create_subscription(Odometry, "sim/ground_truth", self._on_truth)
        self.teleport = user.create_client(Teleport, "sim/teleport")
        self.obstacles = user.create_client(SetObstacles, "sim/set_obstacles")

    def _on_truth(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.pose = (p.x, p.y, yaw_from_quaternion((q.x, q.y, q.z, q.w)))

    def reset(self) -> None:
        self.http.get("/task/stop")
        assert wait_for(lambda: self.nav.core.motion.active is None, 10)
        self.obstacles.call(SetObstaclesRequest(op="clear"), timeout=10)
        assert self.teleport.call(TeleportRequest(pose=Pose2D()), timeout=10).success
        assert wait_for(lambda: self.pose is not None and math.hypot(*self.pose[:2]) < 0.02
                        and abs(self.pose[2]) < 0.02, 10)

    def finish(self, task: dict[str, Any], timeout: float = 40) -> dict[str, Any]:
        box: list[dict[str, Any]] = []

        def done() -> bool:
            t = self.http.get("/task", params={"id": task["id"]}).json()
            box[:] = [t]
            return t["state"] in DONE

        assert wait_for(done, timeout), box
        return box[0]


@pytest.fixture(scope="module")
def module_rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    tmp = tmp_path_factory.mktemp("rig")  # removed by pytest (it keeps the last 3 runs)
    with gateway_robot(tmp) as robot:
        assert robot.gw.graph.wait_for_service("/chassis/set_io", 10)
        robot.add_nav_points(robot.nav.core.maps.current, "p1", POINTS)
        yield Rig(robot)


@pytest.fixture
def rig(module_rig: Rig) -> Rig:
    module_rig.reset()
    return module_rig


def test_local_move_drives_and_turns(rig: Rig) -> None:
    r = rig.http.get("/navigation/start_local_move", params={"distance": 0.5, "angle": 1.57})
    assert r.status_code == 200, r.text
    task = r.json()
    assert task["state"] == "WORKING" and task["name"] == "local move task"
    assert [a["type"] for a in task["sub_tasks"]] == ["local_move_action"]
    done = rig.finish(task)
    assert done["state"] == "COMPLETE", done
    assert rig.pose is not None
    x, y, th = rig.pose
    assert abs(x - 0.5) < 0.03 and abs(y) < 0.03, rig.pose
    assert abs(th - 1.57) < 0.06, rig.pose


def test_method_1_turns_first(rig: Rig) -> None:
    r = rig.http.get("/navigation/start_local_move",
                     params={"distance": -0.3, "angle": 0.8, "method": 1})
    assert r.status_code == 200, r.text
    assert rig.finish(r.json())["state"] == "COMPLETE"
    assert rig.pose is not None
    x, y, th = rig.pose
    assert math.hypot(x + 0.3 * math.cos(0.8), y + 0.3 * math.sin(0.8)) < 0.04, rig.pose
    assert abs(th - 0.8) < 0.06


def test_local_move_stops_before_an_obstacle(rig: Rig) -> None:
    rig.obstacles.call(SetObstaclesRequest(obstacles=[
        Obstacle(id="wall", shape="box", x=0.9, y=0.0, size_x=0.2, size_y=1.0)]), timeout=10)
    r = rig.http.get("/navigation/start_local_move", params={"distance": 1.5})
    done = rig.finish(r.json())
    assert done["state"] == "ERROR"
    result = done["sub_tasks"][0]["result"]
    assert "collision ahead" in result and "723" in result, result
    assert rig.pose is not None and rig.pose[0] < 0.7  # stopped short of touching it


def test_stop_cancels_a_local_move(rig: Rig) -> None:
    r = rig.http.get("/navigation/start_local_move", params={"angle": 12.0})
    task = r.json()
    assert wait_for(lambda: rig.nav.core.motion.active is not None, 10)
    assert rig.http.get("/task/stop", params={"id": task["id"]}).status_code == 200
    assert rig.finish(task)["state"] == "CANCELLED"
    assert wait_for(lambda: rig.nav.core.motion.active is None, 5)


def test_local_move_target_and_index(rig: Rig) -> None:
    r = rig.http.get("/navigation/start_local_move_target", params={
        "x": 0.6, "y": 0.3, "theta": -1.0, "frame_id": "base_link", "xy_tolerance": 0.03,
        "yaw_tolerance": 0.05, "timeout": 60, "start_rotate_enable": "true",
        "target_rotate_enable": "true"})
    assert r.status_code == 200, r.text
    assert r.json()["sub_tasks"][0]["type"] == "local_move_target_action"
    assert rig.finish(r.json())["state"] == "COMPLETE"
    assert rig.pose is not None
    x, y, th = rig.pose
    assert math.hypot(x - 0.6, y - 0.3) < 0.05 and abs(th + 1.0) < 0.08, _poses(rig)
    r = rig.http.get("/navigation/start_local_move_index", params={"index": 1})
    assert r.status_code == 200, r.text
    assert rig.finish(r.json())["state"] == "COMPLETE"
    x, y, th = rig.pose
    assert math.hypot(x - 1.5, y - 0.5) < 0.08 and abs(th - 1.57) < 0.08, _poses(rig)


def _poses(rig: Rig) -> str:
    """The truth and nav's estimate, for a failure: which of the two was off (a flake seen
    at sim speed 10: the heading 0.15-0.23 rad past the target)."""
    est = rig.nav.core.localizer.pose()
    return (f"truth {rig.pose}, nav's estimate "
            f"{None if est is None else (est.x, est.y, est.theta)}")


def test_io_through_rest(rig: Rig) -> None:
    http = rig.http
    assert http.post("/system/io", json={"level": "1", "port": "2"}).json() == {"status": "ok"}
    assert http.get("/system/io").json() == {"status": "ok", "out1": "0", "out2": "1",
                                             "out3": "0"}
    io = rig.chassis.device(IoDevice)
    assert io is not None and io.io.snapshot()[0] == [0, 1, 0]
    assert http.post("/system/io", json={"level": "0", "port": "2"}).status_code == 200
    assert http.get("/system/io").json()["out2"] == "0"
    r = http.put("/system/bw_io", json={"level": 1, "port": 7})
    assert r.status_code == 200, r.text
    bw = http.get("/system/bw_io").json()
    assert bw["out"]["7"] == 1 and bw["out"]["0"] == 0 and len(bw["in"]) == 16
    # Modbus discrete inputs 23-30 are the extension board's outputs 0-7 (§14.1)
    client = ModbusTcpClient("127.0.0.1", port=rig.gw.modbus_port)
    try:
        assert client.connect()

        def output_7() -> bool:
            bits = client.read_discrete_inputs(0, count=30, device_id=1).bits
            return bool(bits[29]) and not any(bits[6:29])
        assert wait_for(output_7, 5)
    finally:
        client.close()
    http.put("/system/bw_io", json={"level": 0, "port": 7})


def test_io_action_in_a_task(rig: Rig) -> None:
    http = rig.http
    r = http.post("/task", json={"name": "io", "sub_tasks": [
        {"type": "io_action", "level": "1", "port": "3"}]})
    assert r.status_code == 200, r.text
    task = r.json()
    http.get("/task/start", params={"id": task["id"]})
    done = rig.finish(task)
    assert done["state"] == "COMPLETE", done
    assert http.get("/system/io").json()["out3"] == "1"
    # navigate to a nav point, move, then set an output: the spec's three actions
    r = http.get("/navigation/start_nav_local_move_io", params={
        "index": 0, "distance": 0.2, "angle": 0, "level": "0", "port": "3"})
    assert r.status_code == 200, r.text
    assert [a["type"] for a in r.json()["sub_tasks"]] == ["nav_action", "local_move_action",
                                                         "io_action"]
    assert rig.finish(r.json(), 60)["state"] == "COMPLETE"
    # /system/io reports the chassis's latched IoState topic, which arrives a moment later
    assert wait_for(lambda: http.get("/system/io").json()["out3"] == "0", 10)
    assert rig.pose is not None and math.hypot(rig.pose[0] - 2.2, rig.pose[1]) < 0.2


@pytest.mark.parametrize(("method", "path", "kw", "code", "words"), [
    ("GET", "/navigation/start_local_move", {"params": {"distance": "far"}}, 400,
     "distance"),
    ("GET", "/navigation/start_local_move", {"params": {"method": 2}}, 400, "method"),
    ("GET", "/navigation/start_local_move", {"params": {"distance": "nan"}}, 400,
     "distance"),
    ("GET", "/navigation/start_local_move", {"params": {"speed": 1}}, 400, "speed"),
    ("GET", "/navigation/start_local_move_target", {"params": {"y": 1}}, 400, "x"),
    ("GET", "/navigation/start_local_move_target",
     {"params": {"x": 1, "y": 1, "frame_id": "odom"}}, 400, "frame_id"),
    ("GET", "/navigation/start_nav_and_local_move", {"params": {"index": 9}}, 404,
     "does not exist"),
    ("GET", "/navigation/start_nav_local_move_io", {"params": {"index": 0, "port": "1"}},
     400, "level"),
    ("POST", "/system/io", {"json": {"level": "1", "port": "4"}}, 400, "port"),
    ("POST", "/system/io", {"json": {"level": "high", "port": "1"}}, 400, "level"),
    ("PUT", "/system/bw_io", {"json": {"level": 1, "port": 8}}, 400, "port"),
])
def test_bad_parameters(module_rig: Rig, method: str, path: str, kw: dict[str, Any],
                        code: int, words: str) -> None:
    r = module_rig.http.request(method, path, **kw)
    assert r.status_code == code, r.text
    body = r.json()
    assert body["status"] == "error" and words in body["description"], body


def test_io_action_with_a_bad_port_is_refused(module_rig: Rig) -> None:
    r = module_rig.http.post("/task", json={"sub_tasks": [
        {"type": "io_action", "level": "1", "port": "9"}]})
    assert r.status_code == 400 and "port" in r.json()["description"]


def test_pause_and_resume_drive_only_what_is_left(rig: Rig) -> None:
    # a move long enough that the pause lands well short of its end on a loaded box
    r = rig.http.get("/navigation/start_local_move", params={"distance": 2.0, "angle": 0.5})
    task = r.json()
    assert wait_for(lambda: rig.pose is not None and rig.pose[0] > 0.3, 20)
    assert rig.http.get("/task/pause", params={"id": task["id"]}).json()["state"] == "PAUSED"
    assert wait_for(lambda: rig.nav.core.motion.active is None, 5)
    assert rig.pose is not None and rig.pose[0] < 1.8
    assert rig.http.get("/task/resume", params={"id": task["id"]}).status_code == 200
    assert rig.finish(task)["state"] == "COMPLETE"
    x, y, th = rig.pose
    assert abs(x - 2.0) < 0.04 and abs(y) < 0.03 and abs(th - 0.5) < 0.06, rig.pose
