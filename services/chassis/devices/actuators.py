"""The slide rail, the jacking lift and its rotation (`Axis`): ``actuators/state``
(zenros_msgs/ActuatorState) and ``actuators/joint_states`` (sensor_msgs/JointState) at 10 Hz
and when a move ends; ``actuators/move`` (zenros_msgs/MoveActuator) homes, stops or moves one
(to a position, or at a speed for a time) within its travel and speed limits."""

from __future__ import annotations

import math
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.sensor_msgs import JointState
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import (
    ActuatorState,
    MoveActuator,
    MoveActuatorRequest,
    MoveActuatorResponse,
)
from zenros.pubsub import Publisher

from ..actuators import ActuatorError, Axis
from ..device import Chassis, Device, Endpoints
from ..param_types import Positive

__all__ = ["ActuatorDevice", "ActuatorParameters"]


class ActuatorParameters(msgspec.Struct, kw_only=True, frozen=True):
    actuators: Annotated[bool, Meta(
        description="the robot has the slide rail and the jacking lift")] = True
    slide_travel: Annotated[Positive, Meta(description="the slide rail's travel (m)")] = 1.0
    slide_speed: Annotated[Positive, Meta(description="its default speed (m/s)")] = 0.1
    slide_max_speed: Positive = 0.3
    jacking_travel: Annotated[Positive, Meta(description="the lift's travel (m)")] = 0.06
    jacking_speed: Positive = 0.02
    jacking_max_speed: Positive = 0.05
    jacking_angle_speed: Annotated[Positive, Meta(
        description="the lift's rotation default speed (rad/s); its travel is -pi..pi")] = 0.5
    jacking_angle_max_speed: Positive = 1.0

    def __post_init__(self) -> None:
        self.axes()

    def axes(self) -> list[Axis]:
        """The three axes, unhomed at their home (raises ValueError for a bad combination)."""
        return [Axis("slide", 0.0, self.slide_travel, self.slide_speed, self.slide_max_speed),
                Axis("jacking", 0.0, self.jacking_travel, self.jacking_speed,
                     self.jacking_max_speed),
                Axis("jacking_rotation", -math.pi, math.pi, self.jacking_angle_speed,
                     self.jacking_angle_max_speed, position=-math.pi)]


class ActuatorDevice(Device[ActuatorParameters]):
    """The axes, stepped with the body; nothing when ``actuators`` is false."""

    Parameters = ActuatorParameters
    _node: Endpoints
    _state: Publisher[ActuatorState]
    _joints: Publisher[JointState]

    def __init__(self, params: ActuatorParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.axes = {a.name: a for a in params.axes()} if params.actuators else {}
        self.inert = not self.axes
        self.rate = 10.0 if self.axes else 0.0
        self._ended = False

    def open(self, node: Endpoints) -> None:
        if not self.axes:
            return
        self._node = node
        self._state = node.create_publisher(ActuatorState, "actuators/state", 10)
        self._joints = node.create_publisher(JointState, "actuators/joint_states", 10)
        node.serve(MoveActuator, "actuators/move", self.handle_move)

    def step(self, dt: float) -> None:
        for axis in self.axes.values():
            self._ended |= axis.step(dt)

    def changed(self) -> bool:
        ended, self._ended = self._ended, False
        return ended

    def state(self) -> ActuatorState:
        axes = list(self.axes.values())
        return ActuatorState(
            header=Header(stamp=self._node.stamp(), frame_id=self.chassis.frames.base),
            name=[a.name for a in axes], position=[a.position for a in axes],
            velocity=[a.velocity for a in axes], low=[a.low for a in axes],
            high=[a.high for a in axes], max_speed=[a.max_speed for a in axes],
            zero_status=[a.zero_status for a in axes],
            moving=[a.moving for a in axes], fault=[a.fault for a in axes])

    def publish(self, stamp: Time) -> None:
        if not self.axes:
            return
        state = self.state()
        if self._state.subscription_count:
            self._state.publish(state)
        if self._joints.subscription_count:
            self._joints.publish(JointState(
                header=Header(stamp=stamp, frame_id=self.chassis.frames.base), name=state.name,
                position=state.position, velocity=state.velocity))

    def handle_move(self, req: MoveActuatorRequest) -> MoveActuatorResponse:
        axis = self.axes.get(req.name)
        if axis is None:
            return MoveActuatorResponse(
                success=False, message=f"no axis {req.name!r}: the axes are "
                                       f"{', '.join(self.axes)}", state=self.state())
        try:
            what = self._command(axis, req)
        except ActuatorError as exc:
            return MoveActuatorResponse(success=False, message=str(exc), state=self.state())
        self._node.logger.info("%s: %s", axis.name, what)
        return MoveActuatorResponse(success=True, message=what, state=self.state())

    @staticmethod
    def _command(axis: Axis, req: MoveActuatorRequest) -> str:
        """Start what ``req`` asks of ``axis``; what it does, in words."""
        if req.stop or req.mode == MoveActuatorRequest.MODE_STOP:
            axis.stop()
            return f"stopped at {axis.position:g}"
        if req.mode == MoveActuatorRequest.MODE_HOME:
            axis.home()
            return "homing"
        if req.mode == MoveActuatorRequest.MODE_SPEED:
            axis.run(req.speed, req.duration)
            return f"running at {req.speed or axis.speed:g} for {req.duration:g} s"
        if req.mode == MoveActuatorRequest.MODE_POSITION:
            axis.move_to(req.position, req.speed)
            return f"moving to {req.position:g}"
        raise ActuatorError(f"mode {req.mode} is not one of 0 (home), 1 (speed), 2 (stop), "
                            "3 (position)")
