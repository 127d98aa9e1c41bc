"""docs/robot-api.md §3.10's readings through a real server from the simulated chassis's
actuators: the slide rail, the lift and its rotation (base_link and map), a move made on the
chassis's service showing in them, and 404 without actuators."""

from __future__ import annotations

import math
from collections.abc import Iterator

import httpx
import pytest
from zenros.context import Context
from zenros.msgs.zenros_msgs import MoveActuator, MoveActuatorRequest
from zenros.node import Node
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.testing import wait_for


@pytest.fixture
def chassis(ctx_pair: list[Context]) -> Iterator[ChassisNode]:
    node = ChassisNode(context=ctx_pair[1], parameter_overrides={
        "camera_rate": 0.0, "speed": 5.0, "jacking_angle_max_speed": 2.0})
    yield node
    node.close()


def test_no_actuators_is_a_404(gw: GatewayNode, http: httpx.Client) -> None:
    r = http.get("/system/slide_pose")
    assert r.status_code == 404 and "actuators/state" in r.json()["description"], r.text


def test_the_axes_read_and_follow_a_move(chassis: ChassisNode, gw: GatewayNode,
                                         http: httpx.Client, ctx_pair: list[Context]) -> None:
    got: list[httpx.Response] = []

    def read(path: str, **params: str) -> bool:
        got.append(http.get(path, params=params))
        return got[-1].status_code == 200

    assert wait_for(lambda: read("/system/slide_pose"), 20), got[-1].text
    assert got[-1].json() == {"zero_status": 1, "current_pose": 0.0, "pose_ratio": 0.0}
    assert read("/system/jacking_pose") and got[-1].json()["zero_status"] == 1
    assert read("/system/jacking_angle") and got[-1].json() == {
        "zero_status": 1, "current_angle": round(-math.pi, 4)}
    user = Node("user", context=ctx_pair[0])
    try:
        move = user.create_client(MoveActuator, "actuators/move")
        res = move.call(MoveActuatorRequest(name="slide", position=0.5, speed=0.3), timeout=10)
        assert res.success, res.message
        refused = move.call(MoveActuatorRequest(name="jacking", position=1.0), timeout=10)
        assert not refused.success and "past its travel" in refused.message
        assert move.call(MoveActuatorRequest(name="jacking_rotation", position=0.5, speed=2.0),
                         timeout=10).success
    finally:
        user.close()
    assert wait_for(lambda: read("/system/slide_pose")
                    and got[-1].json()["current_pose"] == 0.5, 20), got[-1].text
    assert got[-1].json()["pose_ratio"] == 0.5
    assert wait_for(lambda: read("/system/jacking_angle", frame_id="base_link")
                    and got[-1].json()["current_angle"] == 0.5, 20), got[-1].text
    # in map: plus the robot's heading, which only nav knows (not running here)
    r = http.get("/system/jacking_angle", params={"frame_id": "map"})
    assert r.status_code == 503 and "pose in map is unknown" in r.json()["description"], r.text
    gw.core.state.pose = (1.0, 2.0, 3.0)  # as nav's robot_pose would set it
    assert read("/system/jacking_angle", frame_id="map")
    assert got[-1].json()["current_angle"] == round(3.5 - 2 * math.pi, 4)  # wrapped
    r = http.get("/system/jacking_angle", params={"frame_id": "odom"})
    assert r.status_code == 400 and "frame_id" in r.json()["description"], r.text
