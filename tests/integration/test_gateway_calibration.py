"""docs/robot-api.md §3.3's calibrations through a real server and the simulated chassis:
the IMU's gyro bias measured and taken off the ``imu`` topic's readings; the laser's mount
error found by the robot driving itself (a turn, a straight move), CALIBRATED until complete
puts it on /tf_static; the front camera's focal length and yaw found facing a board (put in
the world through sim/set_obstacles), complete puts them in its CameraInfo; refusals with the
reason; 503 without a chassis."""

from __future__ import annotations

import math
from collections.abc import Iterator

import httpx
import pytest
from zenros.context import Context
from zenros.msgs.sensor_msgs import CameraInfo, Imu
from zenros.msgs.tf2_msgs import TFMessage
from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.msgs.zenros_msgs import SetObstacles, SetObstaclesRequest
from zenros.node import Node
from zenros.qos import QOS_SENSOR
from zenros.se2 import Pose2
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for
from zenros.tf.listener import STATIC_LISTENER_QOS

BIAS = 0.02  # rad/s
ERROR = (0.05, -0.03, 0.08)  # the laser's mount error: x, y (m), yaw (rad)


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_rate": 0.0, "actuators": False, "speed": 10.0, "seed": 2,
        "imu_gyro_bias": BIAS, "laser_error_x": ERROR[0], "laser_error_y": ERROR[1],
        "laser_error_yaw": ERROR[2], "range_noise": 0.01, "odom_noise": 0.02})
    yield node
    node.close()


def test_no_chassis_is_a_503(gw: GatewayNode, http: httpx.Client) -> None:
    r = http.get("/system/calibrate_laser/status")
    assert r.status_code == 503 and "calibration/command" in r.json()["description"], r.text


def test_the_imu_calibration_takes_the_bias_off_the_readings(
        chassis: ChassisNode, gw: GatewayNode, http: httpx.Client,
        ctx_pair: list[Context]) -> None:
    user = Node("imu_listener", context=ctx_pair[0])
    heard: list[Imu] = []
    try:
        user.create_subscription(Imu, "imu", heard.append, QOS_SENSOR)
        assert wait_for(lambda: len(heard) > 20, 20)
        assert abs(sum(m.angular_velocity.z for m in heard[-20:]) / 20 - BIAS) < 0.005
        assert wait_for(lambda: http.get("/system/calibrate_laser/status").status_code == 200,
                        20)
        r = http.get("/system/calibrate_imu")
        assert r.status_code == 200 and r.json()["result"] is True, r.text
        assert r.json()["gyro_bias"] == pytest.approx(BIAS, abs=0.001)
        n = len(heard)
        assert wait_for(lambda: len(heard) > n + 50, 20)
        after = heard[n + 10:]
        assert abs(sum(m.angular_velocity.z for m in after) / len(after)) < 0.001
        assert heard[-1].orientation_covariance[0] == -1.0  # no orientation (REP 145)
    finally:
        user.close()


