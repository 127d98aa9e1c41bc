"""The chassis node over real Zenoh at 10x: driving, TF, ground truth, scans, e-stop, bad input."""

from __future__ import annotations

import math
from typing import Any

import msgspec
import numpy as np
import pytest
from zenros.clock import Time
from zenros.msgs.geometry_msgs import Pose2D, Twist, Vector3
from zenros.msgs.nav_msgs import Odometry
from zenros.msgs.rosgraph_msgs import Clock
from zenros.msgs.sensor_msgs import BatteryState, LaserScan
from zenros.msgs.std_msgs import Float64, String
from zenros.msgs.std_srvs import SetBool, SetBoolRequest
from zenros.msgs.zenros_msgs import (
    ChassisState,
    Obstacle,
    SetObstacles,
    SetObstaclesRequest,
    Teleport,
    TeleportRequest,
)
from zenros.services.chassis import config
from zenros.services.chassis.device import Chassis, Device, Endpoints
from zenros.services.chassis.devices import DEVICES
from zenros.services.chassis.node import ChassisNode
from zenros.testing import wait_for
from zenros.tf import Buffer, TransformListener

SPEED = 10.0


class Latest:
    """The newest message of a topic, and how many came."""

    def __init__(self) -> None:
        self.msg: Any = None
        self.count = 0

    def __call__(self, msg: Any) -> None:
        self.msg = msg
        self.count += 1


def yaw(q: Any) -> float:
    return 2 * math.atan2(q.z, q.w)


@pytest.fixture
def rig(make_node: Any) -> dict[str, Any]:
    """The chassis at 10x in session 0; a user node in session 1 listening to everything."""
    chassis: ChassisNode = make_node("chassis", 0, cls=ChassisNode,
                                     parameter_overrides={"speed": SPEED, "seed": 1})
    user = make_node("user", 1)
    got = {name: Latest() for name in ("odom", "truth", "scan", "state", "battery", "clock")}
    user.create_subscription(Odometry, "odom", got["odom"])
    user.create_subscription(Odometry, "sim/ground_truth", got["truth"])
    user.create_subscription(LaserScan, "scan", got["scan"])
    user.create_subscription(ChassisState, "chassis/state", got["state"])
    user.create_subscription(BatteryState, "battery_state", got["battery"])
    user.create_subscription(Clock, "/clock", got["clock"])
    buffer = Buffer()
    listener = TransformListener(buffer, user)
    cmd = user.create_publisher(Twist, "cmd_vel")
    assert wait_for(lambda: all(v.count for v in got.values()), 20), \
        {k: v.count for k, v in got.items()}
    assert cmd.wait_for_subscribers(1, 10)
    return {"chassis": chassis, "user": user, "got": got, "buffer": buffer, "cmd": cmd,
            "listener": listener}


def drive(rig: dict[str, Any], v: float, w: float, until: Any, timeout: float = 20) -> bool:
    """Publish cmd_vel (every 0.1 s of sim time) until ``until()`` holds."""
    cmd, clock = rig["cmd"], rig["got"]["clock"]
    twist = Twist(linear=Vector3(x=v), angular=Vector3(z=w))
    last = [-1.0]

    def step() -> bool:
        t = clock.msg.clock.to_sec()
        if t - last[0] >= 0.1:
            cmd.publish(twist)
            last[0] = t
        return bool(until())

    return wait_for(step, timeout, interval=0.002)


