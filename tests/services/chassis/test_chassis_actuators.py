"""The actuators' axes: homing first, moves within the travel at the asked speed, refusals
with the reason; and the device's state, joint states and move service."""

from __future__ import annotations

import logging
import math
from typing import Any, TypeVar

import pytest
from zenros.msgs.zenros_msgs import MoveActuatorRequest
from zenros.params import Parameters
from zenros.services.chassis.actuators import ActuatorError, Axis
from zenros.services.chassis.config import declare_chassis
from zenros.services.chassis.devices import ActuatorDevice


D = TypeVar("D")


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


def test_speed_mode_runs_for_its_time_and_faults_at_a_limit_homing_again() -> None:
    axis = Axis("slide", 0.0, 1.0, speed=0.1, max_speed=0.3)
    run(axis, 0.1)  # homed at once: it starts on its home switch
    axis.run(0.2, 2.0)  # + up, 2 s
    assert axis.moving
    assert run(axis, 1.0) == 0 and axis.position == pytest.approx(0.2)
    assert axis.velocity == pytest.approx(0.2)
    assert run(axis, 1.5) == 1 and axis.position == pytest.approx(0.4) and not axis.moving
    assert axis.fault == ""
    axis.run(-0.3, 1.0)  # down 0.3 m
    assert run(axis, 1.2) == 1 and axis.position == pytest.approx(0.1)
    axis.run(0.0, 10.0)  # the default speed, up: 1 m away at 0.1 m/s = 9 s of 10
    assert run(axis, 10.0) == 1 and axis.position == 1.0 and not axis.moving
    assert axis.fault == "slide reached its high limit (1) with 1.00 s of its run left"
    with pytest.raises(ActuatorError, match="at its high limit"):
        axis.run(0.1, 1.0)  # no further that way; the fault stays
    assert axis.fault
    axis.run(-0.1, 1.0)  # the other way clears it
    assert axis.fault == "" and run(axis, 1.0) == 1
    for speed, duration, words in ((0.5, 1.0, "within ±0.3"), (0.1, 0.0, "time > 0"),
                                   (float("inf"), 1.0, "speed inf")):
        with pytest.raises(ActuatorError, match=words):
            axis.run(speed, duration)
    axis.home()
    assert axis.zero_status == 0 and axis.moving
    with pytest.raises(ActuatorError, match="not homed"):
        axis.run(0.1, 1.0)
    assert run(axis, 9.5) == 1 and (axis.zero_status, axis.position) == (1, 0.0)


def build_device(kind: type[D], values: dict[str, object]) -> tuple[D, Any]:
    """A chassis built from ``values``, its devices opened on a stand-in node, and its
    device of ``kind``."""
    from test_chassis_devices import StandInNode  # the devices' stand-in node
    cfg = declare_chassis(Parameters("/chassis", values))
    chassis = cfg.build(logging.getLogger("test"))
    node = StandInNode()
    for d in chassis.devices:
        d.open(node)
    device = chassis.device(kind)
    assert device is not None
    return device, (chassis, node)


def build(values: dict[str, object]) -> tuple[ActuatorDevice, Any]:
    return build_device(ActuatorDevice, values)


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


def test_the_device_takes_the_specs_modes() -> None:
    device, (chassis, node) = build({"camera_rate": 0.0})
    move = node.services["actuators/move"]
    chassis.step(0.02)
    speed = move(MoveActuatorRequest(name="slide", mode=MoveActuatorRequest.MODE_SPEED,
                                     speed=0.3, duration=10.0))
    assert speed.success and speed.message == "running at 0.3 for 10 s", speed.message
    for _ in range(250):  # 5 s: 1 m of travel at 0.3 m/s ends at 3.3 s
        chassis.step(0.02)
    state = device.state()
    assert state.position[0] == 1.0 and not state.moving[0]
    assert "reached its high limit" in state.fault[0] and state.fault[1:] == ["", ""]
    home = move(MoveActuatorRequest(name="slide", mode=MoveActuatorRequest.MODE_HOME))
    assert home.success and home.state.zero_status[0] == 0 and home.state.fault[0] == ""
    stop = move(MoveActuatorRequest(name="slide", mode=MoveActuatorRequest.MODE_STOP))
    assert stop.success and stop.message == "stopped at 1"
    assert stop.state.zero_status[0] == -1 and "homing stopped" in stop.state.fault[0]
    refused = move(MoveActuatorRequest(name="slide", position=0.5))
    assert not refused.success and "not homed yet (zero_status -1)" in refused.message
    bad = move(MoveActuatorRequest(name="slide", mode=7))
    assert not bad.success and "mode 7 is not one of 0 (home)" in bad.message
