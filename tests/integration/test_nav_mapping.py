"""Nav's side of mapping over real Zenoh, with the chassis at 10x and a real robot's noise
(odom_noise 0.05, range_noise 0.02): mapping mode with a stand-in SLAM node (nav refuses it
while driving, hands over ``map`` and ``map -> odom``, drives on the SLAM map, takes them
back), save_grid, and navigation on a built map (its frame not the world's) by scan
matching: goals in the built map's frame reached where they are in the world."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import pytest
from standin_slam import map_to_odom_tf, reframe
from zenros.action import ActionClient, GoalStatus
from zenros.maps import GridMap, load_map
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Pose2D, PoseWithCovarianceStamped
from zenros.msgs.nav2_msgs import NavigateToPose, NavigateToPoseGoal, SaveMap, SaveMapRequest
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.tf2_msgs import TFMessage
from zenros.msgs.zenros_msgs.nav import NavStatus
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.slam import (
    SaveGrid,
    SaveGridRequest,
    SetMappingMode,
    SetMappingModeRequest,
)
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.se2 import Pose2
from zenros.services.chassis.node import ChassisNode
from zenros.services.nav.actions.convert import pose_stamped, pose_with_covariance
from zenros.services.nav.node import NavNode
from zenros.services.nav.params import DEMO_MAP
from zenros.testing import linked_contexts, wait_for

# where the built map's frame is in the world (a robot that started mapping elsewhere)
B_IN_WORLD = Pose2(1.5, -0.8, 0.35)
GOAL_TOLERANCE = 0.25


@pytest.fixture
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[ChassisNode, NavNode,
                                                                    Node]]:
    with linked_contexts(3) as ctxs:
        chassis = ChassisNode("chassis", context=ctxs[0], parameter_overrides={
            "speed": 10.0, "seed": 11, "odom_noise": 0.05, "range_noise": 0.02})
        nav = user = None
        try:
            nav = NavNode("nav", context=ctxs[1], parameter_overrides={
                "use_sim_time": True, "maps_dir": str(tmp_path_factory.mktemp("maps"))})
            user = Node("user", context=ctxs[2])
            yield chassis, nav, user
        finally:
            for n in (user, nav, chassis):
                if n is not None:
                    n.close()


def _pose(msg: Odometry) -> Pose2:
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    return Pose2(p.x, p.y, 2 * math.atan2(q.z, q.w))


class Truth:
    """The simulator's true pose (latest), and its recent poses by stamp."""

    def __init__(self, user: Node, topic: str = "sim/ground_truth") -> None:
        self.pose: Pose2 | None = None
        self.by_stamp: dict[int, Pose2] = {}
        user.create_subscription(Odometry, topic, self)

    def __call__(self, msg: Odometry) -> None:
        self.pose = _pose(msg)
        self.by_stamp[msg.header.stamp.nanoseconds] = self.pose
        if len(self.by_stamp) > 400:
            del self.by_stamp[next(iter(self.by_stamp))]


def latched_map(user: Node) -> GridMap:
    """The ``map`` a late joiner gets (one sample expected)."""
    got: list[OccupancyGrid] = []
    sub = user.create_subscription(OccupancyGrid, "map", got.append, QOS_LATCHED)
    try:
        assert wait_for(lambda: bool(got), 10)
    finally:
        user.destroy(sub)
    return GridMap.from_msg(got[-1])


def drive(client: ActionClient, goal_b: Pose2, truth: Truth) -> float:
    """Drive to ``goal_b`` (built frame); how far the robot ends from it in the world."""
    out = client.send_goal(NavigateToPoseGoal(pose=pose_stamped(goal_b, Time())), timeout=90)
    assert out.status is GoalStatus.SUCCEEDED, out.result
    want = B_IN_WORLD * goal_b
    assert truth.pose is not None
    return math.hypot(truth.pose.x - want.x, truth.pose.y - want.y)


