"""The mapping node over real Zenoh: the simulated chassis at 10x with odometry and range
noise, the slam node, and a stand-in nav answering nav/set_mapping_mode and
map_server/save_grid as the contract says nav does (docs/mapping.md)."""

from __future__ import annotations

import math
import shutil
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import zenoh
from zenros.codec import codec_for
from zenros.msgs.geometry_msgs import Twist, Vector3
from zenros.msgs.geometry_msgs import Pose2D
from zenros.msgs.nav_msgs import OccupancyGrid, Odometry
from zenros.msgs.nav_msgs import Path as PathMsg
from zenros.msgs.tf2_msgs import TFMessage
from zenros.msgs.zenros_msgs import slam as sm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.services.chassis.node import ChassisNode
from zenros.services.nav.params import DEMO_MAP
from zenros.services.slam.node import SlamNode
from zenros.testing import linked_contexts, wait_for

SPEED = 10.0


class StandInNav:
    """What nav answers in the mapping contract, recording the requests."""

    def __init__(self, node: Node) -> None:
        self.modes: list[sm.SetMappingModeRequest] = []
        self.saved: list[sm.SaveGridRequest] = []
        self.refuse = ""
        node.create_service(sm.SetMappingMode, "nav/set_mapping_mode", self.on_mode)
        node.create_service(sm.SaveGrid, "map_server/save_grid", self.on_save)

    def on_mode(self, req: sm.SetMappingModeRequest) -> sm.SetMappingModeResponse:
        self.modes.append(req)
        if req.enable and self.refuse:
            return sm.SetMappingModeResponse(code=ResultCode.CONFLICT, message=self.refuse)
        return sm.SetMappingModeResponse()

    def on_save(self, req: sm.SaveGridRequest) -> sm.SaveGridResponse:
        self.saved.append(req)
        return sm.SaveGridResponse(name=req.name)


class Rig:
    def __init__(self, slam: SlamNode, user: Node, graphs: Path) -> None:
        self.slam, self.user, self.graphs = slam, user, graphs
        self.nav = StandInNav(user)
        self.maps: list[OccupancyGrid] = []
        self.states: list[sm.MappingState] = []
        self.tracks: list[PathMsg] = []
        self.map_to_odom: list[TFMessage] = []
        self.truth: list[Odometry] = []
        user.create_subscription(Odometry, "sim/ground_truth", self.truth.append)
        user.create_subscription(OccupancyGrid, "map", self.maps.append, QOS_LATCHED)
        user.create_subscription(sm.MappingState, "slam/state", self.states.append, QOS_LATCHED)
        user.create_subscription(PathMsg, "slam/track", self.tracks.append, QOS_LATCHED)
        user.create_subscription(TFMessage, "/tf", self._on_tf)
        self.start = user.create_client(sm.StartMapping, "slam/start")
        self.stop = user.create_client(sm.StopMapping, "slam/stop")
        self.save = user.create_client(sm.SaveSlamMap, "slam/save")
        self.cmd = user.create_publisher(Twist, "cmd_vel")

    def _on_tf(self, msg: TFMessage) -> None:
        if any(t.header.frame_id == "map" and t.child_frame_id == "odom" for t in msg.transforms):
            self.map_to_odom.append(msg)

    def drive(self, v: float, w: float, sim_seconds: float) -> None:
        """Send cmd_vel for ``sim_seconds`` of sim time (the slam node's clock), then stop."""
        end = self.sim_time() + sim_seconds
        give_up = time.monotonic() + 60
        while self.sim_time() < end and time.monotonic() < give_up:
            self.cmd.publish(Twist(linear=Vector3(x=v), angular=Vector3(z=w)))
            time.sleep(0.005)
        self.cmd.publish(Twist())

    def sim_time(self) -> float:
        return self.slam.now().nanoseconds / 1e9

    @property
    def state(self) -> sm.MappingState:
        return self.states[-1]


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    graphs = tmp_path_factory.mktemp("slam")
    maps = tmp_path_factory.mktemp("maps")
    (maps / "office").mkdir()
    for f in DEMO_MAP.parent.iterdir():  # nav's store: a map built elsewhere, no pose graph
        shutil.copy(f, maps / "office" / f.name.replace(DEMO_MAP.stem, "office"))
    with linked_contexts(3) as ctxs:
        chassis = ChassisNode("chassis", context=ctxs[0], parameter_overrides={
            "speed": SPEED, "seed": 3, "odom_noise": 0.05, "range_noise": 0.02})
        slam = user = None
        try:
            slam = SlamNode("slam", context=ctxs[1], parameter_overrides={
                "use_sim_time": True, "graph_dir": str(graphs), "maps_dir": str(maps)})
            user = Node("user", context=ctxs[2])
            r = Rig(slam, user, graphs)
            assert r.start.wait_for_service(10) and r.save.wait_for_service(10)
            assert wait_for(lambda: r.states and r.state.state == "idle", 10)
            yield r
        finally:
            for n in (user, slam, chassis):
                if n is not None:
                    n.close()