def test_drive_and_odom_tf_truth_agree(rig: dict[str, Any]) -> None:
    got, buffer = rig["got"], rig["buffer"]
    start = got["truth"].msg.pose.pose.position
    assert (start.x, start.y) == (0.0, 0.0)  # the demo map's start pose
    assert drive(rig, 0.5, 0.2, lambda: got["odom"].msg.pose.pose.position.x > 1.5)
    # stop, then compare once the base has halted
    assert drive(rig, 0.0, 0.0, lambda: got["state"].msg is not None
                 and abs(got["odom"].msg.twist.twist.linear.x) < 1e-9)
    odom, truth = got["odom"].msg, got["truth"].msg
    assert odom.header.frame_id == "odom" and odom.child_frame_id == "base_link"
    assert truth.header.frame_id == "map"
    # no odom noise: odom == truth (odom starts at the start pose, here the map origin)
    assert wait_for(lambda: got["truth"].msg.header.stamp == got["odom"].msg.header.stamp, 5)
    o, t = got["odom"].msg.pose.pose, got["truth"].msg.pose.pose
    assert o.position.x == pytest.approx(t.position.x, abs=1e-9)
    assert o.position.y == pytest.approx(t.position.y, abs=1e-9)
    assert yaw(o.orientation) == pytest.approx(yaw(t.orientation), abs=1e-9)
    assert o.position.x > 1.5 and o.position.y > 0.05  # it turned left while driving
    assert odom.pose.covariance[0] > 0 and odom.twist.covariance[35] > 0
    stamp = got["odom"].msg.header.stamp
    assert buffer.can_transform("odom", "laser", stamp, timeout=5)
    tf = buffer.lookup_transform("odom", "base_link", stamp)
    assert tf.transform.translation.x == pytest.approx(o.position.x, abs=1e-9)
    laser = buffer.lookup_transform("base_link", "laser", stamp).transform.translation
    assert (laser.x, laser.z) == pytest.approx((0.1, 0.2))
    # the state names the asked speed and the factor achieved; a loaded box achieves less
    # (the pacer slows down rather than bursting), never more than asked
    state = got["state"].msg
    assert state.speed == SPEED and 0 < state.real_time_factor <= SPEED * 1.2


def test_blocked_corridor_shows_in_the_scan(rig: dict[str, Any]) -> None:
    got, user = rig["got"], rig["user"]
    client = user.create_client(SetObstacles, "sim/set_obstacles")
    ahead = int(np.argmin(np.abs(np.arange(360) * (2 * math.pi / 360) - math.pi)))  # 0 rad
    before = float(got["scan"].msg.ranges[ahead])
    assert before > 5.0  # the corridor is open to the east
    box = Obstacle(id="cart", shape="box", x=2.0, y=0.0, size_x=0.5, size_y=2.6)
    res = client.call(SetObstaclesRequest(obstacles=[box]), timeout=10)
    assert res.success, res.message
    assert [o.id for o in res.obstacles] == ["cart"]
    # laser at x = 0.1: the box's face at x = 1.75
    assert wait_for(lambda: abs(float(got["scan"].msg.ranges[ahead]) - 1.65) < 0.01, 10)
    # driving into it: stops at contact with the bumper pressed, never overlapping it
    assert drive(rig, 0.6, 0.0, lambda: got["state"].msg.bumper, 30)
    # the pose of the contact: the truth stamped no earlier than the state that told it (the
    # two topics reach a loaded test in either order)
    bumped = got["state"].msg.header.stamp
    assert wait_for(lambda: got["truth"].msg.header.stamp >= bumped, 10)
    x = got["truth"].msg.pose.pose.position.x
    assert 1.75 - 0.2 - 0.02 < x <= 1.75 - 0.2
    bad = client.call(SetObstaclesRequest(obstacles=[Obstacle(id="on", x=x, radius=0.1)]),
                      timeout=10)
    assert not bad.success and "overlap the robot" in bad.message
    gone = client.call(SetObstaclesRequest(op="remove", ids=["cart"]), timeout=10)
    assert gone.success and gone.obstacles == []
    assert wait_for(lambda: float(got["scan"].msg.ranges[ahead]) > 5.0, 10)


def test_estop_holds_and_teleport(rig: dict[str, Any]) -> None:
    got, user = rig["got"], rig["user"]
    estop = user.create_client(SetBool, "chassis/set_estop")
    assert estop.call(SetBoolRequest(data=True), timeout=10).success
    assert wait_for(lambda: got["state"].msg.estop, 5)
    t0 = got["clock"].msg.clock.to_sec()
    assert drive(rig, 0.5, 0.0, lambda: got["clock"].msg.clock.to_sec() > t0 + 2.0)
    assert got["truth"].msg.pose.pose.position.x == 0.0  # held for 2 s of commands
    assert estop.call(SetBoolRequest(data=False), timeout=10).success
    assert drive(rig, 0.5, 0.0, lambda: got["truth"].msg.pose.pose.position.x > 0.2)
    # halted before the teleport: a cmd_vel still on its way would move it off the new pose
    assert drive(rig, 0.0, 0.0, lambda: abs(got["truth"].msg.twist.twist.linear.x) < 1e-9)
    tp = user.create_client(Teleport, "sim/teleport")
    res = tp.call(TeleportRequest(pose=Pose2D(x=5.0, y=0.5, theta=1.0)), timeout=10)
    assert res.success, res.message
    assert wait_for(lambda: abs(got["truth"].msg.pose.pose.position.x - 5.0) < 1e-6, 5)
    wall = tp.call(TeleportRequest(pose=Pose2D(x=2.0, y=1.25)), timeout=10)
    assert not wall.success and "does not fit" in wall.message