def test_the_laser_calibration_drives_measures_and_applies(
        chassis: ChassisNode, gw: GatewayNode, http: httpx.Client,
        ctx_pair: list[Context]) -> None:
    assert wait_for(lambda: http.get("/system/calibrate_laser/status").status_code == 200, 20)
    r = http.get("/system/calibrate_laser/status")
    assert r.json()["status"] == "FREE" and r.json()["applied"] == {
        "x": 0.1, "y": 0.0, "yaw": 0.0}, r.text
    r = http.get("/system/calibrate_laser/complete")
    assert r.status_code == 409 and "only a CALIBRATED one" in r.json()["description"]
    r = http.get("/system/calibrate_laser/start")
    assert r.status_code == 200 and r.json()["status"] == "CALIBRATING", r.text
    r = http.get("/system/calibrate_laser/start")
    assert r.status_code == 409 and "running already" in r.json()["description"]
    seen: list[dict[str, object]] = []

    def calibrated() -> bool:
        doc = http.get("/system/calibrate_laser/status").json()
        seen.append(doc)
        assert doc["status"] in ("CALIBRATING", "CALIBRATED"), doc
        return bool(doc["status"] == "CALIBRATED")
    assert wait_for(calibrated, 60, interval=0.2), seen[-1]
    assert any(0 < float(d["progress"]) < 0.9 for d in seen)  # type: ignore[arg-type]
    result = seen[-1]["result"]
    assert isinstance(result, dict)
    want = (0.1 + ERROR[0], ERROR[1], ERROR[2])
    assert math.hypot(result["x"] - want[0], result["y"] - want[1]) < 0.01, result
    assert abs(result["yaw"] - want[2]) < 0.005, result

    user = Node("tf_static_listener", context=ctx_pair[0])
    static: list[TFMessage] = []
    try:
        user.create_subscription(TFMessage, "/tf_static", static.append, STATIC_LISTENER_QOS)
        r = http.get("/system/calibrate_laser/complete")
        assert r.status_code == 200 and r.json()["status"] == "FREE", r.text
        assert r.json()["applied"] == pytest.approx(result)

        def laser_link() -> float | None:
            for msg in reversed(static):
                for t in msg.transforms:
                    if t.child_frame_id == "laser":
                        return float(t.transform.translation.x)
            return None
        assert wait_for(lambda: laser_link() == pytest.approx(result["x"]), 10), laser_link()
    finally:
        user.close()
    r = http.get("/system/calibrate_laser/cancel")
    assert r.status_code == 409 and "no laser calibration to cancel" in r.json()["description"]


def test_the_camera_calibration_faces_a_board_and_applies_the_lens(
        ctx_pair: list[Context], gw: GatewayNode, http: httpx.Client) -> None:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_rate": 10.0, "actuators": False, "speed": 10.0, "seed": 3,
        "camera_error_f": 0.06, "camera_error_yaw": -0.05, "ptz_camera": False})
    user = Node("camera_info_listener", context=ctx_pair[0])
    try:
        assert wait_for(lambda: http.get("/system/calibrate_camera/status").status_code == 200,
                        20)
        r = http.get("/system/calibrate_camera/start")
        assert r.status_code == 409 and "no calibration board" in r.json()["description"]
        assert http.get("/system/calibrate_camera/start",
                        params={"camera_id": 2}).status_code == 404
        obstacles = user.create_client(SetObstacles, "sim/set_obstacles")
        here = node.sim.truth
        board = here * Pose2(2.0, 0.0, 0.0)
        res = obstacles.call(SetObstaclesRequest(obstacles=[ObstacleMsg(
            id="board", shape="box", x=board.x, y=board.y, theta=here.theta, size_x=0.05,
            size_y=0.8)]), timeout=10)
        assert res.success, res.message
        r = http.get("/system/calibrate_camera/start")
        assert r.status_code == 200 and r.json()["result"] == "CALIBRATING", r.text

        def calibrated() -> bool:
            doc = http.get("/system/calibrate_camera/status").json()
            assert doc["status"] in ("CALIBRATING", "CALIBRATED"), doc
            return bool(doc["status"] == "CALIBRATED")
        assert wait_for(calibrated, 60, interval=0.2)
        doc = http.get("/system/calibrate_camera/status").json()
        nominal = doc["applied"]["f"]
        assert doc["result"]["f"] == pytest.approx(nominal * 1.06, rel=0.01), doc
        assert doc["result"]["yaw"] == pytest.approx(-0.05, abs=0.003) and doc["accuracy"] > 50
        infos: list[CameraInfo] = []
        user.create_subscription(CameraInfo, "camera_node/camera_info", infos.append,
                                 QOS_SENSOR)
        assert http.get("/system/calibrate_camera/complete").json()["status"] == "FREE"
        assert wait_for(lambda: bool(infos) and infos[-1].k[0] == pytest.approx(
            doc["result"]["f"]), 20)
    finally:
        user.close()
        node.close()
