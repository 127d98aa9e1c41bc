"""The whole mapping flow with the real peers: the chassis at 5x (test_explore.py says why)
with a real robot's noise (odom_noise 0.05, range_noise 0.02) in a world it has never seen,
the slam node, nav and the explorer: slam/start (nav hands over the map), explore until no
frontier is left and back, slam/save, slam/stop (nav takes the map back, on the saved one),
then a goal on the built map reached where it is in the world."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import pytest
from standin_slam import coverage, reachable_free
from worlds import small_world
from zenros.action import ActionClient, GoalStatus
from zenros.maps import load_map
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs import slam as sm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.node import Node
from zenros.se2 import Pose2
from zenros.services.chassis.node import ChassisNode
from zenros.services.explore.node import ExploreNode
from zenros.services.nav.actions.convert import pose_stamped
from zenros.services.nav.node import NavNode
from zenros.services.slam.node import SlamNode
from zenros.testing import linked_contexts, wait_for

# a whole exploration at 5x: 20-50 s quiet, past the suite's 60 s a test on a loaded box
pytestmark = pytest.mark.timeout(300)


@pytest.fixture
def rig(tmp_path: Path) -> Iterator[tuple[NavNode, Node, Path]]:
    world = small_world(tmp_path / "world")
    with linked_contexts(5) as ctxs:
        nodes: list[Node] = []
        try:
            nodes.append(ChassisNode("chassis", context=ctxs[0], parameter_overrides={
                "speed": 5.0, "seed": 9, "map": str(world), "odom_noise": 0.05,
                "range_noise": 0.02}))
            nav = NavNode("nav", context=ctxs[1], parameter_overrides={
                "use_sim_time": True, "maps_dir": str(tmp_path / "maps"), "map": str(world)})
            nodes.append(nav)
            nodes.append(SlamNode("slam", context=ctxs[2], parameter_overrides={
                "use_sim_time": True, "graph_dir": str(tmp_path / "graphs")}))
            nodes.append(ExploreNode("explore", context=ctxs[3], parameter_overrides={
                "use_sim_time": True}))
            user = Node("user", context=ctxs[4])
            nodes.append(user)
            yield nav, user, world
        finally:
            for n in reversed(nodes):
                n.close()


def test_explore_save_stop_and_navigate_on_the_built_map(
        rig: tuple[NavNode, Node, Path]) -> None:
    nav, user, world_path = rig
    world = load_map(world_path)
    truth: list[Pose2] = []
    user.create_subscription(Odometry, "sim/ground_truth", lambda m: truth.append(Pose2(
        m.pose.pose.position.x, m.pose.pose.position.y, 0.0)))
    start = user.create_client(sm.StartMapping, "slam/start")
    save = user.create_client(sm.SaveSlamMap, "slam/save")
    stop = user.create_client(sm.StopMapping, "slam/stop")
    explore = ActionClient(user, sm.Explore, "explore")
    navigate = ActionClient(user, NavigateToPose, "navigate_to_pose")
    assert start.wait_for_service(20) and explore.wait_for_server(20)
    assert wait_for(lambda: bool(truth) and nav.core.localizer.pose() is not None, 20)

    res = start.call(sm.StartMappingRequest(mode="explore"), timeout=20)
    assert res.code == ResultCode.OK, res.message
    assert nav.core.mapping
    out = explore.send_goal(sm.ExploreGoal(), timeout=600)
    assert out.status is GoalStatus.SUCCEEDED, out.result
    assert wait_for(lambda: math.hypot(truth[-1].x, truth[-1].y) < 0.5, 10), truth[-1]

    res = save.call(sm.SaveSlamMapRequest(name="site2"), timeout=30)
    assert res.code == ResultCode.OK, res.message
    built = nav.core.maps.store.load("site2")
    assert nav.core.maps.store.record("site2").built_by_slam
    res = stop.call(sm.StopMappingRequest(), timeout=30)
    assert res.code == ResultCode.OK, res.message
    assert not nav.core.mapping and nav.core.maps.current == "site2"
    assert nav.core.localizer.mode == "scan_match"

    # the built map's frame is the robot's pose when mapping started: (0, 0, 0) here
    cov = coverage(world, built, reachable_free(world, (0.0, 0.0)))
    print(f"explored with slam: coverage {cov:.3f}, {out.result.goals_reached} goals")
    assert cov >= 0.95

    for x, y in ((10.5, 5.5), (3.0, 0.0)):
        goal = NavigateToPoseGoal(pose=pose_stamped(Pose2(x, y, 0.0), Time()))
        res2 = navigate.send_goal(goal, timeout=120)
        assert res2.status is GoalStatus.SUCCEEDED, res2.result
        assert wait_for(lambda: math.hypot(truth[-1].x - x, truth[-1].y - y) < 0.25, 10), \
            truth[-1]

