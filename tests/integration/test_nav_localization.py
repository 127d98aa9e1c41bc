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
from zenros.se2 import Pose2
from zenros.services.chassis.node import ChassisNode
from zenros.services.nav.actions.convert import pose_stamped, pose_with_covariance
from zenros.services.nav.node import NavNode
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
    truths: dict[int, Odometry] = {}

    def on_truth(msg: Odometry) -> None:
        truths[msg.header.stamp.nanoseconds] = msg

    def on_odom(msg: Odometry) -> None:
        # compare at the same instant: the odometry sample and the truth of its stamp
        t = truths.pop(msg.header.stamp.nanoseconds, None)
        if t is None:
            return
        o, p = msg.pose.pose, t.pose.pose.position
        odom = Pose2(o.position.x, o.position.y,
                     2 * math.atan2(o.orientation.z, o.orientation.w))
        est = nav.core.localizer.map_to_odom * odom
        errors.append(math.hypot(est.x - p.x, est.y - p.y))
        drift.append(math.hypot(odom.x - p.x, odom.y - p.y))  # odom's origin: the map's

    user.create_subscription(Odometry, "sim/ground_truth", on_truth)
    user.create_subscription(Odometry, "odom", on_odom)
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


def test_initialpose_sets_the_estimate_and_the_matcher_pulls_it_back(
        noisy: tuple[ChassisNode, NavNode, Node]) -> None:
    _, nav, user = noisy
    loc = nav.core.localizer
    nav.set_parameter("localization", "odometry")  # no matching: the pose stays as given
    pub = user.create_publisher(PoseWithCovarianceStamped, "initialpose")
    assert pub.wait_for_subscribers(1, 10)
    pub.publish(pose_with_covariance(Pose2(0.1, -0.06, 0.03), Time(), 0.01, 0.01))

    def at(x: float, y: float, tol: float) -> bool:
        p = loc.pose()
        return p is not None and math.hypot(p.x - x, p.y - y) < tol

    assert wait_for(lambda: at(0.1, -0.06, 1e-6), 10)
    nav.set_parameter("localization", "scan_match")  # the robot really stands at (0, 0)
    assert wait_for(lambda: at(0.0, 0.0, 0.02), 10)