def test_mapping_mode_hands_over_the_map_and_the_transform(
        rig: tuple[ChassisNode, NavNode, Node]) -> None:
    _, nav, user = rig
    truth = Truth(user)
    mode = user.create_client(SetMappingMode, "nav/set_mapping_mode")
    navigate = ActionClient(user, NavigateToPose, "navigate_to_pose")
    assert navigate.wait_for_server(10) and mode.wait_for_service(10)
    assert wait_for(lambda: nav.core.localizer.pose() is not None, 10)
    statuses: list[NavStatus] = []
    user.create_subscription(NavStatus, "nav/status", statuses.append, QOS_LATCHED)

    # refused while a goal is driven
    handle = navigate.send_goal_async(NavigateToPoseGoal(pose=pose_stamped(Pose2(22.0, 0.0),
                                                                           Time())))
    assert wait_for(lambda: nav.core.motion.active is not None, 10)
    res = mode.call(SetMappingModeRequest(enable=True), timeout=10)
    assert res.code == ResultCode.CONFLICT and "busy" in res.message
    assert not nav.core.mapping
    navigate.cancel_all_goals()
    assert wait_for(lambda: nav.core.motion.active is None, 10)
    del handle

    res = mode.call(SetMappingModeRequest(enable=True), timeout=10)
    assert res.code == ResultCode.OK, res.message
    # the stand-in SLAM node: the world's map in frame B, B's map -> odom
    built = reframe(load_map(DEMO_MAP), B_IN_WORLD)
    pub = user.create_publisher(OccupancyGrid, "map", QOS_LATCHED)
    pub.publish(built.to_msg("map", user.now()))
    tf_pub = user.create_publisher(TFMessage, "/tf")
    odom_in_world = nav.core.localizer.map_to_odom  # the truth's, before mapping
    m2o = B_IN_WORLD.inverse() * odom_in_world
    nav_m2o: list[Pose2] = []

    def on_tf(msg: TFMessage) -> None:
        for t in msg.transforms:
            if t.child_frame_id == "odom":
                tr = t.transform.translation
                nav_m2o.append(Pose2(tr.x, tr.y, 0.0))

    user.create_subscription(TFMessage, "/tf", on_tf)
    # first as if odometry had drifted 0.25 m unnoticed, corrected mid-drive (a jump)
    sent = [m2o * Pose2(0.2, -0.15, 0.04)]
    timer = user.create_timer(0.05, lambda: tf_pub.publish(map_to_odom_tf(sent[0], user.now())))
    assert wait_for(lambda: nav.core.costmaps.ready and nav.core.localizer.pose() is not None,
                    10)
    late = latched_map(user)  # a late joiner gets the SLAM map, never nav's old one
    assert late.origin == built.origin and late.width == built.width
    assert wait_for(lambda: bool(statuses) and statuses[-1].mapping
                    and statuses[-1].map_name == "", 10)

    goal_b = B_IN_WORLD.inverse() * Pose2(5.0, 4.0, 0.0)
    handle = navigate.send_goal_async(NavigateToPoseGoal(pose=pose_stamped(goal_b, Time())))
    start = truth.pose
    assert start is not None
    assert wait_for(lambda: truth.pose is not None and truth.pose.distance(start) > 1.5, 60)
    sent[0] = m2o  # the SLAM node's correction: the pose jumps 0.25 m, the plan is redone
    seen = len(nav_m2o) + 2  # what is on /tf from here on is the correction, from nobody else
    out = handle.result(timeout=90)
    assert out.status is GoalStatus.SUCCEEDED, out.result
    want = B_IN_WORLD * goal_b
    assert truth.pose.distance(want) < GOAL_TOLERANCE  # type: ignore[union-attr]
    assert len(nav_m2o) > seen + 10
    assert all(math.hypot(p.x - m2o.x, p.y - m2o.y) < 1e-6 for p in nav_m2o[seen:])

    timer.cancel()
    user.destroy(pub)
    res = mode.call(SetMappingModeRequest(enable=False, map_name="nope"), timeout=10)
    assert res.code == ResultCode.NOT_FOUND and nav.core.mapping
    res = mode.call(SetMappingModeRequest(enable=False), timeout=10)
    assert res.code == ResultCode.OK, res.message
    assert latched_map(user).origin == (-3.0, -9.75, 0.0)  # nav's map is back
    assert wait_for(lambda: not statuses[-1].mapping and statuses[-1].map_name == "office", 10)
    # bad requests never break it
    for req in (SetMappingModeRequest(enable=False, use_map_to_odom=True,
                                      map_to_odom=Pose2D(x=math.nan)),):
        assert mode.call(req, timeout=10).code == ResultCode.INVALID


