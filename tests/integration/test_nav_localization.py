"""Localisation with the chassis' odometry noise on, at 10x: the scan matcher keeps the
estimate within 0.1 m of the truth over a drive across the office, while odometry alone
drifts further; initialpose puts the estimate where it is told."""

from __future__ import annotations

import math
from collections.abc import Iterator

import pytest
from zenros.action import ActionClient, GoalStatus
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import PoseWithCovarianceStamped
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.msgs.nav_msgs import Odometry
from zenros.node import Node
from zenros.services.chassis.node import ChassisNode
from zenros.services.nav.convert import pose_stamped, pose_with_covariance
from zenros.services.nav.node import NavNode
from zenros.services.nav.se2 import Pose2
from zenros.testing import linked_contexts, wait_for

ODOM_NOISE = 0.3


@pytest.fixture
def noisy(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[ChassisNode, NavNode,
                                                                      Node]]:
    with linked_contexts(3) as ctxs:
        chassis = ChassisNode("chassis", context=ctxs[0], parameter_overrides={
            "speed": 10.0, "seed": 7, "odom_noise": ODOM_NOISE})
        nav = user = None
        try:
            nav = NavNode("nav", context=ctxs[1], parameter_overrides={
                "use_sim_time": True, "maps_dir": str(tmp_path_factory.mktemp("maps")),
                "localization": "scan_match"})
            user = Node("user", context=ctxs[2])
            yield chassis, nav, user
        finally:
            for n in (user, nav, chassis):
                if n is not None:
                    n.close()


def test_scan_matcher_keeps_the_estimate_on_the_truth(
        noisy: tuple[ChassisNode, NavNode, Node]) -> None:
    chassis, nav, user = noisy
    errors: list[float] = []
    drift: list[float] = []
    latest: dict[str, Odometry] = {}

    def on_truth(msg: Odometry) -> None:
        latest["truth"] = msg
        est = nav.core.localizer.pose_at(msg.header.stamp.nanoseconds)
        odom = latest.get("odom")
        p = msg.pose.pose.position
        if est is not None:
            errors.append(math.hypot(est.x - p.x, est.y - p.y))
        if odom is not None:  # odom's origin is the start pose, the map origin
            o = odom.pose.pose.position
            drift.append(math.hypot(o.x - p.x, o.y - p.y))

    user.create_subscription(Odometry, "odom", lambda m: latest.__setitem__("odom", m))
    user.create_subscription(Odometry, "sim/ground_truth", on_truth)
    client = ActionClient(user, NavigateToPose, "navigate_to_pose")
    assert client.wait_for_server(10)
    assert wait_for(lambda: len(errors) > 10, 10)
    for x, y in ((22.0, -5.0), (5.0, 4.0)):
        goal = NavigateToPoseGoal(pose=pose_stamped(Pose2(x, y), Time()))
        out = client.send_goal(goal, timeout=50)
        assert out.status is GoalStatus.SUCCEEDED, out.result
    assert nav.core.localizer.corrections > 50
    print(f"scan_match error: max {max(errors):.3f} m; odometry alone drifted "
          f"{max(drift):.3f} m")
    assert max(errors) < 0.1
    assert max(drift) > 0.1  # the noise is real: without the matcher it would be off


def test_initialpose_sets_the_estimate(noisy: tuple[ChassisNode, NavNode, Node]) -> None:
    _, nav, user = noisy
    pub = user.create_publisher(PoseWithCovarianceStamped, "initialpose")
    assert pub.wait_for_subscribers(1, 10)
    pub.publish(pose_with_covariance(Pose2(0.05, -0.05, 0.03), Time(), 0.01, 0.01))

    def near() -> bool:
        p = nav.core.localizer.pose()
        return p is not None and math.hypot(p.x - 0.05, p.y + 0.05) < 0.02

    assert wait_for(near, 10)
    assert nav.core.localizer.mode == "scan_match"  # the matcher keeps running
