"""The actuators' axes: homing first, moves within the travel at the asked speed, refusals
with the reason; and the device's state, joint states and move service."""

from __future__ import annotations

import logging
import math
from typing import Any

import pytest
from zenros.msgs.zenros_msgs import MoveActuatorRequest
from zenros.params import Parameters
from zenros.services.chassis.actuators import ActuatorError, Axis
from zenros.services.chassis.config import declare_chassis
from zenros.services.chassis.devices import ActuatorDevice


def run(axis: Axis, seconds: float, dt: float = 0.02) -> int:
    """Steps of ``dt`` for ``seconds``; how many ended a move."""
    return sum(axis.step(dt) for _ in range(round(seconds / dt)))


def test_an_axis_homes_then_moves_at_its_speed_within_its_travel() -> None:
    axis = Axis("slide", 0.0, 1.0, speed=0.1, max_speed=0.3, position=0.4)
    with pytest.raises(ActuatorError, match="not homed"):
        axis.move_to(0.5)
    assert axis.zero_status == 0 and axis.moving
    assert run(axis, 4.1) == 1  # 0.4 m back to the home switch at 0.1 m/s
    assert (axis.zero_status, axis.position, axis.moving) == (1, 0.0, False)
    axis.move_to(0.5)  # the default speed
    run(axis, 2.0)
    assert axis.position == pytest.approx(0.2) and axis.velocity == pytest.approx(0.1)
    assert axis.ratio == pytest.approx(0.2)
    assert run(axis, 3.1) == 1 and axis.position == 0.5 and not axis.moving
    axis.move_to(1.0, 0.25)
    run(axis, 1.0)
    assert axis.position == pytest.approx(0.75)
    axis.stop()
    run(axis, 1.0)
    assert axis.position == pytest.approx(0.75) and axis.velocity == 0.0
    for target, speed, words in ((1.2, 0.0, "past its travel [0, 1]"),
                                 (-0.1, 0.0, "past its travel"),
                                 (float("nan"), 0.0, "past its travel"),
                                 (0.5, 0.5, "speed 0.5 must be 0 (default) up to 0.3"),
                                 (0.5, -1.0, "speed -1")):
        with pytest.raises(ActuatorError, match=words.replace("(", r"\(").replace(")", r"\)")
                           .replace("[", r"\[").replace("]", r"\]")):
            axis.move_to(target, speed)
    assert axis.position == pytest.approx(0.75) and not axis.moving
    with pytest.raises(ValueError, match="empty"):
        Axis("bad", 1.0, 1.0, 0.1, 0.2)


def build(values: dict[str, object]) -> tuple[ActuatorDevice, Any]:
    from test_chassis_devices import StandInNode  # the devices' stand-in node
    cfg = declare_chassis(Parameters("/chassis", values))
    chassis = cfg.build(logging.getLogger("test"))
    node = StandInNode()
    for d in chassis.devices:
        d.open(node)
    device = chassis.device(ActuatorDevice)
    assert device is not None
    return device, (chassis, node)


def test_the_device_publishes_its_axes_and_moves_them_on_request() -> None:
    device, (chassis, node) = build({"camera_rate": 0.0})
    move = node.services["actuators/move"]
    # homing: the rotation starts at -pi, its home; the others at 0
    chassis.step(0.02)
    assert device.changed()
    state = device.state()
    assert state.name == ["slide", "jacking", "jacking_rotation"]
    assert state.zero_status == [1, 1, 1] and state.high[:2] == [1.0, 0.06]
    refused = move(MoveActuatorRequest(name="jacking", position=0.1))
    assert not refused.success and "past its travel [0, 0.06]" in refused.message
    unknown = move(MoveActuatorRequest(name="arm", position=0.1))
    assert not unknown.success and "slide, jacking, jacking_rotation" in unknown.message
    ok = move(MoveActuatorRequest(name="jacking_rotation", position=0.0, speed=1.0))
    assert ok.success and ok.state.moving[2]
    for _ in range(200):
        chassis.step(0.02)
    state = device.state()
    assert state.position[2] == pytest.approx(0.0, abs=1e-9) and not any(state.moving)
    device.publish(state.header.stamp)
    joints = node.publishers["actuators/joint_states"].sent[-1]
    assert joints.name == state.name and joints.position[2] == pytest.approx(0.0, abs=1e-9)
    assert node.publishers["actuators/state"].sent[-1].zero_status == [1, 1, 1]
    off, (_, bare) = build({"camera_rate": 0.0, "actuators": False})
    assert off.rate == 0 and "actuators/move" not in bare.services
    with pytest.raises(ValueError, match="speed"):
        build({"slide_speed": 0.5, "slide_max_speed": 0.3})
    assert math.pi == pytest.approx(-device.axes["jacking_rotation"].low)
