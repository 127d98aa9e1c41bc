"""Chassis parameters: defaults build the demo world; bad values name the parameter."""

from __future__ import annotations

import logging

import pytest
from zenros.errors import InvalidParameterValueError, MapError
from zenros.params import Parameters
from zenros.se2 import Pose2
from zenros.services.chassis.config import DEMO_MAP, ChassisConfig, declare_chassis
from zenros.services.chassis.device import Chassis, Schedule
from zenros.services.chassis.devices import BatteryDevice, DockDevice, LaserDevice


def declare_config(values: dict[str, object]) -> ChassisConfig:
    """What the node does: the parameters declared (``values`` as its overrides), then checked."""
    return declare_chassis(Parameters("/chassis", values))


def dock_pose(chassis: Chassis) -> Pose2:
    dock = chassis.device(DockDevice)
    assert dock is not None and dock.dock is not None
    return dock.dock.pose


def test_defaults_build_the_demo_office() -> None:
    cfg = declare_config({})
    assert cfg.map_path == DEMO_MAP
    chassis = cfg.build(logging.getLogger("test"))
    schedule = Schedule(chassis.devices, cfg.rate)
    laser, battery = chassis.device(LaserDevice), chassis.device(BatteryDevice)
    assert laser is not None and battery is not None
    assert schedule.every(laser) == 5 and schedule.every(battery) == 50
    assert chassis.sim.truth == Pose2(0.0, 0.0, 0.0)  # the office's start pose
    assert dock_pose(chassis).y == pytest.approx(-8.78)


def test_pose_parameters_override_the_map_folder() -> None:
    cfg = declare_config({"start_pose": [5.0, 0.5], "dock_pose": [1.0, 0.0, 3.0]})
    chassis = cfg.build(logging.getLogger("test"))
    assert chassis.sim.truth == Pose2(5.0, 0.5, 0.0)
    assert dock_pose(chassis) == Pose2(1.0, 0.0, 3.0)


@pytest.mark.parametrize(("values", "match"), [
    ({"max_linear_velocity": -1.0}, "'max_linear_velocity': expected a finite number >= 0"),
    ({"range_min": 20.0}, "range_min must be below range_max"),
    ({"rate": 0.0}, "'rate': expected a finite number > 0"),
    ({"speed": 3.0, "publish_clock": False}, "publish_clock is false"),
    ({"start_pose": [1.0, "a"]}, "'start_pose': Expected `float`, got `str` - at `\\$\\[1\\]`"),
    ({"start_pose": [1.0]}, "'start_pose': expected \\[x, y\\] or \\[x, y, theta\\]"),
    ({"battery_initial": 2.0}, "'battery_initial': expected a finite number within 0 .. 1"),
])
def test_bad_values_name_the_parameter(values: dict[str, object], match: str) -> None:
    with pytest.raises(InvalidParameterValueError, match=match):
        declare_config(values)


def test_bad_map_and_blocked_start() -> None:
    with pytest.raises(MapError, match="nope.yaml: cannot read map YAML"):
        declare_config({"map": "/nope.yaml"}).build(logging.getLogger("test"))
    with pytest.raises(ValueError, match="start pose .* does not fit"):
        declare_config({"start_pose": [0.0, 1.25]}).build(logging.getLogger("test"))
