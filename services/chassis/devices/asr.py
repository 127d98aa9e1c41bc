"""The ASR (voice) board (`AsrBoard`): ``asr/state`` (zenros_msgs/AsrBoardState, latched) at
every change and at 10 Hz while a servo turns; ``asr/set`` (zenros_msgs/SetAsrBoard) sets its
IO outputs, a PWM channel or a servo, within the board's limits."""

from __future__ import annotations

import time
from typing import Annotated

import msgspec
from msgspec import Meta
from zenros.clock import Time
from zenros.msgs.std_msgs import Header
from zenros.msgs.zenros_msgs import (
    AsrBoardState,
    SetAsrBoard,
    SetAsrBoardRequest,
    SetAsrBoardResponse,
)
from zenros.pubsub import Publisher
from zenros.qos import QOS_LATCHED

from ..asr_board import AsrBoard, AsrError
from ..device import Chassis, Device, Endpoints
from ..param_types import Positive

__all__ = ["AsrDevice", "AsrParameters"]


class AsrParameters(msgspec.Struct, kw_only=True, frozen=True):
    asr_board: Annotated[bool, Meta(
        description="the robot has the ASR (voice) board: IO, PWM and servo outputs")] = True
    asr_servo_speed: Annotated[Positive, Meta(
        description="how fast its servos turn (degrees a second)")] = 300.0


class AsrDevice(Device[AsrParameters]):
    """The board, its servos stepped with the body; nothing when ``asr_board`` is false."""

    Parameters = AsrParameters
    _node: Endpoints
    _pub: Publisher[AsrBoardState]

    def __init__(self, params: AsrParameters, chassis: Chassis) -> None:
        super().__init__(params, chassis)
        self.board = AsrBoard(servo_speed=params.asr_servo_speed) if params.asr_board else None
        self.inert = self.board is None
        self.rate = 10.0 if self.board is not None else 0.0
        self._dirty = False

    def open(self, node: Endpoints) -> None:
        if self.board is None:
            return
        self._node = node
        self._pub = node.create_publisher(AsrBoardState, "asr/state", QOS_LATCHED)
        node.serve(SetAsrBoard, "asr/set", self.handle_set)
        self._pub.publish(self.state())

    def step(self, dt: float) -> None:
        if self.board is not None:
            self._dirty |= self.board.step(dt)

    def changed(self) -> bool:
        return self._dirty  # a servo arrived: its last angle goes out now

    def state(self) -> AsrBoardState:
        b = self.board
        assert b is not None
        return AsrBoardState(
            header=Header(stamp=self._node.stamp(), frame_id=self.chassis.frames.base),
            io=list(b.io), pwm_freq=list(b.pwm_freq), pwm_percent=list(b.pwm_percent),
            servo_angle=[round(a, 3) for a in b.servo_angle], servo_target=list(b.servo_target))

    def publish(self, stamp: Time) -> None:
        if self.board is not None and (self.board.moving or self._dirty):
            self._dirty = False
            self._pub.publish(self.state())

    def handle_set(self, req: SetAsrBoardRequest) -> SetAsrBoardResponse:
        board = self.board
        assert board is not None
        now = time.monotonic()
        try:
            if req.kind == "io":
                if len(req.ports) != len(req.levels):
                    raise AsrError(f"{len(req.ports)} ports but {len(req.levels)} levels")
                board.set_io(dict(zip(req.ports, req.levels, strict=True)), now)
            elif req.kind == "pwm":
                board.set_pwm(req.port, req.freq, req.percent, now)
            elif req.kind == "servo":
                board.set_servo(req.port, req.angle, now)
            else:
                raise AsrError(f"kind {req.kind!r} is not one of io, pwm, servo")
        except AsrError as exc:
            return SetAsrBoardResponse(success=False, message=str(exc), state=self.state())
        state = self.state()
        self._pub.publish(state)
        self._node.logger.info("ASR board %s set", req.kind)
        return SetAsrBoardResponse(success=True, state=state)
