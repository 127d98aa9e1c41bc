"""docs/robot-api.md §3.10 through a real server from the simulated chassis's actuators: the
readings of the slide rail, the lift and its rotation (base_link and map), a move made on the
chassis's service showing in them, 404 without actuators; the moves as tasks of the real tasks
service (slide_action, jacking_action, jacking_rotate_action), refusals before any task."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import httpx
import pytest
from zenros.context import Context
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped
from zenros.msgs.zenros_msgs import MoveActuator, MoveActuatorRequest
from zenros.node import Node
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.node import GatewayNode
from zenros.services.tasks.node import TasksNode
from zenros.testing import wait_for
from zenros.tf.quaternion import quaternion_from_yaw


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


def test_moves_are_tasks_that_end_where_asked(chassis: ChassisNode, tasks: TasksNode,
                                              gw: GatewayNode, http: httpx.Client,
                                              ctx_pair: list[Context]) -> None:
    def ok(path: str, **params: Any) -> dict[str, Any]:
        r = http.get(path, params=params)
        assert r.status_code == 200, r.text
        return dict(r.json())

    def ended(task: dict[str, Any]) -> dict[str, Any]:
        got: list[dict[str, Any]] = []
        assert wait_for(lambda: got.append(ok("/task", id=task["id"])) or
                        got[-1]["state"] in ("COMPLETE", "ERROR", "CANCELLED"), 30), got[-1:]
        return got[-1]

    assert wait_for(lambda: http.get("/system/slide_pose").status_code == 200, 20)
    task = ok("/system/slide_move_to", pose=0.6, speed=0.3)
    assert task["name"] == "slide_task" and task["state"] == "WORKING", task
    action = task["sub_tasks"][0]
    assert (action["type"], action["mode"], action["pose"], action["speed"]) == (
        "slide_action", 3, 0.6, 0.3)
    done = ended(task)
    assert done["state"] == "COMPLETE" and done["sub_tasks"][0]["progress"] == 1.0, done
    assert ok("/system/slide_pose")["current_pose"] == 0.6
    lift = ended(ok("/system/jacking_move_to", pose=0.05))  # the default speed
    assert lift["state"] == "COMPLETE" and ok("/system/jacking_pose")["current_pose"] == 0.05
    turn = ended(ok("/system/jacking_angle_move_to", angle=1.0, speed=2.0))
    assert turn["state"] == "COMPLETE", turn
    assert ok("/system/jacking_angle") == {"zero_status": 1, "current_angle": 1.0}
    # refused at once, with the reason, and no task made
    before = len(http.get("/task").json())
    for path, params, code, words in (
            ("/system/slide_move_to", {"pose": 1.5}, 400, "past its travel [0, 1]"),
            ("/system/jacking_move_to", {"pose": 0.03, "speed": 0.5}, 400,
             "above its maximum 0.05"),
            ("/system/slide_move_to", {}, 400, "pose"),
            ("/system/slide_move_to", {"pose": "up"}, 400, "pose"),
            ("/system/jacking_angle_move_to", {"angle": 4.0}, 400, "past its travel"),
            ("/system/jacking_angle_move_to", {"angle": 1.0, "frame_id": "map"}, 503,
             "pose in map is unknown")):
        r = http.get(path, params=params)
        assert r.status_code == code and words in r.json()["description"], (path, r.text)
    assert len(http.get("/task").json()) == before
    # in map: the robot heads 3 rad (nav's robot_pose), so map 1.0 is -2.0 in base_link
    user = Node("pose_source", context=ctx_pair[0])
    try:
        pose = PoseWithCovarianceStamped()
        pose.header.frame_id = "map"
        q = pose.pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(3.0)
        pub = user.create_publisher(PoseWithCovarianceStamped, "robot_pose", 10)
        user.create_timer(0.1, lambda: pub.publish(pose))  # as nav does
        assert wait_for(lambda: gw.core.state.pose is not None, 10)
        turn = ended(ok("/system/jacking_angle_move_to", angle=1.0, speed=2.0,
                        frame_id="map"))
        assert turn["state"] == "COMPLETE", turn["sub_tasks"][0]["result"]
        assert ok("/system/jacking_angle") == {"zero_status": 1, "current_angle": -2.0}
        assert ok("/system/jacking_angle", frame_id="map")["current_angle"] == 1.0
    finally:
        user.close()
    # a speed move into the end of the travel: the limit switch stops it, the task errs
    r = http.post("/task", json={"name": "run", "sub_tasks": [
        {"type": "slide_action", "mode": 1, "speed": 0.3, "time": 10}]})
    assert r.status_code == 200, r.text
    ok("/task/start", id=r.json()["id"])
    failed = ended(r.json())
    assert failed["state"] == "ERROR", failed
    assert "reached its high limit (1)" in failed["sub_tasks"][0]["result"], failed
    assert ok("/system/slide_pose")["current_pose"] == 1.0
    # homing is a move too: back to 0
    r = http.post("/task", json={"name": "home", "sub_tasks": [
        {"type": "slide_action", "mode": 0}]})
    ok("/task/start", id=r.json()["id"])
    assert ended(r.json())["state"] == "COMPLETE"
    assert ok("/system/slide_pose") == {"zero_status": 1, "current_pose": 0.0,
                                        "pose_ratio": 0.0}


def test_a_stopped_move_task_stops_the_axis(chassis: ChassisNode, tasks: TasksNode,
                                            gw: GatewayNode, http: httpx.Client) -> None:
    assert wait_for(lambda: http.get("/system/slide_pose").status_code == 200, 20)
    task = http.get("/system/slide_move_to", params={"pose": 1.0, "speed": 0.02}).json()
    assert task["state"] == "WORKING", task
    assert wait_for(lambda: http.get("/system/slide_pose").json()["current_pose"] > 0.01, 20)
    # a new move of the same axis replaces the running one
    again = http.get("/system/slide_move_to", params={"pose": 0.9, "speed": 0.02}).json()
    assert again["state"] == "WORKING", again
    assert http.get("/task", params={"id": task["id"]}).json()["state"] == "CANCELLED"
    r = http.get("/task/stop", params={"id": again["id"]})
    assert r.status_code == 200, r.text
    here = http.get("/system/slide_pose").json()["current_pose"]
    assert here < 0.9
    # stopped: it stays where it is (not moving on to 0.9 at 0.1 m/s sim)
    reads = [http.get("/system/slide_pose").json()["current_pose"] for _ in range(5)]
    assert max(reads) - min(reads) < 0.005, reads
