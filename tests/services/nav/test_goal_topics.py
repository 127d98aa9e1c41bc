"""Goals on topics (goal_pose, patrol_goal), in a deterministic run of nav on the scenario
room: a good goal drives, a bad one is logged and ignored, and nav goes on."""

from __future__ import annotations

import logging
import math
import shutil
from pathlib import Path
from typing import Any

import pytest
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import PoseStamped
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs.nav import PatrolGoal
from zenros.replay import DeterministicRun
from zenros.services.nav.node import NavNode

ROOM = Path(__file__).resolve().parents[2] / "scenarios" / "maps"
T0 = 1_000_000_000
STEP = 50_000_000


def odom(t: int, frame: str) -> Odometry:
    m = Odometry()
    m.header.stamp, m.header.frame_id = Time.from_nanoseconds(t), frame
    m.pose.pose.position.y = 1.5
    m.pose.pose.orientation.w = 1.0
    return m


def drive(tmp_path: Path, goal_topic: str, goal: Any) -> list[Any]:
    """Nav standing at (0, 1.5) for 2 s, the goal at 0.5 s; the cmd_vel it sent."""
    shutil.copytree(ROOM, tmp_path / "maps")
    cmds: list[Any] = []
    with DeterministicRun(T0, lambda topic, msg, t: cmds.append(msg) if topic == "/cmd_vel"
                          else None) as run:
        run.add_node(NavNode, parameter_overrides={
            "maps_dir": str(tmp_path / "maps"), "map": str(tmp_path / "maps/room/room.yaml")})
        t = T0
        for i in range(40):
            t += STEP
            run.deliver("/odom", odom(t, "odom"), t)
            run.deliver("/sim/ground_truth", odom(t, "map"), t)
            if i == 10:
                run.deliver(goal_topic, goal, t)
    return cmds


def pose(x: float, y: float, frame: str = "map") -> PoseStamped:
    g = PoseStamped()
    g.header.frame_id = frame
    g.pose.position.x, g.pose.position.y = x, y
    g.pose.orientation.w = 1.0
    return g


def test_a_goal_pose_drives_towards_it(tmp_path: Path) -> None:
    cmds = drive(tmp_path, "/goal_pose", pose(3.0, 1.5))
    assert cmds and max(c.linear.x for c in cmds) > 0.1


@pytest.mark.parametrize(("goal", "said"), [
    (pose(3.0, 1.5, frame="odom"), "goal_pose in frame 'odom' ignored"),
    (pose(math.nan, 1.5), "goal_pose ignored"),
])
def test_a_bad_goal_pose_is_ignored_with_a_warning(tmp_path: Path, caplog: pytest.LogCaptureFixture,
                                                   goal: PoseStamped, said: str) -> None:
    with caplog.at_level(logging.WARNING):
        cmds = drive(tmp_path, "/goal_pose", goal)
    assert cmds == []
    assert said in caplog.text


def test_a_patrol_goal_visits_the_paths_nav_points(tmp_path: Path) -> None:
    cmds = drive(tmp_path, "/patrol_goal", PatrolGoal(map_name="room", path_name="patrol",
                                                      loops=1))
    assert cmds and any(abs(c.angular.z) > 0.1 for c in cmds)  # turns to the first point


def test_a_patrol_of_an_unknown_path_is_ignored_with_a_warning(
        tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.WARNING):
        cmds = drive(tmp_path, "/patrol_goal", PatrolGoal(map_name="room", path_name="nope"))
    assert cmds == []
    assert "patrol_goal ignored: unknown path 'nope'" in caplog.text
