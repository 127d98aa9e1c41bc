"""Nav's behavior server actions over real Zenoh with the simulated chassis at 10x:
drive_on_heading, backup and spin move the robot's ground truth as asked, with Nav2's
feedback, INVALID_INPUT, TIMEOUT and COLLISION_AHEAD; a cancel stops the robot;
local_move_target reaches a pose given in base_link; malformed goals are rejected."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

import pytest
from zenros.action import ActionClient, GoalStatus
from zenros.errors import GoalRejectedError
from zenros.msgs.builtin_interfaces import Duration
from zenros.msgs.geometry_msgs import Point, Pose2D
from zenros.msgs.nav2_msgs import (
    BackUp,
    BackUpGoal,
    DriveOnHeading,
    DriveOnHeadingGoal,
    DriveOnHeadingResult,
    Spin,
    SpinGoal,
)
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs import (
    LocalMoveTarget,
    LocalMoveTargetGoal,
    LocalMoveTargetResult,
    Obstacle,
    SetObstacles,
    SetObstaclesRequest,
    Teleport,
    TeleportRequest,
)
from zenros.node import Node
from zenros.services.chassis.node import ChassisNode
from zenros.services.nav.node import NavNode
from zenros.testing import linked_contexts, wait_for
from zenros.tf.quaternion import quaternion_from_yaw, yaw_from_quaternion


class Rig:
    def __init__(self, nav: NavNode, user: Node) -> None:
        self.nav = nav
        self.pose = (math.nan, math.nan, math.nan)
        user.create_subscription(Odometry, "sim/ground_truth", self._on_truth)
        self.teleport = user.create_client(Teleport, "sim/teleport")
        self.obstacles = user.create_client(SetObstacles, "sim/set_obstacles")
        self.drive = ActionClient(user, DriveOnHeading, "drive_on_heading")
        self.backup = ActionClient(user, BackUp, "backup")
        self.spin = ActionClient(user, Spin, "spin")
        self.target = ActionClient(user, LocalMoveTarget, "local_move_target")

    def _on_truth(self, msg: Odometry) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.pose = (p.x, p.y, yaw_from_quaternion((q.x, q.y, q.z, q.w)))

    def reset(self) -> None:
        assert wait_for(lambda: self.nav.core.motion.active is None, 10)
        self.obstacles.call(SetObstaclesRequest(op="clear"), timeout=10)
        assert self.teleport.call(TeleportRequest(pose=Pose2D()), timeout=10).success
        assert wait_for(lambda: math.hypot(*self.pose[:2]) < 0.01 and abs(self.pose[2]) < 0.01,
                        10)


@pytest.fixture(scope="module")
def module_rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    with linked_contexts(3) as ctxs:
        nodes: list[Node] = []
        try:
            nodes.append(ChassisNode("chassis", context=ctxs[0],
                                     parameter_overrides={"speed": 10.0}))
            nav = NavNode("nav", context=ctxs[1], parameter_overrides={
                "use_sim_time": True, "maps_dir": str(tmp_path_factory.mktemp("maps"))})
            nodes.append(nav)
            user = Node("user", context=ctxs[2])
            nodes.append(user)
            rig = Rig(nav, user)
            for client in (rig.drive, rig.backup, rig.spin, rig.target):
                assert client.wait_for_server(10)
            assert wait_for(lambda: nav.core.localizer.pose() is not None, 10)
            yield rig
        finally:
            for n in reversed(nodes):
                n.close()


@pytest.fixture
def rig(module_rig: Rig) -> Rig:
    module_rig.reset()
    return module_rig


def test_drive_spin_backup_move_the_robot(rig: Rig) -> None:
    feedback: list[float] = []
    res = rig.drive.send_goal(DriveOnHeadingGoal(target=Point(x=0.6), speed=0.3,
                                                 time_allowance=Duration.from_seconds(30)),
                              lambda m: feedback.append(m.feedback.distance_traveled), 30)
    assert res.status is GoalStatus.SUCCEEDED and res.result.error_code == 0
    assert abs(rig.pose[0] - 0.6) < 0.02 and abs(rig.pose[1]) < 0.02
    assert feedback and 0 < max(feedback) <= 0.61
    assert res.result.total_elapsed_time.to_sec() >= 1.5  # 0.6 m at <= 0.3 m/s, sim time
    res = rig.spin.send_goal(SpinGoal(target_yaw=-math.pi / 2), None, 30)
    assert res.status is GoalStatus.SUCCEEDED
    assert abs(rig.pose[2] + math.pi / 2) < 0.05
    res = rig.backup.send_goal(BackUpGoal(target=Point(x=0.25), speed=0.15), None, 30)
    assert res.status is GoalStatus.SUCCEEDED
    assert math.hypot(rig.pose[0] - 0.6, rig.pose[1] - 0.25) < 0.02  # facing -y, backing


@pytest.mark.parametrize(("goal", "words"), [
    (DriveOnHeadingGoal(target=Point(x=0.5), speed=-0.2), "same sign"),
    (DriveOnHeadingGoal(target=Point(x=0.5, y=0.1), speed=0.2), "along x"),
    (DriveOnHeadingGoal(target=Point(x=0.5), speed=0.0), "non-zero"),
])
def test_invalid_input(module_rig: Rig, goal: DriveOnHeadingGoal, words: str) -> None:
    res = module_rig.drive.send_goal(goal, None, 10)
    assert res.status is GoalStatus.ABORTED
    assert res.result.error_code == DriveOnHeadingResult.INVALID_INPUT
    assert words in res.result.error_msg


def test_timeout_collision_and_cancel(rig: Rig) -> None:
    res = rig.drive.send_goal(DriveOnHeadingGoal(
        target=Point(x=2.0), speed=0.2, time_allowance=Duration.from_seconds(1.0)), None, 30)
    assert res.status is GoalStatus.ABORTED
    assert res.result.error_code == DriveOnHeadingResult.TIMEOUT
    rig.reset()
    rig.obstacles.call(SetObstaclesRequest(obstacles=[
        Obstacle(id="box", shape="box", x=0.8, size_x=0.2, size_y=1.0)]), timeout=10)
    res = rig.drive.send_goal(DriveOnHeadingGoal(target=Point(x=1.5), speed=0.3), None, 30)
    assert res.status is GoalStatus.ABORTED
    assert res.result.error_code == DriveOnHeadingResult.COLLISION_AHEAD
    assert rig.pose[0] < 0.6
    handle = rig.spin.send_goal_async(SpinGoal(target_yaw=20.0))
    assert wait_for(lambda: rig.nav.core.motion.active is not None, 10)
    handle.cancel()
    assert handle.result(10).status is GoalStatus.CANCELED
    assert wait_for(lambda: rig.nav.core.motion.active is None, 5)


def test_local_move_target_in_base_link(rig: Rig) -> None:
    goal = LocalMoveTargetGoal(xy_tolerance=0.02, yaw_tolerance=0.03)
    goal.pose.header.frame_id = "base_link"
    goal.pose.pose.position.x, goal.pose.pose.position.y = 0.5, -0.3
    q = goal.pose.pose.orientation
    q.x, q.y, q.z, q.w = quaternion_from_yaw(1.0)
    res = rig.target.send_goal(goal, None, 60)
    assert res.status is GoalStatus.SUCCEEDED, res.result
    assert math.hypot(rig.pose[0] - 0.5, rig.pose[1] + 0.3) < 0.04
    assert abs(rig.pose[2] - 1.0) < 0.05
    goal.pose.header.frame_id = "elsewhere"
    res = rig.target.send_goal(goal, None, 10)
    assert res.result.error_code == LocalMoveTargetResult.INVALID_INPUT


@pytest.mark.parametrize(("client", "goal"), [
    ("spin", SpinGoal(target_yaw=math.nan)),
    ("drive", DriveOnHeadingGoal(target=Point(x=math.inf), speed=0.2)),
    ("backup", BackUpGoal(target=Point(x=0.2), speed=math.nan)),
])
def test_malformed_goals_are_rejected(module_rig: Rig, client: str, goal: Any) -> None:
    with pytest.raises(GoalRejectedError, match="finite"):
        getattr(module_rig, client).send_goal(goal, None, 10)
