"""Chassis parameters: defaults build the demo world; bad values name the parameter."""

from __future__ import annotations

import logging

import pytest
from zenros.errors import InvalidParameterValueError, MapError
from zenros.param_config import declare_parameters
from zenros.params import Parameters
from zenros.se2 import Pose2
from zenros.services.chassis.config import (
    DEMO_MAP,
    ChassisConfig,
    ChassisParameters,
    chassis_config,
)


def declare_config(values: dict[str, object]) -> ChassisConfig:
    """What the node does: the parameters declared (``values`` as its overrides), then checked."""
    params = Parameters("/chassis", values)
    return chassis_config(declare_parameters(params, ChassisParameters, read_only=True))


def test_defaults_build_the_demo_office() -> None:
    cfg = declare_config({})
    assert cfg.map_path == DEMO_MAP and cfg.scan_every == 5 and cfg.battery_every == 50
    sim = cfg.build(logging.getLogger("test"))
    assert sim.truth == Pose2(0.0, 0.0, 0.0)  # the office's start pose
    assert sim.dock is not None and sim.dock.pose.y == pytest.approx(-8.78)


def test_pose_parameters_override_the_map_folder() -> None:
    cfg = declare_config({"start_pose": [5.0, 0.5], "dock_pose": [1.0, 0.0, 3.0]})
    sim = cfg.build(logging.getLogger("test"))
    assert sim.truth == Pose2(5.0, 0.5, 0.0)
    assert sim.dock is not None and sim.dock.pose == Pose2(1.0, 0.0, 3.0)


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
