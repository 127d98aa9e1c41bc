"""The PTZ camera: its axes over sim time within their limits (absolute and continuous moves,
presets, ONVIF's normalised units), its view (tilt moves the horizon, zoom narrows the field),
its thermal reading (hot where a robot is in view) and the device's services and state."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from test_chassis_actuators import build_device
from zenros.msgs.zenros_msgs import (
    GetPtzTemperatureRequest,
    GotoPtzPresetRequest,
    MovePtzRequest,
    MovePtzSpeedRequest,
)
from zenros.se2 import Pose2
from zenros.services.chassis.camera import DOCK_ID
from zenros.services.chassis.devices import PtzDevice
from zenros.services.chassis.obstacles import Obstacle
from zenros.services.chassis.ptz import (
    PanTiltZoom,
    PtzError,
    PtzLimits,
    UnknownPreset,
    parse_presets,
)
from zenros.services.chassis.ptz_view import Mount, PtzView
from zenros.services.chassis.thermal import ThermalModel, read_rule
from zenros.services.chassis.world import World

LIMITS = PtzLimits(pan_min=-3.0, pan_max=3.0, tilt_min=-0.5, tilt_max=0.5, zoom_max=10.0,
                   pan_speed=1.5, tilt_speed=0.5, zoom_speed=4.0)


def run(head: PanTiltZoom, seconds: float, dt: float = 0.02) -> int:
    """Steps of ``dt`` for ``seconds``; how many ended a move."""
    return sum(head.step(dt) for _ in range(round(seconds / dt)))


def test_an_absolute_move_drives_each_axis_at_its_top_speed_to_the_target() -> None:
    head = PanTiltZoom(LIMITS)
    assert head.normalised() == (0.0, 0.0, 0.0)  # pan 0, level, zoom 1
    head.move(0.5, -1.0, 0.5)  # pan 1.5 rad right, tilt 0.5 down, zoom 5.5
    assert head.target == pytest.approx((1.5, -0.5, 5.5)) and head.moving
    run(head, 0.5)
    assert (head.pan, head.tilt, head.zoom) == pytest.approx((0.75, -0.25, 3.0))
    assert run(head, 0.7) == 1  # tilt arrived at 1 s, pan at 1 s, zoom at 1.125 s
    assert (head.pan, head.tilt, head.zoom) == pytest.approx((1.5, -0.5, 5.5))
    assert head.normalised() == pytest.approx((0.5, -1.0, 0.5)) and not head.moving
    for args, words in (((1.5, 0.0, 0.0), "x (pan) must be a number in [-1, 1], got 1.5"),
                        ((0.0, -1.01, 0.0), "y (tilt)"), ((0.0, 0.0, 1.2), "zoom"),
                        ((math.nan, 0.0, 0.0), "got nan"), ((0.0, 0.0, -0.1), "[0, 1]")):
        with pytest.raises(PtzError, match=words.replace("(", r"\(").replace(")", r"\)")
                           .replace("[", r"\[").replace("]", r"\]")):
            head.move(*args)
    assert (head.pan, head.tilt, head.zoom) == pytest.approx((1.5, -0.5, 5.5))  # unmoved


def test_a_continuous_move_runs_until_a_limit_or_a_stop() -> None:
    head = PanTiltZoom(LIMITS)
    head.move_speed(1.0, 0.0, -0.5)  # zoom already at its 1x limit: that axis stops
    run(head, 1.0)
    assert head.pan == pytest.approx(1.5) and head.zoom == 1.0 and head.moving
    assert head.speeds == (1.0, 0.0, 0.0)
    assert run(head, 2.0) == 1  # reached pan_max after 2 s, then every axis stood still
    assert head.pan == 3.0 and not head.moving
    head.move_speed(-0.5, 1.0, 0.0)
    run(head, 0.5)
    assert (head.pan, head.tilt) == pytest.approx((2.625, 0.25))
    head.move_speed(0.0, 0.0, 0.0)  # all zeros: stop
    assert not head.moving
    run(head, 1.0)
    assert (head.pan, head.tilt) == pytest.approx((2.625, 0.25))
    with pytest.raises(PtzError, match="speed_zoom"):
        head.move_speed(0.0, 0.0, 2.0)


def test_presets_by_name_or_token_and_their_checks() -> None:
    presets = parse_presets(["home=0,-0.1,1", "door=1.2,0.2,4"], LIMITS)
    head = PanTiltZoom(LIMITS, presets)
    assert head.goto_preset("door").name == "door"
    run(head, 2.0)
    assert (head.pan, head.tilt, head.zoom) == pytest.approx((1.2, 0.2, 4.0))
    assert head.goto_preset("1").name == "home"  # tokens count from 1
    with pytest.raises(UnknownPreset, match=r"no preset 'attic'; the presets are home \(1\), "
                                            r"door \(2\)"):
        head.preset("attic")
    for entries, words in ((["home=0,0"], "expected name=pan,tilt,zoom"),
                           (["=0,0,1"], "needs a name"), (["3=0,0,1"], "not a number"),
                           (["a=0,0,1", "a=1,0,1"], "given twice"),
                           (["high=0,0.9,1"], "tilt 0.9 is outside [-0.5, 0.5]"),
                           (["near=0,0,11"], "zoom 11")):
        with pytest.raises(ValueError, match=words.replace("[", r"\[").replace("]", r"\]")):
            parse_presets(entries, LIMITS)


def view(world: World, **kw: Any) -> PtzView:
    mount: dict[str, Any] = {"x": 9.95, "y": 5.0, "z": 1.5, "yaw": 0.0, "hfov": 1.2,
                             "width": 640, "height": 480}
    return PtzView(world, Mount(**(mount | kw)))


def wall_rows(image: np.ndarray, col: int) -> tuple[int, int]:
    """First and last row of the wall's colour band in column ``col`` (bright, yellowish)."""
    px = image[:, col].astype(int)
    wall = (px[:, 0] > px[:, 2] + 15) & (px[:, 1] > px[:, 2] + 10) & (px[:, 0] < 250)
    rows = np.nonzero(wall)[0]
    assert rows.size, "no wall in this column"
    return int(rows[0]), int(rows[-1])


