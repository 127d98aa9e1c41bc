"""The ``explore`` node over real Zenoh: the chassis at 5x in a small world it has never
seen (two rooms and a corridor), nav in mapping mode, a stand-in SLAM node growing the map
from the scans (tests/integration/standin_slam.py), and the explorer driving nav's
navigate_to_pose until no frontier is left, then back to the start. Also: a goal with no map
fails with NO_MAP, cancel stops the robot, bad goals are rejected.

5x, not the 10x of most integration rigs: the whole exploration is hundreds of nav and SLAM
cycles, and at 10x CI's loaded 2-core box failed it in two of its last three runs."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import pytest
from standin_slam import TruthMapper, coverage, reachable_free
from worlds import small_world
from zenros.action import ActionClient, GoalStatus
from zenros.errors import GoalRejectedError
from zenros.maps import load_map
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.slam import (
    Explore,
    ExploreFeedback,
    ExploreGoal,
    SetMappingMode,
    SetMappingModeRequest,
)
from zenros.node import Node
from zenros.se2 import Pose2
from zenros.services.chassis.node import ChassisNode
from zenros.services.explore.explorer import NO_MAP
from zenros.services.explore.node import ExploreNode
from zenros.services.nav.node import NavNode
from zenros.testing import linked_contexts, wait_for

# a whole exploration at 5x: 20-50 s quiet, past the suite's 60 s a test on a loaded box
pytestmark = pytest.mark.timeout(300)


@pytest.fixture
def rig(tmp_path: Path) -> Iterator[tuple[ChassisNode, NavNode, ExploreNode, Node, Path]]:
    world = small_world(tmp_path / "world")
    with linked_contexts(4) as ctxs:
        nodes: list[Node] = []
        try:
            nodes.append(ChassisNode("chassis", context=ctxs[0], parameter_overrides={
                "speed": 5.0, "seed": 5, "map": str(world)}))
            nodes.append(NavNode("nav", context=ctxs[1], parameter_overrides={
                "use_sim_time": True, "maps_dir": str(tmp_path / "maps"), "map": str(world)}))
            nodes.append(ExploreNode("explore", context=ctxs[2], parameter_overrides={
                "use_sim_time": True}))
            nodes.append(Node("user", context=ctxs[3]))
            chassis, nav, explore, user = nodes  # type: ignore[misc]
            yield chassis, nav, explore, user, world  # type: ignore[misc]
        finally:
            for n in reversed(nodes):
                n.close()


@pytest.mark.parametrize("gated", [False, True], ids=["every_scan", "karto_gating"])
def test_explore_maps_a_small_world_and_comes_back(
        rig: tuple[ChassisNode, NavNode, ExploreNode, Node, Path], gated: bool) -> None:
    """With Karto's gating the first map has no free cell: the explorer turns round once."""
    _, nav, _, user, world_path = rig
    world = load_map(world_path)
    explore = ActionClient(user, Explore, "explore")
    mode = user.create_client(SetMappingMode, "nav/set_mapping_mode")
    assert explore.wait_for_server(10) and mode.wait_for_service(10)
    truth: list[Pose2] = []
    user.create_subscription(Odometry, "sim/ground_truth", lambda m: truth.append(Pose2(
        m.pose.pose.position.x, m.pose.pose.position.y, 0.0)))

    # bad goals are rejected; with no map the goal fails at once
    with pytest.raises(GoalRejectedError):
        explore.send_goal(ExploreGoal(progress_timeout=math.nan), timeout=10)

    assert mode.call(SetMappingModeRequest(enable=True), timeout=10).code == ResultCode.OK
    mapper = TruthMapper(user, world, period=0.5, gated=gated)
    mapper.start()
    assert wait_for(lambda: mapper.published > 0 and nav.core.localizer.pose() is not None, 20)
    if gated:
        first = mapper.grid()
        assert first is not None and not (first.grid == 0).any()
    feedback: list[ExploreFeedback] = []
    out = explore.send_goal(ExploreGoal(), feedback_callback=lambda m: feedback.append(
        m.feedback), timeout=400)
    assert out.status is GoalStatus.SUCCEEDED, out.result
    res = out.result
    built = mapper.grid()
    assert built is not None
    # coverage: the free cells the robot could reach, known in the built map (same frame)
    cov = coverage(world, built, reachable_free(world, (0.0, 0.0)))
    print(f"explored: coverage {cov:.3f}, {res.goals_reached} goals reached, "
          f"{res.goals_failed} failed, {res.explored_area_m2:.1f} m2")
    assert cov >= 0.95
    targets = {(round(f.target.x, 1), round(f.target.y, 1)) for f in feedback
               if f.stage == "exploring" and f.frontiers_left > 0}
    assert res.explored_area_m2 > 60 and res.goals_reached >= 1 and len(targets) >= 2
    assert feedback[-1].stage == "returning"
    # back where it started (the truth samples may lag a little behind on a loaded box)
    assert wait_for(lambda: math.hypot(truth[-1].x, truth[-1].y) < 0.5, 10), truth[-1]


def test_explore_without_a_map_fails_and_cancel_stops_the_robot(
        rig: tuple[ChassisNode, NavNode, ExploreNode, Node, Path]) -> None:
    _, nav, explorer, user, world_path = rig
    explorer.set_parameter("wait_for_map", 1.0)
    explore = ActionClient(user, Explore, "explore")
    mode = user.create_client(SetMappingMode, "nav/set_mapping_mode")
    assert explore.wait_for_server(10) and mode.wait_for_service(10)
    # in mapping mode nav no longer serves `map` and no SLAM node does yet: the explorer does
    # not explore the map it got from nav before
    assert wait_for(lambda: explorer._inputs()[0] is not None, 10)
    assert mode.call(SetMappingModeRequest(enable=True), timeout=10).code == ResultCode.OK
    out = explore.send_goal(ExploreGoal(), timeout=30)
    assert out.status is GoalStatus.ABORTED and out.result.error_code == NO_MAP
    assert "no map" in out.result.error_msg

    mapper = TruthMapper(user, load_map(world_path), period=0.5)
    mapper.start()
    handle = explore.send_goal_async(ExploreGoal())
    assert wait_for(lambda: nav.core.motion.active is not None, 30)
    assert handle.cancel()
    res = handle.result(timeout=30)
    assert res.status is GoalStatus.CANCELED
    assert wait_for(lambda: nav.core.motion.active is None, 10)
