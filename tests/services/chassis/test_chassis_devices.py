"""The device seam: the registry's parameters, the schedule, devices against a stand-in node."""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any

import msgspec
import pytest
from zenros.clock import Time
from zenros.msgs.std_srvs import SetBoolRequest
from zenros.msgs.zenros_msgs import ChassisState, IoState, SetIoRequest
from zenros.params import Parameters
from zenros.services.chassis import config
from zenros.services.chassis.config import declare_chassis, parameter_structs
from zenros.services.chassis.device import Chassis, Device, NoParameters, Schedule
from zenros.services.chassis.devices import (
    DEVICES,
    CameraDevice,
    IoDevice,
    StateDevice,
    WindDevice,
)
from zenros.services.chassis.devices.wind import beaufort
from zenros.testing import wait_for

# every parameter the chassis had before its devices were split out: users' launch files and
# `-p name:=value` keep working only while these stay
NAMES = {
    "map", "speed", "publish_clock", "publish_tf", "rate", "scan_rate", "max_linear_velocity",
    "max_reverse_velocity", "max_angular_velocity", "max_linear_acceleration",
    "max_linear_deceleration", "max_angular_acceleration", "cmd_timeout", "scan_beams",
    "range_min", "range_max", "scan_fov", "range_noise", "battery_capacity", "battery_voltage",
    "battery_idle_current", "battery_motion_current", "battery_turn_current",
    "battery_charge_current", "battery_initial", "robot_radius", "odom_noise", "laser_x",
    "laser_y", "laser_yaw", "laser_z", "start_pose", "dock_pose", "dock_tolerance",
    "dock_yaw_tolerance", "seed", "map_frame", "odom_frame", "base_frame", "laser_frame",
    "world_topic", "world_rate", "io_extension_board", "camera_rate", "camera_width",
    "camera_height", "camera_hfov", "camera_z", "camera_front_x", "camera_back_x",
    "camera_jpeg_quality", "wind_speed", "wind_gust", "wind_direction", "actuators",
    "slide_travel", "slide_speed", "slide_max_speed", "jacking_travel", "jacking_speed",
    "jacking_max_speed", "jacking_angle_speed", "jacking_angle_max_speed", "asr_board",
    "asr_servo_speed", "ptz_camera", "ptz_x", "ptz_y", "ptz_z", "ptz_yaw", "ptz_pan_limit",
    "ptz_tilt_min", "ptz_tilt_max", "ptz_zoom_max", "ptz_hfov", "ptz_pan_speed",
    "ptz_tilt_speed", "ptz_zoom_speed", "ptz_width", "ptz_height", "ptz_rate",
    "ptz_jpeg_quality", "ptz_presets", "laser_error_x", "laser_error_y", "laser_error_yaw",
    "imu_rate", "imu_gyro_bias", "imu_gyro_noise", "imu_accel_noise", "imu_frame",
    "calibration", "imu_calibration_time", "laser_calibration_drive", "camera_error_yaw",
    "camera_error_f", "people", "people_rate", "uwb_rate", "uwb_range_noise",
    "uwb_bearing_noise", "building", "building_rate", "microphone_rate", "microphone_chunk",
    "microphone_noise", "microphone_motor_gain",
}
STAMP = Time(sec=1, nanosec=0)


class StandInPublisher:
    def __init__(self, topic: str) -> None:
        self.topic = topic
        self.sent: list[Any] = []
        self.subscription_count = 1

    def publish(self, msg: Any) -> None:
        self.sent.append(msg)

    send_transform = publish  # as a /tf broadcaster