def test_maps_saves_stops_and_continues(rig: Rig) -> None:
    # nothing mapped: save refused, the node idle, its timers (map -> odom, map, state) too
    res = rig.save.call(sm.SaveSlamMapRequest(name="early"), timeout=10)
    assert res.code == ResultCode.CONFLICT, res
    timers = rig.slam._mapping_timers
    assert len(timers) == 3 and all(t.is_canceled() for t in timers) and not rig.map_to_odom
    res = rig.start.call(sm.StartMappingRequest(), timeout=10)
    assert res.code == ResultCode.OK, res.message
    assert rig.nav.modes[-1].enable
    assert wait_for(lambda: rig.state.state == "mapping", 10)
    assert not any(t.is_canceled() for t in timers)
    again = rig.start.call(sm.StartMappingRequest(), timeout=10)
    assert again.code == ResultCode.CONFLICT and "already" in again.message

    driver = threading.Thread(target=rig.drive, args=(0.5, 0.0, 5.0))
    driver.start()
    driver.join()
    assert wait_for(lambda: rig.state.nodes >= 5, 20), rig.state
    assert wait_for(lambda: rig.maps and (rig.maps[-1].grid() == 0).sum() > 1000, 20)
    grid = rig.maps[-1]
    assert grid.header.frame_id == "map" and grid.info.resolution == pytest.approx(0.05)
    assert (grid.grid() == 100).sum() > 100
    assert wait_for(lambda: rig.map_to_odom, 10)
    assert wait_for(lambda: rig.tracks and len(rig.tracks[-1].poses) >= 5, 10)
    # the robot drove ~2.5 m along +x from the map's origin (its start pose)
    assert wait_for(lambda: rig.state.pose.x > 1.5, 10), rig.state.pose
    assert abs(rig.state.pose.y) < 0.2

    for bad in ("", "../etc", "a/b"):
        res = rig.save.call(sm.SaveSlamMapRequest(name=bad), timeout=10)
        assert res.code == ResultCode.INVALID, (bad, res)
    res = rig.save.call(sm.SaveSlamMapRequest(name="site2"), timeout=20)
    assert res.code == ResultCode.OK, res.message
    assert (rig.graphs / "site2.posegraph").is_file()
    assert rig.nav.saved[-1].name == "site2" and rig.nav.saved[-1].grid.info.width > 50
    nodes = rig.state.nodes

    res = rig.stop.call(sm.StopMappingRequest(), timeout=10)
    assert res.code == ResultCode.OK, res.message
    off = rig.nav.modes[-1]
    assert not off.enable and off.map_name == "site2" and off.use_map_to_odom
    assert wait_for(lambda: rig.state.state == "idle", 10)
    assert rig.slam.map_pub is None  # no latched SLAM map left beside nav's
    assert all(t.is_canceled() for t in timers)
    assert rig.stop.call(sm.StopMappingRequest(), timeout=10).code == ResultCode.CONFLICT
    maps_before = len(rig.maps)

    res = rig.start.call(sm.StartMappingRequest(map_name="nope"), timeout=10)
    assert res.code == ResultCode.NOT_FOUND, res
    res = rig.start.call(sm.StartMappingRequest(map_name="../x"), timeout=10)
    assert res.code == ResultCode.INVALID, res
    res = rig.start.call(sm.StartMappingRequest(mode="fly"), timeout=10)
    assert res.code == ResultCode.INVALID, res

    # continue the saved graph where it ended
    res = rig.start.call(sm.StartMappingRequest(map_name="site2"), timeout=10)
    assert res.code == ResultCode.OK, res.message
    assert wait_for(lambda: rig.state.state == "mapping" and rig.state.map_name == "site2", 10)
    assert wait_for(lambda: rig.state.nodes > nodes, 20), rig.state
    assert rig.state.pose.x > 1.5
    assert wait_for(lambda: len(rig.maps) > maps_before, 20)
    assert rig.stop.call(sm.StopMappingRequest(), timeout=10).code == ResultCode.OK