def test_bad_cmd_vel_is_refused_and_the_robot_stops(rig: dict[str, Any],
                                                     caplog: pytest.LogCaptureFixture) -> None:
    got, user = rig["got"], rig["user"]
    assert drive(rig, 0.5, 0.0, lambda: got["truth"].msg.twist.twist.linear.x > 0.3)
    rig["cmd"].publish(Twist(linear=Vector3(x=math.nan)))
    assert wait_for(lambda: got["truth"].msg.twist.twist.linear.x == 0.0, 5)
    assert "cmd_vel refused, stopping: non-finite" in caplog.text
    assert drive(rig, 0.5, 0.0, lambda: got["truth"].msg.twist.twist.linear.x > 0.3)
    rig["cmd"].publish(Twist(linear=Vector3(x=1e6)))
    assert wait_for(lambda: got["truth"].msg.twist.twist.linear.x == 0.0, 5)
    assert "far beyond the limits" in caplog.text
    assert drive(rig, 0.5, 0.0, lambda: got["truth"].msg.twist.twist.linear.x > 0.3)
    wrong = user.create_publisher(String, "cmd_vel")
    wrong.publish(String(data="go"))
    assert wait_for(lambda: got["truth"].msg.twist.twist.linear.x == 0.0, 5)
    assert "not a geometry_msgs/Twist" in caplog.text
    assert rig["chassis"]._thread.is_alive()


def test_robots_sharing_a_world_see_each_other_and_forget_a_gone_one(make_node: Any) -> None:
    """Two chassis on one world_topic: each one's laser sees the other's body straight ahead;
    when one stops, it leaves the other's world."""
    world = {"world_topic": "/sim/world", "speed": SPEED, "seed": 1}
    make_node("chassis", 0, cls=ChassisNode, namespace="/robot1",
              parameter_overrides={**world, "start_pose": [0.0, 0.0, 0.0]})
    two = make_node("chassis", 0, cls=ChassisNode, namespace="/robot2",
                    parameter_overrides={**world, "start_pose": [1.5, 0.0, math.pi]})
    user = make_node("user", 1)
    scans = {r: Latest() for r in ("robot1", "robot2")}
    for r, latest in scans.items():
        user.create_subscription(LaserScan, f"/{r}/scan", latest)

    def ahead(r: str) -> float:
        msg = scans[r].msg
        if msg is None:
            return math.nan
        i = round((0.0 - msg.angle_min) / msg.angle_increment)
        return float(msg.ranges[i])

    # the laser is 0.1 m ahead of the centre, the other body's surface 1.5 - 0.2 m away
    assert wait_for(lambda: abs(ahead("robot1") - 1.2) < 0.05
                    and abs(ahead("robot2") - 1.2) < 0.05, 20), \
        (ahead("robot1"), ahead("robot2"))
    two.close()
    assert wait_for(lambda: ahead("robot1") > 2.0, 20), ahead("robot1")


class TripParameters(msgspec.Struct, kw_only=True, frozen=True):
    trip_rate: float = 4.0