class StandInNode:
    """`Endpoints` without Zenoh: records what the devices open and publish."""

    namespace = "/robot1"
    logger = logging.getLogger("test")

    def __init__(self) -> None:
        self.publishers: dict[str, StandInPublisher] = {}
        self.services: dict[str, Callable[[Any], Any]] = {}
        self.listening: dict[str, Callable[[Any], object]] = {}
        self.static: list[Any] = []
        self.broadcasters = 0
        self.tf = StandInPublisher("/tf")  # what its /tf broadcaster sent

    def create_publisher(self, msg_type: type[Any], topic: str, qos: Any = 10) -> Any:
        self.publishers[topic] = StandInPublisher(topic)
        return self.publishers[topic]

    def listen(self, msg_type: type[Any], topic: str, callback: Callable[[Any], object],
               qos: Any = 10) -> None:
        self.listening[topic] = callback

    def serve(self, srv_type: Any, name: str, handler: Callable[[Any], Any]) -> None:
        self.services[name] = handler

    def transforms(self) -> Any:
        self.broadcasters += 1
        return self.tf

    def static_transform(self, transform: Any) -> None:
        self.static.append(transform)

    def stamp(self) -> Time:
        return STAMP


def build(values: dict[str, object] | None = None) -> tuple[Chassis, StandInNode]:
    cfg = declare_chassis(Parameters("/chassis", values or {}))
    chassis = cfg.build(logging.getLogger("test"))
    node = StandInNode()
    for d in chassis.devices:
        d.open(node)
    return chassis, node


def test_the_parameter_names_are_the_ones_users_know() -> None:
    names = [n for s in parameter_structs() for n in s.__struct_fields__]
    assert len(names) == len(set(names))
    assert set(names) == NAMES


def test_a_parameter_two_structs_declare_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    class Clash(msgspec.Struct, frozen=True):
        scan_rate: float = 1.0

    class Clashing(Device[Clash]):
        Parameters = Clash

    monkeypatch.setattr(config, "DEVICES", (*DEVICES, Clashing))
    with pytest.raises(TypeError, match="'scan_rate' is declared by both LaserParameters "
                                        "and Clash"):
        parameter_structs()


def test_the_devices_open_their_topics_and_services() -> None:
    _, node = build({"camera_rate": 0.0, "actuators": False,  # their own tests, below
                     "asr_board": False, "ptz_camera": False, "imu_rate": 0.0,
                     "calibration": False, "microphone_rate": 0})
    assert set(node.publishers) == {"odom", "sim/ground_truth", "battery_state", "scan",
                                    "chassis/io", "chassis/state", "wind"}
    assert set(node.services) == {"chassis/set_io", "sim/set_people"} and node.listening == {}
    assert node.broadcasters == 1  # odom -> base_link
    [laser] = node.static
    assert (laser.header.frame_id, laser.child_frame_id) == ("base_link", "laser")
    [io] = node.publishers["chassis/io"].sent  # latched, at start
    assert isinstance(io, IoState) and io.outputs == [0, 0, 0]
    _, alone = build({"publish_tf": False, "world_topic": "/sim/world"})
    assert alone.broadcasters == 0
    assert "/sim/world" in alone.publishers and "/sim/world" in alone.listening


def test_a_device_service_answers_and_publishes() -> None:
    chassis, node = build({"io_extension_board": False})
    res = node.services["chassis/set_io"](SetIoRequest(board="main", port=2, level=1))
    assert res.success and res.state.outputs == [0, 1, 0]
    assert node.publishers["chassis/io"].sent[-1].outputs == [0, 1, 0]
    refused = node.services["chassis/set_io"](SetIoRequest(board="ext", port=0, level=1))
    assert not refused.success and "no extension IO board" in refused.message
    io = chassis.device(IoDevice)
    assert io is not None and io.io.snapshot() == ([0, 1, 0], [], [])


def test_each_device_publishes_at_its_rate() -> None:
    chassis, node = build({"rate": 50.0, "scan_rate": 10.0, "camera_rate": 0.0,
                           "actuators": False, "asr_board": False, "ptz_camera": False,
                           "imu_rate": 0.0, "calibration": False, "microphone_rate": 0})
    schedule = Schedule(chassis.devices, 50.0)
    for step in range(1, 101):  # two sim seconds
        chassis.step(0.02)
        schedule.publish(step, STAMP)
    counts = {t: len(p.sent) for t, p in node.publishers.items()}
    # chassis/state: 5 Hz, and once at the first step (its flags were never sent)
    assert counts == {"odom": 100, "sim/ground_truth": 100, "scan": 20, "battery_state": 2,
                      "chassis/state": 11, "chassis/io": 1, "wind": 2}