def test_tilt_moves_the_horizon_and_zoom_narrows_the_view(hall: World) -> None:
    ptz = view(hall)  # 10 m from the east wall (x = 19.95), facing it, lens 1.5 m up
    level = ptz.frame(0.0, 0.0, 1.0, ())
    f = ptz.config(1.0, 0.0).f
    top, bottom = wall_rows(level, 300)
    assert bottom == pytest.approx(240 + f * 1.5 / 10, abs=1.5)
    assert top == pytest.approx(240 - f * 1.0 / 10, abs=1.5)
    up = ptz.frame(0.0, 0.2, 1.0, ())  # tilted up: the wall goes down the image
    t_up, b_up = wall_rows(up, 300)
    assert (t_up - top, b_up - bottom) == pytest.approx((f * math.tan(0.2),) * 2, abs=1.5)
    down = ptz.frame(0.0, -0.4, 1.0, ())
    assert wall_rows(down, 300)[1] == pytest.approx(bottom - f * math.tan(0.4), abs=1.5)
    # zoom: an object off the axis leaves the view, the one ahead grows by the focal ratio
    ahead = Obstacle("crate", "box", 14.95, 5.0, size_x=0.4, size_y=0.4)
    aside = Obstacle("robot:r2", "circle", 14.95, 6.5, radius=0.2)

    def widths(image: np.ndarray) -> tuple[int, int]:
        row = image[245].astype(int)
        orange = (row[:, 0] > row[:, 1] + 40) & (row[:, 0] > row[:, 2] + 40)
        blue = row[:, 2] > row[:, 0] + 40
        return int(orange.sum()), int(blue.sum())

    low = view(hall, z=0.45)  # row 245, just under the horizon, crosses both at 5 m
    wide = widths(low.frame(0.0, 0.0, 1.0, (ahead, aside)))
    tele = widths(low.frame(0.0, 0.0, 3.0, (ahead, aside)))
    assert wide[1] > 10 and tele[1] == 0
    ratio = math.tan(0.6) / math.tan(0.2)  # f at zoom 3 / f at zoom 1
    assert tele[0] == pytest.approx(wide[0] * ratio, rel=0.1)
    # pan turns the view right: the robot on the left comes to the middle
    turned = low.frame(-math.atan2(1.5, 5.0), 0.0, 3.0, (aside,))
    blue = np.nonzero(turned[245, :, 2].astype(int) > turned[245, :, 0].astype(int) + 40)[0]
    assert blue.size and abs(blue.mean() - 320) < 5