def test_navigation_on_a_built_map_by_scan_matching(
        rig: tuple[ChassisNode, NavNode, Node]) -> None:
    _, nav, user = rig
    truth = Truth(user)
    save = user.create_client(SaveGrid, "map_server/save_grid")
    mode = user.create_client(SetMappingMode, "nav/set_mapping_mode")
    navigate = ActionClient(user, NavigateToPose, "navigate_to_pose")
    assert navigate.wait_for_server(10) and save.wait_for_service(10)
    assert wait_for(lambda: truth.pose is not None and nav.core.localizer.pose() is not None,
                    10)
    built = reframe(load_map(DEMO_MAP), B_IN_WORLD)
    odom_in_world = nav.core.localizer.map_to_odom
    m2o = B_IN_WORLD.inverse() * odom_in_world
    res = save.call(SaveGridRequest(name="site2", grid=built.to_msg(), map_to_odom=Pose2D(
        x=m2o.x, y=m2o.y, theta=m2o.theta), use_map_to_odom=True), timeout=20)
    assert res.code == ResultCode.OK, res.message
    res = save.call(SaveGridRequest(name="../x", grid=built.to_msg()), timeout=10)
    assert res.code == ResultCode.INVALID
    res = save.call(SaveGridRequest(name="office", grid=built.to_msg()), timeout=10)
    assert res.code == ResultCode.CONFLICT

    # mapping just stopped: nav goes on from the SLAM node's transform, on the saved map
    assert mode.call(SetMappingModeRequest(enable=True), timeout=10).code == ResultCode.OK
    res = mode.call(SetMappingModeRequest(enable=False, map_name="site2", use_map_to_odom=True,
                                          map_to_odom=Pose2D(x=m2o.x, y=m2o.y,
                                                             theta=m2o.theta)), timeout=20)
    assert res.code == ResultCode.OK, res.message
    loc = nav.core.localizer
    assert nav.core.maps.current == "site2" and loc.mode == "scan_match"
    errors: list[float] = []
    # sampled from the first scan match on the new map on: a pose from before it is in the
    # old map's frame (beside a CPU hog the first sample, 0.2 s after the switch, was 0.5 m)
    matched = loc.corrections
    assert wait_for(lambda: loc.corrections > matched, 10), loc.corrections

    odom = Truth(user, "odom")

    def err() -> float:
        """The estimate (nav's map -> odom with the odometry) against the truth of the same
        stamp (comparing the latest of each measured how late a starved test heard them);
        inf before the two topics share a stamp."""
        for stamp in reversed(list(truth.by_stamp)):
            if stamp in odom.by_stamp:
                w = B_IN_WORLD * (loc.map_to_odom * odom.by_stamp[stamp])
                t = truth.by_stamp[stamp]
                return math.hypot(w.x - t.x, w.y - t.y)
        return math.inf

    sampler = user.create_timer(0.2, lambda: errors.append(err()))
    far: list[float] = []
    for wx, wy in ((22.0, -5.0), (5.0, 4.0), (0.5, 0.0)):
        far.append(drive(navigate, B_IN_WORLD.inverse() * Pose2(wx, wy, 0.0), truth))
    sampler.cancel()
    print(f"built map: goal errors {[round(e, 3) for e in far]} m; localisation error max "
          f"{max(errors):.3f} m over {len(errors)} samples, {loc.corrections} corrections")
    assert max(far) < GOAL_TOLERANCE
    assert max(errors) < 0.15 and loc.corrections > 50

    # relocalise from an initial pose 0.3 m / 0.15 rad off: the wide search finds the robot
    pub = user.create_publisher(PoseWithCovarianceStamped, "initialpose")
    assert pub.wait_for_subscribers(1, 10)
    assert truth.pose is not None
    here_b = B_IN_WORLD.inverse() * truth.pose
    off = Pose2(here_b.x + 0.25, here_b.y - 0.2, here_b.theta + 0.15)
    pub.publish(pose_with_covariance(off, Time(), 0.01, 0.01))
    assert wait_for(lambda: loc.relocalize, 10) or err() < 0.1
    assert wait_for(lambda: not loc.relocalize and err() < 0.08, 15), err()

    # map_saver writes the map it takes from the topic
    saver = user.create_client(SaveMap, "map_saver/save_map")
    assert saver.call(SaveMapRequest(map_url="copy"), timeout=20).result
    assert nav.core.maps.store.load("copy") == nav.core.maps.store.load("site2")
    assert not saver.call(SaveMapRequest(map_url="copy", map_topic="nothing_here"),
                          timeout=20).result
    assert not saver.call(SaveMapRequest(map_url="copy", map_topic="no good!"),
                          timeout=20).result
    assert not saver.call(SaveMapRequest(map_url="../copy"), timeout=20).result


def test_no_automatic_docking_while_mapping(tmp_path: Path) -> None:
    """The dock pose is in the saved map's frame: a low battery in mapping mode waits."""
    with linked_contexts(1) as ctxs:
        nav = NavNode("nav", context=ctxs[0], parameter_overrides={
            "maps_dir": str(tmp_path / "maps"), "auto_charge": True})
        try:
            nav.core.on_odom(1, Pose2(), 0.0, 0.0)
            nav.core.localizer.set_pose(Pose2())
            nav.core.on_battery(0.05, False)
            nav.core.enter_mapping()
            nav._maybe_autocharge(100.0)
            assert nav.core.motion.active is None
            nav.core.leave_mapping()
            nav._maybe_autocharge(200.0)
            assert nav.core.motion.active is not None  # the same battery, on its map: docks
        finally:
            nav.close()