def test_the_cameras_open_their_topics_and_frames_and_render_off_the_step() -> None:
    chassis, node = build({"camera_width": 64, "camera_height": 48})
    bases = ("camera_node", "multi/front", "multi/back")
    cams = {f"{b}/{t}" for b in bases for t in ("image_raw", "image_raw/compressed",
                                                "camera_info")}
    assert cams <= set(node.publishers)
    frames = {(t.header.frame_id, t.child_frame_id) for t in node.static}
    assert {("base_link", "camera_front_link"), ("camera_front_link",
            "camera_front_optical_frame"), ("base_link", "camera_back_link"),
            ("camera_back_link", "camera_back_optical_frame")} <= frames
    camera = chassis.device(CameraDevice)
    assert camera is not None and camera.rate == 10.0
    camera.publish(STAMP)  # hands the frames to the cameras' thread and returns
    assert wait_for(lambda: all(node.publishers[t].sent for t in cams), 10)
    front = node.publishers["multi/front/image_raw"].sent[-1]
    assert (front.width, front.height, front.header.frame_id) == (
        64, 48, "camera_front_optical_frame")
    assert node.publishers["multi/back/image_raw/compressed"].sent[-1].data[:2].tobytes() \
        == b"\xff\xd8"  # a JPEG
    _, off = build({"camera_rate": 0.0})
    assert not cams & set(off.publishers)
    with pytest.raises(ValueError, match="camera z"):
        build({"camera_z": 5.0})


def test_the_wind_sensor_reads_calm_indoors_and_gusts_outdoors() -> None:
    indoor, _ = build()
    wind = indoor.device(WindDevice)
    assert wind is not None
    calm = wind.reading()
    assert (calm.current_speed, calm.max_speed, calm.level) == (0.0, 0.0, 0.0)
    chassis, _ = build({"wind_speed": 9.0, "wind_gust": 2.0, "wind_direction": 270.0,
                        "seed": 3})
    outdoor = chassis.device(WindDevice)
    assert outdoor is not None
    readings = []
    for _ in range(200):
        chassis.step(1.0)
        readings.append(outdoor.reading())
    speeds = [r.current_speed for r in readings]
    assert 8.0 < sum(speeds) / len(speeds) < 10.0 and max(speeds) > 11.0
    assert readings[-1].max_speed == max(speeds)  # 200 s: all within the 10 minutes
    assert {r.level for r in readings} >= {4.0, 5.0}  # Beaufort: 5.5-8 m/s 4, 8-10.8 5
    assert all(r.level == beaufort(r.current_speed) for r in readings)
    assert all(180.0 < r.direction < 360.0 for r in readings)
    assert beaufort(0.0) == 0 and beaufort(33.0) == 12
    with pytest.raises(ValueError, match="wind_direction"):
        build({"wind_direction": 360.0})


def test_a_change_publishes_off_the_schedule() -> None:
    chassis, node = build()
    schedule = Schedule(chassis.devices, chassis.step_rate)
    state = chassis.device(StateDevice)
    assert state is not None and schedule.every(state) == 10
    sent = node.publishers["chassis/state"].sent
    schedule.publish(10, STAMP)  # due
    assert len(sent) == 1 and not sent[-1].estop
    schedule.publish(11, STAMP)  # not due, nothing changed
    assert len(sent) == 1
    chassis.sim.drive.set_estop(True)
    schedule.publish(12, STAMP)  # not due, but the e-stop changed
    assert len(sent) == 2 and isinstance(sent[-1], ChassisState) and sent[-1].estop