class TripMeter(Device[TripParameters]):
    """A device that is not in the registry: the distance driven, on ``trip`` (std_msgs/Float64)
    at ``trip_rate``; ``trip/reset`` (std_srvs/SetBool) zeroes it."""

    Parameters = TripParameters

    def __init__(self, params: TripParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.rate = params.trip_rate
        self.metres = 0.0

    def open(self, node: Endpoints) -> None:
        self.pub = node.create_publisher(Float64, "trip")
        node.serve(SetBool, "trip/reset", self.reset)

    def reset(self, req: SetBoolRequest) -> SetBool.Response:
        self.metres = 0.0
        return SetBool.Response(success=True, message="")

    def step(self, dt: float) -> None:
        self.metres += abs(self.chassis.sim.linear) * dt

    def publish(self, stamp: Time) -> None:
        self.pub.publish(Float64(data=self.metres))


def test_a_registered_device_gets_its_parameters_topic_rate_and_service(
        make_node: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(config, "DEVICES", (*DEVICES, TripMeter))
    chassis: ChassisNode = make_node("chassis", 0, cls=ChassisNode, parameter_overrides={
        "speed": SPEED, "trip_rate": 2.0})
    assert chassis.get_parameter("trip_rate") == 2.0
    user = make_node("user", 1)
    trip, clock = Latest(), Latest()
    user.create_subscription(Float64, "trip", trip)
    user.create_subscription(Clock, "/clock", clock)
    cmd = user.create_publisher(Twist, "cmd_vel")
    assert wait_for(lambda: trip.count > 0 and clock.count > 0, 20), (trip.count, clock.count)
    n0, t0 = trip.count, clock.msg.clock.to_sec()
    assert wait_for(lambda: clock.msg.clock.to_sec() > t0 + 5.0, 20)
    assert 8 <= trip.count - n0 <= 12, trip.count - n0  # 2 Hz of sim time, for 5 s
    rig = {"cmd": cmd, "got": {"clock": clock}}
    assert drive(rig, 0.5, 0.0, lambda: trip.msg.data > 0.2), trip.msg.data
    last = (trip.count, -1.0)

    def halted() -> bool:  # two trip messages in a row alike: the base has stopped
        nonlocal last
        if trip.count == last[0]:
            return False
        same, last = trip.msg.data == last[1], (trip.count, trip.msg.data)
        return same

    assert drive(rig, 0.0, 0.0, halted), trip.msg.data
    reset = user.create_client(SetBool, "trip/reset")
    assert reset.call(SetBoolRequest(data=True), timeout=10).success
    assert wait_for(lambda: trip.msg.data == 0.0, 10), trip.msg.data


def test_cameras_render_the_world_ahead_and_behind(rig: dict[str, Any]) -> None:
    """Front and back cameras on the robot API's topics, raw and JPEG, with their
    calibration and optical frames; an obstacle set in front shows in the front view."""
    import io

    from PIL import Image as PilImage
    from zenros.images import image_to_numpy
    from zenros.msgs.sensor_msgs import CameraInfo, CompressedImage, Image

    user = rig["user"]
    got = {name: Latest() for name in ("front", "alias", "back_jpeg", "info")}
    user.create_subscription(Image, "multi/front/image_raw", got["front"])
    user.create_subscription(Image, "camera_node/image_raw", got["alias"])
    user.create_subscription(CompressedImage, "multi/back/image_raw/compressed",
                             got["back_jpeg"])
    user.create_subscription(CameraInfo, "multi/front/camera_info", got["info"])
    assert wait_for(lambda: all(v.count for v in got.values()), 20), \
        {k: v.count for k, v in got.items()}
    front = got["front"].msg
    assert (front.width, front.height, front.encoding) == (640, 480, "rgb8")
    assert front.header.frame_id == "camera_front_optical_frame"
    assert got["alias"].msg.header.frame_id == "camera_front_optical_frame"
    info = got["info"].msg
    assert (info.width, info.height) == (640, 480) and info.k[2] == 320.0 and info.k[8] == 1.0
    jpeg = got["back_jpeg"].msg
    assert "jpeg" in jpeg.format and jpeg.header.frame_id == "camera_back_optical_frame"
    back = PilImage.open(io.BytesIO(bytes(jpeg.data)))  # an outside decoder reads it
    assert back.size == (640, 480) and back.format == "JPEG"
    # the corridor is open to the east: a crate 1.5 m ahead fills the front view's middle
    before = image_to_numpy(got["front"].msg)[300, 320].astype(int)
    client = user.create_client(SetObstacles, "sim/set_obstacles")
    crate = Obstacle(id="crate", shape="box", x=1.5, y=0.0, size_x=0.4, size_y=0.6)
    assert client.call(SetObstaclesRequest(obstacles=[crate]), timeout=10).success

    def orange() -> bool:
        r, g, b = (int(v) for v in image_to_numpy(got["front"].msg)[300, 320])
        return r > g + 60 and r > b + 60

    assert wait_for(orange, 10), (before, image_to_numpy(got["front"].msg)[300, 320])
    # the crate is only ahead: the back view has none of its colour
    back_px = np.asarray(PilImage.open(io.BytesIO(bytes(got["back_jpeg"].msg.data))))
    assert not ((back_px[..., 0].astype(int) > back_px[..., 1].astype(int) + 60)
                & (back_px[..., 0].astype(int) > back_px[..., 2].astype(int) + 60)).any()
    assert client.call(SetObstaclesRequest(op="remove", ids=["crate"]), timeout=10).success