def test_the_thermal_view_is_hot_where_a_robot_is(hall: World) -> None:
    ptz = view(hall, z=2.4)
    model = ThermalModel()
    empty = read_rule(ptz.thermal(0.0, -0.2, 1.0, (), model))
    assert 20.5 < empty.min <= empty.average <= empty.max < 24.0  # floor, walls, ceiling
    robot = Obstacle("robot:self", "circle", 14.95, 4.0, radius=0.2)  # 5 m ahead, 1 m right
    temps = ptz.thermal(0.0, -0.2, 1.0, (robot,), model)
    assert temps.shape == (120, 160)
    hot = read_rule(temps)
    assert 35.0 <= hot.max <= 40.0 and hot.min == pytest.approx(empty.min)
    expected_x = 0.5 + math.tan(math.atan2(1.0, 5.0)) / math.tan(0.6) / 2  # right of centre
    assert hot.max_at[0] == pytest.approx(expected_x, abs=0.04)
    assert hot.max_at[1] > 0.5  # below the horizon: the motors, near the floor
    assert hot.average > empty.average
    # out of view when the camera pans left; the dock is warm only while charging
    assert read_rule(ptz.thermal(-1.0, -0.2, 1.0, (robot,), model)).max < 24.0
    dock = Obstacle(DOCK_ID, "box", 14.95, 5.0, size_x=0.12, size_y=0.5)
    assert read_rule(ptz.thermal(0.0, -0.2, 1.0, (dock,), model)).max < 24.0
    charging = read_rule(ptz.thermal(0.0, -0.2, 1.0, (dock,), ThermalModel(charging=True)))
    assert charging.max == 30.0 and charging.max_at[0] == pytest.approx(0.5, abs=0.05)


def test_the_device_moves_on_its_services_and_reads_the_robot_hot() -> None:
    device, (chassis, node) = build_device(PtzDevice, {"camera_rate": 0.0})
    assert device.on and device.rate == 5.0
    move, speed = node.services["ptz_camera/move"], node.services["ptz_camera/move_speed"]
    preset = node.services["ptz_camera/goto_preset"]
    thermal = node.services["ptz_camera/temperature"]
    assert {"ptz_camera/image_raw", "ptz_camera/image_raw/compressed", "ptz_camera/camera_info",
            "ptz_camera/state"} <= set(node.publishers)
    assert [t.child_frame_id for t in node.static][-2:] == ["ptz_camera_base",
                                                           "ptz_camera_optical_frame"]
    ok = move(MovePtzRequest(x=0.5, y=-0.5, zoom=0.5))
    assert ok.success and ok.state.moving and device.changed()
    for _ in range(150):  # 3 s of sim time
        chassis.step(0.02)
    state = device.state()
    assert (state.x, state.y, state.zoom_ratio) == pytest.approx((0.5, -0.5, 0.5))
    assert state.pan == pytest.approx(2.967 / 2) and state.zoom == pytest.approx(5.5)
    assert state.hfov == pytest.approx(1.2 / 5.5) and not state.moving
    assert state.presets == ["home", "corridor", "dock", "room"]
    assert (state.width, state.height, state.frame_rate) == (640, 480, 5.0)
    refused = move(MovePtzRequest(x=1.5))
    assert not refused.success and "x (pan)" in refused.message and not refused.not_found
    assert speed(MovePtzSpeedRequest(speed_x=-1.0)).state.moving
    chassis.step(0.5)
    stopped = speed(MovePtzSpeedRequest())
    assert stopped.success and stopped.message == "stopped" and not stopped.state.moving
    assert stopped.state.pan == pytest.approx(2.967 / 2 - 1.5708 * 0.5)
    unknown = preset(GotoPtzPresetRequest(preset="attic"))
    assert not unknown.success and unknown.not_found and "home (1)" in unknown.message
    assert preset(GotoPtzPresetRequest(preset="corridor")).success  # the start pose, zoom 4
    for _ in range(200):
        chassis.step(0.02)
    reading = thermal(GetPtzTemperatureRequest())
    rule = reading.rules[0]
    assert reading.success and (reading.width, reading.height) == (160, 120)
    assert 35.0 <= rule.max_temperature <= 40.0 and rule.id == 1 and not rule.frozen
    assert rule.max_x == pytest.approx(0.5, abs=0.1)
    assert rule.min_temperature <= rule.average_temperature < rule.max_temperature
    assert chassis.sim.teleport(Pose2(2.0, 3.0, 0.0)) == ""  # a room off the corridor
    assert thermal(GetPtzTemperatureRequest()).rules[0].max_temperature < 30.0
    device.publish(state.header.stamp)
    assert node.publishers["ptz_camera/state"].sent[-1].presets[0] == "home"


def test_the_device_is_off_when_asked_or_when_its_mount_is_in_a_wall() -> None:
    off, (_, bare) = build_device(PtzDevice, {"camera_rate": 0.0, "ptz_camera": False})
    assert not off.on and off.rate == 0 and "ptz_camera/move" not in bare.services
    walled, _ = build_device(PtzDevice, {"camera_rate": 0.0, "ptz_x": -50.0})
    assert not walled.on
    for values, words in (({"ptz_presets": ["x=9,0,1"]}, "pan 9"),
                          ({"ptz_z": 3.0}, "ptz_z"),
                          ({"ptz_tilt_min": 0.6}, "tilt range")):
        with pytest.raises(ValueError, match=words):
            build_device(PtzDevice, {"camera_rate": 0.0, **values})