def test_the_documented_new_device_is_one_module_and_one_registry_line(
        monkeypatch: pytest.MonkeyPatch, doc_module: Callable[[str, str], Any]) -> None:
    """The lift of docs/chassis.md's "Adding a device", as written there."""
    lift_device = doc_module("chassis.md", "# services/chassis/devices/lift.py").LiftDevice
    monkeypatch.setattr(config, "DEVICES", (*DEVICES, lift_device))
    chassis, node = build({"lift_speed": 0.02})
    lift = chassis.device(lift_device)
    assert lift is not None and lift.params.lift_speed == 0.02
    assert node.services["lift/move"](SetBoolRequest(data=True)).success
    schedule = Schedule(chassis.devices, 50.0)
    assert schedule.every(lift) == 10
    for step in range(1, 51):  # one sim second at 0.02 m/s
        chassis.step(0.02)
        schedule.publish(step, STAMP)
    heights = [m.data for m in node.publishers["lift/height"].sent]
    assert len(heights) == 5 and heights[-1] == pytest.approx(0.02)
    assert heights == sorted(heights)


def test_a_device_without_parameters_or_publishing_is_inert() -> None:
    chassis, _ = build()
    device: Device[NoParameters] = Device(NoParameters(), chassis)
    device.open(StandInNode())
    device.step(0.02)
    device.publish(STAMP)
    assert Schedule([device], 50.0).every(device) == 0 and not device.changed()


def test_only_the_devices_with_something_to_step_are_stepped_or_asked() -> None:
    """A device with no step of its own is not stepped; one its parameters leave out
    (``inert``: no board, no axes, a rate of 0) is neither stepped nor asked whether it
    changed nor published."""
    chassis, _ = build({"actuators": False, "asr_board": False, "ptz_camera": False,
                        "imu_rate": 0.0, "calibration": False, "microphone_rate": 0})
    inert = {type(d).__name__ for d in chassis.devices if d.inert}
    assert inert == {"ActuatorDevice", "AsrDevice", "PtzDevice", "ImuDevice",
                     "CalibrationDevice", "MicrophoneDevice", "BuildingDevice"}
    stepped = [d for d in chassis.devices if type(d).step is not Device.step and not d.inert]
    assert [s.__self__ for s in chassis._steps] == stepped  # type: ignore[attr-defined]
    assert {type(d).__name__ for d in stepped} == {"OdometryDevice", "PeopleDevice",
                                                    "BatteryDevice", "WindDevice"}
    due = {type(d).__name__ for d, _, _ in Schedule(chassis.devices, 50.0)._due}
    assert not due & inert and "StateDevice" in due
    full, _ = build()  # every device fitted and on: none inert but the building's
    assert [type(d).__name__ for d in full.devices if d.inert] == ["BuildingDevice"]


def test_at_rest_odometry_and_truth_are_stamped_anew_on_the_parts_already_built() -> None:
    """A robot standing still publishes odom, odom -> base_link and the ground truth at
    every step with that step's stamp; their pose and twist parts are those of the last
    message (built once), and built again once the robot moves."""
    chassis, node = build({"actuators": False, "asr_board": False, "ptz_camera": False})
    schedule = Schedule(chassis.devices, 50.0)
    stamps = [Time(sec=1, nanosec=20_000_000 * i) for i in range(3)]
    for step, stamp in enumerate(stamps, 1):
        chassis.step(0.02)
        schedule.publish(step, stamp)
    odom, truth, tf = node.publishers["odom"].sent, node.publishers["sim/ground_truth"].sent, \
        node.tf.sent
    for sent in (odom, truth):
        assert [m.header.stamp for m in sent] == stamps
        assert sent[0].pose is sent[1].pose is sent[2].pose
        assert sent[0].twist is sent[2].twist
    assert [m.header.stamp for m in tf] == stamps and tf[0].transform is tf[2].transform
    assert odom[0].header.frame_id == "odom" and truth[0].header.frame_id == "map"
    chassis.sim.drive.command(0.5, 0.2, chassis.sim.time)
    chassis.step(0.02)
    schedule.publish(4, STAMP)
    moved, link = node.publishers["odom"].sent[-1], node.tf.sent[-1]
    assert moved.pose is not odom[2].pose and moved.twist is not odom[2].twist
    assert moved.pose.pose.position.x > 0 and moved.twist.twist.angular.z > 0
    assert link.transform is not tf[2].transform
    assert link.transform.translation.x == moved.pose.pose.position.x