def test_nav_refusal_is_passed_on(rig: Rig) -> None:
    rig.nav.refuse = "a goal is being driven"
    try:
        res = rig.start.call(sm.StartMappingRequest(), timeout=10)
    finally:
        rig.nav.refuse = ""
    assert res.code == ResultCode.CONFLICT and "goal" in res.message
    assert wait_for(lambda: rig.state.state == "idle" and "goal" in rig.state.message, 10)


def test_garbage_requests_are_refused_and_the_node_keeps_serving(rig: Rig) -> None:
    ctx = rig.user.context
    for client, typ, wrong in ((rig.start, sm.StartMappingRequest, b'{"mode": ["laser"]}'),
                               (rig.save, sm.SaveSlamMapRequest, b'{"name": 5}')):
        codec = codec_for(typ)
        enc = zenoh.Encoding(codec.mime).with_schema(codec.type_name)
        for payload in (b"{not json", wrong, b"\xff\x00", b"[1, 2]"):
            replies = list(ctx.session.get(client.key, payload=payload, encoding=enc,
                                           timeout=5.0, target=zenoh.QueryTarget.BEST_MATCHING))
            assert len(replies) == 1 and replies[0].err is not None, payload
    assert rig.state.state == "idle"
    res = rig.save.call(sm.SaveSlamMapRequest(name="x"), timeout=10)
    assert res.code == ResultCode.CONFLICT  # still answering, still nothing mapped


def test_extends_a_stored_map_with_no_pose_graph(rig: Rig) -> None:
    assert wait_for(lambda: rig.truth, 10)
    p = rig.truth[-1].pose.pose
    truth = (p.position.x, p.position.y, 2 * math.atan2(p.orientation.z, p.orientation.w))
    res = rig.start.call(sm.StartMappingRequest(map_name="office"), timeout=10)
    assert res.code == ResultCode.INVALID and "initial_pose" in res.message
    # told a pose 0.25 m and 3 degrees off: the first scan is relocalised on the stored walls
    guess = Pose2D(x=truth[0] + 0.2, y=truth[1] - 0.15, theta=truth[2] + 0.05)
    res = rig.start.call(sm.StartMappingRequest(map_name="office", initial_pose=guess,
                                                use_initial_pose=True), timeout=10)
    assert res.code == ResultCode.OK, res.message
    try:
        assert wait_for(lambda: rig.state.state == "mapping" and rig.state.nodes >= 1, 20)
        pose = rig.state.pose
        # within two cells of the stored 5 cm grid (its walls are cell centres)
        assert math.hypot(pose.x - truth[0], pose.y - truth[1]) < 0.1, (pose, truth)
        assert abs(pose.theta - truth[2]) < 0.02
        # the stored map is the first layer: the whole office is known at once
        assert wait_for(lambda: rig.maps and rig.state.area_m2 > 300, 20), rig.state
    finally:
        assert rig.stop.call(sm.StopMappingRequest(), timeout=10).code == ResultCode.OK
